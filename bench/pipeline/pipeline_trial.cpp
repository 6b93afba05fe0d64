// The pipeline bench's trials (pipeline_trial.hpp): the capture launch that renders the
// stereo pairs, and one trial of the graph fed with them on the wall clock, with the
// per-stage callback times and latencies from the Tracer and the probe.

#include "bench/pipeline/pipeline_trial.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string_view>
#include <thread>
#include <unordered_map>
#include <utility>

#include "bench/bench_stats.hpp"
#include "bench/common/parking_lot_loop.hpp"
#include "components/stereo_depth/stereo_depth.hpp"
#include "components/tsdf_mapper/tsdf_mapper.hpp"
#include "executors/launch.hpp"
#include "executors/publisher.hpp"

namespace scancrew::bench {

namespace {

constexpr const char* kNs = "r1";           // the robot of launch_cfg/bench/pipeline.yaml
constexpr double kSpeedMps = 0.5;           // thesis 5.3
constexpr double kDrainPollS = 0.3;         // the graph is drained when nothing moved this long
constexpr double kDrainTimeoutS = 30.0;     // after the last pair
constexpr double kActivateTimeoutS = 10.0;  // for the launch to activate its components

// "/r1/stereo" for "stereo"
std::string topic_of(std::string_view port) {
  std::string name("/");
  name += kNs;
  name += '/';
  name += port;
  return name;
}

// "r1/stereo_depth" (the Tracer's name) for the instance "stereo_depth"
std::string traced(std::string_view instance) {
  std::string name(kNs);
  name += '/';
  name += instance;
  return name;
}

double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

Figures figures(const std::vector<double>& v) {
  return {.n = v.size(), .p50 = percentile(v, 0.5), .p99 = percentile(v, 0.99), .max = max_of(v)};
}

std::string join_errors(const std::vector<std::string>& errors) {
  std::string all;
  for (const std::string& e : errors) all += (all.empty() ? "" : "; ") + e;
  return all;
}

const TopicStats* find_stats(const std::vector<TopicStats>& all, const std::string& name) {
  for (const TopicStats& s : all)
    if (s.name == name) return &s;
  return nullptr;
}

uint64_t callbacks_of(const Tracer& tracer, const std::string& component) {
  for (const ComponentTime& c : tracer.component_times())
    if (c.component == component) return c.callbacks;
  return 0;
}

// Waits until every pair the camera published has gone through stereo_depth and every
// depth image through the mapper: both queues empty and no callback of either for
// kDrainPollS. False on timeout.
bool wait_drained(Launch& launch, uint64_t published) {
  const Tracer& tracer = *launch.tracer();
  const std::string stereo = traced("stereo_depth"), mapper = traced("tsdf_mapper");
  const std::string stereo_topic = topic_of("stereo"), depth_topic = topic_of("depth");
  const auto deadline = Clock::now() + std::chrono::duration<double>(kDrainTimeoutS);
  uint64_t last = UINT64_MAX;
  while (Clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::duration<double>(kDrainPollS));
    const std::vector<TopicStats> all = launch.graph().stats();
    const TopicStats* s = find_stats(all, stereo_topic);
    const TopicStats* d = find_stats(all, depth_topic);
    const bool queues_empty =
        s != nullptr && s->taken + s->dropped >= published * s->subscriptions &&
        (d == nullptr || d->taken + d->dropped >= d->published * d->subscriptions);
    const uint64_t ran = callbacks_of(tracer, stereo) + callbacks_of(tracer, mapper);
    if (queues_empty && ran == last) return true;
    last = ran;
  }
  return false;
}

// The compute times of one component's callbacks on one input.
std::vector<double> callback_ms(const Tracer& tracer, const std::string& component,
                                const std::string& what) {
  std::vector<double> ms;
  for (const TraceEvent& e : tracer.events())
    if (tracer.source_component(e.source) == component && tracer.source_what(e.source) == what)
      ms.push_back(static_cast<double>(e.duration_ns) * 1e-6);
  return ms;
}

// The n longest callbacks of a component, whatever their input: stereo_depth matches a pair
// in the callback that completes it, the frame's or its pose's (whichever is taken last);
// the other one only queues a sample (µs, beside the ms of a match).
std::vector<double> longest_callbacks_ms(const Tracer& tracer, const std::string& component,
                                         size_t n) {
  std::vector<double> ms;
  for (const TraceEvent& e : tracer.events())
    if (tracer.source_component(e.source) == component)
      ms.push_back(static_cast<double>(e.duration_ns) * 1e-6);
  std::sort(ms.begin(), ms.end(), std::greater<>());
  ms.resize(std::min(ms.size(), n));
  return ms;
}

// Latencies of `out` from the message of the same stamp in `in` (publish to publish).
std::vector<double> latencies_ms(const std::vector<StampTime>& out,
                                 const std::unordered_map<int64_t, int64_t>& in) {
  std::vector<double> ms;
  ms.reserve(out.size());
  for (const StampTime& m : out)
    if (auto it = in.find(m.stamp_ns); it != in.end())
      ms.push_back(static_cast<double>(m.publish_mono_ns - it->second) * 1e-6);
  return ms;
}

std::unordered_map<int64_t, int64_t> by_stamp(const std::vector<StampTime>& v) {
  std::unordered_map<int64_t, int64_t> m;
  m.reserve(v.size());
  for (const StampTime& s : v) m.emplace(s.stamp_ns, s.publish_mono_ns);
  return m;
}

}  // namespace

