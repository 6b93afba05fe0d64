#include "tests/executors/test_components.hpp"

#include "executors/registry.hpp"

namespace scancrew::test {

std::atomic<int> Talker::constructed{0};
std::atomic<int> Listener::activated{0};

Talker::Config Talker::read_config(ParamReader& p) {
  Config c;
  p.required("period_s", c.period_s, {1e-6, 100});
  p.optional("start", c.start);
  constructed.fetch_add(1);
  return c;
}

Result<void, std::string> Talker::on_configure() {
  out_ = create_publisher<Counter>("out");
  next_ = config_.start;
  create_timer(std::chrono::nanoseconds(static_cast<int64_t>(config_.period_s * 1e9)), [this] {
    auto loan = out_.loan();
    if (!loan) return;
    (*loan)->value = next_++;
    (void)out_.publish(std::move(*loan));
  });
  return {};
}

Result<void, std::string> Listener::on_configure() {
  create_subscription<Counter>("in", {.depth = 8}, [this](Sample<Counter>&& s) {
    received_.fetch_add(1);
    last_.store(s->value);
  });
  return {};
}

Result<void, std::string> BlobListener::on_configure() {
  create_subscription<Blob>("in", {.depth = 2}, [](Sample<Blob>&&) {});
  return {};
}

SCANCREW_REGISTER_COMPONENT(Talker, "test_talker")
SCANCREW_REGISTER_COMPONENT(Listener, "test_listener")
SCANCREW_REGISTER_COMPONENT(BlobListener, "test_blob_listener")

}  // namespace scancrew::test
