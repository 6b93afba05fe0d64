#include "components/dds_bridge/envelope_check.hpp"

#include <algorithm>

#include "interfaces/message_fields.hpp"

namespace scancrew::dds_bridge {

namespace {

constexpr std::string_view kUserDataTag = "scancrew robot ";

}  // namespace

namespace {

// "scancrew robot <id>", then " in <partitions>" (sorted, comma-separated) when there are
std::string partition_suffix(const std::vector<std::string>& partitions) {
  if (partitions.empty()) return {};
  std::vector<std::string> sorted = partitions;
  std::sort(sorted.begin(), sorted.end());
  std::string out = " in ";
  for (size_t i = 0; i < sorted.size(); ++i) out += (i > 0 ? "," : "") + sorted[i];
  return out;
}

}  // namespace

std::vector<uint8_t> participant_user_data(uint32_t robot_id,
                                           const std::vector<std::string>& partitions) {
  const std::string text =
      std::string(kUserDataTag) + std::to_string(robot_id) + partition_suffix(partitions);
  return {text.begin(), text.end()};
}

std::optional<uint32_t> robot_of_user_data(const std::vector<uint8_t>& user_data,
                                           const std::vector<std::string>& partitions) {
  const std::string text(user_data.begin(), user_data.end());
  if (!text.starts_with(kUserDataTag)) return {};
  const std::string suffix = partition_suffix(partitions);
  if (!text.ends_with(suffix) || text.size() < kUserDataTag.size() + suffix.size()) return {};
  const std::string digits =
      text.substr(kUserDataTag.size(), text.size() - kUserDataTag.size() - suffix.size());
  if (digits.empty() || digits.size() > 10) return {};
  uint64_t id = 0;
  for (const char c : digits) {
    if (c < '0' || c > '9') return {};
    id = id * 10 + static_cast<uint64_t>(c - '0');
  }
  if (id >= kUnknownSender) return {};
  return static_cast<uint32_t>(id);
}

bool in_team(const EnvelopeRules& rules, uint32_t robot_id) {
  return rules.team.empty() ||
         std::find(rules.team.begin(), rules.team.end(), robot_id) != rules.team.end();
}

std::optional<Reject> check_envelope(const WireEnvelope& envelope, std::string_view topic_type,
                                     const EnvelopeRules& rules, std::string* detail) {
  const auto say = [&](Reject reject, std::string text) {
    if (detail != nullptr) *detail = std::move(text);
    return reject;
  };
  if (envelope.format_version != rules.format_version)
    return say(Reject::kFormatVersion,
               "robot " + std::to_string(envelope.robot_id) + " sends message format " +
                   std::to_string(envelope.format_version) + ", this build reads " +
                   std::to_string(rules.format_version));
  if (!in_team(rules, envelope.robot_id))
    return say(Reject::kUnknownRobot,
               "robot id " + std::to_string(envelope.robot_id) + " is not in the team");
  // the sending participant must be the one that announced this robot id at discovery
  if (envelope.sender_robot_id != envelope.robot_id)
    return say(Reject::kForgedSender,
               "robot id " + std::to_string(envelope.robot_id) + " from a participant that " +
                   (envelope.sender_robot_id == kUnknownSender
                        ? std::string("announced no robot (or one another participant holds)")
                        : "announced robot " + std::to_string(envelope.sender_robot_id)));
  // type names come from the network: only known names are echoed in full
  if (!msg::with_wire_message(envelope.type_name, []<class T>() {}))
    return say(Reject::kUnknownType,
               "type '" + envelope.type_name.substr(0, 64) + "' is no wire message of this build");
  if (envelope.type_name != topic_type)
    return say(Reject::kTypeMismatch,
               "type '" + envelope.type_name + "' on a topic of '" + std::string(topic_type) + "'");
  if (envelope.payload.size() > rules.max_sample_bytes)
    return say(Reject::kOversize, std::to_string(envelope.payload.size()) +
                                      " bytes, over max_sample_bytes " +
                                      std::to_string(rules.max_sample_bytes));
  return std::nullopt;
}

}  // namespace scancrew::dds_bridge
