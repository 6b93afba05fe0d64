#!/usr/bin/env bash
# Builds with a sanitizer (asan = ASan+UBSan, tsan = TSan) and runs the tests labelled
# "sanitize": the runtime and the mapping core (TSDF integration, meshing, patches, ISEs);
# "sanitize_asan" runs under ASan+UBSan only, "sanitize_tsan" under TSan only.
set -euo pipefail
kind="${1:?usage: sanitize.sh asan|tsan}"
cd "$(dirname "$0")/.."
cmake --preset "$kind" >/dev/null
# only the test binaries: the sanitizer runs cover the "sanitize"-labelled suites
# TSan: the runtime (our executors' threads). ASan+UBSan: the runtime and the mapping core.
# The mapping core runs on TBB, whose library is not built with TSan: TSan would report
# TBB's own work-stealing handshakes as races, so the mapping tests are ASan-only
# (label "sanitize_asan").
targets=(test_executors test_no_allocation test_trace test_interfaces)
# TSan also: the live view's WebSocket server (label "sanitize_tsan").
[ "$kind" = tsan ] && targets+=(test_foxglove_bridge)
[ "$kind" = asan ] && targets+=(test_tsdf test_tsdf_mesh test_tsdf_patch test_ise test_tsga_solver
  test_tsga_planner test_motion_planner test_motion_checks test_planner_params test_core
  test_path_tracker_law
  test_dds_link_model)
cmake --build --preset "$kind" --target "${targets[@]}"
if [ "$kind" = tsan ]; then
  # TSan of g++ 12 cannot map its shadow memory with the 32-bit mmap randomisation of
  # newer kernels ("unexpected memory mapping"); run without address randomisation.
  exec setarch "$(uname -m)" -R ctest --preset tsan -j "$(nproc)"
fi
ctest --preset "$kind" -j "$(nproc)"
