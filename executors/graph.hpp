#pragma once

// Graph: everything one process shares between its components — the clock and the
// topics by name — and a record of who publishes and subscribes where, so the composed
// graph can be printed and checked (unconnected inputs, type mismatches).
//
// Ownership: the Graph owns the topics (shared with the endpoints that use them); it must
// outlive every component, endpoint and sample of the process.
// Thread safety: all member functions may be called from any thread; topic creation and
// endpoint records take a mutex and allocate (set-up time only).

#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/result.hpp"
#include "executors/clock.hpp"
#include "executors/topic.hpp"

namespace scancrew {

struct EndpointInfo {
  enum class Kind { kPublisher, kSubscription };
  Kind kind;
  std::string component;  // fully qualified instance name, e.g. /robot1/stereo
  std::string port;       // the name the component uses in code
  std::string topic;      // the resolved topic name
  std::string type_name;
};

struct GraphReport {
  std::vector<std::string> errors;    // type mismatches
  std::vector<std::string> warnings;  // inputs nobody publishes, outputs nobody reads
  // optional inputs (Component::mark_input_optional) nobody publishes: nothing is wrong, so
  // not warnings; `scancrew graph` lists them
  std::vector<std::string> notes;
  // the inputs nobody publishes (warned above), but those their component marks optional
  std::vector<EndpointInfo> unconnected_inputs;
};

class Graph {
 public:
  explicit Graph(std::shared_ptr<Clock> clock) : clock_(std::move(clock)) {}

  Clock& clock() { return *clock_; }
  const std::shared_ptr<Clock>& clock_ptr() const { return clock_; }

  // The topic of this name, created with pool_size slots if new. An existing topic of
  // another type is an error naming both types and the endpoints already on it.
  template <Message T>
  Result<std::shared_ptr<Topic<T>>, std::string> topic(const std::string& name, size_t pool_size) {
    std::lock_guard lock(mutex_);
    auto it = topics_.find(name);
    if (it == topics_.end()) {
      auto topic = std::make_shared<Topic<T>>(name, pool_size);
      topics_.emplace(name, topic);
      order_.push_back(name);
      return topic;
    }
    if (it->second->type_tag() != message_type_tag<T>())
      return make_unexpected(mismatch_message(name, it->second->type_name(), T::kTypeName));
    return std::static_pointer_cast<Topic<T>>(it->second);
  }

  void record(EndpointInfo endpoint);
  // An input its component does without (Component::mark_input_optional).
  void mark_optional(const std::string& component, const std::string& port);
  std::vector<EndpointInfo> endpoints() const;
  std::vector<std::string> topic_names() const;  // in creation order
  std::shared_ptr<TopicBase> find(const std::string& name) const;
  std::vector<TopicStats> stats() const;
  GraphReport check() const;
  // What failed during the run and lost something (an output not written, a recording that
  // stopped playing): Component::report_failure. scancrew run exits 4 when any did.
  void report_failure(std::string what);
  std::vector<std::string> failures() const;

 private:
  std::string mismatch_message(const std::string& name, const std::string& have,
                               std::string_view want) const;

  std::shared_ptr<Clock> clock_;
  mutable std::mutex mutex_;
  std::set<std::pair<std::string, std::string>> optional_inputs_;  // (component, port)
  std::unordered_map<std::string, std::shared_ptr<TopicBase>> topics_;
  std::vector<std::string> order_;
  std::vector<EndpointInfo> endpoints_;
  std::vector<std::string> failures_;
};

}  // namespace scancrew
