// The Foxglove channels of a recording (components/recorder/foxglove_channels.hpp): which
// types get one, their topics, schemas and JSON, and the image rate (stamp time).

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "components/recorder/foxglove_channels.hpp"
#include "components/recorder/mcap_reader.hpp"

namespace scancrew::recorder {
namespace {

namespace fs = std::filesystem;

struct Read {
  std::map<uint16_t, McapSchema> schemas;
  std::map<uint16_t, McapChannel> channels;
  std::vector<std::pair<uint16_t, nlohmann::json>> messages;
};

Read read_all(const std::string& path) {
  Read out;
  auto reader = McapReader::open(path);
  EXPECT_TRUE(reader) << reader.error();
  while (true) {
    auto m = reader->next();
    EXPECT_TRUE(m) << m.error();
    if (!m || !*m) break;
    const auto& data = (*m)->data;
    out.messages.emplace_back((*m)->channel_id, nlohmann::json::parse(data.begin(), data.end()));
  }
  out.schemas = reader->schemas();
  out.channels = reader->channels();
  return out;
}

TEST(FoxgloveChannels, PosesAndThrottledImagesAsFoxgloveJson) {
  const std::string path =
      (fs::temp_directory_path() / ("scancrew_fox_" + std::to_string(::getpid()) + ".mcap"))
          .string();
  {
    auto mcap = McapWriter::open(path);
    ASSERT_TRUE(mcap) << mcap.error();
    FoxgloveChannels fox("world", 2.0);
    const auto pose = fox.add(*mcap, "/r1/pose_gt", msg::Odometry::kTypeName);
    const auto depth = fox.add(*mcap, "/r1/depth", msg::DepthImage::kTypeName);
    const auto stereo = fox.add(*mcap, "/r1/stereo", msg::StereoFrame::kTypeName);
    EXPECT_FALSE(fox.add(*mcap, "/r1/imu", msg::Imu::kTypeName));  // no Foxglove view
    ASSERT_TRUE(pose && depth && stereo);
    msg::Odometry odom;
    odom.T_world_body.position = {1.5, -2, 0.25};
    msg::DepthImage image;
    image.intrinsics.width = 2;
    image.intrinsics.height = 1;
    image.depth_m = {1.0F, 2.0F};
    msg::StereoFrame frame;
    frame.intrinsics.width = 2;
    frame.intrinsics.height = 1;
    frame.left = {10, 20};
    for (int i = 0; i < 10; ++i) {  // 10 messages at 5 Hz over 2 s: images at 2 Hz keep 4
      const int64_t t = i * 200'000'000LL;
      odom.header.stamp_ns = image.header.stamp_ns = frame.header.stamp_ns = t;
      ASSERT_TRUE(fox.write(*mcap, *pose, odom, t));
      ASSERT_TRUE(fox.write(*mcap, *depth, image, t));
      ASSERT_TRUE(fox.write(*mcap, *stereo, frame, t));
    }
    ASSERT_TRUE(mcap->close());
  }
  const Read r = read_all(path);
  fs::remove(path);
  std::map<std::string, int> count;
  std::map<std::string, std::string> schema_of;
  for (const auto& [id, c] : r.channels) {
    EXPECT_EQ(c.message_encoding, "json");
    EXPECT_EQ(r.schemas.at(c.schema_id).encoding, "jsonschema");
    schema_of[c.topic] = r.schemas.at(c.schema_id).name;
  }
  EXPECT_EQ(schema_of["/foxglove/r1/pose_gt"], "foxglove.PoseInFrame");
  EXPECT_EQ(schema_of["/foxglove/r1/depth"], "foxglove.RawImage");
  EXPECT_EQ(schema_of["/foxglove/r1/stereo/left"], "foxglove.RawImage");
  EXPECT_EQ(r.schemas.size(), 2U);  // RawImage once for both image channels
  for (const auto& [id, j] : r.messages) {
    const std::string& topic = r.channels.at(id).topic;
    ++count[topic];
    if (topic == "/foxglove/r1/pose_gt") {
      EXPECT_DOUBLE_EQ(j["pose"]["position"]["x"].get<double>(), 1.5);
      EXPECT_EQ(j["frame_id"], "world");
    } else {
      EXPECT_EQ(j["frame_id"], "r1/camera");
      EXPECT_EQ(j["width"], 2);
    }
  }
  EXPECT_EQ(count["/foxglove/r1/pose_gt"], 10);
  EXPECT_EQ(count["/foxglove/r1/depth"], 4);  // t = 0, 0.6, 1.2, 1.8 s (0.4 s < 0.5 s)
  EXPECT_EQ(count["/foxglove/r1/stereo/left"], 4);
}

}  // namespace
}  // namespace scancrew::recorder
