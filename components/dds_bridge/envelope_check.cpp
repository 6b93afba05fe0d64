#include "components/dds_bridge/envelope_check.hpp"

#include <algorithm>

#include "interfaces/message_fields.hpp"

namespace scancrew::dds_bridge {

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
