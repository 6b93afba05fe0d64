#pragma once

// A recording: an MCAP file (mcap_writer.hpp, mcap_reader.hpp) whose scancrew channels carry
// our messages, so the replay backend can play it and Foxglove Studio can open it.
//
// Mapping (docs/recording.md):
//   header profile     "scancrew"
//   schema             name = the message type ("scancrew/StereoFrame"), encoding
//                      "scancrew-codec", data = UTF-8 text: the type name and the message
//                      format version (msg::kMessageFormatVersion), one "key: value" a line
//   channel            topic = the absolute topic name ("/r1/stereo"), message encoding
//                      "scancrew", metadata {"format_version": "6"}
//   message            log_time = publish_time = the recorder's receive time (ns, its
//                      clock); data = the message in the codec of interfaces/codec.hpp
// Channels of other message encodings ("json" with Foxglove schemas, say) may sit beside
// ours: the RecordingReader passes over them.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "components/recorder/mcap_reader.hpp"
#include "components/recorder/mcap_writer.hpp"
#include "core/result.hpp"

namespace scancrew::recorder {

inline constexpr std::string_view kMessageEncoding = "scancrew";
inline constexpr std::string_view kSchemaEncoding = "scancrew-codec";

struct LogTopic {
  std::string name;  // absolute topic name, e.g. "/r1/stereo"
  std::string type;  // message type name, e.g. "scancrew/StereoFrame"
};

struct LogEntry {
  uint16_t topic = 0;  // index into RecordingReader::topics()
  int64_t receive_ns = 0;
  std::span<const uint8_t> message;  // valid until the next call to next()
};

// The schema data of a message type (see above).
std::string schema_text(std::string_view type_name);

// A topic name: absolute, at most 256 bytes, printable ASCII without spaces (launch remaps
// and bridge prefixes allow more than letters, digits and '_', so the reader asks no more).
// A recording's names are echoed and become topics: control bytes (an escape sequence) or
// an empty name are a corrupt or hostile file.
bool valid_topic_name(std::string_view name);

// Writes scancrew channels into an MCAP file; mcap() adds channels of other encodings.
// Not thread safe (one writer, one thread at a time).
class RecordingWriter {
 public:
  static Result<RecordingWriter, std::string> open(const std::string& path,
                                                   McapWriterOptions options = {});
  // A channel for `topic` (its type's schema added once); returns the channel id.
  uint16_t add_topic(const LogTopic& topic);
  Result<void, std::string> write(uint16_t channel, int64_t receive_ns,
                                  std::span<const uint8_t> message);
  Result<void, std::string> flush() { return mcap_.flush(); }
  Result<void, std::string> close() { return mcap_.close(); }
  // The messages write() wrote (our channels; not those added through mcap()).
  uint64_t messages() const { return messages_; }
  uint64_t bytes() const { return mcap_.bytes(); }
  McapWriter& mcap() { return mcap_; }

 private:
  explicit RecordingWriter(McapWriter mcap) : mcap_(std::move(mcap)) {}
  McapWriter mcap_;
  std::vector<std::pair<std::string, uint16_t>> schemas_;  // type name, schema id
  uint64_t messages_ = 0;
};

// Reads the scancrew channels of an MCAP file, in file order (the recorded arrival order).
class RecordingReader {
 public:
  // Fails on a missing file or one that is not MCAP.
  static Result<RecordingReader, std::string> open(const std::string& path);

  // The next message on a scancrew channel; nullopt at the end or at a cut (truncated()).
  // A scancrew channel of another format version, or whose topic is no topic name, is an
  // error; so is corrupt input, naming its byte offset.
  Result<std::optional<LogEntry>, std::string> next();
  // Reads the whole file once to collect every scancrew channel, then rewinds.
  Result<void, std::string> scan_topics();
  Result<void, std::string> rewind() { return mcap_.rewind(); }
  const std::vector<LogTopic>& topics() const { return topics_; }
  bool truncated() const { return mcap_.truncated(); }
  uint64_t offset() const { return mcap_.offset(); }
  const std::string& path() const { return mcap_.path(); }

 private:
  explicit RecordingReader(McapReader mcap) : mcap_(std::move(mcap)) {}
  // Maps every channel the reader knows to a topic index (or to none: not ours).
  Result<void, std::string> take_channels();

  McapReader mcap_;
  std::vector<LogTopic> topics_;
  std::vector<int32_t> topic_of_channel_;  // by channel id; -1: not ours; -2: not yet seen
};

}  // namespace scancrew::recorder
