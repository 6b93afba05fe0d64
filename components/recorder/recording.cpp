#include "components/recorder/recording.hpp"

#include <algorithm>
#include <array>
#include <fstream>

#include "executors/log.hpp"
#include "interfaces/message_fields.hpp"

namespace scancrew::recorder {

namespace {

std::string format_version() {
  return std::to_string(msg::kMessageFormatVersion);
}

}  // namespace

std::string schema_text(std::string_view type_name) {
  return "type: " + std::string(type_name) + "\nformat_version: " + format_version() +
         "\ncodec: little-endian, the fields in declaration order (interfaces/codec.hpp, "
         "interfaces/message_fields.hpp)\n";
}

bool valid_topic_name(std::string_view name) {
  return name.size() >= 2 && name.size() <= 256 && name.front() == '/' &&
         std::all_of(name.begin(), name.end(), [](char c) { return c > ' ' && c < 0x7f; });
}

Result<RecordingWriter, std::string> RecordingWriter::open(const std::string& path,
                                                           McapWriterOptions options) {
  auto mcap = McapWriter::open(path, std::move(options));
  if (!mcap) return make_unexpected(mcap.error());
  return RecordingWriter(std::move(mcap).value());
}

uint16_t RecordingWriter::add_topic(const LogTopic& topic) {
  auto known = std::find_if(schemas_.begin(), schemas_.end(),
                            [&](const auto& s) { return s.first == topic.type; });
  if (known == schemas_.end()) {
    const std::string text = schema_text(topic.type);
    const uint16_t id = mcap_.add_schema(
        topic.type, kSchemaEncoding, {reinterpret_cast<const uint8_t*>(text.data()), text.size()});
    known = schemas_.insert(schemas_.end(), {topic.type, id});
  }
  return mcap_.add_channel(topic.name, kMessageEncoding, known->second,
                           {{"format_version", format_version()}});
}

Result<void, std::string> RecordingWriter::write(uint16_t channel, int64_t receive_ns,
                                                 std::span<const uint8_t> message) {
  const auto t = static_cast<uint64_t>(receive_ns);
  auto written = mcap_.write(channel, t, t, message);
  if (written) ++messages_;
  return written;
}

Result<RecordingReader, std::string> RecordingReader::open(const std::string& path) {
  auto mcap = McapReader::open(path);
  if (!mcap) {
    // a recording of the retired format: say how to convert it
    std::array<char, 6> magic{};
    std::ifstream in(path, std::ios::binary);
    if (in.read(magic.data(), magic.size()) && std::string_view(magic.data(), 6) == "SCLOG1")
      return make_unexpected("'" + path + "' is a .sclog recording (retired): convert it with " +
                             "`scancrew convert " + path + " OUT.mcap`");
    return make_unexpected(mcap.error());
  }
  return RecordingReader(std::move(mcap).value());
}

Result<void, std::string> RecordingReader::take_channels() {
  for (const auto& [id, channel] : mcap_.channels()) {
    if (topic_of_channel_.size() <= id) topic_of_channel_.resize(size_t{id} + 1, -2);
    if (topic_of_channel_[id] != -2) continue;
    if (channel.message_encoding != kMessageEncoding) {
      topic_of_channel_[id] = -1;  // not ours (a Foxglove JSON channel, say)
      continue;
    }
    const std::string where = "'" + path() + "': channel " + std::to_string(id) + " ('" +
                              log::printable(channel.topic) + "')";
    const auto version = channel.metadata.find("format_version");
    if (version == channel.metadata.end())
      return make_unexpected(where + " has no format_version in its metadata");
    if (version->second != format_version())
      return make_unexpected(where + " holds messages of format version " +
                             log::printable(version->second) + "; this build reads version " +
                             format_version());
    if (!valid_topic_name(channel.topic))
      return make_unexpected(where + ": '" + log::printable(channel.topic) +
                             "' is not a topic name (absolute, printable, at most 256 bytes)");
    const auto schema = mcap_.schemas().find(channel.schema_id);
    if (schema == mcap_.schemas().end() || schema->second.encoding != kSchemaEncoding)
      return make_unexpected(where + " has no " + std::string(kSchemaEncoding) + " schema");
    topic_of_channel_[id] = static_cast<int32_t>(topics_.size());
    topics_.push_back({channel.topic, schema->second.name});
  }
  return {};
}

Result<std::optional<LogEntry>, std::string> RecordingReader::next() {
  for (;;) {
    auto m = mcap_.next();
    if (!m) return make_unexpected(m.error());
    if (!*m) return std::optional<LogEntry>{};
    const uint16_t id = (*m)->channel_id;
    if (id >= topic_of_channel_.size() || topic_of_channel_[id] == -2)
      if (auto taken = take_channels(); !taken) return make_unexpected(taken.error());
    const int32_t topic = topic_of_channel_[id];
    if (topic < 0) continue;
    return std::optional<LogEntry>{LogEntry{.topic = static_cast<uint16_t>(topic),
                                            .receive_ns = static_cast<int64_t>((*m)->log_time_ns),
                                            .message = (*m)->data}};
  }
}

Result<void, std::string> RecordingReader::scan_topics() {
  if (auto scanned = mcap_.scan(); !scanned) return scanned;
  return take_channels();
}

}  // namespace scancrew::recorder
