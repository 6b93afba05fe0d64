#!/usr/bin/env bash
# Quick start 2: installs, builds and runs every test (release build).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh release
ctest --preset release -j "$(nproc)"