Result<std::vector<FrameCapture::Pair>, std::string> capture(const PipelineBenchOptions& o,
                                                             const ImageSize& size,
                                                             uint32_t frames) {
  const double duration = frames / o.nominal_rate_hz + 10.0;
  char rest[512];
  std::snprintf(rest, sizeof rest, R"(      ground_camera_rate_hz: %.6f
  - type: waypoint_driver
    params: {waypoints_m: %s, loop: true, speed_mps: %.2f}
  - type: bench_frame_capture
    per_robot: false
    params: {robot_ns: %s, frames: %u}
)",
                o.nominal_rate_hz, kParkingLotLoop, kSpeedMps, kNs, frames);
  const std::string text =
      parking_lot_loop_launch(duration, kNs, o.scene_path, o.seed, size.width, size.height) + rest;
  auto made = Launch::from_string(text, "bench_pipeline_capture.yaml");
  if (!made) return make_unexpected(join_errors(made.error()));
  Launch& launch = **made;
  auto* cap = launch.find_component<FrameCapture>();
  if (cap == nullptr) return make_unexpected(std::string("the capture launch has no capture"));
  launch.set_stop_condition([cap, frames] { return cap->pairs_captured() >= frames; });
  launch.run();
  if (cap->pairs_captured() < frames)
    return make_unexpected("captured " + std::to_string(cap->pairs_captured()) + " of " +
                           std::to_string(frames) + " stereo pairs");
  return cap->take_pairs();
}

namespace {

// The trial's counts and each stage's callback and latency figures, from the trace, the
// graph's topic counters and what the probe received (fed: each pair's capture stamp).
void add_figures(Trial& t, const Tracer& tracer, Graph& graph, const PipelineProbe& probe,
                 const tsdf_mapper::TsdfMapper& mapper, const std::vector<StampTime>& fed) {
  t.integrated = mapper.stats().integrated;
  t.dropped = t.pairs - std::min(t.pairs, t.integrated);
  t.snapshots = probe.maps().size();
  t.ise_runs = probe.clusters().size();
  t.plans = probe.plans().size();
  for (const TopicStats& s : graph.stats()) {
    if (s.name == topic_of("stereo")) t.stereo_queue_drops = s.dropped;
    if (s.name == topic_of("depth")) t.depth_queue_drops = s.dropped;
  }

  const auto capture_at = by_stamp(fed);
  const auto depth_at = by_stamp(probe.depth());
  const auto map_at = by_stamp(probe.maps());
  const auto clusters_at = by_stamp(probe.clusters());
  const auto stage = [&](std::string name, const std::string& component, const std::string& input,
                         std::string per, const std::vector<StampTime>& out,
                         const std::unordered_map<int64_t, int64_t>& in) {
    return Stage{.name = std::move(name),
                 .component = component,
                 .input = input,
                 .per = std::move(per),
                 .callback_ms = figures(callback_ms(tracer, component, input)),
                 .from_input_ms = figures(latencies_ms(out, in)),
                 .from_capture_ms = figures(latencies_ms(out, capture_at))};
  };
  // the mapper integrates every depth image and publishes every snapshot_every-th: its
  // callback figures are per image, its latencies per snapshot
  t.stages.push_back(stage("stereo_depth", traced("stereo_depth"), topic_of("stereo"), "pair",
                           probe.depth(), capture_at));
  t.stages.back().callback_ms =
      figures(longest_callbacks_ms(tracer, traced("stereo_depth"), probe.depth().size()));
  t.stages.push_back(stage("tsdf_mapper", traced("tsdf_mapper"), topic_of("depth"), "snapshot",
                           probe.maps(), depth_at));
  t.stages.push_back(stage("ise_extractor", traced("ise_extractor"), topic_of("map"), "ISE run",
                           probe.clusters(), map_at));
  t.stages.push_back(stage("high_level_planner", "high_level_planner", topic_of("clusters"), "plan",
                           probe.plans(), clusters_at));
  t.end_to_end_ms = t.stages.back().from_capture_ms;
}

}  // namespace

