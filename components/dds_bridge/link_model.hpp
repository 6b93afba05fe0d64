#pragma once

// LinkModel: the network a bridge pretends to receive through, applied on top of real DDS so
// an experiment can reproduce a slow, lossy, saturated or cut network (thesis 4.1, Fig. 4.2:
// complete, connected, disconnected and fully disconnected communication graphs).
//
// Applied by the receiving bridge to every sample that passed its checks, in this order:
//  1. partition: the sender and this robot must share a group of `partition` (empty: every
//     robot hears every other); a robot named in no group hears nobody;
//  2. loss: dropped when u < loss_rate, u in [0, 1) a hash of (seed, sender, receiver,
//     topic, sequence number): the same samples are dropped on every run, whatever the
//     arrival order or timing;
//  3. latency and bandwidth: the receiver has one incoming channel of bandwidth_bps shared
//     by all senders (a radio); a sample arriving at t is ready at t + latency, waits for the
//     channel, then occupies it for bytes·8/bandwidth_bps. A sample that would wait more than
//     max_queue_s is dropped (a saturated link). bandwidth_bps 0 means unlimited.
// Times are on the bridge's clock (sim or wall), in ns.
//
// Thread safety: none (the bridge calls it from its executor thread). Allocation: none
// after construction.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace scancrew::dds_bridge {

struct LinkConfig {
  double latency_s = 0.0;      // one-way delay added to every sample
  double bandwidth_bps = 0.0;  // bits/s of this robot's incoming channel; 0: unlimited
  double loss_rate = 0.0;      // share of samples lost, in [0, 1]
  uint64_t seed = 1;           // the loss pattern
  double max_queue_s = 2.0;    // longest wait for the channel before a sample is dropped
  // groups of robot ids that hear each other; empty: a complete communication graph
  std::vector<std::vector<uint32_t>> partition;

  bool enabled() const {
    return latency_s > 0 || bandwidth_bps > 0 || loss_rate > 0 || !partition.empty();
  }
};

// Parses one partition group, "1 2 3" or "1,2,3"; an error message on anything else.
std::string parse_partition_group(std::string_view text, std::vector<uint32_t>& group);

enum class LinkVerdict { kDeliver, kPartitioned, kLost, kSaturated };
std::string_view to_string(LinkVerdict verdict);

class LinkModel {
 public:
  LinkModel(LinkConfig config, uint32_t receiver_id);

  struct Decision {
    LinkVerdict verdict = LinkVerdict::kDeliver;
    int64_t deliver_at_ns = 0;  // kDeliver: when the sample may be published locally
  };
  // topic_key: a stable hash of the DDS topic name (topic_key()). lossy = false: the loss
  // rule spares this sample (a topic not in link_loss_topics).
  Decision admit(uint32_t sender_id, uint64_t topic_key, uint64_t sequence, size_t bytes,
                 int64_t arrival_ns, bool lossy = true);

  bool hears(uint32_t sender_id) const;
  const LinkConfig& config() const { return config_; }

  static uint64_t topic_key(std::string_view dds_topic);
  // The u in [0, 1) of the loss rule (exposed for tests).
  static double loss_draw(uint64_t seed, uint32_t sender_id, uint32_t receiver_id,
                          uint64_t topic_key, uint64_t sequence);

 private:
  LinkConfig config_;
  uint32_t receiver_id_;
  int64_t latency_ns_ = 0;
  int64_t max_queue_ns_ = 0;
  int64_t channel_free_ns_ = INT64_MIN;  // when the incoming channel is next free
};

}  // namespace scancrew::dds_bridge
