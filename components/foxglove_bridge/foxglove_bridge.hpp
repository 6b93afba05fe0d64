#pragma once

// FoxgloveBridge: the live view (docs/visualization.md, "Live view in Foxglove"). Serves the
// process's topics to Foxglove (or any Foxglove WebSocket v1 client) as foxglove_bridge does
// for ROS 2: `scancrew run|sim|robot|station … --live [PORT]` appends it to the graph.
//
// At configure (it is listed after every publisher) it walks the graph's published topics and
// advertises, by message type (foxglove_json.hpp for the conversions):
//   Odometry T            → T (PoseInFrame); for a robot's pose (…/pose_gt, odom, wheel_odom,
//                           pose) T/path (PosesInFrame: a pose per path_period_s); for
//                           …/pose_gt a world → <ns>/base_link on /tf
//   LocalPath T           → T (PosesInFrame)
//   TeamPlan (any)        → /<ns>/tour for each robot (PosesInFrame: its viewpoints in order)
//   ViewpointClusters T   → T (SceneUpdate: spheres) and …/viewpoints (PosesInFrame)
//   IseSet T              → T (SceneUpdate: a cube per ISE, the map's voxel size)
//   MapUpdate …/map       → …/mesh (SceneUpdate: the marching-cubes mesh, ≤ mesh_rate_hz)
//   DepthImage T          → T (RawImage 32FC1, ≤ image_rate_hz) and world → <ns>/camera on /tf
//   StereoFrame T         → T/left (RawImage mono8, ≤ image_rate_hz)
// Rates are in sim time; timestamps are the messages' stamps (sim time).
//
// Cost: a callback converts nothing unless a client subscribes to its channel (an atomic
// load, WsServer::subscribed); only the poses kept for the paths are recorded regardless.
// The mesh is made on the bridge's own thread from the latest snapshot (snapshots are
// immutable), the network on the server's (ws_server.hpp: bounded per-client queues, drops
// counted, reported to the client in a status message and in the log).
// Thread safety: callbacks may run on any executor thread; state shared with the mesh thread
// is under mutex_.

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "components/foxglove_bridge/ws_server.hpp"
#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/map_msgs.hpp"
#include "interfaces/map_update.hpp"
#include "interfaces/nav_msgs.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::foxglove_bridge {

class FoxgloveBridge final : public Component {
 public:
  static constexpr bool kWorld = true;  // an instrument, never charged compute
  static constexpr std::string_view kDescription =
      "live view: serves the process's topics to Foxglove (WebSocket v1, JSON schemas)";
  struct Config {
    int port = 8765;                    // 0: any free port (logged)
    std::string address = "127.0.0.1";  // 0.0.0.0: every interface
    std::string frame_id = "world";
    double image_rate_hz = 2.0;  // per image channel, sim time
    double mesh_rate_hz = 1.0;   // per mesh channel, sim time
    double path_period_s = 1.0;  // a path pose per period (sim s)
    int max_queue_messages = 256;
    int max_queue_mb = 64;
  };
  static Config read_config(ParamReader& p);

  FoxgloveBridge(ComponentContext context, Config config);
  ~FoxgloveBridge() override;

  // The port listened on (after configure); the server's counters.
  uint16_t port() const;
  foxglove::WsServerStats stats() const;
  const std::vector<foxglove::Channel>& channels() const { return channels_; }

 private:
  struct Throttle {
    int64_t last_ns = INT64_MIN;
    bool due(int64_t now_ns, double rate_hz);
  };
  struct PoseTrack {
    uint32_t pose = 0, path = 0;
    std::vector<msg::Pose3> path_poses;
    int64_t last_path_ns = INT64_MIN;
    std::string base_frame;  // "" = no TF for it
  };
  struct MeshJob {
    uint32_t channel = 0;
    std::shared_ptr<const tsdf::MapSnapshot> pending;  // latest not yet meshed
    int64_t stamp_ns = 0;
    Throttle throttle;
    std::unique_ptr<tsdf::Mesher> mesher;
  };

  Result<void, std::string> on_configure() override;
  void on_deactivate() override;
  void on_shutdown() override;

  uint32_t add_channel(std::string topic, foxglove::Schema schema);
  bool wanted(uint32_t channel) const;
  void send(uint32_t channel, int64_t stamp_ns, const nlohmann::json& message);
  std::string frame_of(const std::string& topic, std::string_view child) const;
  std::string robot_ns(uint32_t robot_id) const;

  void add_topic(const std::string& name, std::string_view type);
  void add_pose(const std::string& topic);
  void add_clusters(const std::string& topic);
  void add_ises(const std::string& topic);
  void add_map(const std::string& topic);
  void add_depth(const std::string& topic);
  void add_stereo(const std::string& topic);
  void add_plan(const std::string& topic);
  void on_pose(size_t track, const msg::Odometry& odom);
  void on_map(size_t job, const msg::MapUpdate& update);
  void on_depth(uint32_t channel, size_t throttle, const std::string& frame,
                const msg::DepthImage& depth);
  void mesh_loop();
  void stop_all();

  Config config_;
  std::vector<foxglove::Channel> channels_;
  std::unique_ptr<foxglove::WsServer> server_;
  uint32_t tf_channel_ = 0;
  std::vector<uint32_t> tour_channels_;  // per team member
  bool have_plan_ = false;

  mutable std::mutex mutex_;
  std::vector<PoseTrack> tracks_;
  std::vector<Throttle> image_throttles_;
  std::vector<MeshJob> meshes_;
  double voxel_m_ = 0.1;  // the ISE cubes' size: the latest map's voxel
  std::condition_variable mesh_wake_;
  bool stopping_ = false;
  std::thread mesh_thread_;
};

}  // namespace scancrew::foxglove_bridge
