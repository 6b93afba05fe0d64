// A DDS sample as the bridge takes it in (components/dds_bridge/dds_bridge.cpp, add_import):
// the envelope checks, then the payload decoded as the topic's type, then the team check.
// Bytes 0-3: robot id, 4: the topic's type, 5: flags (bit 0: the envelope names another type,
// its bits 2-7 which; bit 1: another format version), 6: whether the sending participant
// announced another robot, the rest the payload.
#include <cstring>
#include <string>

#include "components/dds_bridge/envelope_check.hpp"
#include "fuzz/fuzz_input.hpp"
#include "interfaces/codec.hpp"
#include "interfaces/message_fields.hpp"

namespace {

template <class... T>
const char* type_name(size_t index, scancrew::msg::TypeList<T...> /*types*/) {
  const char* names[] = {T::kTypeName...};
  return names[index % sizeof...(T)];
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace scancrew;
  if (size < 7) return 0;
  dds_bridge::WireEnvelope envelope;
  std::memcpy(&envelope.robot_id, data, sizeof envelope.robot_id);
  const std::string topic_type = type_name(data[4], msg::WireMessages{});
  envelope.type_name =
      (data[5] & 1) != 0 ? type_name(data[5] >> 2, msg::WireMessages{}) : topic_type;
  envelope.sender_robot_id = data[6] == 0 ? envelope.robot_id : data[6] - 1u;
  envelope.format_version = (data[5] & 2) != 0 ? 0 : msg::kMessageFormatVersion;
  envelope.payload.assign(data + 7, data + size);
  const dds_bridge::EnvelopeRules rules{
      .format_version = msg::kMessageFormatVersion, .team = {1, 2, 3}, .max_sample_bytes = 1 << 16};
  std::string detail;
  if (dds_bridge::check_envelope(envelope, topic_type, rules, &detail)) return 0;
  msg::with_wire_message(topic_type, [&]<class T>() {
    T message;
    if (msg::decode(std::span<const uint8_t>(envelope.payload), message))
      (void)dds_bridge::in_team(rules, message.header.robot_id);
  });
  return 0;
}
