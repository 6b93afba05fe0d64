// Our messages as Foxglove JSON messages: every field the schema requires is there, with the
// values of the message; the schemas shipped are the ones named; base64 is RFC 4648's; the
// protocol's frames and client messages are encoded and parsed as the spec says.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "components/foxglove_bridge/foxglove_json.hpp"
#include "components/foxglove_bridge/ws_protocol.hpp"

namespace scancrew::foxglove {
namespace {

using nlohmann::json;

// Every name in the schema's top-level "required" is a key of the message.
void expect_required_fields(Schema schema, const json& message) {
  const json s = json::parse(schema_text(schema));
  ASSERT_TRUE(s.contains("required")) << schema_name(schema);
  for (const json& key : s["required"])
    EXPECT_TRUE(message.contains(key.get<std::string>()))
        << schema_name(schema) << " lacks " << key;
}

TEST(FoxgloveJson, SchemasAreTheNamedFoxgloveSchemas) {
  for (const Schema s : {Schema::kPoseInFrame, Schema::kPosesInFrame, Schema::kSceneUpdate,
                         Schema::kRawImage, Schema::kFrameTransforms}) {
    const json schema = json::parse(schema_text(s));
    EXPECT_EQ(schema["title"], std::string(schema_name(s)));
    EXPECT_EQ(schema["type"], "object");
  }
}

TEST(FoxgloveJson, TimestampSplitsNanosecondsIntoSecondsAndNanoseconds) {
  EXPECT_EQ(timestamp_json(12'345'678'901), (json{{"sec", 12}, {"nsec", 345'678'901}}));
  EXPECT_EQ(timestamp_json(msg::kStampUnset), (json{{"sec", 0}, {"nsec", 0}}));
}

TEST(FoxgloveJson, PoseInFrameCarriesPositionOrientationAndFrame) {
  msg::Pose3 pose{.position = {1.23456, -2, 0.5}, .orientation = {0.5, 0.5, 0.5, 0.5}};
  const json j = pose_in_frame(pose, 2'000'000'000, "world");
  expect_required_fields(Schema::kPoseInFrame, j);
  EXPECT_EQ(j["frame_id"], "world");
  EXPECT_EQ(j["timestamp"]["sec"], 2);
  EXPECT_DOUBLE_EQ(j["pose"]["position"]["x"].get<double>(), 1.235);  // to the millimetre
  EXPECT_DOUBLE_EQ(j["pose"]["orientation"]["w"].get<double>(), 0.5);
}

TEST(FoxgloveJson, TourIsItsViewpointsInOrderWithYawAsQuaternion) {
  msg::PathSequence tour;
  tour.viewpoints = {{.position = {1, 0, 0}, .yaw_rad = 0},
                     {.position = {2, 0, 0}, .yaw_rad = M_PI}};
  const json j = tour_json(tour, 5, "world");
  expect_required_fields(Schema::kPosesInFrame, j);
  ASSERT_EQ(j["poses"].size(), 2u);
  EXPECT_DOUBLE_EQ(j["poses"][1]["position"]["x"].get<double>(), 2.0);
  EXPECT_NEAR(j["poses"][1]["orientation"]["z"].get<double>(), 1.0, 1e-12);
  EXPECT_NEAR(j["poses"][1]["orientation"]["w"].get<double>(), 0.0, 1e-12);
}

TEST(FoxgloveJson, IsesAreOneCubeEachGreyWhenNoRobotCanScanThem) {
  msg::IseSet ises;
  ises.centers_m = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
  ises.remaining = {1};
  const json j = ises_json(ises, 0.1, "world");
  expect_required_fields(Schema::kSceneUpdate, j);
  ASSERT_EQ(j["entities"].size(), 1u);
  const json& e = j["entities"][0];
  EXPECT_EQ(e["id"], "ises");
  ASSERT_EQ(e["cubes"].size(), 3u);
  EXPECT_DOUBLE_EQ(e["cubes"][0]["size"]["x"].get<double>(), 0.1);
  EXPECT_EQ(e["cubes"][0]["color"], e["cubes"][2]["color"]);
  EXPECT_NE(e["cubes"][0]["color"], e["cubes"][1]["color"]);
  // every array a SceneEntity requires is there
  const json schema = json::parse(schema_text(Schema::kSceneUpdate));
  for (const json& key : schema["properties"]["entities"]["items"]["required"])
    EXPECT_TRUE(e.contains(key.get<std::string>())) << key;
}

TEST(FoxgloveJson, MeshIsOneIndexedTriangleList) {
  tsdf::Mesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}};
  const json j = mesh_json(mesh, 7, "world");
  const json& tri = j["entities"][0]["triangles"][0];
  EXPECT_EQ(tri["points"].size(), 3u);
  EXPECT_EQ(tri["indices"], (json{0, 1, 2}));
  EXPECT_DOUBLE_EQ(tri["points"][1]["x"].get<double>(), 1.0);
}

TEST(FoxgloveJson, DepthImageIs32FC1WithItsBytesInBase64) {
  msg::DepthImage depth;
  depth.header.stamp_ns = 1;
  depth.intrinsics.width = 2;
  depth.intrinsics.height = 1;
  depth.depth_m = {1.5f, std::numeric_limits<float>::quiet_NaN()};
  const json j = depth_image_json(depth, "r1/camera");
  expect_required_fields(Schema::kRawImage, j);
  EXPECT_EQ(j["encoding"], "32FC1");
  EXPECT_EQ(j["step"], 8);
  EXPECT_EQ(j["data"].get<std::string>().size(), 12u);  // 8 bytes → 12 characters
  EXPECT_EQ(j["frame_id"], "r1/camera");
}

TEST(FoxgloveJson, FrameTransformsNameParentAndChild) {
  const FrameTransform tf{
      .stamp_ns = 3, .parent_frame_id = "world", .child_frame_id = "r1/base_link"};
  const json j = frame_transforms_json({&tf, 1});
  expect_required_fields(Schema::kFrameTransforms, j);
  EXPECT_EQ(j["transforms"][0]["child_frame_id"], "r1/base_link");
  EXPECT_TRUE(j["transforms"][0].contains("translation"));
  EXPECT_TRUE(j["transforms"][0].contains("rotation"));
}

TEST(FoxgloveJson, Base64IsRfc4648) {
  const auto b64 = [](std::string_view s) {
    return base64({reinterpret_cast<const uint8_t*>(s.data()), s.size()});
  };
  EXPECT_EQ(b64(""), "");
  EXPECT_EQ(b64("f"), "Zg==");
  EXPECT_EQ(b64("fo"), "Zm8=");
  EXPECT_EQ(b64("foo"), "Zm9v");
  EXPECT_EQ(b64("foobar"), "Zm9vYmFy");
}

TEST(WsProtocol, MessageDataHeadIsOpcodeSubscriptionAndTimestampLittleEndian) {
  const MessageDataHead h = message_data_head(0x01020304u, 0x1122334455667788ull);
  const MessageDataHead expected = {0x01, 0x04, 0x03, 0x02, 0x01, 0x88, 0x77,
                                    0x66, 0x55, 0x44, 0x33, 0x22, 0x11};
  EXPECT_EQ(h, expected);
}

TEST(WsProtocol, AdvertiseListsEachChannelWithItsJsonSchema) {
  const std::vector<Channel> channels = {
      {.id = 1, .topic = "/tf", .schema = Schema::kFrameTransforms},
      {.id = 2, .topic = "/r1/ises", .schema = Schema::kSceneUpdate}};
  const json j = json::parse(advertise_message(channels));
  EXPECT_EQ(j["op"], "advertise");
  ASSERT_EQ(j["channels"].size(), 2u);
  EXPECT_EQ(j["channels"][1]["topic"], "/r1/ises");
  EXPECT_EQ(j["channels"][1]["encoding"], "json");
  EXPECT_EQ(j["channels"][1]["schemaName"], "foxglove.SceneUpdate");
  EXPECT_EQ(j["channels"][1]["schemaEncoding"], "jsonschema");
  EXPECT_EQ(json::parse(j["channels"][1]["schema"].get<std::string>())["title"],
            "foxglove.SceneUpdate");
  EXPECT_EQ(json::parse(server_info_message("x"))["op"], "serverInfo");
}

TEST(WsProtocol, ParsesSubscribeAndUnsubscribeAndRefusesMalformedOnes) {
  const auto sub =
      parse_client_op(R"({"op":"subscribe","subscriptions":[{"id":7,"channelId":2}]})");
  ASSERT_TRUE(sub);
  EXPECT_EQ(sub->kind, ClientOp::Kind::kSubscribe);
  ASSERT_EQ(sub->subscriptions.size(), 1u);
  EXPECT_EQ(sub->subscriptions[0], (std::pair<uint32_t, uint32_t>{7, 2}));
  const auto unsub = parse_client_op(R"({"op":"unsubscribe","subscriptionIds":[7]})");
  ASSERT_TRUE(unsub);
  EXPECT_EQ(unsub->subscription_ids, std::vector<uint32_t>{7});
  EXPECT_EQ(parse_client_op(R"({"op":"getParameters"})")->kind, ClientOp::Kind::kOther);
  EXPECT_FALSE(parse_client_op("not json"));
  EXPECT_FALSE(parse_client_op(R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":2}]})"));
  EXPECT_FALSE(parse_client_op(R"({"subscriptions":[]})"));
}

}  // namespace
}  // namespace scancrew::foxglove
