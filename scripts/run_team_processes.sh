#!/usr/bin/env bash
# Runs a team split over processes on this machine (docs/processes.md): `scancrew sim` and
# one `scancrew robot --robot K` per robot of the launch file, all on loopback, and waits for
# the simulator's process to end the mission. Each process logs to OUT/<process>.log.
#
#   scripts/run_team_processes.sh LAUNCH OUT [options] [-- extra scancrew options]
#     --robots "1 2 3"   the robot ids to start (default: 1 2 3)
#     --station          also start `scancrew station` (a centralized team)
#     --kill K --at-s T  SIGKILL robot K's process once the simulator reports sim time >= T
#     --timeout S        wall seconds before every process is stopped (default 1800)
#     --bin PATH         the scancrew binary (default: build/release/cli/scancrew)
#     --secure           DDS-Security: a team key folder OUT/keys (scancrew keys init, then
#                        keys add for every place started) and --set security.keys=OUT/keys
#   Everything after -- goes to every process (e.g. --set dds_bridge.link_loss_rate=0.2).
# Exit status: the simulator's (0: it wrote its run directory), 124 on timeout.
set -u
launch=${1:?usage: run_team_processes.sh LAUNCH OUT [options]}
out=${2:?usage: run_team_processes.sh LAUNCH OUT [options]}
shift 2
robots="1 2 3" kill_robot="" kill_at="" timeout_s=1800 station=0 secure=0
bin=${SCANCREW_BIN:-build/release/cli/scancrew}
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --robots) robots=$2; shift 2 ;;
    --station) station=1; shift ;;
    --kill) kill_robot=$2; shift 2 ;;
    --at-s) kill_at=$2; shift 2 ;;
    --timeout) timeout_s=$2; shift 2 ;;
    --bin) bin=$2; shift 2 ;;
    --secure) secure=1; shift ;;
    --) shift; extra=("$@"); break ;;
    *) echo "run_team_processes.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x "$bin" ] || { echo "run_team_processes.sh: no scancrew binary at $bin" >&2; exit 2; }
mkdir -p "$out"
# shared-memory files a killed process of an earlier run left behind (clean_dds_shm.sh)
"$(dirname "$0")/clean_dds_shm.sh" >&2
if [ "$secure" = 1 ]; then
  rm -rf "$out/keys"
  places=(--sim)
  [ "$station" = 1 ] && places+=(--station)
  for k in $robots; do places+=("--robot $k"); done
  "$bin" keys init "$out/keys" --team "$(basename "$launch" .yaml)" >/dev/null || exit 2
  for p in "${places[@]}"; do
    # shellcheck disable=SC2086 # "--robot K" is two words
    "$bin" keys add "$out/keys" "$launch" $p || exit 2
  done
  extra+=(--set "security.keys=$out/keys")
fi

pids=()
stop_all() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done; }
trap 'stop_all; exit 130' INT TERM

"$bin" sim "$launch" --out "$out" "${extra[@]}" >"$out/sim.log" 2>&1 &
sim_pid=$!
pids+=("$sim_pid")
declare -A robot_pid
station_pid=""
if [ "$station" = 1 ]; then
  "$bin" station "$launch" --out "$out" "${extra[@]}" >"$out/station.log" 2>&1 &
  station_pid=$!
  pids+=("$station_pid")
fi
for k in $robots; do
  "$bin" robot "$launch" --robot "$k" --out "$out" "${extra[@]}" >"$out/robot_$k.log" 2>&1 &
  robot_pid[$k]=$!
  pids+=("$!")
done
echo "run_team_processes.sh: simulator pid $sim_pid; robots: $(for k in $robots; do printf '%s:%s ' "$k" "${robot_pid[$k]}"; done)"

# the simulator's progress line reads "t   40.0 / 300 s ..."
sim_time() {
  tr '\r' '\n' <"$out/sim.log" | sed -n 's/^t *\([0-9.]*\) \/.*/\1/p' | tail -n 1
}

start=$SECONDS
killed=0
while kill -0 "$sim_pid" 2>/dev/null; do
  if [ -n "$kill_robot" ] && [ "$killed" = 0 ]; then
    t=$(sim_time)
    if [ -n "$t" ] && awk -v t="$t" -v at="$kill_at" 'BEGIN { exit !(t >= at) }'; then
      kill -KILL "${robot_pid[$kill_robot]}" 2>/dev/null
      killed=1
      echo "run_team_processes.sh: killed robot $kill_robot (pid ${robot_pid[$kill_robot]}) at sim time $t s"
    fi
  fi
  if [ $((SECONDS - start)) -ge "$timeout_s" ]; then
    echo "run_team_processes.sh: timeout after $timeout_s s; stopping every process" >&2
    stop_all
    wait
    exit 124
  fi
  sleep 0.2
done
wait "$sim_pid"
status=$?
# the robots (and the station) end when the simulator stops the run; give them a bound
for p in "${robot_pid[@]}" $station_pid; do
  for _ in $(seq 1 300); do kill -0 "$p" 2>/dev/null || break; sleep 0.2; done
  kill "$p" 2>/dev/null
  wait "$p" 2>/dev/null
done
tr '\r' '\n' <"$out/sim.log" | grep -E "^mission |^run directory|^dds " || true
exit "$status"
