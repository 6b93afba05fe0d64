#include "components/foxglove_bridge/ws_server.hpp"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>
#include <unordered_map>

#include "executors/log.hpp"

namespace scancrew::foxglove {

namespace {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;

constexpr auto kStatusPeriod = std::chrono::seconds(2);
constexpr auto kCloseWait = std::chrono::seconds(1);

struct Outgoing {
  bool text = false;
  MessageDataHead head{};
  std::shared_ptr<const std::string> payload;
};

class Session;

}  // namespace

struct WsServer::Impl {
  WsServerConfig config;
  std::vector<Channel> channels;
  std::string advertise;
  std::unordered_map<uint32_t, size_t> index_of;         // channel id → index
  std::unique_ptr<std::atomic<uint32_t>[]> subscribers;  // per channel index
  std::atomic<uint64_t> accepted{0}, sent{0}, bytes{0}, dropped{0};
  net::io_context io{1};
  tcp::acceptor acceptor{io};
  net::steady_timer status_timer{io};
  std::thread thread;
  mutable std::mutex mutex;  // sessions (taken before a session's mutex, never after)
  std::condition_variable sessions_gone;
  std::vector<std::shared_ptr<Session>> sessions;  // destroyed before io
  bool stopped = false;

  void do_accept();
  void on_status_timer();
  void add_subscriber(uint32_t channel, int delta) {
    if (const auto it = index_of.find(channel); it != index_of.end())
      subscribers[it->second].fetch_add(static_cast<uint32_t>(delta));
  }
  void remove(const Session* session);
};

namespace {

// One client: its WebSocket, its subscriptions and its bounded send queue. The network thread
// reads and writes; publishers enqueue under mutex_.
class Session : public std::enable_shared_from_this<Session> {
 public:
  Session(tcp::socket socket, WsServer::Impl& server) : ws_(std::move(socket)), server_(server) {}

  void start() {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.set_option(websocket::stream_base::decorator([](websocket::response_type& res) {
      res.set(beast::http::field::sec_websocket_protocol, std::string(kSubprotocol));
      res.set(beast::http::field::server, "scancrew foxglove_bridge");
    }));
    ws_.read_message_max(1u << 20);
    ws_.async_accept(beast::bind_front_handler(&Session::on_accept, shared_from_this()));
  }

  // Any thread: queues a Message Data frame per subscription to the channel, or drops it.
  void enqueue(uint32_t channel, int64_t timestamp_ns,
               const std::shared_ptr<const std::string>& payload) {
    const std::lock_guard lock(mutex_);
    if (!open_ || closing_) return;
    for (const auto& [subscription, subscribed] : subscriptions_) {
      if (subscribed != channel) continue;
      const bool full = queued_data_ >= server_.config.max_queue_messages ||
                        queued_bytes_ + payload->size() > server_.config.max_queue_bytes;
      if (full) {
        ++dropped_;
        server_.dropped.fetch_add(1);
        continue;
      }
      queue_.push_back(
          {.text = false,
           .head = message_data_head(subscription, static_cast<uint64_t>(timestamp_ns)),
           .payload = payload});
      ++queued_data_;
      queued_bytes_ += payload->size();
    }
    kick();
  }

  // Network thread: a status warning when messages were dropped since the last one.
  void report_drops() {
    const std::lock_guard lock(mutex_);
    if (dropped_ == dropped_reported_ || closing_) return;
    const std::string what = "scancrew: " + std::to_string(dropped_ - dropped_reported_) +
                             " messages dropped for this client (slow connection; " +
                             std::to_string(dropped_) + " in all; queue limit " +
                             std::to_string(server_.config.max_queue_messages) + " messages, " +
                             std::to_string(server_.config.max_queue_bytes >> 20) + " MiB)";
    if (dropped_reported_ == 0) SCANCREW_LOG_WARN("foxglove_bridge: %s", what.c_str());
    dropped_reported_ = dropped_;
    push_control(status_message(StatusLevel::kWarning, what));
  }

  // Network thread: a WebSocket close once the frame being written is out.
  void close() {
    const std::lock_guard lock(mutex_);
    closing_ = true;
    if (!open_) {
      beast::error_code ec;
      beast::get_lowest_layer(ws_).socket().close(ec);
      return;
    }
    if (!writing_) start_close();
  }

 private:
  void on_accept(beast::error_code ec) {
    if (ec) return finish();
    const std::lock_guard lock(mutex_);
    open_ = true;
    push_control(server_info_message(server_.config.name));
    push_control(server_.advertise);
    do_read();
  }

