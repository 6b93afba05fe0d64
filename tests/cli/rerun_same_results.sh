#!/usr/bin/env bash
# `scancrew rerun` repeats a run: FIRST (scancrew run) and SECOND (scancrew rerun FIRST) ran
# the same resolved launch file, and their deterministic results (sim clock, compute time
# free) are identical: paths.csv, coverage.csv and metrics.json's coverage, path lengths,
# errors, goals, replans and stop reason. Usage: rerun_same_results.sh FIRST SECOND
set -euo pipefail
first="$1" second="$2"
cmp "$first/launch.resolved.yaml" "$second/launch.resolved.yaml"
cmp "$first/paths.csv" "$second/paths.csv"
cmp "$first/coverage.csv" "$second/coverage.csv"
keys='coverage|coverage_reachable|total_path_length_m|path_length_m|mean_error_m|rmse_m|goals_reached|replans|stop_reason|sim_time_s|ises_left'
deterministic() { grep -E "^ *\"($keys)\":" "$1/metrics.json"; }
diff <(deterministic "$first") <(deterministic "$second")
# the comparison compares something: both robots moved and the map covers the arena
[ "$(grep -cE '^ +"path_length_m": [1-9][0-9]*\.' "$first/metrics.json")" -eq 2 ]
grep -qE '^  "coverage": 0\.[5-9]' "$first/metrics.json"
# the second run says what it repeated
grep -q "\"rerun_of\": \"$first\"" "$second/run.json"
grep -q '"sets": \[\]' "$second/run.json"
echo "rerun: same results ($(deterministic "$first" | wc -l) metrics, paths and coverage)"
