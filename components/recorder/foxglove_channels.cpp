#include "components/recorder/foxglove_channels.hpp"

#include <climits>
#include <span>
#include <type_traits>

#include "components/foxglove_bridge/foxglove_json.hpp"

namespace scancrew::recorder {

namespace {

using foxglove::Schema;

// The camera frame of a robot's image topic: "/r1/depth" -> "r1/camera" (as the live view).
std::string camera_frame(const std::string& topic) {
  const size_t end = topic.find('/', 1);
  return topic.starts_with('/') && end != std::string::npos ? topic.substr(1, end - 1) + "/camera"
                                                            : std::string("camera");
}

std::span<const uint8_t> bytes_of(const std::string& text) {
  return {reinterpret_cast<const uint8_t*>(text.data()), text.size()};
}

}  // namespace

uint16_t FoxgloveChannels::schema(McapWriter& mcap, int kind) {
  for (const auto& [k, id] : schemas_)
    if (k == kind) return id;
  const auto s = static_cast<Schema>(kind);
  const std::string_view text = foxglove::schema_text(s);
  const uint16_t id = mcap.add_schema(foxglove::schema_name(s), "jsonschema",
                                      {reinterpret_cast<const uint8_t*>(text.data()), text.size()});
  schemas_.emplace_back(kind, id);
  return id;
}

std::optional<size_t> FoxgloveChannels::add(McapWriter& mcap, const std::string& topic,
                                            std::string_view type) {
  std::string name = std::string(kFoxglovePrefix) + topic;
  Schema s{};
  if (type == msg::Odometry::kTypeName) {
    s = Schema::kPoseInFrame;
  } else if (type == msg::LocalPath::kTypeName) {
    s = Schema::kPosesInFrame;
  } else if (type == msg::ViewpointClusters::kTypeName) {
    s = Schema::kSceneUpdate;
  } else if (type == msg::DepthImage::kTypeName) {
    s = Schema::kRawImage;
  } else if (type == msg::StereoFrame::kTypeName) {
    s = Schema::kRawImage;
    name += "/left";
  } else {
    return std::nullopt;
  }
  const uint16_t id = mcap.add_channel(name, "json", schema(mcap, static_cast<int>(s)));
  channels_.push_back({.id = id, .frame = camera_frame(topic)});
  return channels_.size() - 1;
}

bool FoxgloveChannels::image_due(Channel& c, int64_t stamp_ns) const {
  const auto period_ns = static_cast<int64_t>(1e9 / image_rate_hz_);
  if (c.last_image_ns != INT64_MIN && stamp_ns - c.last_image_ns < period_ns) return false;
  c.last_image_ns = stamp_ns;
  return true;
}

template <class T>
Result<void, std::string> FoxgloveChannels::write(McapWriter& mcap, size_t index, const T& message,
                                                  int64_t receive_ns) {
  Channel& c = channels_.at(index);
  const int64_t stamp = message.header.stamp_ns;
  nlohmann::json view;
  if constexpr (std::is_same_v<T, msg::Odometry>) {
    view = foxglove::pose_in_frame(message.T_world_body, stamp, frame_id_);
  } else if constexpr (std::is_same_v<T, msg::LocalPath>) {
    view = foxglove::local_path_json(message, frame_id_);
  } else if constexpr (std::is_same_v<T, msg::ViewpointClusters>) {
    view = foxglove::clusters_json(message, frame_id_);
  } else if constexpr (std::is_same_v<T, msg::DepthImage>) {
    if (!image_due(c, stamp)) return {};
    view = foxglove::depth_image_json(message, c.frame);
  } else {
    static_assert(std::is_same_v<T, msg::StereoFrame>);
    if (!image_due(c, stamp)) return {};
    view = foxglove::mono8_image_json(message.intrinsics.width, message.intrinsics.height,
                                      message.left, stamp, c.frame);
  }
  text_ = view.dump();
  const auto t = static_cast<uint64_t>(receive_ns < 0 ? 0 : receive_ns);
  return mcap.write(c.id, t, t, bytes_of(text_));
}

template Result<void, std::string> FoxgloveChannels::write(McapWriter&, size_t,
                                                           const msg::Odometry&, int64_t);
template Result<void, std::string> FoxgloveChannels::write(McapWriter&, size_t,
                                                           const msg::LocalPath&, int64_t);
template Result<void, std::string> FoxgloveChannels::write(McapWriter&, size_t,
                                                           const msg::ViewpointClusters&, int64_t);
template Result<void, std::string> FoxgloveChannels::write(McapWriter&, size_t,
                                                           const msg::DepthImage&, int64_t);
template Result<void, std::string> FoxgloveChannels::write(McapWriter&, size_t,
                                                           const msg::StereoFrame&, int64_t);

}  // namespace scancrew::recorder
