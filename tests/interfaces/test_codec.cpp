// The message codec round-trips every wire message exactly and refuses malformed bytes:
// truncated at any length, hostile counts, trailing bytes.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "interfaces/codec.hpp"

namespace scancrew::msg {
namespace {

Header header() {
  return {.robot_id = 3, .seq = 42, .stamp_ns = -5, .publish_mono_ns = 1234567};
}

StereoFrame stereo() {
  StereoFrame f;
  f.header = header();
  f.intrinsics = {.width = 3, .height = 2, .fx = 1.5, .fy = 1.5, .cx = 1, .cy = 0.5};
  f.baseline_m = 0.26;
  f.left = {1, 2, 3, 4, 5, 6};
  f.right = {6, 5, 4, 3, 2, 1};
  return f;
}

TeamPlan plan() {
  TeamPlan p;
  p.header = header();
  p.plan_id = 7;
  p.sequences.push_back({.robot_id = 1,
                         .cluster_ids = {4, 5},
                         .viewpoints = {{{1, 2, 3}, 0.5}, {{4, 5, 6}, -0.5}},
                         .utility = 0.25});
  p.sequences.push_back({.robot_id = 2, .cluster_ids = {}, .viewpoints = {}, .utility = 0});
  return p;
}

template <class T>
void expect_round_trip(const T& message) {
  const std::vector<uint8_t> bytes = encode(message);
  T back;
  ASSERT_TRUE(decode(bytes, back)) << T::kTypeName;
  EXPECT_EQ(encode(back), bytes) << T::kTypeName;
}

TEST(Codec, EveryWireMessageRoundTripsExactly) {
  expect_round_trip(stereo());
  expect_round_trip(plan());
  DepthImage d;
  d.header = header();
  d.T_world_cam = {{1, 2, 3}, {0.5, 0.5, -0.5, 0.5}};
  d.depth_m = {1.0F, std::numeric_limits<float>::quiet_NaN(), 3.5F};
  expect_round_trip(d);
  Odometry o;
  o.pose_covariance[7] = 0.125;
  o.tracking_quality = 0.9;
  expect_round_trip(o);
  Maneuver m;
  m.kind = Maneuver::Kind::kStepAside;
  expect_round_trip(m);
  ViewpointClusters c;
  c.clusters.push_back({.id = 9,
                        .gain = 0.1,
                        .viewpoints = {{{{1, 1, 1}, 0}, {1, 2, 3}, kGroundRobotBit}},
                        .robot_types = kGroundRobotBit | kMultirotorBit,
                        .centroid = {1, 2, 0.5}});
  c.ise_count = 17;
  expect_round_trip(c);
  IseSet ises;
  ises.centers_m = {{1, 2, 3}};
  ises.view_directions = {{0, 0, 1}};
  ises.remaining = {0};
  ises.complete = 1;
  expect_round_trip(ises);
  TsdfPatch patch;
  patch.robot_id = 2;
  patch.index = 5;
  patch.patch_id = (uint64_t{2} << 32) | 5;
  patch.block_count = 1;
  patch.data = {0x28, 0xb5, 0x2f, 0xfd, 0, 1, 2};
  expect_round_trip(patch);
  // and the values come back, not only the bytes
  StereoFrame back;
  ASSERT_TRUE(decode(encode(stereo()), back));
  EXPECT_EQ(back.header.seq, 42u);
  EXPECT_EQ(back.header.stamp_ns, -5);
  EXPECT_EQ(back.right, stereo().right);
  EXPECT_EQ(back.intrinsics.fx, 1.5);
}

TEST(Codec, EveryTruncationIsAnError) {
  const std::vector<uint8_t> bytes = encode(plan());
  for (size_t n = 0; n < bytes.size(); ++n) {
    TeamPlan back;
    EXPECT_FALSE(decode(std::span<const uint8_t>(bytes.data(), n), back)) << n;
  }
}

TEST(Codec, TrailingBytesAreAnError) {
  std::vector<uint8_t> bytes = encode(stereo());
  bytes.push_back(0);
  StereoFrame back;
  const auto r = decode(bytes, back);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("1 trailing bytes"), std::string::npos) << r.error();
}

TEST(Codec, AHostileCountIsRefusedBeforeAllocating) {
  // a TeamPlan claiming 2^32-1 path sequences in a 40-byte buffer
  std::vector<uint8_t> bytes = encode(TeamPlan{});
  ASSERT_GE(bytes.size(), 4u);
  for (size_t i = bytes.size() - 4; i < bytes.size(); ++i) bytes[i] = 0xff;
  TeamPlan back;
  const auto r = decode(bytes, back);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("truncated or malformed scancrew/TeamPlan"), std::string::npos)
      << r.error();
  EXPECT_TRUE(back.sequences.empty());
}

TEST(Codec, DecodingReusesTheMessageCapacity) {
  StereoFrame target;
  target.left.reserve(1000);
  const uint8_t* before = target.left.data();
  ASSERT_TRUE(decode(encode(stereo()), target));
  EXPECT_EQ(target.left.data(), before);
}

TEST(Codec, WireMessagesAreFoundByTypeName) {
  std::string found;
  EXPECT_TRUE(with_wire_message("scancrew/Imu", [&]<class T>() { found = T::kTypeName; }));
  EXPECT_EQ(found, "scancrew/Imu");
  EXPECT_FALSE(with_wire_message("scancrew/Nope", [&]<class T>() { found = "wrong"; }));
  EXPECT_EQ(found, "scancrew/Imu");
}

}  // namespace
}  // namespace scancrew::msg
