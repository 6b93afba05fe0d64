// DdsBridge's data path on the executor thread: an export's send, and each tick the
// imports admitted (duplicates, checks, the link model) and delivered when due, with the
// rejects, warnings and peer events (robots joined, back or lost) it reports.

#include <algorithm>

#include "components/dds_bridge/dds_bridge.hpp"
#include "executors/log.hpp"
#include "interfaces/codec.hpp"

namespace scancrew::dds_bridge {

void DdsBridge::send(size_t index, std::span<const uint8_t> bytes) {
  TopicState& t = topics_[index];
  if (bytes.size() > config_.max_sample_bytes) {
    {
      std::lock_guard lock(stats_mutex_);
      ++stats_.topics[index].send_failures;
    }
    warn_once(qualified_name() + ": " + t.spec.name + ": a " + std::to_string(bytes.size()) +
              "-byte message is over max_sample_bytes; not sent (further ones are counted)");
    return;
  }
  WireEnvelope envelope;
  envelope.format_version = msg::kMessageFormatVersion;
  envelope.robot_id = self_id_;
  envelope.seq = ++t.seq;
  envelope.stamp_ns = clock().now_ns();
  envelope.type_name = t.spec.type_name;
  envelope.payload = std::move(t.scratch);
  auto written = link_->write(t.endpoint, envelope);
  t.scratch = std::move(envelope.payload);
  std::lock_guard lock(stats_mutex_);
  TopicCounters& c = stats_.topics[index];
  if (!written) {
    ++c.send_failures;
    return;
  }
  ++c.sent_samples;
  c.sent_bytes += *written;
}

void DdsBridge::tick() {
  std::vector<PeerEvent> events;
  std::vector<uint32_t> restarts;
  {
    std::lock_guard lock(inbox_mutex_);
    restarts.swap(restarts_);
    drained_.insert(drained_.end(), std::make_move_iterator(inbox_.begin()),
                    std::make_move_iterator(inbox_.end()));
    inbox_.clear();
    inbox_wire_bytes_ = 0;
    events.swap(peer_events_);
  }
  // before the samples: a new process's follow its announcement
  for (const uint32_t id : restarts) restart_sender(id);
  if (!held_.empty()) {  // lockstep: samples held back until their step released them
    std::vector<Incoming> held;
    held.swap(held_);
    held.insert(held.end(), std::make_move_iterator(drained_.begin()),
                std::make_move_iterator(drained_.end()));
    drained_.swap(held);
  }
  for (Incoming& in : drained_) admit(std::move(in));
  drained_.clear();

  // deliver what is due, in delivery-time order
  const int64_t now = clock().now_ns();
  while (!pending_.empty() && pending_.top().deliver_at_ns <= now) {
    const Incoming& in = pending_.top().sample;
    Reject reason = Reject::kMalformed;
    const Delivery d = topics_[in.topic].deliver(in.envelope, &reason);
    if (d == Delivery::kPoolExhausted) break;  // the local readers are behind: next tick
    {
      std::lock_guard lock(stats_mutex_);
      TopicCounters& c = stats_.topics[in.topic];
      if (d == Delivery::kPublished)
        ++c.delivered;
      else
        reject(c, reason,
               "from robot " + std::to_string(in.envelope.robot_id) + " on " + c.dds_topic + ": " +
                   (reason == Reject::kMalformed ? "the payload does not decode as " + c.type_name
                                                 : "the message header names a robot not in the "
                                                   "team"));
    }
    pending_.pop();
  }
  for (const PeerEvent& e : events) handle_peer(e);
}

// Executor thread: robot `id` runs a new process (restarted), whose samples follow: its
// sequence numbers start again, and its old process's samples that no step released go.
void DdsBridge::restart_sender(uint32_t id) {
  std::erase_if(last_seq_, [&](const auto& kv) { return kv.first.first == id; });
  const size_t dropped =
      std::erase_if(held_, [&](const Incoming& in) { return in.envelope.robot_id == id; });
  SCANCREW_LOG_INFO("%s: robot %u runs a new process (restarted): its numbering starts again%s",
                    qualified_name().c_str(), id,
                    dropped == 0 ? ""
                                 : ("; " + std::to_string(dropped) +
                                    " samples of its old process that no step released dropped")
                                       .c_str());
}

void DdsBridge::admit(Incoming&& in) {
  if (held_back(in)) {
    held_.push_back(std::move(in));
    return;
  }
  const size_t topic = topic_of_reader_.at(in.topic);
  const TopicState& t = topics_[topic];
  std::lock_guard lock(stats_mutex_);
  TopicCounters& c = stats_.topics[topic];
  if (in.envelope.robot_id == self_id_) {
    ++c.own_ignored;
    return;
  }
  ++c.received_samples;
  c.received_bytes += in.wire_bytes;
  // DDS may hand a sample over again (a transient-local history resent when the writer
  // re-matches): a sequence number not above the sender's last one on this topic is dropped
  uint64_t& last = last_seq_[{in.envelope.robot_id, topic}];
  if (in.envelope.seq <= last) {
    ++c.duplicates;
    return;
  }
  std::string detail;
  if (in.oversize) {
    reject(c, Reject::kOversize,
           "on " + c.dds_topic + ": a payload over max_sample_bytes " +
               std::to_string(config_.max_sample_bytes) + " (not queued)");
    return;
  }
  if (auto reason = check_envelope(in.envelope, t.spec.type_name, rules_, &detail)) {
    reject(c, *reason, "on " + c.dds_topic + ": " + detail);
    return;
  }
  last = in.envelope.seq;
  int64_t deliver_at = in.arrival_ns;
  if (link_model_) {
    const auto d = link_model_->admit(in.envelope.robot_id, t.topic_key, in.envelope.seq,
                                      in.wire_bytes, in.arrival_ns, t.spec.lossy);
    switch (d.verdict) {
      case LinkVerdict::kPartitioned:
        ++c.dropped_partition;
        return;
      case LinkVerdict::kLost:
        ++c.dropped_loss;
        return;
      case LinkVerdict::kSaturated:
        ++c.dropped_saturated;
        return;
      case LinkVerdict::kDeliver:
        deliver_at = d.deliver_at_ns;
        break;
    }
  }
  in.topic = topic;
  pending_.push({deliver_at, pending_order_++, std::move(in)});
}

void DdsBridge::reject(TopicCounters& counters, Reject reason, const std::string& detail) {
  const auto kind = static_cast<size_t>(reason);
  ++counters.rejected[kind];
  if (reject_logged_[kind]) return;
  reject_logged_[kind] = true;
  SCANCREW_LOG_WARN("%s: rejected a sample (%s) %s; further %s samples are counted",
                    qualified_name().c_str(), std::string(to_string(reason)).c_str(),
                    detail.c_str(), std::string(to_string(reason)).c_str());
}

void DdsBridge::warn_once(const std::string& message) {
  std::lock_guard lock(stats_mutex_);
  if (std::find(warned_.begin(), warned_.end(), message) != warned_.end()) return;
  warned_.push_back(message);
  SCANCREW_LOG_WARN("%s: %s", qualified_name().c_str(), message.c_str());
}

void DdsBridge::handle_peer(const PeerEvent& event) {
  if (!in_team(rules_, event.robot_id)) return;
  if (event.alive) {
    // a restarted process numbers its samples from 1 again
    std::erase_if(last_seq_, [&](const auto& kv) { return kv.first.first == event.robot_id; });
    SCANCREW_LOG_INFO("%s: robot %u %s", qualified_name().c_str(), event.robot_id,
                      event.why.c_str());
    return;
  }
  SCANCREW_LOG_WARN("%s: robot %u lost (%s)", qualified_name().c_str(), event.robot_id,
                    event.why.c_str());
  {
    std::lock_guard lock(stats_mutex_);
    ++stats_.peers_lost;
  }
  Publisher<msg::RobotState>* pub = &lost_pub_;
  if (!lost_pubs_.empty()) {
    const auto it = lost_pubs_.find(event.robot_id);
    if (it == lost_pubs_.end()) return;  // the simulator or a station: no robot state
    pub = it->second.get();
  }
  auto loan = pub->loan();
  if (!loan) return;  // counted by the topic (loan failures)
  msg::RobotState& state = **loan;
  state = msg::RobotState{};
  state.header.robot_id = event.robot_id;
  state.header.seq = ++lost_seq_;
  state.header.stamp_ns = clock().now_ns();
  state.mode = msg::RobotState::Mode::kLost;
  (void)pub->forward(std::move(*loan));
}

}  // namespace scancrew::dds_bridge
