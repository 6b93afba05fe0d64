#!/usr/bin/env bash
# A shipped mission run from another directory (its paths relative to the file, not the
# working directory) runs (out of time: exit status 3) and is quiet and honest: no warning,
# no stray " done." line, the last progress line before the components' closing reports,
# and topics.txt's rates in sim time (the 5 Hz cameras at 5.0 Hz whatever the run's speed
# against the wall).
# Usage: quiet_run.sh SCANCREW MISSION(absolute) OUT   (run from any directory but the repo's)
set -euo pipefail
bin="$1" mission="$2" out="$3"
rm -rf "$out"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
status=0
"$bin" run "$mission" --set run.duration_s=2 --out "$out" >"$log" 2>&1 || status=$?
fail() { cat "$log"; echo "quiet_run: $1"; exit 1; }
# 3: out of time (docs/missions.md, "Exit status"), as a 2 s mission is
if [ "$status" -ne 3 ] || ! grep -q 'mission out of time after 2\.0 s simulated' "$log"; then
  fail "exit status $status in $(pwd), not a mission out of time"
fi
! grep -qi 'warning' "$log" || fail "a warning"
! grep -qx ' *done\.' "$log" || fail "a stray ' done.' line"
progress=$(grep -n '^t  *2\.0 / 2 s' "$log" | tail -1 | cut -d: -f1)
closing=$(grep -n '^\[info\] /team_simulator: 2\.0 s simulated' "$log" | cut -d: -f1)
if [ -z "$progress" ] || [ -z "$closing" ]; then
  fail "no last progress line or no closing report"
fi
[ "$progress" -lt "$closing" ] || fail "the last progress line comes after the closing reports"
grep -qE '^/r1/depth +10 +5\.0 ' "$out/topics.txt" || {
  cat "$out/topics.txt"
  fail "/r1/depth: not 10 messages at 5.0 Hz of sim time"
}
echo "quiet_run: quiet, ordered, rates in sim time (run in $(pwd))"