  // With mutex_ held.
  void push_control(std::string text) {
    queue_.push_back(
        {.text = true, .payload = std::make_shared<const std::string>(std::move(text))});
    kick();
  }

  // With mutex_ held: starts the write loop on the network thread if it is idle.
  void kick() {
    if (writing_ || queue_.empty()) return;
    writing_ = true;
    net::post(ws_.get_executor(), [self = shared_from_this()] { self->do_write(); });
  }

  void do_write() {
    Outgoing next;
    {
      const std::lock_guard lock(mutex_);
      if (queue_.empty() || closing_) {
        writing_ = false;
        if (closing_ && open_) start_close();
        return;
      }
      next = queue_.front();
    }
    head_ = next.head;
    ws_.text(next.text);
    auto done = beast::bind_front_handler(&Session::on_write, shared_from_this());
    if (next.text) {
      ws_.async_write(net::buffer(*next.payload), std::move(done));
    } else {
      const std::array<net::const_buffer, 2> frame{net::buffer(head_), net::buffer(*next.payload)};
      ws_.async_write(frame, std::move(done));
    }
  }

  void on_write(beast::error_code ec, size_t /*bytes*/) {
    if (ec) return finish();
    {
      const std::lock_guard lock(mutex_);
      const Outgoing& sent = queue_.front();
      if (!sent.text) {
        --queued_data_;
        queued_bytes_ -= sent.payload->size();
        server_.sent.fetch_add(1);
        server_.bytes.fetch_add(sent.payload->size());
      }
      queue_.pop_front();
    }
    do_write();
  }

  // With mutex_ held.
  void start_close() {
    if (close_started_) return;
    close_started_ = true;
    ws_.async_close(websocket::close_code::going_away,
                    [self = shared_from_this()](beast::error_code) { self->finish(); });
  }

  void do_read() {
    ws_.async_read(buffer_, beast::bind_front_handler(&Session::on_read, shared_from_this()));
  }

  void on_read(beast::error_code ec, size_t /*bytes*/) {
    if (ec) return finish();
    if (ws_.got_text()) handle(beast::buffers_to_string(buffer_.data()));
    buffer_.consume(buffer_.size());
    do_read();
  }

  void handle(const std::string& text) {
    auto op = parse_client_op(text);
    const std::lock_guard lock(mutex_);
    if (!op) {
      push_control(status_message(StatusLevel::kError, "scancrew: " + op.error()));
      return;
    }
    for (const auto& [id, channel] : op->subscriptions) {
      if (!server_.index_of.contains(channel) || subscriptions_.contains(id)) {
        push_control(status_message(StatusLevel::kError, "scancrew: cannot subscribe " +
                                                             std::to_string(id) + " to channel " +
                                                             std::to_string(channel)));
        continue;
      }
      subscriptions_[id] = channel;
      server_.add_subscriber(channel, +1);
    }
    for (const uint32_t id : op->subscription_ids)
      if (const auto it = subscriptions_.find(id); it != subscriptions_.end()) {
        server_.add_subscriber(it->second, -1);
        subscriptions_.erase(it);
      }
  }

