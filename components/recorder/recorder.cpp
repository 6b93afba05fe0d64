#include "components/recorder/recorder.hpp"

#include <chrono>

#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/codec.hpp"

namespace scancrew::recorder {

namespace {

std::string wire_type_names() {
  std::string all;
  [&]<class... T>(msg::TypeList<T...>) {
    ((all += (all.empty() ? "" : ", ") + std::string(T::kTypeName)), ...);
  }(msg::WireMessages{});
  return all;
}

}  // namespace

Recorder::Config Recorder::read_config(ParamReader& p) {
  Config c;
  p.required("path", c.path).doc("the MCAP recording to write (overwritten)");
  p.optional_list("topics", c.topics)
      .doc("the topics to record: \"port\" or \"port:Type\" (required)");
  if (c.topics.empty()) p.report("topics", "required: the list of topics to record");
  p.optional("queue_depth", c.queue_depth, {1, 100000})
      .doc("per topic: messages waiting to be written");
  p.optional("flush_period_s", c.flush_period_s, {0.01, 3600})
      .doc("a crash loses at most this much of the recording (s)");
  p.optional("foxglove_channels", c.foxglove_channels)
      .doc(
          "also write Foxglove JSON views of poses, paths, clusters and images "
          "(/foxglove/<topic>)");
  p.optional("foxglove_image_rate_hz", c.foxglove_image_rate_hz, {0.01, 1000})
      .doc("at most this many images per Foxglove image channel per second of stamps");
  return c;
}

Recorder::Recorder(ComponentContext context, Config config)
    : Component(std::move(context)), config_(std::move(config)) {}

uint64_t Recorder::messages_written() const {
  std::lock_guard lock(mutex_);
  return writer_ ? writer_->messages() : 0;
}

Result<void, std::string> Recorder::on_configure() {
  auto writer = RecordingWriter::open(config_.path);
  if (!writer) return make_unexpected(writer.error());
  writer_.emplace(std::move(writer).value());
  if (config_.foxglove_channels) foxglove_.emplace("world", config_.foxglove_image_rate_hz);
  for (const std::string& spec : config_.topics)
    if (auto added = add(spec); !added) return added;
  create_timer(std::chrono::nanoseconds(static_cast<int64_t>(config_.flush_period_s * 1e9)),
               [this] {
                 std::lock_guard lock(mutex_);
                 if (auto r = writer_->flush(); !r && write_errors_++ == 0)
                   report_failure(r.error() + " (further errors are counted)");
               });
  return {};
}

Result<void, std::string> Recorder::add(const std::string& spec) {
  const size_t colon = spec.find(':');
  const std::string port = spec.substr(0, colon);
  std::string type = colon == std::string::npos ? "" : spec.substr(colon + 1);
  const std::string name = resolve(port);
  if (type.empty()) {
    auto topic = graph().find(name);
    if (!topic)
      return make_unexpected("topic '" + name +
                             "' does not exist yet: list the recorder after the components "
                             "that publish it, or give its type as '" +
                             port + ":Type'");
    type = topic->type_name();
  }
  const uint16_t index = writer_->add_topic({name, type});
  const SubscriptionQos qos{.depth = config_.queue_depth};
  const std::optional<size_t> view =
      foxglove_ ? foxglove_->add(writer_->mcap(), name, type) : std::nullopt;
  const bool known = msg::with_wire_message(type, [&]<class T>() {
    create_subscription<T>(port, qos, [this, index, view](Sample<T>&& sample) {
      std::lock_guard lock(mutex_);
      scratch_.clear();
      msg::encode(*sample, scratch_);
      const int64_t now_ns = clock().now_ns();
      write(index, now_ns, scratch_);
      if constexpr (kHasFoxgloveView<T>)
        if (view)
          if (auto r = foxglove_->write(writer_->mcap(), *view, *sample, now_ns);
              !r && write_errors_++ == 0)
            report_failure(r.error() + " (further errors are counted)");
    });
  });
  if (!known)
    return make_unexpected("topic '" + name + "': type '" + type +
                           "' cannot be recorded; allowed: " + wire_type_names());
  return {};
}

void Recorder::write(uint16_t channel, int64_t receive_ns, std::span<const uint8_t> bytes) {
  if (auto r = writer_->write(channel, receive_ns, bytes); !r && write_errors_++ == 0)
    report_failure(r.error() + " (further errors are counted)");
}

void Recorder::on_deactivate() {
  std::lock_guard lock(mutex_);
  if (auto r = writer_->close(); !r && write_errors_++ == 0) report_failure(r.error());
  SCANCREW_LOG_INFO("%s: %llu messages, %.1f MB in %s%s", qualified_name().c_str(),
                    static_cast<unsigned long long>(writer_->messages()),
                    static_cast<double>(writer_->bytes()) * 1e-6, config_.path.c_str(),
                    write_errors_ ? " (WRITE ERRORS: the recording is incomplete)" : "");
}

SCANCREW_REGISTER_COMPONENT(Recorder, "recorder")

}  // namespace scancrew::recorder
