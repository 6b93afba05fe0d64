#include "components/foxglove_bridge/ws_protocol.hpp"

#include <nlohmann/json.hpp>

namespace scancrew::foxglove {

using nlohmann::json;

std::string server_info_message(std::string_view server_name) {
  return json{{"op", "serverInfo"},
              {"name", server_name},
              {"capabilities", json::array()},
              {"supportedEncodings", json::array()},
              {"metadata", json::object()}}
      .dump();
}

std::string advertise_message(std::span<const Channel> channels) {
  json list = json::array();
  for (const Channel& c : channels)
    list.push_back({{"id", c.id},
                    {"topic", c.topic},
                    {"encoding", "json"},
                    {"schemaName", schema_name(c.schema)},
                    {"schema", schema_text(c.schema)},
                    {"schemaEncoding", "jsonschema"}});
  return json{{"op", "advertise"}, {"channels", std::move(list)}}.dump();
}

std::string status_message(StatusLevel level, std::string_view message) {
  return json{{"op", "status"}, {"level", static_cast<int>(level)}, {"message", message}}.dump();
}

MessageDataHead message_data_head(uint32_t subscription_id, uint64_t timestamp_ns) {
  MessageDataHead head{};
  head[0] = kMessageDataOpcode;
  for (size_t i = 0; i < 4; ++i) head[1 + i] = static_cast<uint8_t>(subscription_id >> (8 * i));
  for (size_t i = 0; i < 8; ++i) head[5 + i] = static_cast<uint8_t>(timestamp_ns >> (8 * i));
  return head;
}

namespace {

bool is_u32(const json& v) {
  return v.is_number_unsigned() && v.get<uint64_t>() <= UINT32_MAX;
}

Result<void, std::string> read_subscribe(const json& j, ClientOp& out) {
  const auto it = j.find("subscriptions");
  if (it == j.end() || !it->is_array())
    return make_unexpected(std::string("subscribe: no \"subscriptions\" array"));
  for (const json& s : *it) {
    if (!s.is_object() || !s.contains("id") || !s.contains("channelId") || !is_u32(s["id"]) ||
        !is_u32(s["channelId"]))
      return make_unexpected("subscribe: a subscription is not {id, channelId}: " + s.dump());
    out.subscriptions.emplace_back(s["id"].get<uint32_t>(), s["channelId"].get<uint32_t>());
  }
  return {};
}

Result<void, std::string> read_unsubscribe(const json& j, ClientOp& out) {
  const auto it = j.find("subscriptionIds");
  if (it == j.end() || !it->is_array())
    return make_unexpected(std::string("unsubscribe: no \"subscriptionIds\" array"));
  for (const json& id : *it) {
    if (!is_u32(id)) return make_unexpected("unsubscribe: not a subscription id: " + id.dump());
    out.subscription_ids.push_back(id.get<uint32_t>());
  }
  return {};
}

}  // namespace

Result<ClientOp, std::string> parse_client_op(std::string_view text) {
  const json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object()) return make_unexpected(std::string("not a JSON object"));
  const auto op = j.find("op");
  if (op == j.end() || !op->is_string()) return make_unexpected(std::string("no \"op\""));
  ClientOp out;
  out.op = op->get<std::string>();
  if (out.op == "subscribe") {
    out.kind = ClientOp::Kind::kSubscribe;
    if (auto r = read_subscribe(j, out); !r) return make_unexpected(r.error());
  } else if (out.op == "unsubscribe") {
    out.kind = ClientOp::Kind::kUnsubscribe;
    if (auto r = read_unsubscribe(j, out); !r) return make_unexpected(r.error());
  }
  return out;
}

}  // namespace scancrew::foxglove
