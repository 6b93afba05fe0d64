#!/usr/bin/env bash
# Quick start 1: installs, builds and runs the main job.
# The main job is the default mission: two ground robots reconstruct the parking lot in the
# distributed architecture (launch_cfg/missions/parking_lot_2_distributed.yaml); the run
# directory (mesh, metrics, pictures, report.html) goes to runs/parking_lot, or to $2.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh release
./build/release/cli/scancrew run "${1:-launch_cfg/missions/parking_lot_2_distributed.yaml}" \
  --out "${2:-runs/parking_lot}"
