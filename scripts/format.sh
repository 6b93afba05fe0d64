#!/usr/bin/env bash
# clang-format over the project's sources: --check fails on a difference, else rewrites.
set -euo pipefail
cd "$(dirname "$0")/.."
# tracked and new (not ignored) files: a file not yet added is checked too
mapfile -t files < <(git ls-files --cached --others --exclude-standard '*.cpp' '*.hpp')
if [ "${1:-}" = "--check" ]; then
  clang-format --dry-run -Werror "${files[@]}"
  echo "format: ${#files[@]} files clean"
else
  clang-format -i "${files[@]}"
fi
