#!/usr/bin/env bash
# The fuzzers (fuzz/, docs/security.md): builds the libFuzzer harnesses (preset fuzz: clang,
# ASan + UBSan) and runs each for SECONDS (default 15) from its seed corpus fuzz/corpus/<h>,
# which stays read-only (new inputs go to build/fuzz/corpus/<h>). Any crash, sanitizer report,
# input slower than 10 s or over 2 GiB fails; its input is written to build/fuzz/crashes/.
# Copy it into fuzz/corpus/<h>/ with the fix: the test fuzz.<h>.corpus then replays it.
#   scripts/fuzz.sh [SECONDS] [HARNESS...]
#   scripts/fuzz.sh --seeds    rewrites the binary seeds (build/release's fuzz_make_seeds)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--seeds" ]; then
  cmake --build --preset release --target fuzz_make_seeds
  exec build/release/fuzz/fuzz_make_seeds fuzz/corpus
fi
seconds="${1:-15}"
shift || true
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=(codec mcap patch envelope launch scene ply run_files)
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
mkdir -p build/fuzz/crashes
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
failed=()
for h in "${harnesses[@]}"; do
  mkdir -p "build/fuzz/corpus/$h"
  log="build/fuzz/$h.log"
  if build/fuzz/fuzz/"${h}"_fuzz -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      -max_len=65536 -print_final_stats=1 -artifact_prefix="build/fuzz/crashes/$h-" \
      "build/fuzz/corpus/$h" "fuzz/corpus/$h" >"$log" 2>&1; then
    echo "fuzz: $h: $(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$') inputs in ${seconds} s, no finding"
  else
    echo "fuzz: $h: FINDING (build/fuzz/crashes/, $log):"
    grep -E "ERROR|runtime error|SUMMARY|Test unit written|No such file" "$log" | head -20 || true
    failed+=("$h")
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: findings in ${failed[*]}" >&2
  exit 1
fi
