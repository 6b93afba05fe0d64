// Writes the binary seeds of the fuzz corpus (fuzz/corpus/{codec,mcap,patch,envelope}): a
// small valid input of each kind, which the fuzzers then mutate. The text seeds (launch and
// scene files, PLY, run files) are copies of the project's own files. Run by
// scripts/fuzz.sh --seeds.
#include <zstd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "components/recorder/recording.hpp"
#include "core/tsdf/patch_codec.hpp"
#include "interfaces/codec.hpp"
#include "interfaces/message_fields.hpp"

namespace {

namespace fs = std::filesystem;
using namespace scancrew;

void write(const fs::path& path, const std::vector<uint8_t>& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
}

template <class... T>
void each_message(msg::TypeList<T...> /*types*/, auto&& fn) {
  size_t i = 0;
  (fn(i++, T{}), ...);
}

// a block with a plane of observed voxels (the patch seed)
msg::TsdfPatch patch_seed(const tsdf::TsdfConfig& config) {
  tsdf::Block block;
  for (int x = 0; x < tsdf::kBlockSide; ++x)
    for (int y = 0; y < tsdf::kBlockSide; ++y)
      for (int z = 0; z < tsdf::kBlockSide; ++z)
        block.at(x, y, z) = {static_cast<float>((z - 4) * config.voxel_m), 1.0f + x};
  msg::TsdfPatch patch;
  const std::vector<tsdf::BlockRef> refs = {{tsdf::BlockIndex(0, 0, 0), &block},
                                            {tsdf::BlockIndex(-1, 2, 0), &block}};
  if (auto stats = tsdf::encode_blocks(refs, config, patch); !stats) {
    std::fprintf(stderr, "make_seeds: %s\n", stats.error().c_str());
    std::exit(1);
  }
  return patch;
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path corpus = argc > 1 ? argv[1] : "fuzz/corpus";
  const tsdf::TsdfConfig config;
  const msg::TsdfPatch patch = patch_seed(config);
  const msg::WireMessages types;

  // codec: the type's index, then a default message (the patch with its payload)
  each_message(types, [&](size_t i, auto message) {
    std::vector<uint8_t> bytes = {static_cast<uint8_t>(i)};
    std::vector<uint8_t> encoded;
    if constexpr (std::is_same_v<decltype(message), msg::TsdfPatch>)
      encoded = msg::encode(patch);
    else
      encoded = msg::encode(message);
    bytes.insert(bytes.end(), encoded.begin(), encoded.end());
    write(corpus / "codec" / ("type_" + std::to_string(i)), bytes);
    // envelope: robot 1, the topic's type, the envelope names it, sent by robot 1, the payload
    std::vector<uint8_t> sample = {1, 0, 0, 0, static_cast<uint8_t>(i), 0, 0};
    sample.insert(sample.end(), encoded.begin(), encoded.end());
    write(corpus / "envelope" / ("type_" + std::to_string(i)), sample);
  });

  // patch: the uncompressed payload with its block count (the harness compresses it)
  std::vector<uint8_t> raw(patch.raw_bytes);
  if (ZSTD_isError(ZSTD_decompress(raw.data(), raw.size(), patch.data.data(), patch.data.size())) !=
      0)
    return 1;
  std::vector<uint8_t> seed = {0, static_cast<uint8_t>(patch.block_count & 0xff),
                               static_cast<uint8_t>(patch.block_count >> 8), 0, 0};
  seed.insert(seed.end(), raw.begin(), raw.end());
  write(corpus / "patch" / "two_blocks", seed);

  // mcap: a recording with two scancrew topics and a JSON channel, three messages in two
  // small chunks, and its summary
  fs::create_directories(corpus / "mcap");
  {
    auto log = recorder::RecordingWriter::open((corpus / "mcap" / "three_messages").string(),
                                               {.chunk_bytes = 256});
    if (!log) return 1;
    const uint16_t sync = log->add_topic({"/team/step_sync", msg::StepSync::kTypeName});
    const uint16_t patches = log->add_topic({"/r1/tsdf_patch", msg::TsdfPatch::kTypeName});
    const std::string schema = R"({"type":"object"})", json = R"({"a":1})";
    const auto bytes = [](const std::string& s) {
      return std::span(reinterpret_cast<const uint8_t*>(s.data()), s.size());
    };
    const uint16_t note = log->mcap().add_channel(
        "/note", "json", log->mcap().add_schema("Note", "jsonschema", bytes(schema)));
    const std::vector<uint8_t> step = msg::encode(msg::StepSync{});
    const std::vector<uint8_t> map = msg::encode(patch);
    if (!log->write(sync, 1000, step) || !log->write(patches, 2000, map) ||
        !log->mcap().write(note, 2500, 2500, bytes(json)) || !log->write(sync, 3000, step) ||
        !log->close())
      return 1;
  }
  std::printf("make_seeds: seeds written under %s\n", corpus.c_str());
  return 0;
}
