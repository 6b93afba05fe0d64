#include "components/recorder/replay.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/codec.hpp"

namespace scancrew::recorder {

Replay::Config Replay::read_config(ParamReader& p) {
  Config c;
  p.required("path", c.path).doc("the MCAP recording to play");
  p.choice("timing", c.timing, kReplayTimingNames)
      .doc(
          "relative (the recorded spacing, from the first tick) or absolute (when the clock "
          "reaches each recorded receive time)");
  p.optional("rate", c.rate, {1e-3, 1e3}).doc("playback speed (relative timing)");
  p.optional("tick_s", c.tick_s, {1e-5, 1}).doc("how often due messages are published (s)");
  p.optional_list("topics", c.topics).doc("absolute names to play (empty: all)");
  return c;
}

Replay::Replay(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

Result<void, std::string> Replay::on_configure() {
  config_.path = input_path("path", config_.path);
  auto reader = RecordingReader::open(config_.path);
  if (!reader) return make_unexpected(reader.error());
  reader_.emplace(std::move(reader).value());
  if (auto scanned = reader_->scan_topics(); !scanned) return scanned;
  for (const std::string& wanted : config_.topics) {
    const auto& t = reader_->topics();
    if (std::none_of(t.begin(), t.end(), [&](const LogTopic& lt) { return lt.name == wanted; }))
      return make_unexpected("topic '" + wanted + "' is not in the recording '" + config_.path +
                             "'");
  }
  for (const LogTopic& topic : reader_->topics()) {
    const bool wanted =
        config_.topics.empty() ||
        std::find(config_.topics.begin(), config_.topics.end(), topic.name) != config_.topics.end();
    if (!wanted) {
      publish_.emplace_back();
      continue;
    }
    const bool known = msg::with_wire_message(topic.type, [&]<class T>() {
      // std::function needs a copyable target: the publisher is shared
      publish_.emplace_back([this, pub = std::make_shared<Publisher<T>>(create_publisher<T>(
                                       topic.name))](std::span<const uint8_t> bytes) {
        auto loan = pub->loan();
        if (!loan) return Outcome::kPoolExhausted;
        if (auto decoded = msg::decode(bytes, **loan); !decoded) {
          if (decode_errors_++ == 0)
            SCANCREW_LOG_ERROR("%s: %s: %s (skipped; further errors are counted)",
                               qualified_name().c_str(), pub->topic_name().c_str(),
                               decoded.error().c_str());
          return Outcome::kDropped;
        }
        (void)pub->forward(std::move(*loan));
        return Outcome::kPublished;
      });
    });
    if (!known)
      return make_unexpected("recording '" + config_.path + "': topic '" + topic.name +
                             "' has type '" + topic.type + "', which this build cannot replay");
  }
  create_timer(std::chrono::nanoseconds(std::llround(config_.tick_s * 1e9)), [this] { tick(); });
  return {};
}

bool Replay::due(int64_t receive_ns, int64_t now_ns) {
  if (config_.timing == ReplayTiming::kAbsolute) return now_ns >= receive_ns;
  if (!start_ns_) {
    start_ns_ = now_ns;
    first_receive_ns_ = receive_ns;
  }
  // in doubles: a forged receive time (INT64_MAX, or below the first) must not overflow
  const double offset =
      (static_cast<double>(receive_ns) - static_cast<double>(*first_receive_ns_)) / config_.rate;
  return static_cast<double>(now_ns - *start_ns_) >= offset;
}

void Replay::tick() {
  const int64_t now = clock().now_ns();
  while (!finished_) {
    if (!pending_) {
      auto next = reader_->next();
      if (!next) {
        report_failure(next.error() + "; replay stops after " + std::to_string(published_) +
                       " messages");
        finished_ = true;
        return;
      }
      if (!*next) {
        finished_ = true;
        // messages that did not decode were skipped: the replay is not whole (exit 4)
        if (decode_errors_ > 0)
          report_failure(std::to_string(decode_errors_) + " message(s) of " + config_.path +
                         " did not decode and were skipped");
        SCANCREW_LOG_INFO(
            "%s: replay of %s done: %llu messages%s", qualified_name().c_str(),
            config_.path.c_str(), static_cast<unsigned long long>(published_),
            reader_->truncated() ? " (the recording is cut short: played up to the cut)" : "");
        return;
      }
      pending_ = *next;
    }
    if (pending_->topic >= publish_.size() || !publish_[pending_->topic]) {  // filtered out
      pending_.reset();
      continue;
    }
    if (!due(pending_->receive_ns, now)) return;
    switch (publish_[pending_->topic](pending_->message)) {
      case Outcome::kPoolExhausted:
        ++pool_waits_;
        return;  // try again at the next tick: nothing is skipped
      case Outcome::kPublished:
        ++published_;
        break;
      case Outcome::kDropped:
        break;
    }
    pending_.reset();
  }
}

void Replay::on_deactivate() {
  if (finished_ || !pending_) return;
  const double now = static_cast<double>(clock().now_ns());
  const double due_ns =
      config_.timing == ReplayTiming::kAbsolute
          ? static_cast<double>(pending_->receive_ns)
          : static_cast<double>(start_ns_.value_or(clock().now_ns())) +
                (static_cast<double>(pending_->receive_ns) -
                 static_cast<double>(first_receive_ns_.value_or(pending_->receive_ns))) /
                    config_.rate;
  const double wait_s = (due_ns - now) * 1e-9;
  char why[160];
  if (wait_s > 0)
    std::snprintf(why, sizeof why,
                  "is due %.3g s after the run's end (a recording longer than the run, or a "
                  "corrupt receive time)",
                  wait_s);
  else
    std::snprintf(why, sizeof why, "was due but its topic's pool stayed full");
  SCANCREW_LOG_WARN(
      "%s: %s not played to its end: %llu messages played; the next (in the record ending at "
      "byte %llu) %s",
      qualified_name().c_str(), config_.path.c_str(), static_cast<unsigned long long>(published_),
      static_cast<unsigned long long>(reader_->offset()), why);
}

SCANCREW_REGISTER_COMPONENT(Replay, "replay")

}  // namespace scancrew::recorder
