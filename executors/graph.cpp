#include "executors/graph.hpp"

#include <set>

namespace scancrew {

void Graph::record(EndpointInfo endpoint) {
  std::lock_guard lock(mutex_);
  endpoints_.push_back(std::move(endpoint));
}

void Graph::mark_optional(const std::string& component, const std::string& port) {
  std::lock_guard lock(mutex_);
  optional_inputs_.emplace(component, port);
}

void Graph::report_failure(std::string what) {
  std::lock_guard lock(mutex_);
  failures_.push_back(std::move(what));
}

std::vector<std::string> Graph::failures() const {
  std::lock_guard lock(mutex_);
  return failures_;
}

std::vector<EndpointInfo> Graph::endpoints() const {
  std::lock_guard lock(mutex_);
  return endpoints_;
}

std::vector<std::string> Graph::topic_names() const {
  std::lock_guard lock(mutex_);
  return order_;
}

std::shared_ptr<TopicBase> Graph::find(const std::string& name) const {
  std::lock_guard lock(mutex_);
  auto it = topics_.find(name);
  return it == topics_.end() ? nullptr : it->second;
}

std::vector<TopicStats> Graph::stats() const {
  std::vector<TopicStats> out;
  for (const std::string& name : topic_names()) out.push_back(find(name)->stats());
  return out;
}

std::string Graph::mismatch_message(const std::string& name, const std::string& have,
                                    std::string_view want) const {
  std::string users;
  for (const EndpointInfo& e : endpoints_) {
    if (e.topic != name) continue;
    users += (users.empty() ? "" : ", ") + e.component + "." + e.port;
  }
  return "topic type mismatch on '" + name + "': it carries '" + have + "' (used by " +
         (users.empty() ? std::string("nobody yet") : users) + ") but this endpoint wants '" +
         std::string(want) + "'";
}

GraphReport Graph::check() const {
  std::lock_guard lock(mutex_);
  GraphReport report;
  std::set<std::string> published, subscribed;
  for (const EndpointInfo& e : endpoints_)
    (e.kind == EndpointInfo::Kind::kPublisher ? published : subscribed).insert(e.topic);
  for (const EndpointInfo& e : endpoints_) {
    if (e.kind == EndpointInfo::Kind::kSubscription && !published.count(e.topic)) {
      const bool optional = optional_inputs_.count({e.component, e.port}) > 0;
      (optional ? report.notes : report.warnings)
          .push_back("unconnected input: " + e.component + "." + e.port + " reads '" + e.topic +
                     "' (" + e.type_name + ") but nothing publishes it" +
                     (optional ? " (optional)" : ""));
      if (!optional) report.unconnected_inputs.push_back(e);
    }
    if (e.kind == EndpointInfo::Kind::kPublisher && !subscribed.count(e.topic))
      report.warnings.push_back("unread output: " + e.component + "." + e.port + " writes '" +
                                e.topic + "' (" + e.type_name + ") but nothing subscribes");
  }
  // endpoints recorded with a type other than their topic's (creation failed for them)
  for (const EndpointInfo& e : endpoints_) {
    auto it = topics_.find(e.topic);
    if (it != topics_.end() && it->second->type_name() != e.type_name)
      report.errors.push_back("type mismatch: " + e.component + "." + e.port + " wants '" +
                              e.type_name + "' on '" + e.topic + "', which carries '" +
                              it->second->type_name() + "'");
  }
  return report;
}

}  // namespace scancrew
