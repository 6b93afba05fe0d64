#include "components/recorder/mcap_writer.hpp"

#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <system_error>

#include "components/recorder/mcap_format.hpp"
#include "core/check.hpp"

namespace scancrew::recorder {

using mcap::Fields;
using mcap::Opcode;

namespace {

std::string errno_text() {
  return std::error_code(errno, std::generic_category()).message();  // thread-safe strerror
}

uint8_t op(Opcode o) {
  return static_cast<uint8_t>(o);
}

}  // namespace

void McapWriter::FileCloser::operator()(std::FILE* f) const {
  (void)std::fclose(f);  // close() reports errors before it
}

McapWriter::McapWriter(std::unique_ptr<std::FILE, FileCloser> file, std::string path,
                       McapWriterOptions options)
    : file_(std::move(file)),
      path_(std::move(path)),
      options_(std::move(options)),
      zstd_(ZSTD_createCCtx(), [](void* c) { ZSTD_freeCCtx(static_cast<ZSTD_CCtx*>(c)); }),
      crc_(mcap::kCrcInit) {}

McapWriter::McapWriter(McapWriter&&) noexcept = default;
McapWriter& McapWriter::operator=(McapWriter&&) noexcept = default;

McapWriter::~McapWriter() {
  if (file_ && !closed_) (void)close();
}

Result<McapWriter, std::string> McapWriter::open(const std::string& path,
                                                 McapWriterOptions options) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) return make_unexpected("cannot create the recording '" + path + "': " + errno_text());
  McapWriter w(std::move(file), path, std::move(options));
  std::vector<uint8_t> head(mcap::kMagic.begin(), mcap::kMagic.end()), header;
  Fields(header).string(w.options_.profile).string(w.options_.library);
  append_record(head, op(Opcode::kHeader), header);
  if (auto r = w.emit(head); !r) return make_unexpected(r.error());
  return w;
}

void McapWriter::append_record(std::vector<uint8_t>& out, uint8_t opcode,
                               std::span<const uint8_t> content) {
  Fields(out).put(opcode).put(static_cast<uint64_t>(content.size())).bytes(content);
}

Result<void, std::string> McapWriter::failed() {
  return make_unexpected("cannot write the recording '" + path_ + "': " + errno_text());
}

Result<void, std::string> McapWriter::emit(std::span<const uint8_t> bytes) {
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_.get()) != bytes.size()) return failed();
  crc_ = mcap::crc32_update(crc_, bytes);
  offset_ += bytes.size();
  return {};
}

uint16_t McapWriter::add_schema(std::string_view name, std::string_view encoding,
                                std::span<const uint8_t> data) {
  SCANCREW_CHECK(schemas_.size() < UINT16_MAX - 1, "McapWriter: too many schemas");
  const auto id = static_cast<uint16_t>(schemas_.size() + 1);
  std::vector<uint8_t> content, record;
  Fields(content).put(id).string(name).string(encoding).put(static_cast<uint32_t>(data.size()));
  Fields(content).bytes(data);
  append_record(record, op(Opcode::kSchema), content);
  (void)emit(record);  // an error shows again at the next write or close
  schemas_.push_back(std::move(record));
  return id;
}

uint16_t McapWriter::add_channel(std::string_view topic, std::string_view message_encoding,
                                 uint16_t schema_id,
                                 const std::map<std::string, std::string>& metadata) {
  SCANCREW_CHECK(schema_id <= schemas_.size(), "McapWriter: channel on an unknown schema");
  SCANCREW_CHECK(channels_.size() < UINT16_MAX - 1, "McapWriter: too many channels");
  const auto id = static_cast<uint16_t>(channels_.size() + 1);
  std::vector<uint8_t> content;
  Fields f(content);
  f.put(id).put(schema_id).string(topic).string(message_encoding);
  const size_t map_at = f.size();
  f.put(uint32_t{0});
  for (const auto& [key, value] : metadata) f.string(key).string(value);
  f.patch_u32(map_at, static_cast<uint32_t>(f.size() - map_at - sizeof(uint32_t)));
  Channel channel;
  append_record(channel.record, op(Opcode::kChannel), content);
  (void)emit(channel.record);  // an error shows again at the next write or close
  channels_.push_back(std::move(channel));
  return id;
}

