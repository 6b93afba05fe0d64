#pragma once

// The Foxglove WebSocket protocol, v1 (subprotocol "foxglove.websocket.v1";
// github.com/foxglove/ws-protocol, docs/spec.md): the messages the server sends and the
// client messages it understands. Only what a live view needs: serverInfo, advertise,
// status and binary Message Data out; subscribe and unsubscribe in. Pure functions.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "components/foxglove_bridge/foxglove_json.hpp"
#include "core/result.hpp"

namespace scancrew::foxglove {

inline constexpr std::string_view kSubprotocol = "foxglove.websocket.v1";

// A channel the server advertises (JSON-encoded messages of a Foxglove schema).
struct Channel {
  uint32_t id = 0;
  std::string topic;
  Schema schema = Schema::kPoseInFrame;
};

// Text messages (JSON).
std::string server_info_message(std::string_view server_name);
std::string advertise_message(std::span<const Channel> channels);
enum class StatusLevel : uint8_t { kInfo = 0, kWarning = 1, kError = 2 };
std::string status_message(StatusLevel level, std::string_view message);

// Binary Message Data: opcode 0x01, the client's subscription id (u32 LE), the message's
// timestamp (u64 LE, ns), then the payload. This is the 13-byte head.
inline constexpr uint8_t kMessageDataOpcode = 0x01;
using MessageDataHead = std::array<uint8_t, 13>;
MessageDataHead message_data_head(uint32_t subscription_id, uint64_t timestamp_ns);

// A client's text message, parsed.
struct ClientOp {
  enum class Kind : uint8_t { kSubscribe, kUnsubscribe, kOther };
  Kind kind = Kind::kOther;
  std::string op;                                            // as the client named it
  std::vector<std::pair<uint32_t, uint32_t>> subscriptions;  // kSubscribe: (id, channelId)
  std::vector<uint32_t> subscription_ids;                    // kUnsubscribe
};
// An error names what is malformed (not JSON, no "op", a bad subscription).
Result<ClientOp, std::string> parse_client_op(std::string_view text);

}  // namespace scancrew::foxglove
