#include "bench/dds/dds_bench.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <thread>

#include "bench/bench_stats.hpp"
#include "bench/dds/dds_pair.hpp"
#include "components/dds_bridge/dds_link.hpp"
#include "components/dds_bridge/team_keys.hpp"
#include "executors/clock.hpp"

namespace scancrew::bench {

namespace {

using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;

constexpr size_t kWarmupMessages = 20;
// a message not arrived after this is given up on; this many in a row end the case
constexpr double kArrivalWaitSeconds = 2.0;
constexpr int kGiveUpAfterMisses = 3;

// Ends the process (status 3) when an armed stage outlives its bound: the bench's own waits are
// bounded, Fast DDS's set-up and teardown are not (2.9 can deadlock deleting a writer while it
// unmatches a reader, seen once here), and a benchmark in CI must not hang.
class Watchdog {
 public:
  Watchdog() : thread_([this] { watch(); }) {}
  ~Watchdog() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    changed_.notify_all();
    thread_.join();
  }
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

  void arm(std::string stage, double seconds) {
    {
      std::lock_guard lock(mutex_);
      stage_ = std::move(stage);
      deadline_ = std::chrono::steady_clock::now() +
                  std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                      std::chrono::duration<double>(seconds));
      armed_ = true;
    }
    changed_.notify_all();
  }
  void disarm() {
    std::lock_guard lock(mutex_);
    armed_ = false;
  }

 private:
  void watch() {
    std::unique_lock lock(mutex_);
    while (!stop_) {
      if (!armed_) {
        changed_.wait(lock);
        continue;
      }
      const auto deadline = deadline_;
      if (changed_.wait_until(lock, deadline) == std::cv_status::timeout && armed_ && !stop_ &&
          deadline_ == deadline) {
        std::fprintf(stderr, "bench dds: %s did not end within its bound; exiting\n",
                     stage_.c_str());
        std::fflush(stderr);
        std::_Exit(3);
      }
    }
  }

  std::mutex mutex_;
  std::condition_variable changed_;
  std::string stage_;
  std::chrono::steady_clock::time_point deadline_;
  bool armed_ = false, stop_ = false;
  std::thread thread_;  // last: starts once the members above exist
};

// The kernel's count of UDP datagrams dropped for a full receive buffer (/proc/net/snmp,
// "Udp: ... RcvbufErrors"), for this network namespace; -1 when unreadable.
int64_t udp_rcvbuf_errors() {
  std::ifstream snmp("/proc/net/snmp");
  std::string names, values;
  while (std::getline(snmp, names))
    if (names.rfind("Udp: ", 0) == 0 && std::getline(snmp, values)) break;
  std::istringstream n(names), v(values);
  std::string name, value;
  while (n >> name && v >> value)
    if (name == "RcvbufErrors") return std::strtoll(value.c_str(), nullptr, 10);
  return -1;
}

int64_t drops_since(int64_t before) {
  const int64_t now = udp_rcvbuf_errors();
  return before < 0 || now < 0 ? -1 : now - before;
}

struct Plan {
  size_t samples = 0, burst = 0, bursts = 0, window = 0;
  std::vector<size_t> payloads;
};

Plan plan_of(const DdsBenchOptions& o) {
  Plan p;
  p.samples = static_cast<size_t>(o.samples > 0 ? o.samples : (o.quick ? 100 : 1000));
  p.burst = static_cast<size_t>(o.burst > 0 ? o.burst : (o.quick ? 100 : 500));
  p.bursts = static_cast<size_t>(o.bursts > 0 ? o.bursts : (o.quick ? 1 : 3));
  p.window = o.window > 0 ? std::min(o.window, o.depth) : o.depth;
  p.payloads = o.payload_bytes;
  if (p.payloads.empty())
    p.payloads = o.quick ? std::vector<size_t>{64, 64 << 10}
                         : std::vector<size_t>{64, 4 << 10, 64 << 10, 1 << 20};
  return p;
}

