#pragma once

// Recorder: writes chosen topics to a recording (MCAP, components/recorder/recording.hpp)
// so any session can be played again by the replay backend or opened in Foxglove Studio.
// Each message is stored whole (header included) with the time the recorder received it,
// in arrival order. The file is closed (summary and footer written) at deactivation; a
// crash before it keeps every chunk flushed, at most flush_period_s old.
//
// Topics are ports, relative to the recorder's namespace or absolute ("/r1/stereo"). The
// message type is taken from the topic when a component configured before the recorder
// created it; otherwise give it as "port:Type", e.g. "cmd_vel:scancrew/VelocityCommand".
// Only wire messages (msg::WireMessages) can be recorded. Poses, paths, clusters and images
// get a Foxglove JSON channel too ("/foxglove/<topic>", foxglove_channels.hpp), so
// Foxglove shows the recording; the replay plays our channels only.

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "components/recorder/foxglove_channels.hpp"
#include "components/recorder/recording.hpp"
#include "executors/component.hpp"
#include "executors/params.hpp"

namespace scancrew::recorder {

class Recorder final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "writes chosen topics to an MCAP recording for the replay backend and Foxglove";
  struct Config {
    std::string path;                     // the recording to write (overwritten)
    std::vector<std::string> topics;      // "port" or "port:Type"
    uint32_t queue_depth = 64;            // per topic: messages waiting to be written
    double flush_period_s = 1.0;          // a crash loses at most this much of the recording
    bool foxglove_channels = true;        // Foxglove JSON views beside (foxglove_channels.hpp)
    double foxglove_image_rate_hz = 2.0;  // their images, at most (as the live view's)
  };
  static Config read_config(ParamReader& p);

  Recorder(ComponentContext context, Config config);

  uint64_t messages_written() const;
  uint64_t write_errors() const { return write_errors_; }

 private:
  Result<void, std::string> on_configure() override;
  void on_deactivate() override;
  Result<void, std::string> add(const std::string& spec);
  void write(uint16_t channel, int64_t receive_ns, std::span<const uint8_t> bytes);

  Config config_;
  mutable std::mutex mutex_;  // the writer, from every topic's callback
  std::optional<RecordingWriter> writer_;
  std::optional<FoxgloveChannels> foxglove_;
  std::vector<uint8_t> scratch_;
  uint64_t write_errors_ = 0;
};

}  // namespace scancrew::recorder
