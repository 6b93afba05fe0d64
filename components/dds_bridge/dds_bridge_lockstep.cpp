// The lockstep of a team split over processes (docs/processes.md): the simulator's bridge
// leads, the robots' (and a station's) bridges follow, and their sim clocks advance together.
//
//   leader                                  follower k
//   run_until(t1); write {t1, marks}  ->    wait for t1 and the marked samples; release them
//                                            run_until(t1); write {t1, own marks}
//   wait for every follower's t1 and  <-
//   its marked samples; release them
//   run_until(t2); write {t2, marks} ...
//
// A mark is (sender, DDS topic, last sequence number written): the leader's marks are its
// own writers' and the followers' latest, so a follower sees, at the start of step t, exactly
// what every bridge wrote up to the step before: samples written later are held back
// (held_back) until a step releases them, and every sample admitted in a tick is stamped
// with that tick's sim time. Reliable topics only: a best-effort sample may never arrive.
// A peer reported lost (DDS liveliness) is waited for no more by the leader (a follower
// waits for a lost leader, which a healed partition brings back); a wait longer than
// lockstep_timeout_s (wall) ends the run with an error rather than hanging. A waiting follower
// writes its last step again every second: a restarted robot's new process, whose first steps
// the others refused while its old process still held its id, is heard once it holds it.
// A process that starts behind the leader (a restarted robot) jumps to the leader's time.

#include <chrono>
#include <cinttypes>
#include <limits>
#include <map>
#include <thread>

#include "components/dds_bridge/dds_bridge.hpp"
#include "executors/log.hpp"
#include "interfaces/codec.hpp"

namespace scancrew::dds_bridge {

namespace {

constexpr int64_t kReady = -1;  // a follower's t_ns before its first step: set up and matched

}  // namespace

class DdsBridge::Lockstep final : public StepGate {
 public:
  Lockstep(DdsBridge& bridge, bool leader, std::vector<uint32_t> followers)
      : b_(bridge), leader_(leader), followers_(std::move(followers)) {
    for (const TopicState& t : b_.topics_)
      if (!t.spec.exported) imported_[t.topic_key] = t.endpoint;
  }

  std::optional<int64_t> before_step(int64_t target_ns) override {
    if (!started_) {
      // DDS calls take Fast DDS's locks, which its listener threads hold while they call
      // on_sample / on_sync (that take sync_mutex_): never call DDS under sync_mutex_
      if (!wait(
              "every bridged topic to match a peer", [this] { return all_matched(); },
              /*timeout_s=*/-1, /*cancellable=*/true, /*locked=*/false))
        return std::nullopt;
      if (!leader_) write(kReady, false, {});
      started_ = true;
    }
    return leader_ ? lead(target_ns) : follow(target_ns);
  }

  void after_step(int64_t now_ns) override {
    std::vector<msg::StepMark> marks = own_marks();
    if (leader_) {
      const std::lock_guard lock(b_.sync_mutex_);
      for (const uint32_t f : followers_) {
        const auto it = b_.syncs_.find(f);
        if (it == b_.syncs_.end() || b_.lost_.contains(f)) continue;
        marks.insert(marks.end(), it->second.marks.begin(), it->second.marks.end());
      }
    }
    write(now_ns, false, std::move(marks));
    last_t_ = now_ns;
  }

  void finish(int64_t now_ns) override {
    write(now_ns, true, {});
    if (!leader_ || !started_) return;
    // the followers end their runs (and write their results) on this stop: wait for them a
    // little, so that the simulator's process does not leave before they heard it
    const double timeout_s = std::min(b_.config_.lockstep_timeout_s, 30.0);
    wait(
        "the followers to stop",
        [this] {
          for (const uint32_t f : followers_) {
            const auto it = b_.syncs_.find(f);
            if (!b_.lost_.contains(f) && (it == b_.syncs_.end() || it->second.stop == 0))
              return false;
          }
          return true;
        },
        timeout_s, /*cancellable=*/false);
  }

 private:
  // leader: every follower stepped to the last announced time, and its marked samples are in
  std::optional<int64_t> lead(int64_t target_ns) {
    const bool first = last_t_ == std::numeric_limits<int64_t>::min();
    const bool ok = wait(first ? "every follower to be ready" : "every follower's step", [&] {
      for (const uint32_t f : followers_) {
        if (b_.lost_.contains(f)) continue;
        const auto it = b_.syncs_.find(f);
        if (it == b_.syncs_.end()) return false;
        if (it->second.stop != 0) continue;  // it ended its run (an error): not waited for
        if (first ? it->second.t_ns < kReady : it->second.t_ns < last_t_) return false;
        if (!marks_in(it->second.marks)) return false;
      }
      return true;
    });
    if (!ok) return std::nullopt;
    const std::lock_guard lock(b_.sync_mutex_);
    for (const uint32_t f : followers_)
      if (const auto it = b_.syncs_.find(f); it != b_.syncs_.end()) release(it->second.marks);
    return target_ns;
  }

