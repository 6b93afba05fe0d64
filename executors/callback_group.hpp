#pragma once

// CallbackGroup: which callbacks may run at the same time (rclcpp's rule).
//  - mutually exclusive: at most one callback of the group runs at any time;
//  - reentrant: callbacks of the group may run concurrently, including the same one.
// A single-threaded executor runs one callback at a time whatever the group.
// Thread safety: try_enter()/leave() may be called from any thread.

#include <atomic>
#include <string>
#include <string_view>

#include "core/enum_names.hpp"

namespace scancrew {

class CallbackGroup {
 public:
  enum class Type { kMutuallyExclusive, kReentrant };

  CallbackGroup(std::string name, Type type) : name_(std::move(name)), type_(type) {}
  CallbackGroup(const CallbackGroup&) = delete;
  CallbackGroup& operator=(const CallbackGroup&) = delete;

  const std::string& name() const { return name_; }
  Type type() const { return type_; }

  // True when a callback of this group may start now; for a mutually exclusive group
  // the caller then owns the group until leave().
  bool try_enter() {
    if (type_ == Type::kReentrant) return true;
    bool expected = false;
    return busy_.compare_exchange_strong(expected, true, std::memory_order_acquire);
  }
  void leave() {
    if (type_ == Type::kMutuallyExclusive) busy_.store(false, std::memory_order_release);
  }

 private:
  std::string name_;
  Type type_;
  std::atomic<bool> busy_{false};
};

inline constexpr EnumNames<CallbackGroup::Type, 2> kCallbackGroupTypeNames = {
    {{CallbackGroup::Type::kMutuallyExclusive, "mutually_exclusive"},
     {CallbackGroup::Type::kReentrant, "reentrant"}}};
std::string_view to_string(CallbackGroup::Type type);

}  // namespace scancrew
