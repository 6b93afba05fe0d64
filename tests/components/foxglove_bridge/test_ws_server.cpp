// The Foxglove WebSocket server against real clients on loopback (Boost.Beast, synchronous):
// a client negotiates the subprotocol, gets serverInfo then advertise, and after subscribing
// gets Message Data frames with its subscription id; a client that never reads cannot stall
// publish(): its queue stays bounded and what does not fit is dropped, counted, and reported
// to the client in a status message.

#include <gtest/gtest.h>

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <nlohmann/json.hpp>
#include <thread>

#include "components/foxglove_bridge/ws_server.hpp"

namespace scancrew::foxglove {
namespace {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;
using nlohmann::json;

std::unique_ptr<WsServer> start_server(size_t max_messages = 256) {
  auto server = WsServer::start({.port = 0, .max_queue_messages = max_messages},
                                {{.id = 1, .topic = "/tf", .schema = Schema::kFrameTransforms},
                                 {.id = 2, .topic = "/r1/depth", .schema = Schema::kRawImage}});
  EXPECT_TRUE(server) << server.error();
  return std::move(server).value();
}

// A connected client that asked for the Foxglove subprotocol; the server's answer kept.
struct Client {
  net::io_context io;
  websocket::stream<tcp::socket> ws{io};
  std::string subprotocol;

  explicit Client(uint16_t port) {
    tcp::resolver resolver(io);
    net::connect(ws.next_layer(), resolver.resolve("127.0.0.1", std::to_string(port)));
    ws.set_option(websocket::stream_base::decorator([](websocket::request_type& req) {
      req.set(beast::http::field::sec_websocket_protocol, "foxglove.websocket.v1");
    }));
    websocket::response_type res;
    ws.handshake(res, "127.0.0.1", "/");
    subprotocol = std::string(res[beast::http::field::sec_websocket_protocol]);
  }
  std::string read(bool* text = nullptr) {
    beast::flat_buffer buffer;
    ws.read(buffer);
    if (text != nullptr) *text = ws.got_text();
    return beast::buffers_to_string(buffer.data());
  }
  void send(const json& message) {
    ws.text(true);
    ws.write(net::buffer(message.dump()));
  }
};

// Waits (up to 2 s) for the server to see the subscription: it is read on the server's thread.
bool wait_subscribed(const WsServer& server, uint32_t channel) {
  for (int i = 0; i < 200 && !server.subscribed(channel); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return server.subscribed(channel);
}

TEST(WsServer, ClientGetsServerInfoAdvertiseAndItsSubscribedMessages) {
  auto server = start_server();
  ASSERT_NE(server->port(), 0);
  Client client(server->port());
  EXPECT_EQ(client.subprotocol, "foxglove.websocket.v1");
  EXPECT_EQ(json::parse(client.read())["op"], "serverInfo");
  const json advertise = json::parse(client.read());
  EXPECT_EQ(advertise["op"], "advertise");
  ASSERT_EQ(advertise["channels"].size(), 2u);
  EXPECT_FALSE(server->subscribed(2));
  client.send({{"op", "subscribe"}, {"subscriptions", {{{"id", 42}, {"channelId", 2}}}}});
  ASSERT_TRUE(wait_subscribed(*server, 2));
  EXPECT_FALSE(server->subscribed(1));
  server->publish(1, 5, std::make_shared<const std::string>("{\"not\":\"subscribed\"}"));
  server->publish(2, 0x0102030405060708, std::make_shared<const std::string>("{\"a\":1}"));
  bool text = true;
  const std::string frame = client.read(&text);
  EXPECT_FALSE(text);
  ASSERT_EQ(frame.size(), 13u + 7u);
  EXPECT_EQ(static_cast<uint8_t>(frame[0]), 0x01);
  EXPECT_EQ(static_cast<uint8_t>(frame[1]), 42);  // the client's subscription id, LE
  EXPECT_EQ(static_cast<uint8_t>(frame[5]), 0x08);
  EXPECT_EQ(frame.substr(13), "{\"a\":1}");
  client.send({{"op", "unsubscribe"}, {"subscriptionIds", {42}}});
  for (int i = 0; i < 200 && server->subscribed(2); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_FALSE(server->subscribed(2));
  EXPECT_EQ(server->stats().messages_sent, 1u);
  EXPECT_EQ(server->stats().messages_dropped, 0u);
}

TEST(WsServer, ClientThatNeverReadsNeitherStallsPublishNorGrowsTheQueue) {
  constexpr size_t kQueue = 8;
  auto server = start_server(kQueue);
  Client stalled(server->port());
  stalled.read();  // serverInfo
  stalled.read();  // advertise
  stalled.send({{"op", "subscribe"}, {"subscriptions", {{{"id", 1}, {"channelId", 2}}}}});
  ASSERT_TRUE(wait_subscribed(*server, 2));
  // 400 MB offered to a client that reads nothing: far beyond the socket buffers
  const auto payload = std::make_shared<const std::string>(1u << 20, 'x');
  constexpr int kMessages = 400;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kMessages; ++i) server->publish(2, i, payload);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 2.0) << "publish() waited for the client";
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const WsServerStats s = server->stats();
  EXPECT_GT(s.messages_dropped, 0u);
  // what was not dropped was sent into the socket or is still queued (at most kQueue)
  EXPECT_LE(static_cast<uint64_t>(kMessages) - s.messages_dropped, s.messages_sent + kQueue);
  EXPECT_EQ(s.clients_now, 1u);
  // reading at last, the client gets a status warning with the count (within ~2 s)
  json status;
  for (int frames = 0; frames < 1000 && status.is_null(); ++frames) {
    bool text = false;
    const std::string frame = stalled.read(&text);
    if (text) status = json::parse(frame);
  }
  EXPECT_EQ(status["op"], "status");
  EXPECT_EQ(status["level"], 1);  // warning
  EXPECT_NE(status["message"].get<std::string>().find("dropped"), std::string::npos);
  server->stop();  // returns although the client never answers the close
  EXPECT_EQ(server->stats().clients_now, 0u);
}

TEST(WsServer, PortInUseIsRefusedWithTheAddress) {
  auto first = start_server();
  auto second = WsServer::start({.port = first->port()}, {});
  ASSERT_FALSE(second);
  EXPECT_NE(second.error().find(std::to_string(first->port())), std::string::npos)
      << second.error();
}

}  // namespace
}  // namespace scancrew::foxglove
