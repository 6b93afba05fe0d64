// DdsBridge::read_config: the bridge's parameters (docs/dds_bridge.md lists them).

#include <algorithm>
#include <cmath>
#include <string_view>

#include "components/dds_bridge/dds_bridge.hpp"

namespace scancrew::dds_bridge {

namespace {

// The placeholders a name may hold once, as a whole segment (expanded at configure).
constexpr std::string_view kTeam = "{team}", kOthers = "{others}", kSelf = "{self}";

std::string without_placeholders(std::string name) {
  for (const std::string_view p : {kTeam, kOthers, kSelf})
    if (const auto at = name.find(p); at != std::string::npos)
      name.replace(at, p.size(), p.substr(1, p.size() - 2));
  return name;
}

bool valid_topic_name(const std::string& name) {
  if (name.empty() || name == "/" || name.back() == '/') return false;
  // a placeholder fills a whole segment: "/{team}/depth", "{others}/patch"
  for (const std::string_view p : {kTeam, kOthers, kSelf}) {
    const auto at = name.find(p);
    if (at == std::string::npos) continue;
    const size_t end = at + p.size();
    if ((at != 0 && name[at - 1] != '/') || (end != name.size() && name[end] != '/')) return false;
  }
  const std::string plain = without_placeholders(name);
  return std::all_of(plain.begin(), plain.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '/';
  });
}

// "robot_state" -> "robot_state", "/team/plan" -> "team_plan", "/{others}/patch" ->
// "others_patch"
std::string topic_key(const std::string& name) {
  std::string key = without_placeholders(name);
  if (key.front() == '/') key.erase(0, 1);
  std::replace(key.begin(), key.end(), '/', '_');
  return key;
}

void read_topics(ParamReader& p, const char* list_key, bool exported,
                 std::vector<BridgedTopic>& topics, std::string_view doc) {
  std::vector<std::string> names;
  p.optional_list(list_key, names).doc(doc);
  for (const std::string& name : names) {
    if (!valid_topic_name(name)) {
      p.report(list_key, "'" + name +
                             "' is not a topic name (letters, digits, '_' and '/'; {team}, "
                             "{others} or {self} as a whole segment)");
      continue;
    }
    const bool duplicate = std::any_of(topics.begin(), topics.end(), [&](const BridgedTopic& t) {
      return t.exported == exported && t.name == name;
    });
    if (duplicate) {
      p.report(list_key, "'" + name + "' is listed twice");
      continue;
    }
    topics.push_back({.name = name, .key = topic_key(name), .exported = exported});
  }
}

// A topic both exported and imported reads the same keys twice (and must: DDS QoS must
// match on both sides of a topic).
void read_topic_params(ParamReader& p, BridgedTopic& t) {
  p.optional("type_" + t.key, t.type_name)
      .doc("per topic (<key>: the name without a leading /, / replaced by _): its message type");
  p.choice("qos_" + t.key, t.qos.reliability, kReliabilityNames)
      .doc("per topic: reliable or best_effort");
  p.optional("depth_" + t.key, t.qos.depth, {1, 400})
      .doc("per topic: keep-last history (also the export's local queue)");
  p.optional("transient_local_" + t.key, t.qos.transient_local)
      .doc("per topic: a late joiner gets the last depth samples");
}

// A list of robot ids (whole numbers).
void read_robot_ids(ParamReader& p, const char* key, std::vector<uint32_t>& out,
                    std::string_view doc) {
  std::vector<double> ids;
  p.optional_list(key, ids, 0, {0, 4294967294.0}).doc(doc);
  for (const double id : ids) {
    if (id != std::floor(id)) p.report(key, "robot ids are whole numbers");
    out.push_back(static_cast<uint32_t>(id));
  }
}

// The link model's keys (docs/dds_bridge.md, "Link model"); the topics are read.
void read_link(ParamReader& p, DdsBridge::Config& c) {
  p.optional("link_latency_s", c.link.latency_s, {0, 60}).doc("link model: latency (s; 0: none)");
  p.optional("link_bandwidth_bps", c.link.bandwidth_bps, {0, 1e12})
      .doc(
          "link model: the receiver's incoming bandwidth, shared by all senders (bit/s; 0: "
          "unlimited)");
  p.optional("link_loss_rate", c.link.loss_rate, {0, 1})
      .doc("link model: share of samples lost (deterministic per seed)");
  p.optional("link_seed", c.link.seed).doc("link model: seed of the loss");
  p.optional("link_max_queue_s", c.link.max_queue_s, {0, 3600})
      .doc("link model: a sample that would wait longer is dropped as saturated (s)");
  std::vector<std::string> lossy;
  p.optional_list("link_loss_topics", lossy)
      .doc("imported topics (as listed) the loss applies to (empty: all)");
  for (const std::string& name : lossy)
    if (std::none_of(c.topics.begin(), c.topics.end(),
                     [&](const BridgedTopic& t) { return !t.exported && t.name == name; }))
      p.report("link_loss_topics", "'" + name + "' is not an imported topic");
  if (!lossy.empty())
    for (BridgedTopic& t : c.topics)
      t.lossy = std::find(lossy.begin(), lossy.end(), t.name) != lossy.end();
  std::vector<std::string> groups;
  p.optional_list("link_partition", groups)
      .doc(
          "link model: groups of robot ids, e.g. [\"1 2\", \"1 3\"]; a sample passes if sender and "
          "receiver share a group (empty: all)");
  for (const std::string& text : groups) {
    std::vector<uint32_t> group;
    if (std::string problem = parse_partition_group(text, group); !problem.empty())
      p.report("link_partition", problem);
    else
      c.link.partition.push_back(std::move(group));
  }
}

}  // namespace

