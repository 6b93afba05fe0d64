#include "executors/trace.hpp"

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <map>
#include <set>
#include <system_error>
#include <utility>

#include "executors/clock.hpp"

namespace scancrew {

struct Tracer::ComponentStats {
  explicit ComponentStats(std::string n) : name(std::move(n)) {}
  std::string name;
  std::atomic<int64_t> total_ns{0};
  LatencyHistogram durations;  // its count is the number of callbacks
};

namespace {

// A small number per thread, the same for every tracer (the trace's tid).
uint32_t thread_number() {
  static std::atomic<uint32_t> next{1};
  thread_local uint32_t number = 0;
  if (number == 0) number = next.fetch_add(1, std::memory_order_relaxed);
  return number;
}

// "r1/tsdf_mapper" -> "r1"; "simulator" -> "" (a component of the whole team).
std::string namespace_of(const std::string& component) {
  const size_t slash = component.rfind('/');
  return slash == std::string::npos ? std::string() : component.substr(0, slash);
}

// A JSON string literal, quotes included.
std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(c));
      out += escaped;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f != nullptr) std::fclose(f);
  }
};

}  // namespace

Tracer::Tracer(size_t max_events)
    : capacity_(max_events),
      origin_ns_(monotonic_now_ns()),
      events_(std::make_unique_for_overwrite<TraceEvent[]>(max_events)) {}

Tracer::~Tracer() = default;

uint32_t Tracer::component_index(const std::string& name) {
  for (size_t i = 0; i < components_.size(); ++i)
    if (components_[i]->name == name) return static_cast<uint32_t>(i);
  components_.push_back(std::make_unique<ComponentStats>(name));
  return static_cast<uint32_t>(components_.size() - 1);
}

void Tracer::attach(Executable& executable) {
  std::string component = executable.trace_component();
  if (component.empty()) {
    // built outside a Component: its callback group stands for it
    component = executable.group().name();
    if (!component.empty() && component.front() == '/') component.erase(0, 1);
  }
  const std::string& what = executable.trace_what();
  sources_.push_back({component_index(component), what.empty() ? "callback" : what});
  executable.set_trace_id(static_cast<uint32_t>(sources_.size() - 1));
}

bool Tracer::execute(Executable& executable) {
  const uint32_t source = executable.trace_id();
  if (!enabled() || source >= sources_.size()) return executable.execute();
  const int64_t start_ns = monotonic_now_ns();
  const bool ran = executable.execute();
  if (ran) record(source, start_ns, monotonic_now_ns());
  return ran;
}

void Tracer::record(uint32_t source, int64_t start_ns, int64_t end_ns) {
  const int64_t duration_ns = end_ns - start_ns;
  ComponentStats& stats = *components_[sources_[source].component];
  stats.total_ns.fetch_add(duration_ns, std::memory_order_relaxed);
  stats.durations.record(duration_ns);
  const size_t slot = next_.fetch_add(1, std::memory_order_relaxed);
  if (slot < capacity_)
    events_[slot] = {start_ns - origin_ns_, duration_ns, source, thread_number()};
  else
    dropped_.fetch_add(1, std::memory_order_relaxed);
}

size_t Tracer::event_count() const {
  return std::min(next_.load(std::memory_order_acquire), capacity_);
}

const std::string& Tracer::source_component(uint32_t source) const {
  return components_.at(sources_.at(source).component)->name;
}

const std::string& Tracer::source_what(uint32_t source) const {
  return sources_.at(source).what;
}

std::vector<ComponentTime> Tracer::component_times() const {
  std::vector<ComponentTime> times;
  times.reserve(components_.size());
  for (const auto& c : components_) {
    ComponentTime t;
    t.component = c->name;
    t.callbacks = c->durations.count();
    t.total_ms = static_cast<double>(c->total_ns.load(std::memory_order_relaxed)) * 1e-6;
    t.p50_ms = static_cast<double>(c->durations.percentile_ns(0.5)) * 1e-6;
    t.p99_ms = static_cast<double>(c->durations.percentile_ns(0.99)) * 1e-6;
    times.push_back(std::move(t));
  }
  std::sort(times.begin(), times.end(), [](const ComponentTime& a, const ComponentTime& b) {
    return a.total_ms != b.total_ms ? a.total_ms > b.total_ms : a.component < b.component;
  });
  return times;
}

Result<void, std::string> Tracer::write_chrome_trace(const std::string& path) const {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "w"));
  if (!file) {
    const int error = errno;
    return make_unexpected(path + ": cannot open for writing (" +
                           std::generic_category().message(error) + ")");
  }
  std::FILE* f = file.get();

  // processes: one per robot namespace, in the order the components were attached
  std::map<std::string, uint32_t> pid_of_namespace;
  std::vector<std::string> process_names;
  std::vector<uint32_t> pid_of_component;
  pid_of_component.reserve(components_.size());
  for (const auto& c : components_) {
    const std::string ns = namespace_of(c->name);
    auto [it, added] =
        pid_of_namespace.emplace(ns, static_cast<uint32_t>(process_names.size() + 1));
    if (added) process_names.push_back(ns.empty() ? "team" : ns);
    pid_of_component.push_back(it->second);
  }
  // the names of each source, escaped once
  struct Named {
    std::string name, cat;
    uint32_t pid;
  };
  std::vector<Named> named;
  named.reserve(sources_.size());
  for (const Source& s : sources_)
    named.push_back({json_string(components_[s.component]->name), json_string(s.what),
                     pid_of_component[s.component]});

  std::fputs("{\"traceEvents\":[", f);
  const char* separator = "\n";
  std::set<std::pair<uint32_t, uint32_t>> threads;  // (pid, tid)
  for (const TraceEvent& e : events()) {
    const Named& n = named[e.source];
    std::fprintf(f,
                 "%s{\"name\":%s,\"cat\":%s,\"ph\":\"X\",\"ts\":%.3f,\"dur\":%.3f,"
                 "\"pid\":%" PRIu32 ",\"tid\":%" PRIu32 "}",
                 separator, n.name.c_str(), n.cat.c_str(), static_cast<double>(e.start_ns) * 1e-3,
                 static_cast<double>(e.duration_ns) * 1e-3, n.pid, e.thread);
    separator = ",\n";
    threads.emplace(n.pid, e.thread);
  }
  for (size_t p = 0; p < process_names.size(); ++p) {
    std::fprintf(f,
                 "%s{\"name\":\"process_name\",\"ph\":\"M\",\"pid\":%zu,\"tid\":0,"
                 "\"args\":{\"name\":%s}}",
                 separator, p + 1, json_string(process_names[p]).c_str());
    separator = ",\n";
  }
  for (const auto& [pid, tid] : threads) {
    std::fprintf(f,
                 "%s{\"name\":\"thread_name\",\"ph\":\"M\",\"pid\":%" PRIu32 ",\"tid\":%" PRIu32
                 ",\"args\":{\"name\":\"executor thread %" PRIu32 "\"}}",
                 separator, pid, tid, tid);
    separator = ",\n";
  }
  std::fprintf(f,
               "\n],\"displayTimeUnit\":\"ms\",\"otherData\":{\"dropped_events\":%" PRIu64
               ",\"recorded_events\":%zu}}\n",
               dropped_events(), event_count());
  const bool write_failed = std::ferror(f) != 0;
  if (std::fclose(file.release()) != 0 || write_failed)
    return make_unexpected(path + ": write failed");
  return {};
}

}  // namespace scancrew
