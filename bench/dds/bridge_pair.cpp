// The bridge side of `scancrew bench dds` (dds_bench.hpp): two launches in this process, each
// on its own thread and wall clock, as two robot processes would be:
//   robot 1: bench_dds_source (publishes msg::TsdfPatch on /r1/patch) -> dds_bridge
//            exporting `patch`;
//   robot 2: bench_dds_sink (takes /r2/remote/patch) <- dds_bridge importing `patch`.
// The bridges run with `transport: loopback, intraprocess: false` (UDPv4 on 127.0.0.1, Fast
// DDS's in-process shortcut off for the process), a domain and partition of the bench's, the
// bench's depth on `patch`, the bench's import poll period (the bridge's default, 2 ms, unless
// asked otherwise), and every other parameter at its default.
// With keys, each launch holds `security: {keys: DIR}` and runs as its place.

#include <atomic>
#include <chrono>
#include <functional>
#include <thread>

#include "bench/dds/dds_pair.hpp"
#include "components/dds_bridge/dds_bridge.hpp"
#include "executors/clock.hpp"
#include "executors/component.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"
#include "interfaces/map_msgs.hpp"

namespace scancrew::bench {

namespace {

using dds_bridge::DdsBridge;

// Publishes bench patches on `patch` when the bench asks (from the bench's thread:
// publishers are thread safe). No thesis equations: measurement only.
class DdsBenchSource final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "bench dds: publishes stamped patches on the bench's demand";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  DdsBenchSource(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

  bool active() const { return active_.load(); }
  // Waits up to 5 s for a free slot of the topic's pool (the bridge holds the samples it has
  // not exported yet).
  bool send(size_t payload_bytes, uint32_t phase, uint32_t index) {
    const int64_t deadline = monotonic_now_ns() + 5'000'000'000;
    while (monotonic_now_ns() < deadline) {
      auto loan = patch_.loan();
      if (!loan) {
        std::this_thread::sleep_for(std::chrono::microseconds(50));
        continue;
      }
      msg::TsdfPatch& m = **loan;
      m.robot_id = robot_id();
      m.index = index;
      m.patch_id = (uint64_t{robot_id()} << 32) | index;
      m.voxel_size_m = 0.05;
      m.data.resize(payload_bytes);
      stamp_payload(m.data, phase, index);
      return patch_.publish(std::move(*loan)).has_value();
    }
    return false;
  }

 private:
  Result<void, std::string> on_configure() override {
    patch_ = create_publisher<msg::TsdfPatch>("patch");
    return {};
  }
  void on_activate() override { active_.store(true); }
  void on_deactivate() override { active_.store(false); }

  Publisher<msg::TsdfPatch> patch_;
  std::atomic<bool> active_{false};
};
SCANCREW_REGISTER_COMPONENT(DdsBenchSource, "bench_dds_source")

// Hands every imported patch's payload to the bench's Arrivals, on the executor's thread.
class DdsBenchSink final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "bench dds: times the patches the bridge imports";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  DdsBenchSink(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

  // Set before the launch runs; the Arrivals outlive it.
  void set_arrivals(Arrivals* arrivals) { arrivals_ = arrivals; }
  bool active() const { return active_.load(); }

 private:
  Result<void, std::string> on_configure() override {
    // deeper than the topic's pool (16): the queue never drops, the bridge waits for a slot
    create_subscription<msg::TsdfPatch>("remote/patch", {.depth = 64},
                                        [this](Sample<msg::TsdfPatch>&& s) {
                                          if (arrivals_ != nullptr) arrivals_->arrived(s->data);
                                        });
    return {};
  }
  void on_activate() override { active_.store(true); }
  void on_deactivate() override { active_.store(false); }

  Arrivals* arrivals_ = nullptr;
  std::atomic<bool> active_{false};
};
SCANCREW_REGISTER_COMPONENT(DdsBenchSink, "bench_dds_sink")

// One launch running on its own thread until destroyed.
class RunningLaunch {
 public:
  explicit RunningLaunch(std::unique_ptr<Launch> launch) : launch_(std::move(launch)) {}
  void start() {
    thread_ = std::thread([this] {
      launch_->run();
      done_.store(true);
    });
  }
  ~RunningLaunch() {
    if (!thread_.joinable()) return;
    while (!done_.load()) {  // run() clears a stop requested before it started
      launch_->request_stop();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    thread_.join();
  }
  RunningLaunch(const RunningLaunch&) = delete;
  RunningLaunch& operator=(const RunningLaunch&) = delete;
  Launch& launch() { return *launch_; }

 private:
  std::unique_ptr<Launch> launch_;
  std::thread thread_;
  std::atomic<bool> done_{false};
};

std::string launch_text(uint32_t robot, const PairSetup& s) {
  const bool sender = robot == 1;
  const std::string security = s.keys_dir.empty() ? "" : "security: {keys: " + s.keys_dir + "}\n";
  return "clock: wall\nexecutor: {type: single_threaded}\nrun: {duration_s: 0}\n" + security +
         "robots:\n  - {id: " + std::to_string(robot) + ", namespace: r" + std::to_string(robot) +
         "}\ncomponents:\n" +
         (sender ? "  - {type: bench_dds_source}\n" : "  - {type: bench_dds_sink}\n") +
         "  - type: dds_bridge\n    params: {domain_id: " + std::to_string(s.domain_id) +
         ", partitions: [" + s.partition +
         "], transport: loopback, intraprocess: false, team_ids: [1, 2], " +
         (sender ? "export_topics" : "import_topics") +
         ": [patch], type_patch: scancrew/TsdfPatch, depth_patch: " + std::to_string(s.depth) +
         ", poll_period_s: " + std::to_string(s.bridge_poll_period_s) + "}\n";
}

Result<std::unique_ptr<RunningLaunch>, std::string> compose(uint32_t robot, const PairSetup& s) {
  auto launch = Launch::from_string(launch_text(robot, s), "bench_dds_r" + std::to_string(robot));
  if (!launch) {
    std::string all;
    for (const std::string& e : launch.error()) all += e + "; ";
    return make_unexpected(all);
  }
  return std::make_unique<RunningLaunch>(std::move(launch).value());
}

bool wait_until(const std::function<bool()>& pred, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < deadline) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return pred();
}

class BridgePair final : public DdsPair {
 public:
  BridgePair(std::unique_ptr<RunningLaunch> sender, std::unique_ptr<RunningLaunch> receiver)
      : sender_(std::move(sender)), receiver_(std::move(receiver)) {}
  // the sender goes first, the receiver once its reader has unmatched the sender's writer
  // (bounded): Fast DDS 2.9 can deadlock deleting an endpoint while it unmatches a peer's
  ~BridgePair() override {
    sender_.reset();
    (void)wait_until([&] { return receiver_bridge().matched("patch", false) == 0; }, 5);
    receiver_.reset();
  }
  BridgePair(const BridgePair&) = delete;
  BridgePair& operator=(const BridgePair&) = delete;
  bool send(size_t payload_bytes, uint32_t phase, uint32_t index) override {
    return source().send(payload_bytes, phase, index);
  }

