#!/usr/bin/env bash
# clang-tidy (.clang-tidy) over the project's own sources, using build/release's compile
# database. Any warning fails. The TSDF bench's Open3D peer is left out: Open3D's headers are
# slow to parse, and it is a measurement harness. Every other benchmark is covered (bench/ipc's
# 5 files, Fast DDS's and iceoryx's headers included, take about 30 s). The fuzzers' seed maker is
# not (fuzz/ builds only with clang's libFuzzer).
set -euo pipefail
cd "$(dirname "$0")/.."
[ -f build/release/compile_commands.json ] || ./scripts/build.sh release
mapfile -t files < <(git ls-files 'core/*.cpp' 'executors/*.cpp' 'components/*.cpp' 'cli/*.cpp' 'sim/*.cpp' 'eval/*.cpp' 'report/*.cpp' 'scenegen/*.cpp' \
  'bench/commands.cpp' 'bench/common/*.cpp' 'bench/ipc/*.cpp' 'bench/dds/*.cpp' 'bench/pipeline/*.cpp' 'bench/planner/*.cpp' 'bench/eval/*.cpp' 'bench/sim/*.cpp' 'bench/perception/*.cpp' 'bench/tsdf/*.cpp' 'bench/ise/*.cpp' 'bench/tsp/*.cpp' ':!bench/tsdf/open3d_peer.cpp')
out=$(mktemp)
# one clang-tidy per core, 8 files each (2 cores: 8.2 min; one process took 17.8 of CI's 47.6 min);
# xargs fails when any of them does
jobs=$(nproc 2>/dev/null || echo 2)
if ! printf '%s\0' "${files[@]}" |
  xargs -0 -n 8 -P "$jobs" clang-tidy -p build/release --quiet --warnings-as-errors='*' >"$out" 2>&1; then
  grep -v "warnings generated" "$out"
  rm -f "$out"
  echo "lint: clang-tidy found problems" >&2
  exit 1
fi
rm -f "$out"
echo "lint: ${#files[@]} files clean"
