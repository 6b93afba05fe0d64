#pragma once

// Quality of service of intra-process topics. Everything is bounded: a topic owns a
// fixed pool of slots, every subscription a fixed-depth queue.

#include <cstddef>
#include <string_view>

#include "core/enum_names.hpp"

namespace scancrew {

enum class History {
  kKeepLast,  // a full queue drops its oldest sample to take the new one (counted as a drop)
  kFailFast,  // publish() fails with PublishError::kQueueFull and delivers to nobody
};
inline constexpr EnumNames<History, 2> kHistoryNames = {
    {{History::kKeepLast, "keep_last"}, {History::kFailFast, "fail_fast"}}};
std::string_view to_string(History history);

struct PublisherQos {
  // Slots in the topic's pool, fixed when the topic is created by its first endpoint.
  // Must cover: samples queued in every subscription + samples held by callbacks + loans.
  size_t pool_size = 16;
};

struct SubscriptionQos {
  size_t depth = 4;  // queue capacity in samples
  History history = History::kKeepLast;
};

}  // namespace scancrew