Result<void, std::string> McapWriter::write(uint16_t channel_id, uint64_t log_time_ns,
                                            uint64_t publish_time_ns,
                                            std::span<const uint8_t> data) {
  SCANCREW_CHECK(channel_id >= 1 && channel_id <= channels_.size(),
                 "McapWriter::write: unknown channel");
  if (closed_) return make_unexpected("the recording '" + path_ + "' is closed");
  Channel& channel = channels_[channel_id - 1];
  Fields(channel.index).put(log_time_ns).put(static_cast<uint64_t>(chunk_.size()));
  Fields(chunk_)
      .put(op(Opcode::kMessage))
      .put(static_cast<uint64_t>(2 + 4 + 8 + 8 + data.size()))
      .put(channel_id)
      .put(channel.sequence++)
      .put(log_time_ns)
      .put(publish_time_ns)
      .bytes(data);
  ++channel.count;
  if (chunk_messages_++ == 0) chunk_start_ns_ = chunk_end_ns_ = log_time_ns;
  chunk_start_ns_ = std::min(chunk_start_ns_, log_time_ns);
  chunk_end_ns_ = std::max(chunk_end_ns_, log_time_ns);
  start_ns_ = message_count_ == 0 ? log_time_ns : std::min(start_ns_, log_time_ns);
  end_ns_ = message_count_ == 0 ? log_time_ns : std::max(end_ns_, log_time_ns);
  ++message_count_;
  if (chunk_.size() >= options_.chunk_bytes) return write_chunk();
  return {};
}

Result<void, std::string> McapWriter::write_chunk() {
  if (chunk_messages_ == 0) return {};
  auto* zstd = static_cast<ZSTD_CCtx*>(zstd_.get());
  compressed_.resize(ZSTD_compressBound(chunk_.size()));
  const size_t n = ZSTD_compressCCtx(zstd, compressed_.data(), compressed_.size(), chunk_.data(),
                                     chunk_.size(), options_.zstd_level);
  if (ZSTD_isError(n) != 0)
    return make_unexpected("cannot compress a chunk of '" + path_ + "': " + ZSTD_getErrorName(n));
  constexpr std::string_view kZstd = "zstd";
  ChunkIndex index{.start_ns = chunk_start_ns_,
                   .end_ns = chunk_end_ns_,
                   .offset = offset_,
                   .compressed = n,
                   .uncompressed = chunk_.size()};
  scratch_.clear();
  Fields(scratch_)
      .put(op(Opcode::kChunk))
      .put(static_cast<uint64_t>(8 + 8 + 8 + 4 + 4 + kZstd.size() + 8 + n))
      .put(chunk_start_ns_)
      .put(chunk_end_ns_)
      .put(static_cast<uint64_t>(chunk_.size()))
      .put(mcap::crc32(chunk_))
      .string(kZstd)
      .put(static_cast<uint64_t>(n));
  if (auto r = emit(scratch_); !r) return r;
  if (auto r = emit(std::span<const uint8_t>(compressed_).first(n)); !r) return r;
  index.length = offset_ - index.offset;
  // one MessageIndex per channel in the chunk: (log time, offset in the uncompressed records)
  scratch_.clear();
  for (size_t i = 0; i < channels_.size(); ++i) {
    std::vector<uint8_t>& entries = channels_[i].index;
    if (entries.empty()) continue;
    const auto id = static_cast<uint16_t>(i + 1);
    index.index_offsets[id] = offset_ + scratch_.size();
    Fields(scratch_)
        .put(op(Opcode::kMessageIndex))
        .put(static_cast<uint64_t>(2 + 4 + entries.size()))
        .put(id)
        .put(static_cast<uint32_t>(entries.size()))
        .bytes(entries);
    entries.clear();
  }
  index.index_length = scratch_.size();
  if (auto r = emit(scratch_); !r) return r;
  chunk_indexes_.push_back(std::move(index));
  chunk_.clear();
  chunk_messages_ = 0;
  return {};
}

