#include "components/recorder/log_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "executors/log.hpp"
#include "interfaces/message_fields.hpp"

namespace scancrew::recorder {

namespace {

constexpr uint8_t kTopicRecord = 1;
constexpr uint8_t kMessageRecord = 2;
constexpr size_t kRecordHeader = 1 + sizeof(uint32_t);
// a record longer than this is corruption, not data (the largest message is a few MB)
constexpr uint32_t kMaxRecordBytes = 1u << 30;

template <class T>
bool get(std::span<const uint8_t> in, size_t& at, T& v) {
  if (in.size() - at < sizeof(T)) return false;
  std::memcpy(&v, in.data() + at, sizeof(T));
  at += sizeof(T);
  return true;
}

bool get_string(std::span<const uint8_t> in, size_t& at, std::string& s) {
  uint16_t n = 0;
  if (!get(in, at, n) || in.size() - at < n) return false;
  s.assign(reinterpret_cast<const char*>(in.data() + at), n);
  at += n;
  return true;
}

std::string errno_text() {
  return std::error_code(errno, std::generic_category()).message();  // thread-safe strerror
}

}  // namespace

void LogReader::FileCloser::operator()(std::FILE* f) const {
  (void)std::fclose(f);  // read only: nothing to lose
}

LogReader::LogReader(std::unique_ptr<std::FILE, FileCloser> file, std::string path, uint64_t size)
    : file_(std::move(file)), path_(std::move(path)), size_(size) {}

Result<LogReader, std::string> LogReader::open(const std::string& path) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) return make_unexpected("cannot open the recording '" + path + "': " + errno_text());
  if (std::fseek(file.get(), 0, SEEK_END) != 0)
    return make_unexpected("cannot read the recording '" + path + "': " + errno_text());
  const long size = std::ftell(file.get());
  std::rewind(file.get());
  uint8_t header[kLogHeaderSize] = {};
  if (size < static_cast<long>(kLogHeaderSize) ||
      std::fread(header, 1, kLogHeaderSize, file.get()) != kLogHeaderSize ||
      std::memcmp(header, kLogMagic, sizeof(kLogMagic)) != 0)
    return make_unexpected("'" + path + "' is not a scancrew recording (.sclog)");
  uint32_t version = 0;
  std::memcpy(&version, header + sizeof(kLogMagic), sizeof version);
  if (version != msg::kMessageFormatVersion)
    return make_unexpected("'" + path + "' holds messages of format version " +
                           std::to_string(version) + "; this build reads version " +
                           std::to_string(msg::kMessageFormatVersion));
  LogReader reader(std::move(file), path, static_cast<uint64_t>(size));
  reader.offset_ = kLogHeaderSize;
  return reader;
}

Result<std::optional<uint8_t>, std::string> LogReader::read_record(bool want_payload) {
  if (offset_ == size_) return std::optional<uint8_t>{};
  uint8_t header[kRecordHeader] = {};
  if (size_ - offset_ < kRecordHeader ||
      std::fread(header, 1, kRecordHeader, file_.get()) != kRecordHeader) {
    truncated_ = true;
    return std::optional<uint8_t>{};
  }
  uint32_t length = 0;
  std::memcpy(&length, header + 1, sizeof length);
  const uint8_t kind = header[0];
  if ((kind != kTopicRecord && kind != kMessageRecord) || length > kMaxRecordBytes)
    return make_unexpected("'" + path_ + "': corrupt record at byte " + std::to_string(offset_));
  if (size_ - offset_ - kRecordHeader < length) {
    truncated_ = true;
    return std::optional<uint8_t>{};
  }
  if (want_payload || kind == kTopicRecord) {
    buffer_.resize(length);
    if (std::fread(buffer_.data(), 1, length, file_.get()) != length)
      return make_unexpected("cannot read '" + path_ + "': " + errno_text());
  } else if (std::fseek(file_.get(), length, SEEK_CUR) != 0) {
    return make_unexpected("cannot read '" + path_ + "': " + errno_text());
  }
  offset_ += kRecordHeader + length;
  return std::optional<uint8_t>{kind};
}

