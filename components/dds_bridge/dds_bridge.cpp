#include "components/dds_bridge/dds_bridge.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "components/dds_bridge/team_keys.hpp"
#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/codec.hpp"

namespace scancrew::dds_bridge {

DdsBridge::DdsBridge(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

DdsBridge::~DdsBridge() {
  // no DDS callback may reach this object once its members start to go
  if (link_) link_->close();
}

Result<void, std::string> DdsBridge::on_configure() {
  self_id_ = config_.bridge_id >= 0 ? static_cast<uint32_t>(config_.bridge_id) : robot_id();
  rules_.format_version = msg::kMessageFormatVersion;
  rules_.max_sample_bytes = config_.max_sample_bytes;
  rules_.team = config_.team_ids;
  if (rules_.team.empty()) {
    rules_.team.push_back(0);  // a station
    rules_.team.push_back(config_.simulator_id);
    for (const TeamMember& m : team()) rules_.team.push_back(m.id);
  }
  if (config_.link.enabled()) link_model_.emplace(config_.link, self_id_);
  if (auto expanded = expand_templates(); !expanded) return expanded;
  // every topic's type before any DDS entity exists
  for (BridgedTopic& spec : config_.topics)
    if (auto typed = resolve_type(spec); !typed) return typed;

  auto dds = link_config();
  if (!dds) return make_unexpected(dds.error());
  auto link = DdsLink::create(*dds, link_callbacks());
  if (!link) return make_unexpected(qualified_name() + ": " + link.error());
  link_ = std::move(link).value();

  stats_.topics.reserve(config_.topics.size());
  topics_.reserve(config_.topics.size());
  for (const BridgedTopic& spec : config_.topics)
    if (auto added = add_topic(spec); !added) return added;
  data_readers_.store(topic_of_reader_.size());
  if (config_.lockstep != LockstepRole::kNone)
    if (auto sync = make_lockstep(); !sync) return sync;
  create_lost_publishers();
  create_timer(std::chrono::nanoseconds(std::llround(config_.poll_period_s * 1e9)),
               [this] { tick(); });
  return {};
}

// The DDS link's settings from the configuration, with DDS-Security when keys are given.
Result<DdsLinkConfig, std::string> DdsBridge::link_config() const {
  DdsLinkConfig dds;
  dds.domain_id = config_.domain_id;
  dds.partitions = config_.partitions;
  dds.transport = config_.transport;
  dds.initial_peers = config_.initial_peers;
  dds.initial_peers_range = config_.initial_peers_range;
  dds.intraprocess = config_.intraprocess;
  dds.liveliness_lease_s = config_.liveliness_lease_s;
  dds.participant_name = "scancrew" + qualified_name();
  dds.robot_id = self_id_;
  if (!security_keys().empty()) {
    // authenticated and encrypted as this bridge's place (docs/security.md)
    const std::string place = place_name(self_id_, config_.simulator_id);
    auto properties = security_properties(security_keys(), place);
    if (!properties) return make_unexpected(qualified_name() + ": " + properties.error());
    auto team_name = team_of_keys(security_keys());
    if (!team_name) return make_unexpected(qualified_name() + ": security: " + team_name.error());
    dds.security_properties = std::move(*properties);
    dds.security_team = *team_name;
    dds.simulator_id = config_.simulator_id;
    SCANCREW_LOG_INFO("%s: DDS-Security on: authenticated as %s of team %s, encrypted",
                      qualified_name().c_str(), place.c_str(), team_name->c_str());
  }
  return dds;
}

// The DDS link's callbacks: samples, peers, restarted processes and warnings.
DdsLink::Callbacks DdsBridge::link_callbacks() {
  DdsLink::Callbacks callbacks;
  // DDS threads: queue and return
  callbacks.on_sample = [this](size_t reader, WireEnvelope&& envelope, size_t bytes) {
    queue_sample(reader, std::move(envelope), bytes);
  };
  callbacks.on_peer = [this](uint32_t id, bool alive, std::string_view why) {
    {
      const std::lock_guard lock(sync_mutex_);
      if (alive) {
        alive_.insert(id);
        lost_.erase(id);
      } else {
        lost_.insert(id);
      }
      sync_cv_.notify_all();
    }
    std::lock_guard lock(inbox_mutex_);
    peer_events_.push_back({id, alive, std::string(why)});
  };
  // a restarted robot's new process numbers its samples from 1 again: its lockstep state
  // starts again now, and the executor's next tick, before it takes any of the new process's
  // samples, starts its duplicate test again and drops what its old process wrote that no
  // step released
  callbacks.on_new_process = [this](uint32_t id) {
    {
      const std::lock_guard lock(sync_mutex_);
      std::erase_if(received_max_, [&](const auto& kv) { return kv.first.first == id; });
      std::erase_if(released_, [&](const auto& kv) { return kv.first.first == id; });
      syncs_.erase(id);
    }
    std::lock_guard lock(inbox_mutex_);
    restarts_.push_back(id);
  };
  callbacks.on_warning = [this](const std::string& message) { warn_once(message); };
  return callbacks;
}

// A DDS thread's sample: the lockstep's goes to on_sync, a topic's to the bounded inbox.
void DdsBridge::queue_sample(size_t reader, WireEnvelope&& envelope, size_t bytes) {
  if (reader >= data_readers_.load()) {  // the lockstep's reader, added after the topics'
    on_sync(std::move(envelope));
    return;
  }
  // checked before queueing: a sample over max_sample_bytes (its payload, or a type name
  // longer than any wire type's) is not kept, its envelope is, to be counted; the lockstep's
  // receive marks count a sample only from a participant that announced its robot, in the
  // team (received, whether or not it is then accepted: a restarted robot's new process,
  // refused until its old one leaves, does not send those samples again)
  const bool oversize =
      envelope.payload.size() > config_.max_sample_bytes || envelope.type_name.size() > 256;
  if (oversize) {
    envelope.payload = {};
    envelope.type_name.clear();
  }
  if (envelope.claimed_robot_id == envelope.robot_id && in_team(rules_, envelope.robot_id)) {
    const std::lock_guard lock(sync_mutex_);
    uint64_t& max = received_max_[{envelope.robot_id, reader}];
    max = std::max(max, envelope.seq);
    sync_cv_.notify_all();
  }
  Incoming in{reader, std::move(envelope), bytes, clock().now_ns(), oversize};
  const size_t kept = oversize ? 0 : bytes;
  std::lock_guard lock(inbox_mutex_);
  if (kept > config_.inbox_bytes) {  // larger than the whole inbox: dropped, counted
    ++inbox_drops_[in.topic];
    return;
  }
  // bounded in samples and in bytes (as received): the oldest go first
  while (!inbox_.empty() && (inbox_.size() >= config_.inbox_samples ||
                             inbox_wire_bytes_ + kept > config_.inbox_bytes)) {
    ++inbox_drops_[inbox_.front().topic];
    inbox_wire_bytes_ -= inbox_.front().oversize ? 0 : inbox_.front().wire_bytes;
    inbox_.pop_front();
  }
  inbox_wire_bytes_ += kept;
  inbox_.push_back(std::move(in));
  ++taken_;
}

// The robot-loss report publishers: one per robot for a "{lost}" port, else one.
void DdsBridge::create_lost_publishers() {
  // "{lost}" in lost_port: the report goes to the lost robot's own topic, e.g.
  // "/{lost}/robot_state"
  if (config_.lost_port.find("{lost}") != std::string::npos) {
    for (const TeamMember& m : team()) {
      std::string port = config_.lost_port;
      port.replace(port.find("{lost}"), 6, m.ns);
      lost_pubs_[m.id] =
          std::make_shared<Publisher<msg::RobotState>>(create_publisher<msg::RobotState>(port));
    }
  } else {
    lost_pub_ = create_publisher<msg::RobotState>(config_.lost_port);
  }
}

Result<std::vector<std::string>, std::string> expand_topic_name(const std::string& name,
                                                                const std::vector<TeamMember>& team,
                                                                uint32_t self_id) {
  std::string placeholder;
  for (const char* p : {"{team}", "{others}", "{self}"})
    if (name.find(p) != std::string::npos) placeholder = p;
  if (placeholder.empty()) return std::vector<std::string>{name};
  std::vector<std::string> out;
  for (const TeamMember& m : team) {
    if (m.ns.empty())
      return make_unexpected("topic '" + name + "': " + placeholder +
                             " needs the launch file's robots, each with a namespace");
    if ((placeholder == "{others}" && m.id == self_id) ||
        (placeholder == "{self}" && m.id != self_id))
      continue;
    std::string t = name;
    t.replace(t.find(placeholder), placeholder.size(), m.ns);
    out.push_back(std::move(t));
  }
  if (placeholder == "{self}" && out.empty())
    return make_unexpected("topic '" + name +
                           "': {self} names a per-robot bridge's own robot (per_robot: true)");
  return out;
}

std::string dds_topic_name(const std::string& prefix, const std::string& name) {
  return prefix + (name.front() == '/' ? name.substr(1) : name);
}

Result<void, std::string> DdsBridge::expand_templates() {
  std::vector<BridgedTopic> expanded;
  for (const BridgedTopic& spec : config_.topics) {
    auto names = expand_topic_name(spec.name, team(), robot_id());
    if (!names) return make_unexpected(qualified_name() + ": " + names.error());
    for (std::string& name : *names) {
      const bool duplicate = std::any_of(expanded.begin(), expanded.end(), [&](const auto& e) {
        return e.exported == spec.exported && e.name == name;
      });
      if (duplicate)
        return make_unexpected(qualified_name() + ": topic '" + name + "' is listed twice (" +
                               spec.name + ")");
      BridgedTopic t = spec;
      t.name = std::move(name);
      expanded.push_back(std::move(t));
    }
  }
  config_.topics = std::move(expanded);
  return {};
}

std::string DdsBridge::local_port(const BridgedTopic& spec) const {
  if (spec.exported || spec.name.front() == '/') return spec.name;
  return config_.import_prefix + spec.name;
}

Result<void, std::string> DdsBridge::resolve_type(BridgedTopic& spec) {
  // the parameter, else the local topic of the import port, else the local topic of the name
  const std::string port = local_port(spec);
  if (spec.type_name.empty())
    for (const std::string& candidate : {resolve(port), resolve(spec.name)})
      if (auto topic = graph().find(candidate)) {
        spec.type_name = topic->type_name();
        break;
      }
  if (spec.type_name.empty())
    return make_unexpected(qualified_name() + ": topic '" + spec.name +
                           "': its type is unknown: list the bridge after the component that "
                           "uses it, or set type_" +
                           spec.key + " (e.g. scancrew/RobotState)");
  if (!msg::with_wire_message(spec.type_name, []<class T>() {}))
    return make_unexpected(qualified_name() + ": topic '" + spec.name + "': type '" +
                           spec.type_name + "' is not a wire message");
  return {};
}

Result<void, std::string> DdsBridge::add_topic(const BridgedTopic& spec) {
  TopicState state;
  state.spec = spec;
  // lockstep: a reader that matches after the first samples were written still gets them
  // (its `depth` last), so that every process sees the same samples from the first step
  if (config_.lockstep != LockstepRole::kNone && spec.qos.reliability == Reliability::kReliable)
    state.spec.qos.transient_local = true;
  const std::string dds_topic = dds_topic_name(config_.dds_prefix, spec.name);
  state.topic_key = LinkModel::topic_key(dds_topic);
  const std::string port = local_port(spec);
  auto endpoint = spec.exported ? link_->add_writer(dds_topic, state.spec.qos)
                                : link_->add_reader(dds_topic, state.spec.qos);
  if (!endpoint) return make_unexpected(qualified_name() + ": " + endpoint.error());
  state.endpoint = *endpoint;
  if (!spec.exported) {
    if (state.endpoint != topic_of_reader_.size())
      return make_unexpected(qualified_name() + ": DDS reader indices out of order");
    topic_of_reader_.push_back(topics_.size());
  }

  TopicCounters counters;
  counters.name = spec.name;
  counters.local = resolve(port);
  counters.dds_topic = dds_topic;
  counters.type_name = state.spec.type_name;
  counters.exported = spec.exported;
  {
    std::lock_guard lock(stats_mutex_);
    stats_.topics.push_back(std::move(counters));
  }
  topics_.push_back(std::move(state));
  const size_t index = topics_.size() - 1;
  msg::with_wire_message(topics_[index].spec.type_name, [&]<class T>() {
    if (spec.exported)
      add_export<T>(index);
    else
      add_import<T>(index);
  });
  return {};
}

template <class T>
void DdsBridge::add_export(size_t index) {
  const SubscriptionQos qos{.depth = topics_[index].spec.qos.depth};
  create_subscription<T>(topics_[index].spec.name, qos, [this, index](Sample<T>&& sample) {
    std::vector<uint8_t>& bytes = topics_[index].scratch;
    bytes.clear();
    msg::encode(*sample, bytes);
    send(index, bytes);
  });
}

template <class T>
void DdsBridge::add_import(size_t index) {
  auto pub = std::make_shared<Publisher<T>>(create_publisher<T>(local_port(topics_[index].spec)));
  topics_[index].deliver = [this, pub](const WireEnvelope& envelope, Reject* reason) {
    if (!pub->valid()) return Delivery::kRejected;
    auto loan = pub->loan();
    if (!loan) return Delivery::kPoolExhausted;
    if (auto decoded = msg::decode(envelope.payload, **loan); !decoded) {
      *reason = Reject::kMalformed;
      return Delivery::kRejected;
    }
    if (!in_team(rules_, (*loan)->header.robot_id)) {
      *reason = Reject::kUnknownRobot;
      return Delivery::kRejected;
    }
    (void)pub->forward(std::move(*loan));
    return Delivery::kPublished;
  };
}

void DdsBridge::on_activate() {
  if (auto announced = link_->announce(); !announced)
    warn_once(announced.error() + ": teammates will not see this robot's loss");
  active_now_.store(true);
}

void DdsBridge::on_deactivate() {
  active_now_.store(false);
  const BridgeStats s = stats();
  for (const TopicCounters& t : s.topics) {
    if (t.exported) {
      SCANCREW_LOG_INFO(
          "%s: %s -> %s: sent %llu samples, %llu bytes%s", qualified_name().c_str(),
          t.local.c_str(), t.dds_topic.c_str(), static_cast<unsigned long long>(t.sent_samples),
          static_cast<unsigned long long>(t.sent_bytes), t.send_failures ? " (SEND FAILURES)" : "");
    } else {
      SCANCREW_LOG_INFO(
          "%s: %s -> %s: received %llu samples, %llu bytes; delivered %llu; link drops %llu "
          "(partition %llu, loss %llu, saturated %llu); inbox drops %llu; rejected %llu; "
          "duplicates %llu",
          qualified_name().c_str(), t.dds_topic.c_str(), t.local.c_str(),
          static_cast<unsigned long long>(t.received_samples),
          static_cast<unsigned long long>(t.received_bytes),
          static_cast<unsigned long long>(t.delivered),
          static_cast<unsigned long long>(t.link_dropped()),
          static_cast<unsigned long long>(t.dropped_partition),
          static_cast<unsigned long long>(t.dropped_loss),
          static_cast<unsigned long long>(t.dropped_saturated),
          static_cast<unsigned long long>(t.dropped_inbox),
          static_cast<unsigned long long>(t.rejected_total()),
          static_cast<unsigned long long>(t.duplicates));
    }
  }
}

void DdsBridge::on_shutdown() {
  if (link_) link_->close();
}

BridgeStats DdsBridge::stats() const {
  BridgeStats s;
  {
    std::lock_guard lock(stats_mutex_);
    s = stats_;
  }
  std::lock_guard lock(inbox_mutex_);
  s.taken = taken_;
  s.inbox = inbox_.size();
  for (const auto& [reader, drops] : inbox_drops_)
    if (reader < topic_of_reader_.size() && topic_of_reader_[reader] < s.topics.size())
      s.topics[topic_of_reader_[reader]].dropped_inbox = drops;
  return s;
}

size_t DdsBridge::matched(std::string_view name, bool exported) const {
  for (const TopicState& t : topics_)
    if (t.spec.name == name && t.spec.exported == exported)
      return exported ? link_->writer_matches(t.endpoint) : link_->reader_matches(t.endpoint);
  return 0;
}

size_t DdsBridge::peers_alive() const {
  return link_ ? link_->peers_alive() : 0;
}

SCANCREW_REGISTER_COMPONENT(DdsBridge, "dds_bridge")

}  // namespace scancrew::dds_bridge
