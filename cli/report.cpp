#include "cli/report.hpp"

#include <unistd.h>

#include <map>
#include <string>

namespace scancrew::cli {

void print_graph(std::FILE* out, Launch& launch) {
  const Graph& graph = launch.graph();
  std::fprintf(out, "components (%zu):\n", launch.components().size());
  for (const auto& c : launch.components())
    std::fprintf(out, "  %-28s robot %u, %zu executables, state %s\n", c->qualified_name().c_str(),
                 c->robot_id(), c->executables().size(),
                 std::string(to_string(c->state())).c_str());
  std::map<std::string, std::pair<std::string, std::string>> who;  // topic -> (pubs, subs)
  for (const EndpointInfo& e : graph.endpoints()) {
    auto& [pubs, subs] = who[e.topic];
    std::string& list = e.kind == EndpointInfo::Kind::kPublisher ? pubs : subs;
    list += (list.empty() ? "" : ", ") + e.component + "." + e.port;
  }
  const auto names = graph.topic_names();
  std::fprintf(out, "topics (%zu):\n", names.size());
  for (const std::string& name : names) {
    const auto topic = graph.find(name);
    const auto& [pubs, subs] = who[name];
    std::fprintf(out, "  %s [%s]\n    publishers:  %s\n    subscribers: %s\n", name.c_str(),
                 topic->type_name().c_str(), pubs.empty() ? "(none)" : pubs.c_str(),
                 subs.empty() ? "(none)" : subs.c_str());
  }
  const GraphReport report = graph.check();
  for (const auto& n : report.notes) std::fprintf(out, "note: %s\n", n.c_str());
  for (const auto& w : report.warnings) std::fprintf(out, "warning: %s\n", w.c_str());
  for (const auto& e : report.errors) std::fprintf(out, "error: %s\n", e.c_str());
  if (report.errors.empty() && report.warnings.empty()) std::fprintf(out, "graph check: ok\n");
}

namespace {

// A DOT quoted string: backslashes and quotes escaped, control characters dropped.
std::string dot_quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out + "\"";
}

// A two-line DOT label: first, then second.
std::string dot_label(const std::string& first, const std::string& second) {
  const std::string a = dot_quoted(first), b = dot_quoted(second);
  return a.substr(0, a.size() - 1) + "\\n" + b.substr(1);
}

}  // namespace

void print_graph_dot(std::FILE* out, Launch& launch, const std::string& title) {
  const Graph& graph = launch.graph();
  std::fprintf(out, "digraph %s {\n  rankdir=LR;\n  node [fontname=\"Helvetica\"];\n",
               dot_quoted(title).c_str());
  for (const auto& c : launch.components())
    std::fprintf(out, "  %s [shape=box, label=%s];\n",
                 dot_quoted("c:" + c->qualified_name()).c_str(),
                 dot_quoted(c->qualified_name()).c_str());
  std::map<std::string, std::pair<bool, bool>> ends;  // topic -> (published, read)
  for (const EndpointInfo& e : graph.endpoints())
    (e.kind == EndpointInfo::Kind::kPublisher ? ends[e.topic].first : ends[e.topic].second) = true;
  for (const std::string& name : graph.topic_names()) {
    const auto& [published, read] = ends[name];
    std::fprintf(out, "  %s [shape=ellipse, label=%s%s];\n", dot_quoted("t:" + name).c_str(),
                 dot_label(name, graph.find(name)->type_name()).c_str(),
                 published && read ? "" : ", style=dashed, color=red");
  }
  for (const EndpointInfo& e : graph.endpoints()) {
    const bool publishes = e.kind == EndpointInfo::Kind::kPublisher;
    const std::string component = dot_quoted("c:" + e.component),
                      topic = dot_quoted("t:" + e.topic);
    std::fprintf(out, "  %s -> %s;\n", (publishes ? component : topic).c_str(),
                 (publishes ? topic : component).c_str());
  }
  std::fprintf(out, "}\n");
}

void print_topic_stats(std::FILE* out, const Graph& graph, double run_s) {
  std::fprintf(
      out,
      "# rate_hz: messages per second of the launch's clock (%.1f s of it); latencies: wall time\n",
      run_s);
  std::fprintf(out, "%-32s %9s %9s %9s %7s %7s %9s %9s %9s\n", "topic", "published", "rate_hz",
               "taken", "dropped", "no_loan", "p50_us", "p99_us", "max_us");
  for (const TopicStats& s : graph.stats())
    std::fprintf(
        out, "%-32s %9llu %9.1f %9llu %7llu %7llu %9.1f %9.1f %9.1f\n", s.name.c_str(),
        static_cast<unsigned long long>(s.published),
        run_s > 0 ? static_cast<double>(s.published) / run_s : 0.0,
        static_cast<unsigned long long>(s.taken),
        static_cast<unsigned long long>(s.dropped) + static_cast<unsigned long long>(s.rejected),
        static_cast<unsigned long long>(s.loan_failures),
        static_cast<double>(s.latency_p50_ns) * 1e-3, static_cast<double>(s.latency_p99_ns) * 1e-3,
        static_cast<double>(s.latency_max_ns) * 1e-3);
}

void print_progress(std::FILE* out, const Graph& graph, double elapsed_s, double duration_s,
                    bool final) {
  static const bool tty = isatty(fileno(out)) != 0;
  uint64_t published = 0, dropped = 0, no_loan = 0;
  for (const TopicStats& s : graph.stats()) {
    published += s.published;
    dropped += s.dropped + s.rejected;
    no_loan += s.loan_failures;
  }
  char bar[21] = "";
  if (duration_s > 0) {
    const int filled = static_cast<int>(20 * std::min(1.0, elapsed_s / duration_s));
    for (int i = 0; i < 20; ++i) bar[i] = i < filled ? '#' : '.';
    bar[20] = '\0';
  }
  std::fprintf(out, "%s[%s] %7.1f / %.1f s  messages %llu  dropped %llu  loan failures %llu%s",
               tty ? "\r" : "", bar, elapsed_s, duration_s,
               static_cast<unsigned long long>(published), static_cast<unsigned long long>(dropped),
               static_cast<unsigned long long>(no_loan), tty && !final ? "" : "\n");
  std::fflush(out);
}

}  // namespace scancrew::cli
