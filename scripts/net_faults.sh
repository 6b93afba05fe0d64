#!/usr/bin/env bash
# Real network faults for a team split over processes (docs/reliability.md): each process
# (the simulator, each robot) in a network namespace of its own, joined by veth pairs to a
# Linux bridge in a hub namespace, the bridges on `transport: udp` with unicast discovery
# (10.77.0.0/24; nothing outside these namespaces is touched). Needs root.
#
#   scripts/net_faults.sh FAULT OUT [--robots "1 2 3"] [--timeout S] [--bin PATH]
#                         [-- extra scancrew options]
#     FAULT  none        the namespaces alone (the control)
#            netem       50 ms delay and 10 % loss on every sender's link: iptables' statistic
#                        match drops, tests/net/net_delay holds every packet 50 ms (NFQUEUE):
#                        this machine's kernel has no packet schedulers, so no tc netem
#            partition   robot 2 cut off from sim time PART_AT (default 10 s) for PART_S (default
#                        60 s) of sim time (its link to the hub down), then healed
#            reboot      robot 2's process SIGKILLed at sim time REBOOT_AT (default 60 s) and
#                        started again REBOOT_AFTER (default 10) s of wall later, as a rebooted
#                        robot rejoins
#            range       robots 1 and 3 out of each other's range from sim time RANGE_AT
#                        (default 10 s) on, for good (iptables drops what either sends the
#                        other); both still reach robot 2 and the simulator: robot 2 relays
#                        the map between them (thesis Fig. 4.2)
#     OUT    run directory (the processes' logs, the summary in OUT/faults.txt)
#   The launch file is launch_cfg/processes/arena_team.yaml unless LAUNCH=... is set.
# Exit status: 0 when the team finished (mission complete) and the robots' maps converged:
# every robot holds as many patches as the one that holds most, but for the ones still in
# flight when the leader stopped the run (at most one per teammate: the run stops on the step
# that completes the mission), and none twice (held = made + received; duplicates are
# counted apart); 1 otherwise; 2 on a setup error.
set -u
fault=${1:?usage: net_faults.sh none|netem|partition|reboot|range OUT [options]}
out=${2:?usage: net_faults.sh FAULT OUT [options]}
shift 2
launch=${LAUNCH:-launch_cfg/processes/arena_team.yaml}
robots="1 2 3" timeout_s=1800
bin=${SCANCREW_BIN:-build/release/cli/scancrew}
delay_bin=${NET_DELAY_BIN:-build/release/tests/net/net_delay}
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --robots) robots=$2; shift 2 ;;
    --timeout) timeout_s=$2; shift 2 ;;
    --bin) bin=$2; shift 2 ;;
    --) shift; extra=("$@"); break ;;
    *) echo "net_faults.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
case "$fault" in none | netem | partition | reboot | range) ;; *) echo "net_faults.sh: unknown fault $fault" >&2; exit 2 ;; esac
# 77: skipped (ctest's SKIP_RETURN_CODE): not root
[ "$(id -u)" = 0 ] || { echo "net_faults.sh: needs root (network namespaces, iptables)" >&2; exit 77; }
[ -x "$bin" ] || { echo "net_faults.sh: no scancrew binary at $bin" >&2; exit 2; }
if { [ "$fault" = partition ] || [ "$fault" = reboot ]; } && ! grep -qw 2 <<<"$robots"; then
  echo "net_faults.sh: $fault acts on robot 2, which --robots does not start" >&2
  exit 2
fi
if [ "$fault" = range ] && ! { grep -qw 1 <<<"$robots" && grep -qw 2 <<<"$robots" && grep -qw 3 <<<"$robots"; }; then
  echo "net_faults.sh: range needs robots 1, 2 and 3" >&2
  exit 2
fi
if [ "$fault" = netem ] || [ "$fault" = range ]; then
  command -v iptables >/dev/null || { echo "net_faults.sh: no iptables" >&2; exit 2; }
fi
if [ "$fault" = netem ]; then
  [ -x "$delay_bin" ] || { echo "net_faults.sh: no net_delay at $delay_bin (libnetfilter-queue-dev)" >&2; exit 2; }
fi
bin=$(realpath "$bin")
mkdir -p "$out"
# shared-memory files a killed process of an earlier run left behind (clean_dds_shm.sh)
"$(dirname "$0")/clean_dds_shm.sh" >&2
out=$(realpath "$out")
# a rerun into the same folder: the logs of the last run go first, or the loop below would read
# the last run's sim time before the new simulator has truncated its log
rm -f "$out/sim.log" "$out"/robot_*.log "$out/faults.txt" "$out/net_delay.log"

