#!/usr/bin/env bash
# Builds with a sanitizer (asan = ASan+UBSan, tsan = TSan) and runs the tests labelled
# "sanitize" (runtime and, as they land, mapping).
set -euo pipefail
kind="${1:?usage: sanitize.sh asan|tsan}"
cd "$(dirname "$0")/.."
cmake --preset "$kind" >/dev/null
# only the test binaries: the sanitizer runs cover the "sanitize"-labelled suites
cmake --build --preset "$kind" --target test_executors test_no_allocation test_interfaces
if [ "$kind" = tsan ]; then
  # TSan of g++ 12 cannot map its shadow memory with the 32-bit mmap randomisation of
  # newer kernels ("unexpected memory mapping"); run without address randomisation.
  exec setarch "$(uname -m)" -R ctest --preset tsan -j "$(nproc)"
fi
ctest --preset "$kind" -j "$(nproc)"