Result<Trial, std::string> run_trial(const PipelineBenchOptions& o, const ImageSize& size,
                                     std::span<const FrameCapture::Pair> pairs, double rate_hz) {
  LaunchOptions lo;
  lo.overrides = {"executor.threads=" + std::to_string(o.threads),
                  "stereo_depth.num_disparities=" + std::to_string(size.num_disparities()),
                  "bench_pipeline_probe.capacity=" + std::to_string(pairs.size() + 16)};
  lo.overrides.insert(lo.overrides.end(), o.sets.begin(), o.sets.end());
  auto made = Launch::from_file(o.launch_path, lo);
  if (!made) return make_unexpected(join_errors(made.error()));
  Launch& launch = **made;
  if (launch.settings().clock != ClockType::kWall ||
      launch.settings().executor == LaunchSettings::ExecutorType::kStep)
    return make_unexpected(o.launch_path +
                           ": the bench runs the graph on the wall clock with a threaded "
                           "executor (clock: wall, executor: multi_threaded)");
  auto* probe = launch.find_component<PipelineProbe>();
  auto* mapper = launch.find_component<tsdf_mapper::TsdfMapper>();
  auto* stereo = launch.find_component<stereo_depth::StereoDepth>();
  if (probe == nullptr || mapper == nullptr || stereo == nullptr)
    return make_unexpected(o.launch_path +
                           ": needs a stereo_depth, a tsdf_mapper and a bench_pipeline_probe");
  launch.enable_tracing(64 * pairs.size() + 4096);

  Graph& graph = launch.graph();
  auto stereo_topic = graph.topic<msg::StereoFrame>(topic_of("stereo"), 4);
  auto pose_topic = graph.topic<msg::Odometry>(topic_of("pose_gt"), 8);
  if (!stereo_topic || !pose_topic)
    return make_unexpected(!stereo_topic ? stereo_topic.error() : pose_topic.error());
  // the camera driver's publishers (no component: they never wait for an executor thread)
  Publisher<msg::StereoFrame> camera(*stereo_topic, 1, &graph.clock(), nullptr);
  Publisher<msg::Odometry> pose(*pose_topic, 1, &graph.clock(), nullptr);

  Trial t;
  t.rate_hz = rate_hz;
  std::vector<StampTime> fed;  // capture stamp, publish time of each pair
  fed.reserve(pairs.size());
  std::string feed_error;
  std::thread feeder([&] {
    const auto activate_by = Clock::now() + std::chrono::duration<double>(kActivateTimeoutS);
    while (!probe->active() && Clock::now() < activate_by)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (!probe->active()) {
      feed_error = "the graph did not activate within " + std::to_string(kActivateTimeoutS) + " s";
      launch.request_stop();
      return;
    }
    const auto t0 = Clock::now();
    const auto period = std::chrono::duration<double>(1.0 / rate_hz);
    for (size_t k = 0; k < pairs.size(); ++k) {
      std::this_thread::sleep_until(
          t0 + std::chrono::duration_cast<Clock::duration>(period * static_cast<double>(k)));
      const int64_t stamp = graph.clock().now_ns();
      ++t.pairs;
      auto p = pose.loan();
      auto f = camera.loan();
      if (!p || !f) {
        ++t.camera_drops;
        continue;
      }
      **p = pairs[k].pose;
      (*p)->header.stamp_ns = stamp;
      **f = pairs[k].frame;
      (*f)->header.stamp_ns = stamp;
      (void)pose.publish(std::move(*p));
      fed.push_back({.stamp_ns = stamp, .publish_mono_ns = monotonic_now_ns()});
      (void)camera.publish(std::move(*f));
    }
    const double fed_s = seconds_between(t0, Clock::now());
    t.fed_rate_hz = t.pairs > 1 ? static_cast<double>(t.pairs - 1) / fed_s : 0;
    t.drained = wait_drained(launch, fed.size());
    launch.request_stop();
  });
  const auto start = Clock::now();
  launch.run();
  feeder.join();
  t.wall_s = seconds_between(start, Clock::now());
  if (!feed_error.empty()) return make_unexpected(feed_error);

  add_figures(t, *launch.tracer(), graph, *probe, *mapper, fed);
  return t;
}

}  // namespace scancrew::bench