Result<void, std::string> LogReader::take_topic() {
  size_t at = 0;
  uint16_t index = 0;
  LogTopic topic;
  if (!get(std::span<const uint8_t>(buffer_), at, index) || !get_string(buffer_, at, topic.name) ||
      !get_string(buffer_, at, topic.type) || at != buffer_.size())
    return make_unexpected("'" + path_ + "': malformed topic record before byte " +
                           std::to_string(offset_));
  if (!valid_topic_name(topic.name))
    return make_unexpected("'" + path_ + "': topic record before byte " + std::to_string(offset_) +
                           ": '" + log::printable(topic.name) +
                           "' is not a topic name (absolute, printable, at most 256 bytes)");
  if (index < topics_.size()) {
    if (topics_[index].name != topic.name || topics_[index].type != topic.type)
      return make_unexpected("'" + path_ + "': topic " + std::to_string(index) +
                             " is declared twice, differently");
    return {};
  }
  if (index != topics_.size())
    return make_unexpected("'" + path_ + "': topic " + std::to_string(index) +
                           " declared out of order");
  topics_.push_back(std::move(topic));
  return {};
}

Result<std::optional<LogEntry>, std::string> LogReader::next() {
  for (;;) {
    auto kind = read_record(true);
    if (!kind) return make_unexpected(kind.error());
    if (!*kind) return std::optional<LogEntry>{};
    if (**kind == kTopicRecord) {
      if (auto t = take_topic(); !t) return make_unexpected(t.error());
      continue;
    }
    LogEntry e;
    size_t at = 0;
    if (!get(std::span<const uint8_t>(buffer_), at, e.topic) ||
        !get(std::span<const uint8_t>(buffer_), at, e.receive_ns) || e.topic >= topics_.size())
      return make_unexpected("'" + path_ + "': malformed message record before byte " +
                             std::to_string(offset_));
    e.message = std::span<const uint8_t>(buffer_).subspan(at);
    return std::optional<LogEntry>{e};
  }
}

Result<void, std::string> LogReader::rewind() {
  if (std::fseek(file_.get(), static_cast<long>(kLogHeaderSize), SEEK_SET) != 0)
    return make_unexpected("cannot read '" + path_ + "': " + errno_text());
  offset_ = kLogHeaderSize;
  truncated_ = false;
  return {};
}

Result<void, std::string> LogReader::scan_topics() {
  for (;;) {
    auto kind = read_record(false);
    if (!kind) return make_unexpected(kind.error());
    if (!*kind) break;
    if (**kind == kTopicRecord)
      if (auto t = take_topic(); !t) return make_unexpected(t.error());
  }
  return rewind();
}

Result<ConvertSummary, std::string> convert_sclog(const std::string& in, const std::string& out) {
  auto reader = LogReader::open(in);
  if (!reader) return make_unexpected(reader.error());
  if (auto scanned = reader->scan_topics(); !scanned) return make_unexpected(scanned.error());
  auto writer = RecordingWriter::open(out);
  if (!writer) return make_unexpected(writer.error());
  std::vector<uint16_t> channels;
  for (const LogTopic& topic : reader->topics()) channels.push_back(writer->add_topic(topic));
  ConvertSummary summary{.topics = channels.size()};
  for (;;) {
    auto entry = reader->next();
    if (!entry) return make_unexpected(entry.error());
    if (!*entry) break;
    if (auto w = writer->write(channels[(*entry)->topic], (*entry)->receive_ns, (*entry)->message);
        !w)
      return make_unexpected(w.error());
    ++summary.messages;
  }
  if (auto closed = writer->close(); !closed) return make_unexpected(closed.error());
  summary.truncated = reader->truncated();
  return summary;
}

}  // namespace scancrew::recorder
