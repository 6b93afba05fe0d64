#pragma once

// McapWriter: writes an MCAP file (https://mcap.dev/spec), written from the specification.
//
// Layout: magic, Header (profile, library), then the data section: Schema and Channel
// records outside chunks, where they are added; messages in zstd-compressed Chunks, each
// followed by one MessageIndex per channel it holds; DataEnd (the data section's CRC). Then
// the summary section: every Schema, every Channel, Statistics, one ChunkIndex per chunk;
// the SummaryOffset records of those four groups; Footer (with the summary's CRC); magic.
// Indexed readers (Foxglove Studio, @mcap/core's McapIndexedReader, `mcap info`) use the
// summary; a file cut short (a crash) keeps every chunk written before the cut.
//
// The writer is generic: any schema encoding ("jsonschema", our "scancrew-codec"), any
// message encoding ("json", "scancrew"). Not thread safe: one writer, one thread at a time.
// write() allocates only while the chunk buffer grows to its size.

#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.hpp"

namespace scancrew::recorder {

struct McapWriterOptions {
  std::string profile = "scancrew";  // the Header's profile
  std::string library = "scancrew";  // the Header's library
  size_t chunk_bytes = 4u << 20;     // a chunk is closed once its records reach this size
  int zstd_level = 3;                // zstd's default: ~300 MB/s, most of the gain
};

class McapWriter {
 public:
  // Creates (overwrites) `path` and writes the magic and the Header.
  static Result<McapWriter, std::string> open(const std::string& path,
                                              McapWriterOptions options = {});
  McapWriter(McapWriter&&) noexcept;
  McapWriter& operator=(McapWriter&&) noexcept;
  // Closes the file if close() was not called (errors are lost: call close()).
  ~McapWriter();

  // A schema; returns its id (1, 2, ...; 0 means "no schema" in a channel).
  uint16_t add_schema(std::string_view name, std::string_view encoding,
                      std::span<const uint8_t> data);
  // A channel on `schema_id` (0: none); returns its id (1, 2, ...).
  uint16_t add_channel(std::string_view topic, std::string_view message_encoding,
                       uint16_t schema_id, const std::map<std::string, std::string>& metadata = {});
  // A message on `channel` (an id add_channel returned; checked). Times in ns.
  Result<void, std::string> write(uint16_t channel, uint64_t log_time_ns, uint64_t publish_time_ns,
                                  std::span<const uint8_t> data);
  // Writes the open chunk and flushes the file: a crash after it loses nothing before it.
  Result<void, std::string> flush();
  // Writes the open chunk, DataEnd, the summary and the Footer, and closes the file. Once.
  Result<void, std::string> close();

  uint64_t messages() const { return message_count_; }
  uint64_t bytes() const { return offset_; }  // written to the file so far
  const std::string& path() const { return path_; }

 private:
  struct FileCloser {
    void operator()(std::FILE* f) const;
  };
  struct ChunkIndex {
    uint64_t start_ns = 0, end_ns = 0, offset = 0, length = 0, index_length = 0;
    uint64_t compressed = 0, uncompressed = 0;
    std::map<uint16_t, uint64_t> index_offsets;
  };
  struct Channel {
    std::vector<uint8_t> record;  // the whole Channel record, for the summary
    uint32_t sequence = 0;
    uint64_t count = 0;
    std::vector<uint8_t> index;  // this chunk's MessageIndex entries (log time, offset)
  };
  McapWriter(std::unique_ptr<std::FILE, FileCloser> file, std::string path,
             McapWriterOptions options);
  // Appends a whole record to `out`.
  static void append_record(std::vector<uint8_t>& out, uint8_t opcode,
                            std::span<const uint8_t> content);
  Result<void, std::string> emit(std::span<const uint8_t> bytes);
  Result<void, std::string> write_chunk();
  Result<void, std::string> write_summary();
  Result<void, std::string> failed();

  std::unique_ptr<std::FILE, FileCloser> file_;
  std::string path_;
  McapWriterOptions options_;
  std::shared_ptr<void> zstd_;  // ZSTD_CCtx, kept between chunks
  uint64_t offset_ = 0;
  uint32_t crc_ = 0;                           // running CRC of the section being written
  std::vector<std::vector<uint8_t>> schemas_;  // whole Schema records
  std::vector<Channel> channels_;              // index: id - 1
  std::vector<ChunkIndex> chunk_indexes_;
  std::vector<uint8_t> chunk_, compressed_, scratch_;
  uint64_t chunk_start_ns_ = 0, chunk_end_ns_ = 0, chunk_messages_ = 0;
  uint64_t message_count_ = 0, start_ns_ = 0, end_ns_ = 0;
  bool closed_ = false;
};

}  // namespace scancrew::recorder
