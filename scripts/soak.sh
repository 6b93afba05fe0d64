#!/usr/bin/env bash
# Soak: one long simulated team mission, its resident memory sampled every simulated minute,
# and the growth over the second half fitted by least squares (docs/reliability.md). Runs
# outside CI (about 35 minutes of wall time on 2 cores for the default hour).
#
#   scripts/soak.sh [MISSION] [SIM_SECONDS] [OUT]
#     MISSION      a launch or mission file (default: the parking lot's four, distributed)
#     SIM_SECONDS  simulated length (default 3600); the mission does not stop at completion:
#                  the team keeps mapping, planning and exchanging with nothing left to do
#     OUT          run directory (default runs/soak); OUT/soak.csv holds the samples
# Exit status: 0 when the second half's RSS slope is at most 2 MiB per simulated hour and the
# run ended normally (exit 0 or 3), 1 otherwise.
set -euo pipefail
cd "$(dirname "$0")/.."
mission=${1:-launch_cfg/missions/parking_lot_4_distributed.yaml}
sim_s=${2:-3600}
out=${3:-runs/soak}
bin=${SCANCREW_BIN:-build/release/cli/scancrew}
max_slope_mib_per_h=2
[ -x "$bin" ] || ./scripts/build.sh release
mkdir -p "$out"
"$bin" run "$mission" --out "$out" --trace-events 0 --set run.duration_s="$sim_s" \
  --set mission_monitor.stop_when_complete=false --set mission_monitor.stall_timeout_s=0 \
  >"$out/soak.log" 2>&1 &
pid=$!
trap 'kill "$pid" 2>/dev/null' INT TERM
echo "sim_s,rss_kib,wall_s" >"$out/soak.csv"
start=$SECONDS
next=0
while kill -0 "$pid" 2>/dev/null; do
  # the progress line reads "t  120.0 / 3600 s ..."
  t=$(tr '\r' '\n' <"$out/soak.log" | sed -n 's/^t *\([0-9.]*\) \/.*/\1/p' | tail -n 1)
  # (not at the end: the run's final mesh and evaluation are not the steady state)
  if [ -n "$t" ] && awk -v t="$t" -v n="$next" -v e="$sim_s" 'BEGIN { exit !(t >= n && t < e) }'; then
    rss=$(awk '/^VmRSS:/ { print $2 }' "/proc/$pid/status" 2>/dev/null || true)
    [ -n "$rss" ] && echo "$t,$rss,$((SECONDS - start))" >>"$out/soak.csv"
    printf 'soak: t %7.1f s  RSS %s MiB\r' "$t" "$((${rss:-0} / 1024))"
    next=$(awk -v t="$t" 'BEGIN { print (int(t / 60) + 1) * 60 }')
  fi
  sleep 0.5
done
set +e
wait "$pid"
status=$?
set -e
echo
samples=$(($(wc -l <"$out/soak.csv") - 1))
# least squares over the second half of the samples: MiB per simulated hour
read -r slope first last < <(awk -F, -v half="$((samples / 2))" '
  NR > 1 && NR - 1 > half { n++; x = $1 / 3600; y = $2 / 1024; sx += x; sy += y; sxx += x * x;
                            sxy += x * y; if (n == 1) f = y; l = y }
  END { d = n * sxx - sx * sx; printf "%.3f %.1f %.1f\n", (n > 1 && d > 0) ? (n * sxy - sx * sy) / d : 0, f, l }' \
  "$out/soak.csv")
echo "soak: $samples samples over ${sim_s} s simulated in $((SECONDS - start)) s wall, exit status $status"
echo "soak: second half: RSS ${first} -> ${last} MiB, slope ${slope} MiB per simulated hour (limit ${max_slope_mib_per_h})"
if [ "$status" != 0 ] && [ "$status" != 3 ]; then
  echo "soak: the run failed (exit status $status, $out/soak.log)" >&2
  exit 1
fi
if [ "$samples" -lt 4 ] || awk -v s="$slope" -v m="$max_slope_mib_per_h" 'BEGIN { exit !(s > m) }'; then
  echo "soak: memory grows (or too few samples): see $out/soak.csv" >&2
  exit 1
fi
