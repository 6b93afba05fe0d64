#pragma once

// Replay: the `replay` backend. Plays a recording (MCAP) written by the recorder,
// publishing every message on the topic it was recorded from, whole (robot id, sequence
// number and stamp as recorded; only publish_mono_ns is new), in recorded order and with
// the recorded spacing in time, scaled by `rate`. A robot graph runs on it unchanged.
//
// timing: relative  the first message goes out at the first tick, the others keep their
//                   spacing (on the wall or sim clock);
//         absolute  each message goes out when the clock reaches its recorded receive time
//                   (replaying beside a simulator on the same sim time).
// A message that finds its topic's pool exhausted waits for the next tick: nothing is
// skipped. A recording cut short plays up to the cut and says so. Channels that are not
// scancrew's (message encoding other than "scancrew": Foxglove JSON, say) are passed over.

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "components/recorder/recording.hpp"
#include "core/enum_names.hpp"
#include "executors/component.hpp"
#include "executors/params.hpp"

namespace scancrew::recorder {

// When a recorded message goes out (param `timing`; see above).
enum class ReplayTiming : uint8_t { kRelative, kAbsolute };

inline constexpr EnumNames<ReplayTiming, 2> kReplayTimingNames = {
    {{ReplayTiming::kRelative, "relative"}, {ReplayTiming::kAbsolute, "absolute"}}};

class Replay final : public Component {
 public:
  // not on a robot or the station: never charged compute (StepExecutor)
  static constexpr bool kWorld = true;
  static constexpr std::string_view kDescription =
      "the replay backend: plays an MCAP recording on its recorded topics";
  struct Config {
    std::string path;
    ReplayTiming timing = ReplayTiming::kRelative;  // relative | absolute
    double rate = 1.0;                              // playback speed (relative timing)
    double tick_s = 0.001;                          // how often due messages are published
    std::vector<std::string> topics;                // absolute names to play; empty: all
  };
  static Config read_config(ParamReader& p);

  Replay(ComponentContext context, Config config);

  bool finished() const { return finished_; }
  uint64_t published() const { return published_; }
  uint64_t decode_errors() const { return decode_errors_; }
  uint64_t pool_waits() const { return pool_waits_; }
  bool truncated() const { return reader_ && reader_->truncated(); }

 private:
  enum class Outcome { kPublished, kPoolExhausted, kDropped };
  using PublishFn = std::function<Outcome(std::span<const uint8_t>)>;

  Result<void, std::string> on_configure() override;
  // A replay stopped before the recording's end says where (a forged far-future receive time
  // held the rest back silently).
  void on_deactivate() override;
  void tick();
  bool due(int64_t receive_ns, int64_t now_ns);

  Config config_;
  std::optional<RecordingReader> reader_;
  std::vector<PublishFn> publish_;  // per topic of the recording; empty when filtered out
  std::optional<LogEntry> pending_;
  std::optional<int64_t> start_ns_, first_receive_ns_;
  bool finished_ = false;
  uint64_t published_ = 0, decode_errors_ = 0, pool_waits_ = 0;
};

}  // namespace scancrew::recorder
