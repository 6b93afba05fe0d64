#!/usr/bin/env bash
# Quick start 1: installs, builds and runs the main job.
# Until the mission exists (step 9) the main job is the runtime demo graph: two robots,
# each with a synthetic stereo camera, a disparity probe and a monitor, for 5 s.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh release
./build/release/cli/scancrew run "${1:-launch_cfg/demo_runtime.yaml}"