  // follower: the leader's next time, and every sample it marks. A leader reported lost (a
  // partition, a dead process) is waited for up to lockstep_timeout_s: after a partition
  // heals, this follower steps straight to the leader's time (its own clock stood still, as
  // its simulated body got nothing to act on) and the team goes on with it
  std::optional<int64_t> follow(int64_t target_ns) {
    const uint32_t leader = b_.config_.simulator_id;
    bool reported = false;
    const bool ok = wait(
        "the simulator's step",
        [&] {
          // a stop already heard ends the run, lost leader or not
          if (const auto it = b_.syncs_.find(leader); it != b_.syncs_.end() && it->second.stop != 0)
            return true;
          if (b_.lost_.contains(leader)) {
            if (!reported)
              SCANCREW_LOG_WARN(
                  "%s: lockstep: the simulator (bridge %u) is lost: waiting for it "
                  "(lockstep_timeout_s)",
                  b_.qualified_name().c_str(), leader);
            reported = true;
            return false;
          }
          const auto it = b_.syncs_.find(leader);
          if (it == b_.syncs_.end()) return false;
          if (it->second.stop != 0) return true;
          return it->second.t_ns >= target_ns && marks_in(it->second.marks);
        },
        /*timeout_s=*/-1, /*cancellable=*/true, /*locked=*/true, /*rewrite=*/true);
    if (!ok) return std::nullopt;
    if (reported)
      SCANCREW_LOG_INFO("%s: lockstep: the simulator is back; stepping to its time",
                        b_.qualified_name().c_str());
    const std::lock_guard lock(b_.sync_mutex_);
    const msg::StepSync& sync = b_.syncs_.at(leader);
    if (sync.stop != 0) return std::nullopt;
    release(sync.marks);
    return sync.t_ns;
  }

  // Under sync_mutex_: every marked sample of a topic this bridge imports has been taken
  // (or its sender is lost).
  bool marks_in(const std::vector<msg::StepMark>& marks) const {
    for (const msg::StepMark& m : marks) {
      if (m.seq == 0 || m.robot_id == b_.self_id_ || b_.lost_.contains(m.robot_id)) continue;
      const auto reader = imported_.find(m.topic_key);
      if (reader == imported_.end()) continue;
      const auto it = b_.received_max_.find({m.robot_id, reader->second});
      if (it == b_.received_max_.end() || it->second < m.seq) return false;
    }
    return true;
  }

  // Under sync_mutex_ (the executor does not run now: it is this thread's).
  void release(const std::vector<msg::StepMark>& marks) {
    for (const msg::StepMark& m : marks) {
      uint64_t& r = b_.released_[{m.robot_id, m.topic_key}];
      r = std::max(r, m.seq);
    }
  }

  bool all_matched() const {
    if (b_.link_->writer_matches(b_.sync_writer_) == 0 ||
        b_.link_->reader_matches(b_.sync_reader_) == 0)
      return false;
    for (const TopicState& t : b_.topics_) {
      const size_t n = t.spec.exported ? b_.link_->writer_matches(t.endpoint)
                                       : b_.link_->reader_matches(t.endpoint);
      if (n == 0) return false;
    }
    return true;
  }

  std::vector<msg::StepMark> own_marks() const {
    std::vector<msg::StepMark> marks;
    for (const TopicState& t : b_.topics_)
      if (t.spec.exported && t.spec.qos.reliability == Reliability::kReliable)
        marks.push_back({.robot_id = b_.self_id_, .topic_key = t.topic_key, .seq = t.seq});
    return marks;
  }

  void write(int64_t t_ns, bool stop, std::vector<msg::StepMark> marks) {
    last_written_ = Written{t_ns, stop, marks};
    msg::StepSync sync;
    sync.header.robot_id = b_.self_id_;
    sync.header.seq = ++seq_;
    sync.header.stamp_ns = t_ns;
    sync.t_ns = t_ns;
    sync.stop = stop ? 1 : 0;
    sync.marks = std::move(marks);
    WireEnvelope envelope;
    envelope.format_version = msg::kMessageFormatVersion;
    envelope.robot_id = b_.self_id_;
    envelope.seq = seq_;
    envelope.stamp_ns = t_ns;
    envelope.type_name = msg::StepSync::kTypeName;
    msg::encode(sync, envelope.payload);
    if (auto written = b_.link_->write(b_.sync_writer_, envelope); !written)
      SCANCREW_LOG_ERROR("%s: lockstep: %s", b_.qualified_name().c_str(), written.error().c_str());
  }

