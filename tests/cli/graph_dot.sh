#!/usr/bin/env bash
# `scancrew graph --dot` writes a Graphviz digraph of a shipped launch file: its components
# as boxes, its topics as ellipses, publisher -> topic -> subscriber edges; Graphviz's dot
# accepts it where it is installed. Usage: graph_dot.sh SCANCREW LAUNCH
set -euo pipefail
bin="$1" launch="$2"
dot_text="$("$bin" graph "$launch" --dot)"
fail() { printf '%s\n' "$dot_text" | head -40; echo "graph_dot: $1"; exit 1; }
[[ "$(printf '%s\n' "$dot_text" | head -1)" == "digraph \""*"\" {" ]] || fail "no digraph header"
[[ "$(printf '%s\n' "$dot_text" | tail -1)" == "}" ]] || fail "no closing brace"
for line in '"c:/team_simulator" [shape=box' '"c:/tsdf_mapper" [shape=box' \
  '"c:/r1/path_tracker" [shape=box' '"c:/mission_monitor" [shape=box' \
  '"t:/r1/depth" [shape=ellipse, label="/r1/depth\nscancrew/DepthImage"]' \
  '"c:/team_simulator" -> "t:/r1/depth";' '"t:/r1/cmd_vel" -> "c:/team_simulator";' \
  '"c:/tsdf_mapper" -> "t:/map";'; do
  printf '%s\n' "$dot_text" | grep -qF -- "$line" || fail "missing: $line"
done
# a quiet mission: no dashed (unconnected or unread) topic
! printf '%s\n' "$dot_text" | grep -q 'style=dashed' || fail "a dashed topic"
if command -v dot >/dev/null; then
  printf '%s\n' "$dot_text" | dot -Tsvg >/dev/null || fail "dot -Tsvg refused it"
  echo "graph_dot: ok (dot -Tsvg accepts it)"
else
  echo "graph_dot: ok (Graphviz's dot is not installed: not rendered)"
fi