// A team's keys for the two places of every pair, in a fresh temporary folder.
Result<std::string, std::string> make_keys() {
  const fs::path dir =
      fs::temp_directory_path() / ("scancrew_bench_dds_keys_" + std::to_string(::getpid()));
  std::error_code ec;
  fs::remove_all(dir, ec);
  if (auto ok = dds_bridge::init_team_keys(dir.string(), "bench"); !ok)
    return make_unexpected(ok.error());
  for (const char* place : {"robot_1", "robot_2"}) {
    dds_bridge::PlaceGrant grant;
    grant.place = place;
    grant.publish = {kDdsBenchTopic, std::string(dds_bridge::kPresenceTopic)};
    grant.subscribe = grant.publish;
    if (auto ok = dds_bridge::add_place_keys(dir.string(), grant); !ok)
      return make_unexpected(ok.error());
  }
  return dir.string();
}

// Sends `n` messages one at a time, each a random 2–4 ms after the previous one arrived (or
// was given up on). Returns how many were sent.
size_t latency_phase(DdsPair& pair, Arrivals& arrivals, uint32_t phase, size_t payload, size_t n,
                     std::mt19937& rng) {
  std::uniform_int_distribution<int> gap_us(2000, 4000);
  arrivals.start_phase(phase, n);
  size_t sent = 0;
  int misses = 0;
  for (size_t i = 0; i < n; ++i) {
    if (i > 0 && !arrivals.wait_for(i, kArrivalWaitSeconds) && ++misses >= kGiveUpAfterMisses)
      break;
    std::this_thread::sleep_for(std::chrono::microseconds(gap_us(rng)));
    if (!pair.send(payload, phase, static_cast<uint32_t>(i))) break;
    ++sent;
  }
  arrivals.wait_for(sent, 2 * kArrivalWaitSeconds);
  return sent;
}

DdsLatencyResult measure_latency(DdsPair& pair, Arrivals& arrivals, uint32_t& phase, size_t payload,
                                 size_t samples, std::mt19937& rng) {
  (void)latency_phase(pair, arrivals, ++phase, payload, kWarmupMessages, rng);
  DdsLatencyResult r;
  r.payload_bytes = payload;
  r.messages = latency_phase(pair, arrivals, ++phase, payload, samples, rng);
  std::vector<int64_t> delays = arrivals.delays_ns();
  r.received = std::min(delays.size(), r.messages);
  r.messages = samples;  // what could not be sent counts as lost
  if (!delays.empty()) {
    std::sort(delays.begin(), delays.end());
    const auto at = [&](double q) {
      return static_cast<double>(
                 delays[static_cast<size_t>(q * static_cast<double>(delays.size() - 1))]) *
             1e-3;
    };
    r.p50_us = at(0.5);
    r.p99_us = at(0.99);
    r.max_us = static_cast<double>(delays.back()) * 1e-3;
  }
  return r;
}

struct Burst {
  size_t received = 0;
  double seconds = 0;  // first write to last arrival
};

// `burst` messages back to back, at most `window` unreceived.
Burst one_burst(DdsPair& pair, Arrivals& arrivals, uint32_t phase, size_t payload, size_t burst,
                size_t window) {
  arrivals.start_phase(phase, burst);
  const int64_t t0 = monotonic_now_ns();
  size_t sent = 0;
  for (size_t i = 0; i < burst; ++i) {
    if (i >= window && !arrivals.wait_for(i - window + 1, 5.0)) break;
    if (!pair.send(payload, phase, static_cast<uint32_t>(i))) break;
    ++sent;
  }
  arrivals.wait_for(sent, 10.0);
  Burst b;
  b.received = std::min(arrivals.count(), burst);
  if (b.received > 0) b.seconds = static_cast<double>(arrivals.last_arrival_ns() - t0) * 1e-9;
  return b;
}

