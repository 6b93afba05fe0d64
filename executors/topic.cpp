#include "executors/topic.hpp"

namespace scancrew {

namespace {
thread_local PublishDeferral* t_deferral = nullptr;
}  // namespace

PublishDeferral* PublishDeferral::current() {
  return t_deferral;
}

PublishDeferral::Scope::Scope(PublishDeferral* deferral) : previous_(t_deferral) {
  t_deferral = deferral;
}

PublishDeferral::Scope::~Scope() {
  t_deferral = previous_;
}

std::string_view to_string(LoanError error) {
  switch (error) {
    case LoanError::kPoolExhausted:
      return "pool exhausted: every slot of the topic's pool is loaned or held by readers";
  }
  return "?";
}

std::string_view to_string(PublishError error) {
  switch (error) {
    case PublishError::kQueueFull:
      return "queue full: a fail-fast subscription has no room; nothing was delivered";
    case PublishError::kInvalidLoan:
      return "invalid loan: empty, already published, or from another topic";
    case PublishError::kInactive:
      return "inactive: the publishing component is not active";
  }
  return "?";
}

std::string_view to_string(History history) {
  return name_of(kHistoryNames, history);
}

TopicStats TopicBase::base_stats() const {
  TopicStats s;
  s.name = name_;
  s.type_name = type_name_;
  s.published = published_.load(std::memory_order_relaxed);
  s.loan_failures = loan_failures_.load(std::memory_order_relaxed);
  s.rejected = rejected_.load(std::memory_order_relaxed);
  const int64_t first = first_publish_ns_.load(std::memory_order_relaxed);
  const int64_t last = last_publish_ns_.load(std::memory_order_relaxed);
  if (s.published > 1 && last > first)
    s.rate_hz = static_cast<double>(s.published - 1) * 1e9 / static_cast<double>(last - first);
  return s;
}

}  // namespace scancrew
