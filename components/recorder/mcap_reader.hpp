#pragma once

// McapReader: reads an MCAP file (https://mcap.dev/spec) from its start, record by record,
// as a stream: it needs no summary, so a file cut short (a crash, a full disk) reads up to
// its last whole record outside chunks or its last whole chunk, and says where it was cut.
// Schema and Channel records are taken in passing, inside or outside chunks; chunks are
// decompressed whole (zstd, or none; lz4 is refused by name) and their CRC checked; the
// summary after DataEnd is not read. Corrupt input is an error that names its byte offset,
// never a crash (fuzz/mcap_fuzz.cpp).
//
// Not thread safe. A message's data is valid until the next call to next().

#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/result.hpp"

namespace scancrew::recorder {

struct McapSchema {
  uint16_t id = 0;
  std::string name, encoding;
  std::vector<uint8_t> data;
};

struct McapChannel {
  uint16_t id = 0, schema_id = 0;
  std::string topic, message_encoding;
  std::map<std::string, std::string> metadata;
};

struct McapMessage {
  uint16_t channel_id = 0;
  uint32_t sequence = 0;
  uint64_t log_time_ns = 0, publish_time_ns = 0;
  std::span<const uint8_t> data;  // valid until the next call to next()
};

class McapReader {
 public:
  // Fails on a missing file or one that does not start with the MCAP magic and a Header.
  static Result<McapReader, std::string> open(const std::string& path);

  // The next message; nullopt at DataEnd or where the file is cut (truncated() says so).
  Result<std::optional<McapMessage>, std::string> next();
  // Reads the whole data section once for its schemas and channels, then rewinds.
  Result<void, std::string> scan();
  Result<void, std::string> rewind();

  const std::map<uint16_t, McapSchema>& schemas() const { return schemas_; }
  const std::map<uint16_t, McapChannel>& channels() const { return channels_; }
  const std::string& profile() const { return profile_; }
  bool truncated() const { return truncated_; }
  // The byte offset where the record last read (a chunk, or a record outside chunks) ends.
  uint64_t offset() const { return offset_; }
  const std::string& path() const { return path_; }

 private:
  struct FileCloser {
    void operator()(std::FILE* f) const;
  };
  McapReader(std::unique_ptr<std::FILE, FileCloser> file, std::string path, uint64_t size);
  // The next record outside chunks (opcode; content in record_); nullopt at a cut.
  Result<std::optional<uint8_t>, std::string> read_record();
  Result<void, std::string> open_chunk(uint64_t at);
  // Takes a Schema, Channel or Message record (content); other opcodes are skipped.
  Result<std::optional<McapMessage>, std::string> take(uint8_t opcode,
                                                       std::span<const uint8_t> content,
                                                       uint64_t at);
  std::string corrupt(uint64_t at, const std::string& what) const;

  std::unique_ptr<std::FILE, FileCloser> file_;
  std::string path_, profile_;
  uint64_t size_ = 0, data_start_ = 0, offset_ = 0;
  std::vector<uint8_t> record_, chunk_;
  size_t chunk_at_ = 0;        // next record in chunk_
  uint64_t chunk_offset_ = 0;  // file offset of the chunk being read
  bool in_chunk_ = false, ended_ = false, truncated_ = false;
  std::map<uint16_t, McapSchema> schemas_;
  std::map<uint16_t, McapChannel> channels_;
};

}  // namespace scancrew::recorder
