#include "components/path_player/path_player.hpp"

#include <chrono>
#include <cmath>

#include "executors/registry.hpp"

namespace scancrew::path_player {

PathPlayer::Config PathPlayer::read_config(ParamReader& p) {
  Config c;
  std::vector<double> values;
  p.optional_list("waypoints", values, 0, {-1e6, 1e6})
      .doc("x, y, z (m), yaw (deg) quadruples, world frame, at least one");
  if (values.empty() || values.size() % 4 != 0)
    p.report("waypoints", "needs x, y, z (m), yaw (deg) quadruples, at least one");
  else
    for (size_t i = 0; i + 3 < values.size(); i += 4)
      c.waypoints.push_back(
          {{values[i], values[i + 1], values[i + 2]}, values[i + 3] * M_PI / 180.0});
  p.optional("plan_id", c.plan_id).doc("the plan id the path carries");
  p.optional("start_s", c.start_s, {0, 1e7})
      .doc("first sent at this time on the launch's clock (s)");
  p.optional("period_s", c.period_s, {0, 1e7})
      .doc("then sent again every period_s, unchanged (s; 0: sent once)");
  return c;
}

PathPlayer::PathPlayer(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

Result<void, std::string> PathPlayer::on_configure() {
  path_ = create_publisher<msg::LocalPath>("local_path");
  next_ns_ = std::llround(config_.start_s * 1e9);
  // a fine timer; sending is due at start_s, then every period_s
  create_timer(std::chrono::milliseconds(50), [this] { on_tick(); });
  return {};
}

void PathPlayer::on_tick() {
  const int64_t now = clock().now_ns();
  if (next_ns_ < 0 || now < next_ns_) return;
  next_ns_ = config_.period_s > 0 ? now + std::llround(config_.period_s * 1e9) : -1;
  auto loan = path_.loan();
  if (!loan) return;
  msg::LocalPath& out = **loan;
  out.header.stamp_ns = now;
  out.plan_id = config_.plan_id;
  out.waypoints = config_.waypoints;
  if (path_.publish(std::move(*loan))) ++sent_;
}

SCANCREW_REGISTER_COMPONENT(PathPlayer, "path_player")

}  // namespace scancrew::path_player
