#!/usr/bin/env bash
# Configures and builds one preset (release, debug, asan, tsan) into build/<preset>.
set -euo pipefail
preset="${1:-release}"
cd "$(dirname "$0")/.."
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