  DdsBenchSource& source() { return *sender_->launch().find_component<DdsBenchSource>(); }
  DdsBridge& sender_bridge() { return *sender_->launch().find_component<DdsBridge>(); }
  DdsBenchSink& sink() { return *receiver_->launch().find_component<DdsBenchSink>(); }
  DdsBridge& receiver_bridge() { return *receiver_->launch().find_component<DdsBridge>(); }

 private:
  std::unique_ptr<RunningLaunch> sender_, receiver_;
};

}  // namespace

Result<std::unique_ptr<DdsPair>, std::string> make_bridge_pair(const PairSetup& setup,
                                                               Arrivals& arrivals) {
  auto sender = compose(1, setup);
  if (!sender) return make_unexpected("robot 1's launch: " + sender.error());
  auto receiver = compose(2, setup);
  if (!receiver) return make_unexpected("robot 2's launch: " + receiver.error());
  (*receiver)->launch().find_component<DdsBenchSink>()->set_arrivals(&arrivals);
  (*sender)->start();
  (*receiver)->start();
  auto pair = std::make_unique<BridgePair>(std::move(*sender), std::move(*receiver));
  if (!wait_until([&] { return pair->source().active() && pair->sender_bridge().active(); }, 30) ||
      !wait_until([&] { return pair->sink().active() && pair->receiver_bridge().active(); }, 30))
    return make_unexpected("a launch did not start within 30 s (its log above says why)");
  // the writer matched the reader and the reader the writer: a volatile reader misses what
  // was written before
  if (!wait_until(
          [&] {
            return pair->sender_bridge().matched("patch", true) >= 1 &&
                   pair->receiver_bridge().matched("patch", false) >= 1;
          },
          30))
    return make_unexpected("the bridges' DDS writer and reader of 'patch' did not match in 30 s");
  return std::unique_ptr<DdsPair>(std::move(pair));
}

}  // namespace scancrew::bench
