// The TSDF map patch decoder (components/tsdf/patch_codec.hpp). Random bytes are seldom a
// zstd frame, so the input is usually compressed here first and the decoder's own checks
// (counts, indices, codes) see it: byte 0 bit 0 picks raw (as received) or compressed,
// bytes 1-2 give the block count.
#include <zstd.h>

#include <vector>

#include "components/tsdf/patch_codec.hpp"
#include "fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 3) return 0;
  const scancrew::tsdf::TsdfConfig config;  // the receiver's: the patch must match it
  scancrew::msg::TsdfPatch patch;
  patch.voxel_size_m = config.voxel_m;
  patch.truncation_m = config.truncation_m;
  patch.block_count = data[1] | (uint32_t{data[2]} << 8);
  const uint8_t* payload = data + 3;
  const size_t payload_size = size - 3;
  if ((data[0] & 1) != 0) {
    patch.data.assign(payload, payload + payload_size);
    patch.raw_bytes = static_cast<uint32_t>(payload_size);
  } else {
    patch.data.resize(ZSTD_compressBound(payload_size));
    const size_t n = ZSTD_compress(patch.data.data(), patch.data.size(), payload, payload_size, 1);
    if (ZSTD_isError(n) != 0) return 0;
    patch.data.resize(n);
    patch.raw_bytes = static_cast<uint32_t>(payload_size);
  }
  (void)scancrew::tsdf::decode_patch(patch, config);
  return 0;
}