// `bursts` bursts; the rate is the median burst's.
DdsThroughputResult measure_throughput(DdsPair& pair, Arrivals& arrivals, uint32_t& phase,
                                       size_t payload, size_t burst, size_t bursts, size_t window) {
  DdsThroughputResult r;
  r.payload_bytes = payload;
  r.messages = burst * bursts;
  r.bursts = bursts;
  std::vector<double> rates, seconds;
  for (size_t k = 0; k < bursts; ++k) {
    const Burst b = one_burst(pair, arrivals, ++phase, payload, burst, window);
    r.received += b.received;
    if (b.received == 0 || b.seconds <= 0) continue;
    rates.push_back(static_cast<double>(b.received) / b.seconds);
    seconds.push_back(b.seconds);
  }
  if (!rates.empty()) {
    r.messages_per_s = percentile(rates, 0.5);
    r.seconds = percentile(seconds, 0.5);
    r.mb_per_s = r.messages_per_s * static_cast<double>(payload) * 1e-6;
  }
  return r;
}

const char* on_off(bool secure) {
  return secure ? "on" : "off";
}

std::string payload_label(size_t bytes) {
  if (bytes >= (1 << 20) && bytes % (1 << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  if (bytes >= 1024 && bytes % 1024 == 0) return std::to_string(bytes >> 10) + " KiB";
  return std::to_string(bytes) + " B";
}

// The on / off ratios of one system: p50 latency at 64 KiB (or the largest payload below it),
// throughput.
struct SecurityCost {
  std::string system;
  size_t payload_bytes = 0;
  double p50_off_us = 0, p50_on_us = 0, mb_off = 0, mb_on = 0;
  double latency_ratio() const { return p50_off_us > 0 ? p50_on_us / p50_off_us : 0; }
  double throughput_ratio() const { return mb_off > 0 ? mb_on / mb_off : 0; }
};

std::vector<SecurityCost> security_costs(const std::vector<DdsLatencyResult>& latency,
                                         const std::vector<DdsThroughputResult>& throughput) {
  std::vector<SecurityCost> costs;
  for (const char* system : {"bridge", "fastdds"}) {
    SecurityCost c;
    c.system = system;
    for (const DdsLatencyResult& r : latency)
      if (r.system == system && r.payload_bytes <= (64 << 10))
        c.payload_bytes = std::max(c.payload_bytes, r.payload_bytes);
    for (const DdsLatencyResult& r : latency)
      if (r.system == system && r.payload_bytes == c.payload_bytes)
        (r.secure ? c.p50_on_us : c.p50_off_us) = r.p50_us;
    for (const DdsThroughputResult& r : throughput)
      if (r.system == system) (r.secure ? c.mb_on : c.mb_off) = r.mb_per_s;
    costs.push_back(c);
  }
  return costs;
}

void print_tables(const std::vector<DdsLatencyResult>& latency,
                  const std::vector<DdsThroughputResult>& throughput,
                  const std::vector<SecurityCost>& costs, size_t window, double load) {
  std::printf("latency, one way (one message in flight; UDPv4 on 127.0.0.1; load %.2f)\n", load);
  std::printf("%-8s %-8s %9s %8s %10s %10s %10s %6s %12s\n", "system", "security", "payload",
              "messages", "p50_us", "p99_us", "max_us", "lost", "rcvbuf_drops");
  for (const DdsLatencyResult& r : latency)
    std::printf("%-8s %-8s %9s %8zu %10.1f %10.1f %10.1f %6zu %12lld\n", r.system.c_str(),
                on_off(r.secure), payload_label(r.payload_bytes).c_str(), r.messages, r.p50_us,
                r.p99_us, r.max_us, r.lost(), static_cast<long long>(r.rcvbuf_drops));
  std::printf(
      "\nthroughput (bursts, at most %zu unreceived; first write to last arrival; the median "
      "burst)\n",
      window);
  std::printf("%-8s %-8s %9s %8s %9s %11s %9s %6s %12s\n", "system", "security", "payload",
              "messages", "seconds", "messages/s", "MB/s", "lost", "rcvbuf_drops");
  for (const DdsThroughputResult& r : throughput)
    std::printf("%-8s %-8s %9s %8zu %9.3f %11.0f %9.1f %6zu %12lld\n", r.system.c_str(),
                on_off(r.secure), payload_label(r.payload_bytes).c_str(), r.messages, r.seconds,
                r.messages_per_s, r.mb_per_s, r.lost(), static_cast<long long>(r.rcvbuf_drops));
  std::printf("\nsecurity cost (on / off):\n");
  for (const SecurityCost& c : costs)
    std::printf(
        "  %-8s p50 latency at %s x%.2f (%.0f -> %.0f us), throughput x%.2f (%.1f -> %.1f "
        "MB/s)\n",
        c.system.c_str(), payload_label(c.payload_bytes).c_str(), c.latency_ratio(), c.p50_off_us,
        c.p50_on_us, c.throughput_ratio(), c.mb_off, c.mb_on);
}

Json to_json(const std::vector<DdsLatencyResult>& latency,
             const std::vector<DdsThroughputResult>& throughput,
             const std::vector<SecurityCost>& costs, const DdsBenchOptions& options, double load) {
  Json out;
  out["transport"] = "udpv4_loopback";
  out["depth"] = options.depth;
  out["window"] = plan_of(options).window;
  out["bridge_poll_period_s"] = options.bridge_poll_period_s;
  out["load_average"] = load;
  out["latency"] = Json::array();
  for (const DdsLatencyResult& r : latency)
    out["latency"].push_back({{"system", r.system},
                              {"security", on_off(r.secure)},
                              {"payload_bytes", r.payload_bytes},
                              {"messages", r.messages},
                              {"received", r.received},
                              {"lost", r.lost()},
                              {"p50_us", r.p50_us},
                              {"p99_us", r.p99_us},
                              {"max_us", r.max_us},
                              {"udp_rcvbuf_drops", r.rcvbuf_drops}});
  out["throughput"] = Json::array();
  for (const DdsThroughputResult& r : throughput)
    out["throughput"].push_back({{"system", r.system},
                                 {"security", on_off(r.secure)},
                                 {"payload_bytes", r.payload_bytes},
                                 {"messages", r.messages},
                                 {"received", r.received},
                                 {"lost", r.lost()},
                                 {"seconds", r.seconds},
                                 {"messages_per_s", r.messages_per_s},
                                 {"mb_per_s", r.mb_per_s},
                                 {"bursts", r.bursts},
                                 {"udp_rcvbuf_drops", r.rcvbuf_drops}});
  out["security_cost"] = Json::array();
  for (const SecurityCost& c : costs)
    out["security_cost"].push_back({{"system", c.system},
                                    {"latency_payload_bytes", c.payload_bytes},
                                    {"latency_p50_ratio", c.latency_ratio()},
                                    {"throughput_ratio", c.throughput_ratio()}});
  return out;
}

// The pairs' common set-up: a domain and partition of this process's own, the options' depth
// and poll period (no keys yet).
PairSetup pair_setup(const DdsBenchOptions& options) {
  const uint32_t pid = static_cast<uint32_t>(::getpid());
  PairSetup setup;
  setup.domain_id = 10 + pid % 200;
  setup.partition = "scancrew_bench_dds_" + std::to_string(pid);
  setup.depth = options.depth;
  setup.bridge_poll_period_s = options.bridge_poll_period_s;
  return setup;
}

// Measures one pair's latency at every payload of the plan and appends the results, the UDP
// drops counted; progress on stderr unless --json.
void add_latencies(DdsPair& pair, Arrivals& arrivals, uint32_t& phase, const Plan& plan,
                   const DdsBenchOptions& options, const char* system, bool secure,
                   std::mt19937& rng, std::vector<DdsLatencyResult>& latency) {
  for (const size_t payload : plan.payloads) {
    const int64_t drops = udp_rcvbuf_errors();
    DdsLatencyResult r = measure_latency(pair, arrivals, phase, payload, plan.samples, rng);
    r.rcvbuf_drops = drops_since(drops);
    r.system = system;
    r.secure = secure;
    latency.push_back(r);
    if (!options.json)
      std::fprintf(stderr, "  %s security %s %s: p50 %.1f us, %zu lost\n", system, on_off(secure),
                   payload_label(payload).c_str(), r.p50_us, r.lost());
  }
}

// Measures one pair's throughput at the burst payload, the UDP drops counted.
DdsThroughputResult pair_throughput(DdsPair& pair, Arrivals& arrivals, uint32_t& phase,
                                    const Plan& plan, const DdsBenchOptions& options,
                                    const char* system, bool secure) {
  const int64_t drops = udp_rcvbuf_errors();
  DdsThroughputResult t = measure_throughput(pair, arrivals, phase, options.burst_payload_bytes,
                                             plan.burst, plan.bursts, plan.window);
  t.rcvbuf_drops = drops_since(drops);
  t.system = system;
  t.secure = secure;
  return t;
}

// The messages lost over every latency and throughput case.
size_t lost_messages(const std::vector<DdsLatencyResult>& latency,
                     const std::vector<DdsThroughputResult>& throughput) {
  size_t lost = 0;
  for (const DdsLatencyResult& r : latency) lost += r.lost();
  for (const DdsThroughputResult& r : throughput) lost += r.lost();
  return lost;
}

}  // namespace

int run_dds_bench(const DdsBenchOptions& options) {
  const Plan plan = plan_of(options);
  PairSetup setup = pair_setup(options);
  auto keys = make_keys();
  if (!keys) {
    std::fprintf(stderr, "bench dds: cannot make the team's keys: %s\n", keys.error().c_str());
    return 2;
  }
  std::fprintf(stderr,
               "bench dds: %zu latency messages per case, throughput %zu x %zu messages of %s, "
               "depth %u, bridge "
               "poll %.4g s, domain %u; keys in %s\n",
               plan.samples, plan.bursts, plan.burst,
               payload_label(options.burst_payload_bytes).c_str(), setup.depth,
               setup.bridge_poll_period_s, setup.domain_id, keys->c_str());

  std::vector<DdsLatencyResult> latency;
  std::vector<DdsThroughputResult> throughput;
  std::mt19937 rng(1);
  Arrivals arrivals;
  Watchdog watchdog;
  uint32_t phase = 0;
  int status = 0;
  for (const char* system : {"bridge", "fastdds"}) {
    for (const bool secure : {false, true}) {
      setup.keys_dir = secure ? *keys : std::string();
      const std::string name = std::string(system) + ", security " + on_off(secure);
      // discovery waits up to 30 s per launch and per match
      watchdog.arm("setting up " + name, 120);
      auto pair = std::string(system) == "bridge" ? make_bridge_pair(setup, arrivals)
                                                  : make_fastdds_pair(setup, arrivals);
      watchdog.disarm();
      if (!pair) {
        std::fprintf(stderr, "bench dds: %s, security %s: %s\n", system, on_off(secure),
                     pair.error().c_str());
        status = 2;
        continue;
      }
      add_latencies(**pair, arrivals, phase, plan, options, system, secure, rng, latency);
      const DdsThroughputResult t =
          pair_throughput(**pair, arrivals, phase, plan, options, system, secure);
      throughput.push_back(t);
      watchdog.arm("tearing down " + name, 60);
      pair->reset();
      watchdog.disarm();
      if (!options.json)
        std::fprintf(stderr, "  %s security %s throughput: %.1f MB/s, %zu lost\n", system,
                     on_off(secure), t.mb_per_s, t.lost());
    }
  }
  std::error_code ec;
  fs::remove_all(*keys, ec);

  const std::vector<SecurityCost> costs = security_costs(latency, throughput);
  const double load = load_average();
  if (options.json)
    std::printf("%s\n", to_json(latency, throughput, costs, options, load).dump().c_str());
  else
    print_tables(latency, throughput, costs, plan.window, load);
  const size_t lost = lost_messages(latency, throughput);
  if (lost > 0) {
    std::fprintf(stderr, "bench dds: %zu messages lost\n", lost);
    status = std::max(status, 1);
  }
  return status;
}

}  // namespace scancrew::bench
