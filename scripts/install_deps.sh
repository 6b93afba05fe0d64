#!/usr/bin/env bash
# Installs every Debian 12 package scancrew needs to build, test and benchmark.
# Idempotent: does nothing when all are present. Runs as root, or through sudo.
set -euo pipefail

PACKAGES=(
  # toolchain
  g++ cmake ninja-build pkg-config git
  # runtime: config, command line, JSON
  libyaml-cpp-dev libcli11-dev nlohmann-json3-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # Fast DDS (inter-robot bridge; side-by-side peer of `scancrew bench ipc`); OpenSSL (scancrew
  # keys: DDS-Security's certificates and signed documents); iproute2, iptables and
  # libnetfilter-queue (the network-fault runs: namespaces, loss, delay)
  libfastrtps-dev libfastcdr-dev libssl-dev iproute2 iptables libnetfilter-queue-dev
  # fuser: scripts/clean_dds_shm.sh (Fast DDS shared memory a killed process left)
  psmisc
  # iceoryx (side-by-side peer of `scancrew bench ipc`); Debian's iceoryx headers include
  # <sys/acl.h> without depending on libacl1-dev
  iceoryx libiceoryx-posh-dev libiceoryx-hoofs-dev libacl1-dev
  # MuJoCo team simulator, headless rendering (EGL, Mesa llvmpipe), mesh import
  libmujoco-dev libqhull-dev libegl-dev libegl-mesa0 libgl1-mesa-dri libopengl-dev
  libassimp-dev libpng-dev
  # perception, hardware backend (V4L2 cameras through OpenCV)
  libopencv-dev libeigen3-dev
  # mapping: parallel integration, patch compression, OctoMap export; Open3D is the
  # side-by-side peer of `scancrew bench tsdf`
  libtbb-dev libzstd-dev liboctomap-dev libopen3d-dev
  # low-level planner: OMPL LazyPRM* (its CMake config hard-codes the three Boost .so
  # paths), FCL collision checks against the OctoMap octree; ViSP visual-servoing tracker
  libompl-dev libboost-serialization-dev libboost-filesystem-dev libboost-system-dev
  libfcl-dev libvisp-dev
  # style checks run in CI; the fuzzers (clang's libFuzzer, scripts/fuzz.sh)
  clang-format clang-tidy clang libclang-rt-14-dev
  # headless browser of the report's 3D-view test
  chromium
)
# Node and npm (web tooling in web/: the report's three.js bundle, the Node clients of the
# live-view and MCAP tests). Debian's packages unless a Node is already installed.
command -v node >/dev/null && command -v npm >/dev/null || PACKAGES+=(nodejs npm)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
  exec "$(dirname "$0")/web_deps.sh"
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install_deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
exec "$(dirname "$0")/web_deps.sh"
