#!/usr/bin/env bash
# Quick start 2: installs, builds and runs every test (release build).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh release
# A team run as separate processes over DDS (net.*, cli.team_processes*) gets one retry,
# printed by ctest: after a partition heals, robot 2 sometimes never rediscovers the
# simulator (docs/reliability.md, "Known flaky"); every other test must pass at once.
multiprocess='^(net\.|cli\.team_processes)'
ctest --preset release -j "$(nproc)" -E "$multiprocess"
ctest --preset release -j "$(nproc)" -R "$multiprocess" --repeat until-pass:2
