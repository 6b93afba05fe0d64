#pragma once

// The recording file (.sclog) that the recorder writes and the replay backend plays.
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

#include "core/result.hpp"

namespace scancrew::recorder {

struct LogTopic {
  std::string name;  // absolute topic name, e.g. "/r1/stereo"
  std::string type;  // message type name, e.g. "scancrew/StereoFrame"
};

class LogWriter {
 public:
  static Result<LogWriter, std::string> open(const std::string& path);
  LogWriter(LogWriter&&) noexcept = default;
  LogWriter& operator=(LogWriter&&) noexcept = default;
  ~LogWriter();

  uint16_t add_topic(const LogTopic& topic);
  Result<void, std::string> write(uint16_t topic, int64_t receive_ns,
                                  std::span<const uint8_t> message);
  Result<void, std::string> flush();
  uint64_t messages() const { return messages_; }
  uint64_t bytes() const { return bytes_; }

 private:
  struct FileCloser {
    void operator()(std::FILE* f) const;
  };
  LogWriter(std::unique_ptr<std::FILE, FileCloser> file, std::string path);
  Result<void, std::string> record(uint8_t kind, std::span<const uint8_t> payload);

  std::unique_ptr<std::FILE, FileCloser> file_;
  std::string path_;
  std::vector<LogTopic> topics_;
  std::vector<uint8_t> scratch_;
  uint64_t messages_ = 0, bytes_ = 0;
};

struct LogEntry {
  uint16_t topic = 0;
  int64_t receive_ns = 0;
  std::span<const uint8_t> message;  // valid until the next call to next()
};

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

inline constexpr char kLogMagic[8] = {'S', 'C', 'L', 'O', 'G', '1', '\n', '\0'};
inline constexpr size_t kLogHeaderSize = sizeof(kLogMagic) + sizeof(uint32_t);

}  // namespace scancrew::recorder
