#pragma once

// Component: the base class of everything in a robot graph (rclcpp's lifecycle node,
// without the service plumbing).
//
// Lifecycle: unconfigured --configure--> inactive --activate--> active
//            active --deactivate--> inactive;  any --shutdown--> finalized.
// on_configure() creates the endpoints and timers (nothing runs yet); while inactive,
// no callback of the component runs and its publishers refuse to publish
// (PublishError::kInactive); incoming samples wait in their bounded queues.
//
// Each component has a typed Config (a plain struct with defaults and units) read by
// its static read_config(ParamReader&) at launch; algorithms never see YAML.
//
// Thread safety: lifecycle transitions are made by one thread (the launcher) while no
// executor is spinning the component's executables, or with the executor running (the
// active flag is atomic). Endpoints are created in on_configure() only.

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "core/robot/robot_kind.hpp"
#include "executors/graph.hpp"
#include "executors/publisher.hpp"
#include "executors/run_summary.hpp"
#include "executors/subscription.hpp"
#include "executors/timer.hpp"

namespace scancrew {

// Per-port QoS set in the launch file (missing fields keep the code's choice).
struct PortQos {
  std::optional<size_t> pool_size;
  std::optional<size_t> depth;
  std::optional<History> history;
};

// A robot of the team, as the launch file declares it (robots: section).
struct TeamMember {
  uint32_t id = 0;
  std::string ns;  // namespace, e.g. "robot1"
  robot::RobotKind kind = robot::RobotKind::kGround;
  double start_x_m = 0, start_y_m = 0, start_z_m = 0, start_yaw_rad = 0;
};

struct ComponentContext {
  Graph* graph = nullptr;
  std::shared_ptr<const std::vector<TeamMember>> team;  // every robot of the launch file
  std::string name;                                     // instance name, e.g. "stereo_depth"
  std::string ns;                                       // namespace, e.g. "robot1" ("" = root)
  uint32_t robot_id = 0;
  std::map<std::string, std::string> remaps;      // port -> topic name (relative or absolute)
  std::map<std::string, PortQos> qos;             // port -> QoS overrides
  std::shared_ptr<CallbackGroup> callback_group;  // default group of the component
  std::string security_keys;                      // LaunchSettings::security_keys
  // Where a relative input file's path is relative to (input_path): the launch file's
  // directory ("": the working directory), but for the keys given with --set (set_keys).
  std::string launch_dir;
  std::set<std::string> set_keys;
};

enum class LifecycleState { kUnconfigured, kInactive, kActive, kFinalized };
std::string_view to_string(LifecycleState state);

class Component {
 public:
  explicit Component(ComponentContext context);
  virtual ~Component();
  Component(const Component&) = delete;
  Component& operator=(const Component&) = delete;

  // Transitions. An invalid transition or a failing hook returns a message.
  Result<void, std::string> configure();
  Result<void, std::string> activate();
  Result<void, std::string> deactivate();
  Result<void, std::string> shutdown();
  LifecycleState state() const { return state_; }

  // "/robot1/stereo" (or "/stereo" at the root).
  const std::string& qualified_name() const { return qualified_name_; }
  uint32_t robot_id() const { return context_.robot_id; }
  // The executables to hand to an executor after configure().
  const std::vector<Executable*>& executables() const { return executables_; }
  // The port names the component used (for remap validation).
  const std::vector<std::string>& ports() const { return ports_; }

  // Adds what this component has to say about the run (executors/run_summary.hpp): a
  // mapper its map, a planner its tours, the simulator its contacts. Default: nothing.
  virtual void summarize(RunSummary& into) const { (void)into; }

  // Resolves a port to its topic: remap if any, then the namespace for relative names.
  std::string resolve(std::string_view port) const;
  // The same port of a teammate: its remap applied in namespace `ns` ("/<ns>/<topic>"); an
  // absolute remap stays as it is. A component that reads every robot's pose subscribes
  // resolve_in("pose", m.ns) for each, so one remap (pose: odom) serves them all.
  std::string resolve_in(std::string_view port, std::string_view ns) const;

 protected:
  // Create endpoints and timers here. Return an error message to fail configuration.
  virtual Result<void, std::string> on_configure() = 0;
  virtual void on_activate() {}
  virtual void on_deactivate() {}
  virtual void on_shutdown() {}

