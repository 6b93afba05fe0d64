#!/usr/bin/env bash
# Reruns the experiment of one docs/results page: every fenced line of the page that starts
# with "scancrew " runs, in the page's order, with the build's binary; each command's output
# goes to runs/results/<page>/<n>.log and the commands' own --out folders (the tables are
# what those commands print and write). Commands with a <placeholder> are listed and skipped.
# Long: a page's commands are its whole experiment (minutes to hours).
# Usage: rerun_results.sh PAGE [--print]   (PAGE: e.g. planner or docs/results/planner.md;
#        --print lists the commands and runs nothing)
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 1 ] || { echo "usage: rerun_results.sh PAGE [--print]" >&2; exit 2; }
page="$1"
[ -f "$page" ] || page="docs/results/${page%.md}.md"
[ -f "$page" ] || { echo "rerun_results: no page $1 (docs/results/*.md)" >&2; exit 2; }
bin=build/release/cli/scancrew
name=$(basename "$page" .md)
out="runs/results/$name"
mapfile -t commands < <(awk '/^```/{fenced=!fenced; next} fenced && /^scancrew /' "$page")
[ "${#commands[@]}" -gt 0 ] || { echo "rerun_results: $page quotes no command" >&2; exit 2; }
if [ "${2:-}" = "--print" ]; then
  printf '%s\n' "${commands[@]}"
  exit 0
fi
[ -x "$bin" ] || { echo "rerun_results: no binary at $bin (./scripts/build.sh release)" >&2; exit 2; }
mkdir -p "$out"
n=0
for line in "${commands[@]}"; do
  n=$((n + 1))
  if [[ "$line" == *"<"* ]]; then
    echo "[$n/${#commands[@]}] skipped (placeholder): $line"
    continue
  fi
  echo "[$n/${#commands[@]}] $line  > $out/$n.log"
  read -ra words <<< "${line#scancrew }"
  "$bin" "${words[@]}" > "$out/$n.log" 2>&1 || { echo "rerun_results: failed, see $out/$n.log" >&2; exit 1; }
done
echo "rerun_results: ${#commands[@]} command(s) of $page; logs in $out/"