  // Waits (wall clock, bounded) until ready() holds, under sync_mutex_ (locked) or polling
  // without it; false, with an error line, on timeout or cancel. rewrite: the last step
  // written is written again every second of the wait (DDS is called without sync_mutex_).
  template <class Ready>
  bool wait(const char* what, Ready ready, double timeout_s = -1, bool cancellable = true,
            bool locked = true, bool rewrite = false) {
    if (timeout_s < 0) timeout_s = b_.config_.lockstep_timeout_s;
    const auto start = std::chrono::steady_clock::now();
    const auto deadline = start + std::chrono::duration<double>(timeout_s);
    auto next_rewrite = start + std::chrono::seconds(1);
    std::unique_lock lock(b_.sync_mutex_, std::defer_lock);
    if (locked) lock.lock();
    while (!ready()) {
      if (cancellable && cancelled()) return false;
      const auto now = std::chrono::steady_clock::now();
      if (rewrite && last_written_ && now >= next_rewrite) {
        next_rewrite = now + std::chrono::seconds(1);
        if (locked) lock.unlock();
        const Written again = *last_written_;
        write(again.t_ns, again.stop, again.marks);
        if (locked) lock.lock();
        continue;
      }
      if (now >= deadline) {
        SCANCREW_LOG_ERROR("%s: lockstep: waited %.0f s for %s (lockstep_timeout_s); the run ends",
                           b_.qualified_name().c_str(), timeout_s, what);
        return false;
      }
      if (locked)
        b_.sync_cv_.wait_for(lock, std::chrono::milliseconds(50));
      else
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return true;
  }

  DdsBridge& b_;
  const bool leader_;
  const std::vector<uint32_t> followers_;
  std::map<uint64_t, size_t> imported_;  // DDS topic key -> reader, of the topics it reads
  struct Written {
    int64_t t_ns;
    bool stop;
    std::vector<msg::StepMark> marks;
  };
  std::optional<Written> last_written_;  // the last step written (a waiting follower's again)
  bool started_ = false;
  int64_t last_t_ = std::numeric_limits<int64_t>::min();  // the last step written
  uint64_t seq_ = 0;
};

Result<void, std::string> DdsBridge::make_lockstep() {
  const bool leader = config_.lockstep == LockstepRole::kLeader;
  if (leader && self_id_ != config_.simulator_id)
    return make_unexpected(qualified_name() + ": lockstep: leader: its bridge_id (" +
                           std::to_string(self_id_) + ") must be simulator_id (" +
                           std::to_string(config_.simulator_id) +
                           "), the id the followers wait for");
  if (!leader && self_id_ == config_.simulator_id)
    return make_unexpected(qualified_name() + ": lockstep: follower: bridge_id " +
                           std::to_string(self_id_) + " is the simulator's (simulator_id)");
  std::vector<uint32_t> followers = config_.lockstep_followers;
  if (followers.empty())
    for (const TeamMember& m : team()) followers.push_back(m.id);
  const DdsTopicQos qos{
      .reliability = Reliability::kReliable, .depth = 64, .transient_local = true};
  auto writer = link_->add_writer(std::string(kLockstepTopic), qos);
  if (!writer) return make_unexpected(qualified_name() + ": " + writer.error());
  auto reader = link_->add_reader(std::string(kLockstepTopic), qos);
  if (!reader) return make_unexpected(qualified_name() + ": " + reader.error());
  sync_writer_ = *writer;
  sync_reader_ = *reader;
  lockstep_ = std::make_unique<Lockstep>(*this, leader, std::move(followers));
  return {};
}

StepGate* DdsBridge::step_gate() {
  return lockstep_.get();
}

// DDS thread: a peer's StepSync.
void DdsBridge::on_sync(WireEnvelope&& envelope) {
  if (envelope.robot_id == self_id_) return;
  // only from the participant that announced that bridge id, in the team (a forged stop or
  // step would end or run every follower)
  if (envelope.sender_robot_id != envelope.robot_id || !in_team(rules_, envelope.robot_id)) {
    // (one message whatever the claimed id: a forger picks the ids)
    warn_once("lockstep: a sample on " + std::string(kLockstepTopic) +
              " from a participant that did not announce its bridge id, or from a bridge not "
              "in the team: ignored");
    return;
  }
  msg::StepSync sync;
  if (envelope.format_version != msg::kMessageFormatVersion ||
      envelope.type_name != msg::StepSync::kTypeName || !msg::decode(envelope.payload, sync)) {
    warn_once("lockstep: a sample on " + std::string(kLockstepTopic) + " from bridge " +
              std::to_string(envelope.robot_id) + " is no StepSync of this build; ignored");
    return;
  }
  const std::lock_guard lock(sync_mutex_);
  syncs_[envelope.robot_id] = std::move(sync);
  sync_cv_.notify_all();
}

// Executor thread: true when a lockstep bridge must hold `in` back (written after the step
// released so far); a sample let through is stamped with this tick's time.
bool DdsBridge::held_back(Incoming& in) {
  if (!lockstep_) return false;
  in.arrival_ns = clock().now_ns();
  const TopicState& t = topics_[topic_of_reader_.at(in.topic)];
  if (t.spec.qos.reliability != Reliability::kReliable || in.envelope.robot_id == self_id_)
    return false;
  // a sample whose sender or robot id is refused is not held (it would wait for a release
  // that never comes, for ever): admit() counts and drops it now
  if (in.oversize || in.envelope.sender_robot_id != in.envelope.robot_id ||
      !in_team(rules_, in.envelope.robot_id))
    return false;
  const auto it = released_.find({in.envelope.robot_id, t.topic_key});
  return it == released_.end() || in.envelope.seq > it->second;
}

}  // namespace scancrew::dds_bridge