DdsBridge::Config DdsBridge::read_config(ParamReader& p) {
  Config c;
  p.optional("domain_id", c.domain_id, {0, 232}).doc("DDS domain");
  p.optional_list("partitions", c.partitions)
      .doc("DDS partitions of every writer and reader (empty: the default partition)");
  p.choice("transport", c.transport, kTransportNames)
      .doc(
          "loopback (127.0.0.1 only), shm (shared memory + UDPv4 loopback), udp (every interface) "
          "or builtin (Fast DDS defaults)");
  p.optional_list("initial_peers", c.initial_peers).doc("IPv4 addresses for unicast discovery");
  p.optional("initial_peers_range", c.initial_peers_range, {1, 120})
      .doc("participants per peer host that unicast discovery reaches");
  p.optional("intraprocess", c.intraprocess)
      .doc("false turns Fast DDS's in-process shortcut off for the whole process");
  read_topics(p, "export_topics", true, c.topics,
              "topics to export (at least one topic in all); {self}, {others}, {team} as a whole "
              "segment expand over the launch's robots");
  read_topics(p, "import_topics", false, c.topics,
              "topics to import; an absolute import lands on its own name");
  if (c.topics.empty())
    p.report("export_topics", "nothing to bridge: list export_topics and/or import_topics");
  for (BridgedTopic& t : c.topics) read_topic_params(p, t);
  // an absolute name both exported and imported would loop back onto itself
  for (const BridgedTopic& e : c.topics)
    for (const BridgedTopic& i : c.topics)
      if (e.exported && !i.exported && e.name == i.name && e.name.front() == '/')
        p.report("import_topics", "'" + e.name +
                                      "' is exported too: an absolute import lands on its own "
                                      "name, where the export would send it back");
  p.optional("dds_prefix", c.dds_prefix).doc("DDS topic = prefix + name");
  p.optional("import_prefix", c.import_prefix).doc("local port of an import = prefix + name");
  if (c.import_prefix.empty() || c.import_prefix.front() == '/')
    p.report("import_prefix", "must be a non-empty relative name, e.g. 'remote/'");
  p.optional("lost_port", c.lost_port)
      .doc("where robot-loss reports go ({lost}: the lost robot's namespace)");

  read_robot_ids(p, "team_ids", c.team_ids,
                 "robot ids allowed to send (empty: the launch file's robots, 0 and the "
                 "simulator's id)");
  p.optional("max_sample_bytes", c.max_sample_bytes, {64, 4294967295.0})
      .doc("larger payloads are refused, both ways (bytes)");
  p.optional("inbox_samples", c.inbox_samples, {1, 1e7})
      .doc("DDS → executor queue; when full the oldest is dropped (counted)");
  p.optional("inbox_bytes", c.inbox_bytes, {1024, 1e12})
      .doc("and the queue's bytes: over it the oldest are dropped (counted)");
  p.optional("poll_period_s", c.poll_period_s, {1e-4, 1.0})
      .doc("how often the executor delivers imports (s)");
  p.optional("liveliness_lease_s", c.liveliness_lease_s, {0.1, 3600})
      .doc("a silent teammate is reported lost after this (s)");
  // 4294967295 is kUnknownSender (a participant that announced no id)
  p.optional("bridge_id", c.bridge_id, {-1, 4294967294.0})
      .doc("the id in this bridge's envelopes (-1: its robot's id, 0 for a station)");
  p.optional("simulator_id", c.simulator_id, {1, 4294967294.0})
      .doc(
          "the simulator process's bridge id (accepted in the default team; the lockstep's "
          "leader)");
  p.choice("lockstep", c.lockstep, kLockstepRoleNames)
      .doc("none, leader or follower: step with the other processes (docs/processes.md)");
  read_robot_ids(p, "lockstep_followers", c.lockstep_followers,
                 "the lockstep leader's followers (empty: the launch's robots)");
  p.optional("lockstep_timeout_s", c.lockstep_timeout_s, {0.1, 86400})
      .doc("the longest wall wait for a step (s)");

  read_link(p, c);
  return c;
}

}  // namespace scancrew::dds_bridge
