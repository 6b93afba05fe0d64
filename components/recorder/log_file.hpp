#pragma once

// The retired recording format (.sclog), kept only to convert old files to MCAP
// (`scancrew convert IN.sclog OUT.mcap`); the recorder writes MCAP (recording.hpp).
//
// Layout, little-endian:
//   file header   "SCLOG1\n\0" (8 bytes), u32 message format version (msg::kMessageFormatVersion)
//   records       u8 kind, u32 payload length, payload
//     kind 1, topic    u16 topic index, u16 name length, name, u16 type length, type name
//     kind 2, message  u16 topic index, i64 receive time (ns, the recorder's clock),
//                      the message in the codec of interfaces/codec.hpp
// Topics are declared before their first message. A file cut short (a crash, a full disk)
// reads up to its last whole record and says where it was cut.

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "components/recorder/recording.hpp"
#include "core/result.hpp"

namespace scancrew::recorder {

class LogReader {
 public:
  // Fails on a missing file, a file that is not a recording, or another format version.
  static Result<LogReader, std::string> open(const std::string& path);

  // The next message; nullopt at the end of the file. Topic records are taken in
  // passing. A record cut short ends the file (truncated() says so); a corrupt one is an
  // error naming its byte offset.
  Result<std::optional<LogEntry>, std::string> next();
  const std::vector<LogTopic>& topics() const { return topics_; }
  // Reads the whole file once to collect every topic (skipping over messages), then rewinds.
  Result<void, std::string> scan_topics();
  Result<void, std::string> rewind();
  bool truncated() const { return truncated_; }
  uint64_t offset() const { return offset_; }
  const std::string& path() const { return path_; }

 private:
  struct FileCloser {
    void operator()(std::FILE* f) const;
  };
  LogReader(std::unique_ptr<std::FILE, FileCloser> file, std::string path, uint64_t size);
  // Reads the next record (kind and payload into buffer_); nullopt at the end or at a cut.
  Result<std::optional<uint8_t>, std::string> read_record(bool want_payload);
  Result<void, std::string> take_topic();

  std::unique_ptr<std::FILE, FileCloser> file_;
  std::string path_;
  uint64_t size_ = 0;
  std::vector<uint8_t> buffer_;
  std::vector<LogTopic> topics_;
  uint64_t offset_ = 0;
  bool truncated_ = false;
};

struct ConvertSummary {
  uint64_t topics = 0, messages = 0;
  bool truncated = false;  // the .sclog was cut short: converted up to the cut
};

// Writes every topic and message of the .sclog `in` to the MCAP recording `out` (each topic a
// scancrew channel, in the .sclog's order; receive times kept), as the recorder would have.
Result<ConvertSummary, std::string> convert_sclog(const std::string& in, const std::string& out);

inline constexpr char kLogMagic[8] = {'S', 'C', 'L', 'O', 'G', '1', '\n', '\0'};
inline constexpr size_t kLogHeaderSize = sizeof(kLogMagic) + sizeof(uint32_t);

}  // namespace scancrew::recorder
