#pragma once

// The Foxglove channels of a recording: beside a recorded topic's own channel (our codec, for
// the replay backend), a "json" channel with a Foxglove schema that Foxglove shows without
// knowing our codec (components/foxglove_bridge/foxglove_json.hpp, the live view's
// conversions). Topic "/foxglove" + the recorded topic ("/foxglove/r1/pose_gt"); a stereo
// frame's left image on "/foxglove/r1/stereo/left".
//
//   Odometry           foxglove.PoseInFrame      every message
//   LocalPath          foxglove.PosesInFrame     every message
//   ViewpointClusters  foxglove.SceneUpdate      every message
//   DepthImage         foxglove.RawImage 32FC1   at most image_rate_hz (stamp time)
//   StereoFrame        foxglove.RawImage mono8   at most image_rate_hz, the left image
//
// Other types get no Foxglove channel. Views, not data: the replay reads only our channels.
// Not thread safe (the recorder's lock guards it).

#include <climits>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "components/recorder/mcap_writer.hpp"
#include "core/result.hpp"
#include "interfaces/map_msgs.hpp"
#include "interfaces/nav_msgs.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::recorder {

inline constexpr std::string_view kFoxglovePrefix = "/foxglove";

// Whether FoxgloveChannels::write() takes a T.
template <class T>
inline constexpr bool kHasFoxgloveView =
    std::is_same_v<T, msg::Odometry> || std::is_same_v<T, msg::LocalPath> ||
    std::is_same_v<T, msg::ViewpointClusters> || std::is_same_v<T, msg::DepthImage> ||
    std::is_same_v<T, msg::StereoFrame>;

class FoxgloveChannels {
 public:
  FoxgloveChannels(std::string frame_id, double image_rate_hz)
      : frame_id_(std::move(frame_id)), image_rate_hz_(image_rate_hz) {}

  // The Foxglove channel of `topic` (of message type `type`), added to `mcap`; nullopt for
  // a type without one. Returns its index for write().
  std::optional<size_t> add(McapWriter& mcap, const std::string& topic, std::string_view type);

  // Writes the Foxglove view of `message` on channel `index` (from add()), unless the
  // channel's rate skips it. Times in ns.
  template <class T>
  Result<void, std::string> write(McapWriter& mcap, size_t index, const T& message,
                                  int64_t receive_ns);

 private:
  struct Channel {
    uint16_t id = 0;
    std::string frame;  // an image's camera frame: "r1/camera"
    int64_t last_image_ns = INT64_MIN;
  };
  bool image_due(Channel& c, int64_t stamp_ns) const;
  uint16_t schema(McapWriter& mcap, int kind);

  std::string frame_id_;
  double image_rate_hz_;
  std::vector<Channel> channels_;
  std::vector<std::pair<int, uint16_t>> schemas_;  // foxglove::Schema, schema id
  std::string text_;
};

extern template Result<void, std::string> FoxgloveChannels::write(McapWriter&, size_t,
                                                                  const msg::Odometry&, int64_t);
extern template Result<void, std::string> FoxgloveChannels::write(McapWriter&, size_t,
                                                                  const msg::LocalPath&, int64_t);
extern template Result<void, std::string> FoxgloveChannels::write(McapWriter&, size_t,
                                                                  const msg::ViewpointClusters&,
                                                                  int64_t);
extern template Result<void, std::string> FoxgloveChannels::write(McapWriter&, size_t,
                                                                  const msg::DepthImage&, int64_t);
extern template Result<void, std::string> FoxgloveChannels::write(McapWriter&, size_t,
                                                                  const msg::StereoFrame&, int64_t);

}  // namespace scancrew::recorder