# namespaces: sc<pid>-hub (the bridge), sc<pid>-sim, sc<pid>-r<k>; addresses .1 sim, .1+k robots
tag="sc$$"
places=(sim)
for k in $robots; do places+=("r$k"); done
declare -A addr
addr[sim]=10.77.0.1
for k in $robots; do addr[r$k]=10.77.0.$((1 + k)); done
peers=$(for p in "${places[@]}"; do printf '%s,' "${addr[$p]}"; done)
peers="[${peers%,}]"

pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  wait 2>/dev/null
  for p in "${places[@]}" hub; do ip netns del "$tag-$p" 2>/dev/null; done
  for p in "${places[@]}"; do ip link del "v$$$p" 2>/dev/null; done  # a pair not yet moved
}
trap 'cleanup; exit 130' INT TERM
trap cleanup EXIT

ip netns add "$tag-hub" || exit 2
ip -n "$tag-hub" link set lo up
ip -n "$tag-hub" link add br0 type bridge
ip -n "$tag-hub" link set br0 up
for p in "${places[@]}"; do
  ns="$tag-$p"
  ip netns add "$ns" || exit 2
  ip link add "v$$$p" type veth peer name "h$$$p" || exit 2
  ip link set "v$$$p" netns "$ns" || exit 2
  ip link set "h$$$p" netns "$tag-hub" || exit 2
  ip -n "$ns" link set lo up
  ip -n "$ns" link set "v$$$p" name eth0
  ip -n "$ns" addr add "${addr[$p]}/24" dev eth0
  ip -n "$ns" link set eth0 up
  ip -n "$tag-hub" link set "h$$$p" master br0
  ip -n "$tag-hub" link set "h$$$p" up
  if [ "$fault" = netem ]; then
    ip netns exec "$ns" iptables -A OUTPUT -o eth0 -m statistic --mode random \
      --probability "${NET_LOSS:-0.1}" -j DROP || exit 2
    ip netns exec "$ns" iptables -A OUTPUT -o eth0 -j NFQUEUE --queue-num 0 || exit 2
    ip netns exec "$ns" "$delay_bin" 0 50 2>>"$out/net_delay.log" &
    pids+=("$!")
  fi
done

net=(--set "sim_bridge.transport=udp" --set "sim_bridge.initial_peers=$peers"
     --set "dds_bridge.transport=udp" --set "dds_bridge.initial_peers=$peers")
ip netns exec "$tag-sim" "$bin" sim "$launch" --out "$out" "${net[@]}" "${extra[@]}" \
  >"$out/sim.log" 2>&1 &
sim_pid=$!
pids+=("$sim_pid")
declare -A robot_pid
start_robot() {  # k, log file
  ip netns exec "$tag-r$1" "$bin" robot "$launch" --robot "$1" --out "$out" "${net[@]}" \
    "${extra[@]}" >"$2" 2>&1 &
  robot_pid[$1]=$!
  pids+=("$!")
}
for k in $robots; do start_robot "$k" "$out/robot_$k.log"; done

sim_time() { tr '\r' '\n' <"$out/sim.log" | sed -n 's/^t *\([0-9.]*\) \/.*/\1/p' | tail -n 1; }
part_at=${PART_AT:-10} part_s=${PART_S:-60} reboot_at=${REBOOT_AT:-60} range_at=${RANGE_AT:-10}
start=$SECONDS cut_at="" healed=0 killed_at=""
after() { [ -n "$1" ] && awk -v t="$1" -v at="$2" 'BEGIN { exit !(t >= at) }'; }
while kill -0 "$sim_pid" 2>/dev/null; do
  t=$(sim_time)
  if [ "$fault" = partition ] && [ -z "$cut_at" ] && after "$t" "$part_at"; then
    ip -n "$tag-hub" link set "h$$r2" down || { echo "net_faults.sh: cannot cut robot 2" >&2; exit 2; }
    cut_at=$t
    echo "net_faults.sh: robot 2 cut off at sim time $t s (wall $((SECONDS - start)) s)" | tee -a "$out/faults.txt"
  fi
  if [ "$fault" = range ] && [ -z "$cut_at" ] && after "$t" "$range_at"; then
    for pair in "r1 r3" "r3 r1"; do
      read -r here there <<<"$pair"
      if ! ip netns exec "$tag-$here" iptables -A INPUT -s "${addr[$there]}" -j DROP ||
        ! ip netns exec "$tag-$here" iptables -A OUTPUT -d "${addr[$there]}" -j DROP; then
        echo "net_faults.sh: cannot cut robots 1 and 3 apart" >&2
        exit 2
      fi
    done
    cut_at=$t healed=1  # for good
    echo "net_faults.sh: robots 1 and 3 out of each other's range from sim time $t s (wall $((SECONDS - start)) s)" | tee -a "$out/faults.txt"
  fi
  if [ "$fault" = reboot ] && [ -z "$killed_at" ] && after "$t" "$reboot_at"; then
    kill -KILL "${robot_pid[2]}"
    killed_at=$SECONDS
    mv "$out/robot_2.log" "$out/robot_2_before_reboot.log"
    echo "net_faults.sh: robot 2 killed at sim time $t s (wall $((SECONDS - start)) s)" | tee -a "$out/faults.txt"
  fi
  if [ -n "$killed_at" ] && [ "$healed" = 0 ] && [ $((SECONDS - killed_at)) -ge "${REBOOT_AFTER:-10}" ]; then
    start_robot 2 "$out/robot_2.log"
    healed=1
    echo "net_faults.sh: robot 2 started again at sim time $t s (wall $((SECONDS - start)) s)" | tee -a "$out/faults.txt"
  fi
  if [ -n "$cut_at" ] && [ "$healed" = 0 ] && after "$t" "$(awk -v a="$cut_at" -v d="$part_s" 'BEGIN { print a + d }')"; then
    ip -n "$tag-hub" link set "h$$r2" up || { echo "net_faults.sh: cannot heal robot 2" >&2; exit 2; }
    healed=1
    echo "net_faults.sh: robot 2 back at sim time $t s (wall $((SECONDS - start)) s)" | tee -a "$out/faults.txt"
  fi
  if [ $((SECONDS - start)) -ge "$timeout_s" ]; then
    echo "net_faults.sh: timeout after $timeout_s s" | tee -a "$out/faults.txt" >&2
    exit 1
  fi
  sleep 0.2
