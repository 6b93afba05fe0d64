#include "components/foxglove_bridge/foxglove_bridge.hpp"

#include <cmath>
#include <set>

#include "components/foxglove_bridge/foxglove_json.hpp"
#include "executors/log.hpp"
#include "executors/registry.hpp"

namespace scancrew::foxglove_bridge {

namespace {

using foxglove::Schema;

bool ends_with(std::string_view s, std::string_view tail) {
  return s.size() >= tail.size() && s.substr(s.size() - tail.size()) == tail;
}

// "/r1/clusters", "clusters", "viewpoints" → "/r1/viewpoints"; a topic not ending in `from`
// gets "/<to>" appended.
std::string renamed(const std::string& topic, std::string_view from, std::string_view to) {
  if (ends_with(topic, from)) return topic.substr(0, topic.size() - from.size()) + std::string(to);
  return topic + "/" + std::string(to);
}

}  // namespace

FoxgloveBridge::Config FoxgloveBridge::read_config(ParamReader& p) {
  Config c;
  p.optional("port", c.port, {0, 65535})
      .doc("TCP port of the WebSocket server (0: any free port, logged)");
  p.optional("address", c.address)
      .doc("address to listen on (127.0.0.1: this machine only; 0.0.0.0: every interface)");
  p.optional("frame_id", c.frame_id).doc("the world frame the poses, scenes and /tf refer to");
  p.optional("image_rate_hz", c.image_rate_hz, {0.01, 100})
      .doc("at most this many images per image channel per sim second");
  p.optional("mesh_rate_hz", c.mesh_rate_hz, {0.01, 1})
      .doc("at most this many meshes per mesh channel per sim second (≤ 1)");
  p.optional("path_period_s", c.path_period_s, {0.01, 3600})
      .doc("a robot's path keeps one pose per period (sim s)");
  p.optional("max_queue_messages", c.max_queue_messages, {1, 1'000'000})
      .doc("messages queued per client before further ones are dropped (and counted)");
  p.optional("max_queue_mb", c.max_queue_mb, {1, 4096})
      .doc("bytes queued per client before further messages are dropped (MiB)");
  return c;
}

FoxgloveBridge::FoxgloveBridge(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

FoxgloveBridge::~FoxgloveBridge() {
  stop_all();
}

bool FoxgloveBridge::Throttle::due(int64_t now_ns, double rate_hz) {
  const auto period_ns = static_cast<int64_t>(1e9 / rate_hz);
  if (last_ns != INT64_MIN && now_ns - last_ns < period_ns && now_ns >= last_ns) return false;
  last_ns = now_ns;
  return true;
}

uint32_t FoxgloveBridge::add_channel(std::string topic, Schema schema) {
  const auto id = static_cast<uint32_t>(channels_.size() + 1);
  channels_.push_back({.id = id, .topic = std::move(topic), .schema = schema});
  return id;
}

bool FoxgloveBridge::wanted(uint32_t channel) const {
  return server_ != nullptr && channel != 0 && server_->subscribed(channel);
}

void FoxgloveBridge::send(uint32_t channel, int64_t stamp_ns, const nlohmann::json& message) {
  const int64_t t = stamp_ns == msg::kStampUnset ? clock().now_ns() : stamp_ns;
  server_->publish(channel, t, std::make_shared<const std::string>(message.dump()));
}

// "/r1/depth" → "r1/camera"; a topic outside the team's namespaces → "<child>".
std::string FoxgloveBridge::frame_of(const std::string& topic, std::string_view child) const {
  const size_t end = topic.find('/', 1);
  if (topic.starts_with('/') && end != std::string::npos) {
    const std::string ns = topic.substr(1, end - 1);
    for (const TeamMember& m : team())
      if (m.ns == ns) return ns + "/" + std::string(child);
  }
  return std::string(child);
}

std::string FoxgloveBridge::robot_ns(uint32_t robot_id) const {
  for (const TeamMember& m : team())
    if (m.id == robot_id) return m.ns;
  return "";
}

Result<void, std::string> FoxgloveBridge::on_configure() {
  tf_channel_ = add_channel("/tf", Schema::kFrameTransforms);
  std::set<std::string> published;
  for (const EndpointInfo& e : graph().endpoints())
    if (e.kind == EndpointInfo::Kind::kPublisher) published.insert(e.topic);
  for (const std::string& name : graph().topic_names())
    if (published.contains(name))
      if (auto topic = graph().find(name)) add_topic(name, topic->type_name());
  foxglove::WsServerConfig server{
      .address = config_.address,
      .port = static_cast<uint16_t>(config_.port),
      .name = "scancrew " + qualified_name(),
      .max_queue_messages = static_cast<size_t>(config_.max_queue_messages),
      .max_queue_bytes = static_cast<size_t>(config_.max_queue_mb) << 20};
  auto started = foxglove::WsServer::start(server, channels_);
  if (!started) return make_unexpected("live view: " + started.error());
  server_ = std::move(started).value();
  if (!meshes_.empty()) mesh_thread_ = std::thread([this] { mesh_loop(); });
  const std::string host = config_.address == "0.0.0.0" ? "localhost" : config_.address;
  SCANCREW_LOG_INFO(
      "live view: ws://%s:%u (%zu channels; Foxglove: Open connection → Foxglove WebSocket)",
      host == "127.0.0.1" ? "localhost" : host.c_str(), static_cast<unsigned>(server_->port()),
      channels_.size());
  return {};
}

void FoxgloveBridge::add_topic(const std::string& name, std::string_view type) {
  if (type == msg::Odometry::kTypeName) {
    add_pose(name);
  } else if (type == msg::LocalPath::kTypeName) {
    const uint32_t ch = add_channel(name, Schema::kPosesInFrame);
    create_subscription<msg::LocalPath>(name, {.depth = 1}, [this, ch](Sample<msg::LocalPath>&& s) {
      if (wanted(ch)) send(ch, s->header.stamp_ns, foxglove::local_path_json(*s, config_.frame_id));
    });
  } else if (type == msg::TeamPlan::kTypeName) {
    add_plan(name);
  } else if (type == msg::ViewpointClusters::kTypeName) {
    add_clusters(name);
  } else if (type == msg::IseSet::kTypeName) {
    add_ises(name);
  } else if (type == msg::MapUpdate::kTypeName) {
    add_map(name);
  } else if (type == msg::DepthImage::kTypeName) {
    add_depth(name);
  } else if (type == msg::StereoFrame::kTypeName) {
    add_stereo(name);
  }
}

void FoxgloveBridge::add_pose(const std::string& topic) {
  const size_t k = tracks_.size();
  // a path for a robot's own pose (not, say, the low-level planner's skipped_goal)
  const std::string last = topic.substr(topic.rfind('/') + 1);
  const bool robot_pose =
      last == "pose_gt" || last == "odom" || last == "wheel_odom" || last == "pose";
  PoseTrack track{.pose = add_channel(topic, Schema::kPoseInFrame),
                  .path = robot_pose ? add_channel(topic + "/path", Schema::kPosesInFrame) : 0};
  if (ends_with(topic, "/pose_gt")) track.base_frame = frame_of(topic, "base_link");
  tracks_.push_back(std::move(track));
  create_subscription<msg::Odometry>(topic, {.depth = 4},
                                     [this, k](Sample<msg::Odometry>&& s) { on_pose(k, *s); });
}

void FoxgloveBridge::on_pose(size_t k, const msg::Odometry& odom) {
  const int64_t t =
      odom.header.stamp_ns == msg::kStampUnset ? clock().now_ns() : odom.header.stamp_ns;
  bool path_grew = false;
  {
    const std::lock_guard lock(mutex_);
    PoseTrack& track = tracks_[k];
    const auto period_ns = static_cast<int64_t>(config_.path_period_s * 1e9);
    if (track.path != 0 &&
        (track.last_path_ns == INT64_MIN || t - track.last_path_ns >= period_ns)) {
      track.path_poses.push_back(odom.T_world_body);
      track.last_path_ns = t;
      path_grew = true;
    }
  }
  const PoseTrack& track = tracks_[k];  // the channels and frame are set at configure
  if (wanted(track.pose))
    send(track.pose, t, foxglove::pose_in_frame(odom.T_world_body, t, config_.frame_id));
  if (!track.base_frame.empty() && wanted(tf_channel_)) {
    const foxglove::FrameTransform tf{.stamp_ns = t,
                                      .parent_frame_id = config_.frame_id,
                                      .child_frame_id = track.base_frame,
                                      .T_parent_child = odom.T_world_body};
    send(tf_channel_, t, foxglove::frame_transforms_json({&tf, 1}));
  }
  if (path_grew && wanted(track.path)) {
    nlohmann::json path;
    {
      const std::lock_guard lock(mutex_);
      path = foxglove::poses_in_frame(tracks_[k].path_poses, t, config_.frame_id);
    }
    send(track.path, t, path);
  }
}

void FoxgloveBridge::add_plan(const std::string& topic) {
  if (!have_plan_) {
    have_plan_ = true;
    for (const TeamMember& m : team())
      tour_channels_.push_back(add_channel("/" + m.ns + "/tour", Schema::kPosesInFrame));
  }
  create_subscription<msg::TeamPlan>(topic, {.depth = 2}, [this](Sample<msg::TeamPlan>&& s) {
    for (const msg::PathSequence& seq : s->sequences)
      for (size_t i = 0; i < team().size(); ++i)
        if (team()[i].id == seq.robot_id && wanted(tour_channels_[i]))
          send(tour_channels_[i], s->header.stamp_ns,
               foxglove::tour_json(seq, s->header.stamp_ns, config_.frame_id));
  });
}

void FoxgloveBridge::add_clusters(const std::string& topic) {
  const uint32_t scene = add_channel(topic, Schema::kSceneUpdate);
  const uint32_t views =
      add_channel(renamed(topic, "clusters", "viewpoints"), Schema::kPosesInFrame);
  create_subscription<msg::ViewpointClusters>(
      topic, {.depth = 1}, [this, scene, views](Sample<msg::ViewpointClusters>&& s) {
        if (wanted(scene))
          send(scene, s->header.stamp_ns, foxglove::clusters_json(*s, config_.frame_id));
        if (wanted(views))
          send(views, s->header.stamp_ns, foxglove::viewpoints_json(*s, config_.frame_id));
      });
}

void FoxgloveBridge::add_ises(const std::string& topic) {
  const uint32_t ch = add_channel(topic, Schema::kSceneUpdate);
  create_subscription<msg::IseSet>(topic, {.depth = 1}, [this, ch](Sample<msg::IseSet>&& s) {
    if (!wanted(ch)) return;
    double voxel_m = 0;
    {
      const std::lock_guard lock(mutex_);
      voxel_m = voxel_m_;
    }
    send(ch, s->header.stamp_ns, foxglove::ises_json(*s, voxel_m, config_.frame_id));
  });
}

void FoxgloveBridge::add_depth(const std::string& topic) {
  const uint32_t ch = add_channel(topic, Schema::kRawImage);
  const size_t throttle = image_throttles_.size();
  image_throttles_.emplace_back();
  create_subscription<msg::DepthImage>(
      topic, {.depth = 1},
      [this, ch, throttle, frame = frame_of(topic, "camera")](Sample<msg::DepthImage>&& s) {
        on_depth(ch, throttle, frame, *s);
      });
}

void FoxgloveBridge::on_depth(uint32_t channel, size_t throttle, const std::string& frame,
                              const msg::DepthImage& depth) {
  const int64_t t = depth.header.stamp_ns;
  if (wanted(tf_channel_)) {
    const foxglove::FrameTransform tf{.stamp_ns = t,
                                      .parent_frame_id = config_.frame_id,
                                      .child_frame_id = frame,
                                      .T_parent_child = depth.T_world_cam};
    send(tf_channel_, t, foxglove::frame_transforms_json({&tf, 1}));
  }
  if (!wanted(channel)) return;
  {
    const std::lock_guard lock(mutex_);
    if (!image_throttles_[throttle].due(t, config_.image_rate_hz)) return;
  }
  send(channel, t, foxglove::depth_image_json(depth, frame));
}

void FoxgloveBridge::add_stereo(const std::string& topic) {
  const uint32_t ch = add_channel(topic + "/left", Schema::kRawImage);
  const size_t throttle = image_throttles_.size();
  image_throttles_.emplace_back();
  create_subscription<msg::StereoFrame>(
      topic, {.depth = 1},
      [this, ch, throttle, frame = frame_of(topic, "camera")](Sample<msg::StereoFrame>&& s) {
        if (!wanted(ch)) return;
        {
          const std::lock_guard lock(mutex_);
          if (!image_throttles_[throttle].due(s->header.stamp_ns, config_.image_rate_hz)) return;
        }
        send(ch, s->header.stamp_ns,
             foxglove::mono8_image_json(s->intrinsics.width, s->intrinsics.height, s->left,
                                        s->header.stamp_ns, frame));
      });
}

void FoxgloveBridge::add_map(const std::string& topic) {
  const size_t k = meshes_.size();
  meshes_.push_back({.channel = add_channel(renamed(topic, "map", "mesh"), Schema::kSceneUpdate),
                     .mesher = std::make_unique<tsdf::Mesher>()});
  create_subscription<msg::MapUpdate>(topic, {.depth = 1},
                                      [this, k](Sample<msg::MapUpdate>&& s) { on_map(k, *s); });
}

void FoxgloveBridge::on_map(size_t k, const msg::MapUpdate& update) {
  if (!update.map) return;
  const std::lock_guard lock(mutex_);
  voxel_m_ = update.map->voxel_m();
  MeshJob& job = meshes_[k];
  if (!wanted(job.channel) || !job.throttle.due(update.header.stamp_ns, config_.mesh_rate_hz))
    return;
  job.pending = update.map;  // replaces one not meshed yet: the queue is one deep
  job.stamp_ns = update.header.stamp_ns;
  mesh_wake_.notify_one();
}

// The mesh thread: meshes the latest pending snapshot of each map (incrementally: the mesher
// keeps the blocks of the last one), sends it.
void FoxgloveBridge::mesh_loop() {
  std::unique_lock lock(mutex_);
  while (true) {
    mesh_wake_.wait(lock, [this] {
      if (stopping_) return true;
      for (const MeshJob& j : meshes_)
        if (j.pending) return true;
      return false;
    });
    if (stopping_) return;
    for (MeshJob& job : meshes_) {
      if (!job.pending) continue;
      const auto snapshot = std::move(job.pending);
      job.pending.reset();
      const int64_t stamp = job.stamp_ns;
      lock.unlock();
      job.mesher->update(*snapshot);  // the mesher is this thread's alone
      const auto message = foxglove::mesh_json(job.mesher->assemble(tsdf::Weld::kAcrossBlocks),
                                               stamp, config_.frame_id);
      send(job.channel, stamp, message);
      lock.lock();
    }
  }
}

uint16_t FoxgloveBridge::port() const {
  return server_ ? server_->port() : 0;
}

foxglove::WsServerStats FoxgloveBridge::stats() const {
  return server_ ? server_->stats() : foxglove::WsServerStats{};
}

void FoxgloveBridge::on_deactivate() {
  const foxglove::WsServerStats s = stats();
  SCANCREW_LOG_INFO("%s: %llu client(s); %llu messages sent (%.1f MB), %llu dropped (slow clients)",
                    qualified_name().c_str(), static_cast<unsigned long long>(s.clients_accepted),
                    static_cast<unsigned long long>(s.messages_sent),
                    static_cast<double>(s.bytes_sent) * 1e-6,
                    static_cast<unsigned long long>(s.messages_dropped));
  stop_all();
}

void FoxgloveBridge::on_shutdown() {
  stop_all();
}

void FoxgloveBridge::stop_all() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  mesh_wake_.notify_all();
  if (mesh_thread_.joinable()) mesh_thread_.join();
  if (server_) server_->stop();
}

SCANCREW_REGISTER_COMPONENT(FoxgloveBridge, "foxglove_bridge")

}  // namespace scancrew::foxglove_bridge
