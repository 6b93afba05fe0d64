#!/usr/bin/env bash
# Checks that every `scancrew ...` command quoted in docs/results/*.md still parses: each is
# given to `scancrew --parse-only`, which checks the subcommand, its options, their values
# and that the files named exist, and runs nothing. Commands with a <placeholder> are
# counted and skipped. Usage: check_results_commands.sh [SCANCREW_BINARY]
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-build/release/cli/scancrew}"
[ -x "$bin" ] || { echo "check_results_commands: no binary at $bin" >&2; exit 2; }
# inline code spans and fenced lines that start with "scancrew " (backticks are literal)
# shellcheck disable=SC2016
mapfile -t commands < <(grep -ohE '`scancrew [^`]+`|^scancrew .*' docs/results/*.md | tr -d '`' | sort -u)
[ "${#commands[@]}" -gt 0 ] || { echo "check_results_commands: no commands found" >&2; exit 2; }
checked=0 skipped=0 failed=0
for line in "${commands[@]}"; do
  if [[ "$line" == *"<"* ]]; then skipped=$((skipped + 1)); continue; fi
  read -ra words <<< "${line#scancrew }"
  if ! err=$("$bin" --parse-only "${words[@]}" 2>&1 >/dev/null); then
    echo "FAIL: $line"
    echo "  $err" | head -3
    failed=$((failed + 1))
  fi
  checked=$((checked + 1))
done
echo "check_results_commands: $checked checked, $failed failed, $skipped skipped (placeholders)"
[ "$failed" -eq 0 ]