done
wait "$sim_pid"
sim_status=$?
# a fault the run ended before is no test of it
fault_missed=""
if [ "$fault" = reboot ] && [ "$healed" = 0 ]; then
  fault_missed="the team finished before robot 2 was started again (set REBOOT_AT earlier or REBOOT_AFTER shorter)"
elif { [ "$fault" = partition ] || [ "$fault" = range ]; } && [ -z "$cut_at" ]; then
  fault_missed="the team finished before the fault was applied (set PART_AT or RANGE_AT earlier)"
elif [ "$fault" = partition ] && [ "$healed" = 0 ]; then
  fault_missed="the team finished before the partition healed (set PART_S shorter)"
fi
[ -n "$fault_missed" ] && echo "net_faults.sh: $fault_missed" | tee -a "$out/faults.txt" >&2
sleep 3  # the robots write their meshes and last log lines when the leader stops
for p in "${pids[@]}"; do kill -INT "$p" 2>/dev/null; done
wait 2>/dev/null

# the summary: the simulator's verdict, then each robot's patches
{
  echo "fault: $fault; wall $((SECONDS - start)) s; simulator exit status $sim_status"
  tr '\r' '\n' <"$out/sim.log" | grep -E "^mission (complete|out of time|stalled)" | tail -n 1
  grep -h "tsdf_mapper: patches" "$out"/robot_*.log
} | tee -a "$out/faults.txt"
# every robot holds the same patches: held = made + received (duplicates counted apart, so a
# patch is never held twice); a rebooted robot's "made" counts its new process's only, so
# the reference is the most any robot holds
total=0
declare -A made received
for k in $robots; do
  line=$(grep -h "/r$k/tsdf_mapper: patches" "$out/robot_$k.log" | tail -n 1)
  made[$k]=$(sed -n 's/.*patches: \([0-9]*\) made.*/\1/p' <<<"$line")
  received[$k]=$(sed -n 's/.*, \([0-9]*\) received,.*/\1/p' <<<"$line")
  [ -n "${made[$k]}" ] || { echo "net_faults.sh: robot $k wrote no mapper summary" | tee -a "$out/faults.txt"; exit 1; }
  held=$((made[$k] + received[$k]))
  [ "$held" -gt "$total" ] && total=$held
done
converged=1 teammates=$(($(wc -w <<<"$robots") - 1)) missing_all=""
for k in $robots; do
  missing=$((total - made[$k] - received[$k]))
  missing_all+=" r$k:$missing"
  if [ "$missing" -lt 0 ] || [ "$missing" -gt "$teammates" ]; then converged=0; fi
done
complete=$(tr '\r' '\n' <"$out/sim.log" | grep -c "^mission complete")
echo "net_faults.sh: complete=$complete converged=$converged; patches held at most $total, missing per robot$missing_all (in flight at the stop: at most $teammates)" | tee -a "$out/faults.txt"
[ "$sim_status" = 0 ] && [ "$complete" -ge 1 ] && [ "$converged" = 1 ] && [ -z "$fault_missed" ]
