#pragma once

// Components registered only in the runtime test binaries.

#include <atomic>
#include <string_view>

#include "executors/component.hpp"
#include "executors/params.hpp"
#include "tests/executors/test_messages.hpp"

namespace scancrew::test {

// Publishes an incrementing Counter every period_s (required parameter).
class Talker final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: publishes a counter";
  struct Config {
    double period_s = 0;
    uint64_t start = 1;
  };
  static Config read_config(ParamReader& p);
  Talker(ComponentContext context, Config config)
      : Component(std::move(context)), config_(config) {}

  static std::atomic<int> constructed;

 private:
  Result<void, std::string> on_configure() override;
  Config config_;
  Publisher<Counter> out_;
  uint64_t next_ = 0;
};

// Subscribes to Counter on port "in" and counts what it gets.
class Listener final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: counts counters";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  Listener(ComponentContext context, Config /*config*/) : Component(std::move(context)) {}

  uint64_t received() const { return received_.load(); }
  uint64_t last_value() const { return last_.load(); }
  static std::atomic<int> activated;

 private:
  Result<void, std::string> on_configure() override;
  void on_activate() override { activated.fetch_add(1); }
  std::atomic<uint64_t> received_{0}, last_{0};
};

// Subscribes to Blob on port "in": wired to a Counter topic, a type mismatch.
class BlobListener final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: reads blobs";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  BlobListener(ComponentContext context, Config /*config*/) : Component(std::move(context)) {}

 private:
  Result<void, std::string> on_configure() override;
};

}  // namespace scancrew::test
