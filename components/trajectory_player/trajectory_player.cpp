#include "components/trajectory_player/trajectory_player.hpp"

#include <algorithm>
#include <chrono>

#include "executors/registry.hpp"
#include "report/run_files.hpp"

namespace scancrew::trajectory_player {

TrajectoryPlayer::Config TrajectoryPlayer::read_config(ParamReader& p) {
  Config c;
  p.required("paths_csv", c.paths_csv)
      .doc("the run's paths.csv (t_s, robot_id, x_m, y_m, z_m, yaw_rad)");
  p.optional("lead_s", c.lead_s, {0, 1e4})
      .doc(
          "the target is the pose recorded this long after now (s; after the last sample, the last "
          "pose)");
  return c;
}

TrajectoryPlayer::TrajectoryPlayer(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

Result<void, std::string> TrajectoryPlayer::on_configure() {
  config_.paths_csv = input_path("paths_csv", config_.paths_csv);
  auto samples = report::read_paths_csv(config_.paths_csv);
  if (!samples) return make_unexpected(samples.error());
  for (const report::PathSample& s : *samples) {
    if (s.robot_id != robot_id()) continue;
    if (!times_s_.empty() && !(s.t_s > times_s_.back()))
      return make_unexpected(config_.paths_csv + ": robot " + std::to_string(robot_id()) +
                             "'s times do not increase at t = " + std::to_string(s.t_s) + " s");
    times_s_.push_back(s.t_s);
    waypoints_.push_back({.position = {s.x_m, s.y_m, s.z_m}, .yaw_rad = s.yaw_rad});
  }
  if (times_s_.empty())
    return make_unexpected(config_.paths_csv + " has no row for robot " +
                           std::to_string(robot_id()));
  path_ = create_publisher<msg::LocalPath>("local_path");
  create_timer(std::chrono::milliseconds(50), [this] { on_tick(); });
  return {};
}

void TrajectoryPlayer::on_tick() {
  const double due_s = static_cast<double>(clock().now_ns()) * 1e-9 + config_.lead_s;
  // the first sample at or after now + lead_s; the last one past the end
  const size_t k = std::min<size_t>(
      std::lower_bound(times_s_.begin(), times_s_.end(), due_s - 1e-9) - times_s_.begin(),
      times_s_.size() - 1);
  if (k == target_) return;
  auto loan = path_.loan();
  if (!loan) return;  // tried again at the next tick
  msg::LocalPath& out = **loan;
  out.header.stamp_ns = clock().now_ns();
  out.plan_id = k + 1;
  out.waypoints.assign(1, waypoints_[k]);
  if (path_.publish(std::move(*loan))) {
    target_ = k;
    ++sent_;
  }
}

SCANCREW_REGISTER_COMPONENT(TrajectoryPlayer, "trajectory_player")

}  // namespace scancrew::trajectory_player
