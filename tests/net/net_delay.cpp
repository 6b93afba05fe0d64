// net_delay: holds every packet of an NFQUEUE queue for a fixed time, then lets it through:
// a link delay for the network-fault runs (scripts/net_faults.sh) on kernels without packet
// schedulers (tc netem). Packets are released in arrival order; the kernel queue is bounded
// (a packet that finds it full is dropped, as on a congested link).
//
//   net_delay QUEUE DELAY_MS     (root; iptables ... -j NFQUEUE --queue-num QUEUE)
// Runs until SIGINT or SIGTERM.

#include <arpa/inet.h>
#include <libnetfilter_queue/libnetfilter_queue.h>
#include <linux/netfilter.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>

namespace {

using Clock = std::chrono::steady_clock;

struct Held {
  uint32_t id;
  Clock::time_point due;
};

struct State {
  std::deque<Held> held;
  Clock::duration delay{};
};

volatile sig_atomic_t stop = 0;

int on_packet(nfq_q_handle* /*queue*/, nfgenmsg* /*message*/, nfq_data* data, void* user) {
  auto* state = static_cast<State*>(user);
  const nfqnl_msg_packet_hdr* header = nfq_get_msg_packet_hdr(data);
  if (header == nullptr) return 0;
  state->held.push_back({ntohl(header->packet_id), Clock::now() + state->delay});
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: net_delay QUEUE DELAY_MS\n");
    return 2;
  }
  const int queue_num = std::atoi(argv[1]);
  State state;
  state.delay = std::chrono::microseconds(static_cast<int64_t>(std::atof(argv[2]) * 1000));
  signal(SIGINT, [](int) { stop = 1; });
  signal(SIGTERM, [](int) { stop = 1; });

  nfq_handle* handle = nfq_open();
  if (handle == nullptr) {
    std::perror("net_delay: nfq_open");
    return 1;
  }
  nfq_q_handle* queue =
      nfq_create_queue(handle, static_cast<uint16_t>(queue_num), on_packet, &state);
  if (queue == nullptr || nfq_set_mode(queue, NFQNL_COPY_META, 0) < 0) {
    std::fprintf(stderr, "net_delay: cannot bind queue %d (another reader? root?)\n", queue_num);
    return 1;
  }
  nfq_set_queue_maxlen(queue, 20000);
  const int fd = nfq_fd(handle);
  int buffer = 8 << 20;
  setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &buffer, sizeof buffer);
  std::fprintf(stderr, "net_delay: queue %d, %.1f ms\n", queue_num, std::atof(argv[2]));
  alignas(8) char packet[65536 + 512];
  while (stop == 0) {
    // release what is due, then wait for a packet or the next due time
    const auto now = Clock::now();
    while (!state.held.empty() && state.held.front().due <= now) {
      nfq_set_verdict(queue, state.held.front().id, NF_ACCEPT, 0, nullptr);
      state.held.pop_front();
    }
    int timeout_ms = 100;
    if (!state.held.empty())
      timeout_ms = static_cast<int>(
          std::chrono::ceil<std::chrono::milliseconds>(state.held.front().due - Clock::now())
              .count());
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, timeout_ms < 0 ? 0 : timeout_ms) <= 0) continue;
    const ssize_t n = recv(fd, packet, sizeof packet, MSG_DONTWAIT);
    if (n > 0) nfq_handle_packet(handle, packet, static_cast<int>(n));
  }
  for (const Held& h : state.held) nfq_set_verdict(queue, h.id, NF_ACCEPT, 0, nullptr);
  nfq_destroy_queue(queue);
  nfq_close(handle);
  return 0;
}
