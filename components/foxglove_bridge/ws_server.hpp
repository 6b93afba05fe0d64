#pragma once

// WsServer: a Foxglove WebSocket (v1) server on its own network thread (Boost.Beast over
// Boost.Asio), serving a fixed set of JSON channels (ws_protocol.hpp) to any number of
// clients, as foxglove_bridge does for ROS 2.
//
// A client gets serverInfo and advertise on connecting, then the messages of the channels it
// subscribes to. Each client has a bounded send queue (max_queue_messages and
// max_queue_bytes): a message that does not fit is dropped for that client and counted,
// and the client gets a `status` warning with the count (at most every 2 s), so a slow or
// stalled client never blocks publish() nor grows memory without bound. Control messages
// (serverInfo, advertise, status) are never dropped; they are few and small.
//
// Thread safety: publish(), subscribed(), stats() and port() may be called from any thread.
// subscribed(channel) is one atomic load: a publisher asks it first and converts nothing
// while no client listens. stop() (and the destructor) closes the clients (a WebSocket
// close, up to 1 s) and joins the network thread.

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "components/foxglove_bridge/ws_protocol.hpp"
#include "core/result.hpp"

namespace scancrew::foxglove {

struct WsServerConfig {
  std::string address = "127.0.0.1";   // to listen on; 0.0.0.0: every interface
  uint16_t port = 8765;                // 0: any free port (port() says which)
  std::string name = "scancrew";       // serverInfo's name
  size_t max_queue_messages = 256;     // per client
  size_t max_queue_bytes = 64u << 20;  // per client
};

struct WsServerStats {
  uint64_t clients_accepted = 0;  // since start
  uint64_t clients_now = 0;
  uint64_t messages_sent = 0;     // Message Data frames written, all clients
  uint64_t bytes_sent = 0;        // their payload bytes
  uint64_t messages_dropped = 0;  // not queued: a client's queue was full
};

class WsServer {
 public:
  // Binds and listens (the port is taken when this returns), then starts the network thread.
  static Result<std::unique_ptr<WsServer>, std::string> start(WsServerConfig config,
                                                              std::vector<Channel> channels);
  ~WsServer();
  WsServer(const WsServer&) = delete;
  WsServer& operator=(const WsServer&) = delete;

  uint16_t port() const;
  // Whether any client subscribes to the channel (an unknown id: false).
  bool subscribed(uint32_t channel_id) const;
  // Queues the payload for every client subscribed to the channel (each of its subscriptions);
  // drops it for a client whose queue is full. The payload is shared, not copied.
  void publish(uint32_t channel_id, int64_t timestamp_ns,
               const std::shared_ptr<const std::string>& payload);
  WsServerStats stats() const;
  void stop();

  struct Impl;

 private:
  explicit WsServer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace scancrew::foxglove