  template <Message T>
  Publisher<T> create_publisher(std::string_view port, PublisherQos qos = {}) {
    const std::string topic_name = resolve(port);
    if (auto o = port_qos(port); o && o->pool_size) qos.pool_size = *o->pool_size;
    auto topic = context_.graph->topic<T>(topic_name, qos.pool_size);
    note_port(port, topic_name, T::kTypeName, EndpointInfo::Kind::kPublisher, topic.has_value());
    if (!topic) {
      errors_.push_back(qualified_name_ + "." + std::string(port) + ": " + topic.error());
      return {};
    }
    return Publisher<T>(std::move(topic).value(), context_.robot_id, &context_.graph->clock(),
                        &active_);
  }

  // The input `port` (already created) is one the component does without: a mission whose
  // graph leaves it unconnected is not refused for it (scancrew run).
  void mark_input_optional(std::string_view port);

  // The subscription lives as long as the component; null when the topic has another
  // type (configure() then fails with the reason).
  template <Message T>
  Subscription<T>* create_subscription(std::string_view port, SubscriptionQos qos,
                                       typename Subscription<T>::Callback callback) {
    return subscribe<T>(port, resolve(port), qos, std::move(callback));
  }
  // The same `port` of the teammate in namespace `ns` (resolve_in): recorded as the port, so
  // the component's remap and qos for it serve every teammate's subscription as its own.
  template <Message T>
  Subscription<T>* create_teammate_subscription(std::string_view port, std::string_view ns,
                                                SubscriptionQos qos,
                                                typename Subscription<T>::Callback callback) {
    return subscribe<T>(port, resolve_in(port, ns), qos, std::move(callback));
  }

  // A timer on the graph's clock (wall or sim), firing every period while active.
  Timer* create_timer(std::chrono::nanoseconds period, Timer::Callback callback);

  Clock& clock() { return context_.graph->clock(); }
  // The robots of the launch file (empty when the component was built outside one).
  const std::vector<TeamMember>& team() const;
  // The launch file's security.keys (empty: none).
  const std::string& security_keys() const { return context_.security_keys; }
  // The file a path parameter (`key`) names, to read: a relative path is relative to the
  // launch file's directory, as a scene's mesh files are to the scene (MuJoCo's file=,
  // ROS 2 launch's include), but one given with --set, typed at a shell, is relative to
  // the working directory. Absolute and empty paths come back as they are.
  std::string input_path(std::string_view key, const std::string& value) const;
  Graph& graph() { return *context_.graph; }
  // Something failed that loses data or output (a file not written, a replay stopped):
  // logged as an error and kept by the graph, so the run's exit status says so.
  void report_failure(const std::string& what);

 private:
  std::optional<PortQos> port_qos(std::string_view port) const;
  // The name a Tracer reports the component's callbacks by: "robot1/stereo".
  std::string trace_name() const { return qualified_name_.substr(1); }
  void note_port(std::string_view port, const std::string& topic, std::string_view type,
                 EndpointInfo::Kind kind, bool connected);
  template <Message T>
  Subscription<T>* subscribe(std::string_view port, const std::string& topic_name,
                             SubscriptionQos qos, typename Subscription<T>::Callback callback) {
    if (auto o = port_qos(port)) {
      if (o->depth) qos.depth = *o->depth;
      if (o->history) qos.history = *o->history;
    }
    auto topic = context_.graph->topic<T>(topic_name, PublisherQos{}.pool_size);
    note_port(port, topic_name, T::kTypeName, EndpointInfo::Kind::kSubscription, topic.has_value());
    if (!topic) {
      errors_.push_back(qualified_name_ + "." + std::string(port) + ": " + topic.error());
      return nullptr;
    }
    auto sub = std::make_unique<Subscription<T>>(std::move(topic).value(), qos, std::move(callback),
                                                 *context_.callback_group, &active_);
    Subscription<T>* raw = sub.get();
    raw->set_trace_component(trace_name());
    owned_.push_back(std::move(sub));
    executables_.push_back(raw);
    return raw;
  }

  ComponentContext context_;
  std::string qualified_name_;
  LifecycleState state_ = LifecycleState::kUnconfigured;
  std::atomic<bool> active_{false};
  std::vector<std::unique_ptr<Executable>> owned_;
  std::vector<Executable*> executables_;
  std::vector<Timer*> timers_;
  std::vector<std::string> ports_;
  std::vector<std::string> errors_;
};

}  // namespace scancrew
