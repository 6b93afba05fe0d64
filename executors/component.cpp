#include "executors/component.hpp"

#include <algorithm>
#include <filesystem>

#include "executors/log.hpp"

namespace scancrew {

std::string_view to_string(LifecycleState state) {
  switch (state) {
    case LifecycleState::kUnconfigured:
      return "unconfigured";
    case LifecycleState::kInactive:
      return "inactive";
    case LifecycleState::kActive:
      return "active";
    case LifecycleState::kFinalized:
      return "finalized";
  }
  return "?";
}

std::string_view to_string(CallbackGroup::Type type) {
  return name_of(kCallbackGroupTypeNames, type);
}

Component::Component(ComponentContext context) : context_(std::move(context)) {
  SCANCREW_CHECK(context_.graph != nullptr, "a component needs a graph");
  if (!context_.callback_group)
    context_.callback_group =
        std::make_shared<CallbackGroup>(context_.name, CallbackGroup::Type::kMutuallyExclusive);
  qualified_name_ = (context_.ns.empty() ? "" : "/" + context_.ns) + "/" + context_.name;
}

Component::~Component() = default;

std::string Component::input_path(std::string_view key, const std::string& value) const {
  const std::filesystem::path path(value);
  if (value.empty() || path.is_absolute() || context_.launch_dir.empty() ||
      context_.set_keys.count(std::string(key)) > 0)
    return value;
  return (std::filesystem::path(context_.launch_dir) / path).lexically_normal().string();
}

static Result<void, std::string> bad_transition(const std::string& who, std::string_view what,
                                                LifecycleState from) {
  return make_unexpected(who + ": cannot " + std::string(what) + " from state '" +
                         std::string(to_string(from)) + "'");
}

Result<void, std::string> Component::configure() {
  if (state_ != LifecycleState::kUnconfigured)
    return bad_transition(qualified_name_, "configure", state_);
  auto result = on_configure();
  if (!result) errors_.push_back(qualified_name_ + ": " + result.error());
  if (!errors_.empty()) {
    std::string all;
    for (const auto& e : errors_) all += (all.empty() ? "" : "\n") + e;
    return make_unexpected(all);
  }
  state_ = LifecycleState::kInactive;
  return {};
}

Result<void, std::string> Component::activate() {
  if (state_ != LifecycleState::kInactive)
    return bad_transition(qualified_name_, "activate", state_);
  for (Timer* t : timers_) t->reset();
  on_activate();
  state_ = LifecycleState::kActive;
  active_.store(true, std::memory_order_release);
  return {};
}

Result<void, std::string> Component::deactivate() {
  if (state_ != LifecycleState::kActive)
    return bad_transition(qualified_name_, "deactivate", state_);
  active_.store(false, std::memory_order_release);
  on_deactivate();
  state_ = LifecycleState::kInactive;
  return {};
}

Result<void, std::string> Component::shutdown() {
  if (state_ == LifecycleState::kFinalized)
    return bad_transition(qualified_name_, "shutdown", state_);
  if (state_ == LifecycleState::kActive) (void)deactivate();
  on_shutdown();
  state_ = LifecycleState::kFinalized;
  return {};
}

std::string Component::resolve(std::string_view port) const {
  return resolve_in(port, context_.ns);
}

std::string Component::resolve_in(std::string_view port, std::string_view ns) const {
  std::string name(port);
  if (auto it = context_.remaps.find(name); it != context_.remaps.end()) name = it->second;
  if (!name.empty() && name.front() == '/') return name;
  return (ns.empty() ? "" : "/" + std::string(ns)) + "/" + name;
}

std::optional<PortQos> Component::port_qos(std::string_view port) const {
  auto it = context_.qos.find(std::string(port));
  if (it == context_.qos.end()) return std::nullopt;
  return it->second;
}

void Component::note_port(std::string_view port, const std::string& topic, std::string_view type,
                          EndpointInfo::Kind kind, bool connected) {
  ports_.emplace_back(port);
  // an endpoint refused for its type is reported by configure(), not recorded in the graph
  if (connected)
    context_.graph->record({kind, qualified_name_, std::string(port), topic, std::string(type)});
}

void Component::report_failure(const std::string& what) {
  SCANCREW_LOG_ERROR("%s: %s", qualified_name_.c_str(), what.c_str());
  context_.graph->report_failure(qualified_name_ + ": " + what);
}

void Component::mark_input_optional(std::string_view port) {
  context_.graph->mark_optional(qualified_name_, std::string(port));
}

const std::vector<TeamMember>& Component::team() const {
  static const std::vector<TeamMember> none;
  return context_.team ? *context_.team : none;
}

Timer* Component::create_timer(std::chrono::nanoseconds period, Timer::Callback callback) {
  auto timer = std::make_unique<Timer>(clock(), period.count(), std::move(callback),
                                       *context_.callback_group, &active_);
  Timer* raw = timer.get();
  raw->set_trace_component(trace_name());
  owned_.push_back(std::move(timer));
  executables_.push_back(raw);
  timers_.push_back(raw);
  return raw;
}

}  // namespace scancrew
