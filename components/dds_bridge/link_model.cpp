#include "components/dds_bridge/link_model.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace scancrew::dds_bridge {

namespace {

// splitmix64's finaliser: a cheap, well-mixed 64-bit hash step.
uint64_t mix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

bool contains(const std::vector<uint32_t>& group, uint32_t id) {
  return std::find(group.begin(), group.end(), id) != group.end();
}

}  // namespace

std::string parse_partition_group(std::string_view text, std::vector<uint32_t>& group) {
  group.clear();
  size_t at = 0;
  while (at < text.size()) {
    if (text[at] == ' ' || text[at] == ',') {
      ++at;
      continue;
    }
    uint32_t id = 0;
    const auto [end, ec] = std::from_chars(text.data() + at, text.data() + text.size(), id);
    if (ec != std::errc{} || (end != text.data() + text.size() && *end != ' ' && *end != ',')) {
      std::string message = "'";
      message += text;
      message += "' is not a group of robot ids, e.g. \"1 2 3\"";
      return message;
    }
    group.push_back(id);
    at = static_cast<size_t>(end - text.data());
  }
  if (group.empty()) return "an empty group; a group lists the robot ids that hear each other";
  return {};
}

std::string_view to_string(LinkVerdict verdict) {
  switch (verdict) {
    case LinkVerdict::kDeliver:
      return "deliver";
    case LinkVerdict::kPartitioned:
      return "partitioned";
    case LinkVerdict::kLost:
      return "lost";
    case LinkVerdict::kSaturated:
      return "saturated";
  }
  return "?";
}

LinkModel::LinkModel(LinkConfig config, uint32_t receiver_id)
    : config_(std::move(config)),
      receiver_id_(receiver_id),
      latency_ns_(std::llround(config_.latency_s * 1e9)),
      max_queue_ns_(std::llround(config_.max_queue_s * 1e9)) {}

uint64_t LinkModel::topic_key(std::string_view dds_topic) {
  uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a
  for (const char c : dds_topic) h = (h ^ static_cast<uint8_t>(c)) * 0x100000001b3ULL;
  return h;
}

double LinkModel::loss_draw(uint64_t seed, uint32_t sender_id, uint32_t receiver_id,
                            uint64_t topic_key, uint64_t sequence) {
  uint64_t h = mix(seed);
  h = mix(h ^ ((uint64_t{sender_id} << 32) | receiver_id));
  h = mix(h ^ topic_key);
  h = mix(h ^ sequence);
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

bool LinkModel::hears(uint32_t sender_id) const {
  if (config_.partition.empty()) return true;
  return std::any_of(config_.partition.begin(), config_.partition.end(), [&](const auto& group) {
    return contains(group, sender_id) && contains(group, receiver_id_);
  });
}

LinkModel::Decision LinkModel::admit(uint32_t sender_id, uint64_t topic_key, uint64_t sequence,
                                     size_t bytes, int64_t arrival_ns, bool lossy) {
  if (!hears(sender_id)) return {LinkVerdict::kPartitioned};
  if (lossy && config_.loss_rate > 0 &&
      loss_draw(config_.seed, sender_id, receiver_id_, topic_key, sequence) < config_.loss_rate)
    return {LinkVerdict::kLost};
  const int64_t ready_ns = arrival_ns + latency_ns_;
  if (config_.bandwidth_bps <= 0) return {LinkVerdict::kDeliver, ready_ns};
  const int64_t start_ns = std::max(ready_ns, channel_free_ns_);
  if (start_ns - ready_ns > max_queue_ns_) return {LinkVerdict::kSaturated};
  const auto transfer_ns =
      std::llround(static_cast<double>(bytes) * 8.0 / config_.bandwidth_bps * 1e9);
  channel_free_ns_ = start_ns + transfer_ns;
  return {LinkVerdict::kDeliver, channel_free_ns_};
}

}  // namespace scancrew::dds_bridge