  // Network thread, once: the client is gone; its subscriptions no longer count.
  void finish() {
    {
      const std::lock_guard lock(mutex_);
      if (finished_) return;
      finished_ = true;
      closing_ = true;
      for (const auto& [id, channel] : subscriptions_) server_.add_subscriber(channel, -1);
      subscriptions_.clear();
      queue_.clear();
    }
    server_.remove(this);
  }

  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_;
  WsServer::Impl& server_;
  MessageDataHead head_{};  // of the frame being written (network thread)
  std::mutex mutex_;
  std::deque<Outgoing> queue_;
  size_t queued_data_ = 0, queued_bytes_ = 0;  // Message Data frames queued, their payload bytes
  bool open_ = false, writing_ = false, closing_ = false, close_started_ = false;
  bool finished_ = false;
  std::unordered_map<uint32_t, uint32_t> subscriptions_;  // subscription id → channel id
  uint64_t dropped_ = 0, dropped_reported_ = 0;
};

}  // namespace

void WsServer::Impl::do_accept() {
  acceptor.async_accept([this](beast::error_code ec, tcp::socket socket) {
    if (ec) return;  // closed by stop()
    auto session = std::make_shared<Session>(std::move(socket), *this);
    {
      const std::lock_guard lock(mutex);
      sessions.push_back(session);
    }
    accepted.fetch_add(1);
    session->start();
    do_accept();
  });
}

void WsServer::Impl::on_status_timer() {
  status_timer.expires_after(kStatusPeriod);
  status_timer.async_wait([this](beast::error_code ec) {
    if (ec) return;
    std::vector<std::shared_ptr<Session>> now;
    {
      const std::lock_guard lock(mutex);
      now = sessions;
    }
    for (const auto& s : now) s->report_drops();
    on_status_timer();
  });
}

void WsServer::Impl::remove(const Session* session) {
  std::shared_ptr<Session> last;  // destroyed outside the lock
  const std::lock_guard lock(mutex);
  for (auto it = sessions.begin(); it != sessions.end(); ++it)
    if (it->get() == session) {
      last = std::move(*it);
      sessions.erase(it);
      break;
    }
  sessions_gone.notify_all();
}

Result<std::unique_ptr<WsServer>, std::string> WsServer::start(WsServerConfig config,
                                                               std::vector<Channel> channels) {
  auto impl = std::make_unique<Impl>();
  impl->config = std::move(config);
  impl->advertise = advertise_message(channels);
  impl->subscribers = std::make_unique<std::atomic<uint32_t>[]>(channels.size());
  for (size_t i = 0; i < channels.size(); ++i) impl->index_of[channels[i].id] = i;
  impl->channels = std::move(channels);
  beast::error_code ec;
  const auto address = net::ip::make_address(impl->config.address, ec);
  const std::string where = impl->config.address + ":" + std::to_string(impl->config.port);
  if (ec) return make_unexpected("address '" + impl->config.address + "': " + ec.message());
  const tcp::endpoint endpoint(address, impl->config.port);
  if (impl->acceptor.open(endpoint.protocol(), ec); ec)
    return make_unexpected("cannot open a socket for " + where + ": " + ec.message());
  impl->acceptor.set_option(net::socket_base::reuse_address(true), ec);
  if (impl->acceptor.bind(endpoint, ec); ec)
    return make_unexpected("cannot listen on " + where + ": " + ec.message());
  if (impl->acceptor.listen(net::socket_base::max_listen_connections, ec); ec)
    return make_unexpected("cannot listen on " + where + ": " + ec.message());
  impl->do_accept();
  impl->on_status_timer();
  Impl* raw = impl.get();
  impl->thread = std::thread([raw] { raw->io.run(); });
  return std::unique_ptr<WsServer>(new WsServer(std::move(impl)));
}

WsServer::WsServer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

WsServer::~WsServer() {
  stop();
}

uint16_t WsServer::port() const {
  beast::error_code ec;
  const auto endpoint = impl_->acceptor.local_endpoint(ec);
  return ec ? impl_->config.port : endpoint.port();
}

bool WsServer::subscribed(uint32_t channel_id) const {
  const auto it = impl_->index_of.find(channel_id);
  return it != impl_->index_of.end() &&
         impl_->subscribers[it->second].load(std::memory_order_relaxed) > 0;
}

void WsServer::publish(uint32_t channel_id, int64_t timestamp_ns,
                       const std::shared_ptr<const std::string>& payload) {
  const std::lock_guard lock(impl_->mutex);
  for (const auto& s : impl_->sessions) s->enqueue(channel_id, timestamp_ns, payload);
}

WsServerStats WsServer::stats() const {
  WsServerStats s;
  s.clients_accepted = impl_->accepted.load();
  s.messages_sent = impl_->sent.load();
  s.bytes_sent = impl_->bytes.load();
  s.messages_dropped = impl_->dropped.load();
  const std::lock_guard lock(impl_->mutex);
  s.clients_now = impl_->sessions.size();
  return s;
}

void WsServer::stop() {
  if (!impl_ || impl_->stopped) return;
  impl_->stopped = true;
  Impl& impl = *impl_;
  net::post(impl.io, [&impl] {
    beast::error_code ec;
    impl.acceptor.close(ec);
    impl.status_timer.cancel();
    std::vector<std::shared_ptr<Session>> now;
    {
      const std::lock_guard lock(impl.mutex);
      now = impl.sessions;
    }
    for (const auto& s : now) s->close();
  });
  {
    std::unique_lock lock(impl.mutex);
    impl.sessions_gone.wait_for(lock, kCloseWait, [&impl] { return impl.sessions.empty(); });
  }
  impl.io.stop();
  if (impl.thread.joinable()) impl.thread.join();
  const std::lock_guard lock(impl.mutex);
  impl.sessions.clear();
}

}  // namespace scancrew::foxglove
