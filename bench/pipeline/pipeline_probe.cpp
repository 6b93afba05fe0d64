#include "bench/pipeline/pipeline_probe.hpp"

#include <algorithm>
#include <utility>

#include "executors/registry.hpp"
#include "interfaces/map_msgs.hpp"
#include "interfaces/map_update.hpp"

namespace scancrew::bench {

FrameCapture::Config FrameCapture::read_config(ParamReader& p) {
  Config c;
  p.optional("robot_ns", c.robot_ns);
  p.optional("frames", c.frames, {1, 100000});
  return c;
}

FrameCapture::FrameCapture(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

Result<void, std::string> FrameCapture::on_configure() {
  const std::string ns = "/" + config_.robot_ns + "/";
  pairs_.reserve(config_.frames);
  create_subscription<msg::StereoFrame>(ns + "stereo", {.depth = 16},
                                        [this](Sample<msg::StereoFrame>&& f) {
                                          if (pairs_.size() >= config_.frames) return;
                                          frames_.push_back(*f);
                                          match();
                                        });
  create_subscription<msg::Odometry>(ns + "pose_gt", {.depth = 16},
                                     [this](Sample<msg::Odometry>&& p) {
                                       poses_.push_back(*p);
                                       match();
                                     });
  return {};
}

// Pairs each waiting frame with the pose of its stamp; poses older than every waiting
// frame are of no use and go.
void FrameCapture::match() {
  for (auto f = frames_.begin(); f != frames_.end() && pairs_.size() < config_.frames;) {
    const auto p = std::find_if(poses_.begin(), poses_.end(), [&](const msg::Odometry& o) {
      return o.header.stamp_ns == f->header.stamp_ns;
    });
    if (p == poses_.end()) {
      ++f;
      continue;
    }
    pairs_.push_back({.frame = std::move(*f), .pose = *p});
    f = frames_.erase(f);
  }
  int64_t oldest = INT64_MAX;
  for (const msg::StereoFrame& f : frames_) oldest = std::min(oldest, f.header.stamp_ns);
  std::erase_if(poses_, [&](const msg::Odometry& o) { return o.header.stamp_ns < oldest; });
  if (pairs_.size() >= config_.frames) frames_.clear();
}

PipelineProbe::Config PipelineProbe::read_config(ParamReader& p) {
  Config c;
  p.optional("robot_ns", c.robot_ns);
  p.optional("plan_topic", c.plan_topic);
  p.optional("capacity", c.capacity, {1, 10000000});
  return c;
}

PipelineProbe::PipelineProbe(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

Result<void, std::string> PipelineProbe::on_configure() {
  for (auto* v : {&depth_, &maps_, &clusters_, &plans_}) v->reserve(config_.capacity);
  const std::string ns = "/" + config_.robot_ns + "/";
  // deep queues: the probe must not lose what it times; its callbacks only copy 16 bytes
  const SubscriptionQos qos{.depth = 64};
  const auto keep = [](std::vector<StampTime>& into, const msg::Header& h) {
    into.push_back({.stamp_ns = h.stamp_ns, .publish_mono_ns = h.publish_mono_ns});
  };
  create_subscription<msg::DepthImage>(
      ns + "depth", qos, [this, keep](Sample<msg::DepthImage>&& s) { keep(depth_, s->header); });
  create_subscription<msg::MapUpdate>(
      ns + "map", qos, [this, keep](Sample<msg::MapUpdate>&& s) { keep(maps_, s->header); });
  create_subscription<msg::ViewpointClusters>(
      ns + "clusters", qos,
      [this, keep](Sample<msg::ViewpointClusters>&& s) { keep(clusters_, s->header); });
  create_subscription<msg::TeamPlan>(
      config_.plan_topic, qos,
      [this, keep](Sample<msg::TeamPlan>&& s) { keep(plans_, s->header); });
  return {};
}

SCANCREW_REGISTER_COMPONENT(FrameCapture, "bench_frame_capture")
SCANCREW_REGISTER_COMPONENT(PipelineProbe, "bench_pipeline_probe")

}  // namespace scancrew::bench