Result<void, std::string> McapWriter::flush() {
  if (closed_) return {};
  if (auto r = write_chunk(); !r) return r;
  if (std::fflush(file_.get()) != 0) return failed();
  return {};
}

Result<void, std::string> McapWriter::close() {
  if (closed_) return {};
  closed_ = true;
  Result<void, std::string> done = write_chunk();
  if (done) {
    std::vector<uint8_t> data_end, content;
    Fields(content).put(mcap::crc32_final(crc_));
    append_record(data_end, op(Opcode::kDataEnd), content);
    done = emit(data_end);
  }
  if (done) done = write_summary();
  if (std::fclose(file_.release()) != 0 && done) done = failed();
  return done;
}

Result<void, std::string> McapWriter::write_summary() {
  const uint64_t summary_start = offset_;
  crc_ = mcap::kCrcInit;
  std::vector<uint8_t> offsets, content, record;
  // emits a group of records and notes it in a SummaryOffset record
  auto group = [&](Opcode opcode, const std::vector<std::vector<uint8_t>>& records) {
    const uint64_t start = offset_;
    for (const auto& r : records)
      if (auto e = emit(r); !e) return e;
    content.clear();
    Fields(content).put(op(opcode)).put(start).put(offset_ - start);
    if (!records.empty()) append_record(offsets, op(Opcode::kSummaryOffset), content);
    return Result<void, std::string>{};
  };
  std::vector<std::vector<uint8_t>> channels, statistics(1), chunk_indexes;
  for (const Channel& c : channels_) channels.push_back(c.record);
  content.clear();
  Fields s(content);
  s.put(message_count_).put(static_cast<uint16_t>(schemas_.size()));
  s.put(static_cast<uint32_t>(channels_.size())).put(uint32_t{0}).put(uint32_t{0});
  s.put(static_cast<uint32_t>(chunk_indexes_.size())).put(start_ns_).put(end_ns_);
  s.put(static_cast<uint32_t>(channels_.size() * (2 + 8)));
  for (size_t i = 0; i < channels_.size(); ++i)
    s.put(static_cast<uint16_t>(i + 1)).put(channels_[i].count);
  append_record(statistics[0], op(Opcode::kStatistics), content);
  for (const ChunkIndex& c : chunk_indexes_) {
    content.clear();
    Fields f(content);
    f.put(c.start_ns).put(c.end_ns).put(c.offset).put(c.length);
    f.put(static_cast<uint32_t>(c.index_offsets.size() * (2 + 8)));
    for (const auto& [id, at] : c.index_offsets) f.put(id).put(at);
    f.put(c.index_length).string("zstd").put(c.compressed).put(c.uncompressed);
    chunk_indexes.emplace_back();
    append_record(chunk_indexes.back(), op(Opcode::kChunkIndex), content);
  }
  for (auto [opcode, records] :
       {std::pair{Opcode::kSchema, &schemas_}, std::pair{Opcode::kChannel, &channels},
        std::pair{Opcode::kStatistics, &statistics},
        std::pair{Opcode::kChunkIndex, &chunk_indexes}})
    if (auto e = group(opcode, *records); !e) return e;
  const uint64_t summary_offset_start = offset_;
  if (auto e = emit(offsets); !e) return e;
  // the Footer; its CRC covers the summary up to and including summary_offset_start
  record.clear();
  Fields(record).put(op(Opcode::kFooter)).put(uint64_t{8 + 8 + 4}).put(summary_start);
  Fields(record).put(summary_offset_start);
  if (auto e = emit(record); !e) return e;
  record.clear();
  Fields(record).put(mcap::crc32_final(crc_)).bytes(mcap::kMagic);
  return emit(record);
}

}  // namespace scancrew::recorder
