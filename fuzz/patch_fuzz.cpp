// The TSDF map patch decoder (core/tsdf/patch_codec.hpp). Random bytes are seldom a
// zstd frame, so the input is usually compressed here first and the decoder's own checks
// (counts, indices, codes) see it. Byte 0: bit 0 raw (as received) or compressed; bit 1 a
// raw_bytes field that is not the payload's size (bytes 3-4 then add to it); bit 2 a voxel
// size, bit 3 a truncation that is not the receiver's. Bytes 1-2: the block count.
#include <zstd.h>

#include <vector>

#include "core/tsdf/patch_codec.hpp"
#include "fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 5) return 0;
  const scancrew::tsdf::TsdfConfig config;  // the receiver's: the patch must match it
  scancrew::msg::TsdfPatch patch;
  patch.voxel_size_m = (data[0] & 4) != 0 ? config.voxel_m * (1 + data[3] / 64.0) : config.voxel_m;
  patch.truncation_m =
      (data[0] & 8) != 0 ? config.truncation_m * (data[4] / 128.0) : config.truncation_m;
  patch.block_count = data[1] | (uint32_t{data[2]} << 8);
  const uint8_t* payload = data + 5;
  const size_t payload_size = size - 5;
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
  if ((data[0] & 2) != 0)  // a size field that lies: larger or smaller than the payload
    patch.raw_bytes = static_cast<uint32_t>((data[3] & 1) != 0 ? payload_size * (1 + data[4])
                                                               : payload_size / (1 + data[4]));
  (void)scancrew::tsdf::decode_patch(patch, config);
  return 0;
}
