#pragma once

// EnumNames: an enum's values beside the names a launch file, a log line or a run
// directory spells them with; the one place each name is written. ParamReader::choice
// parses with it (the error lists the names), name_of() prints with it. Like rclcpp's
// parameter descriptors, the allowed values are data, not a chain of string compares.

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

namespace scancrew {

template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

template <class E, size_t N>
using EnumNames = std::array<EnumName<E>, N>;

// The name of `value`; "?" for a value the table leaves out (a bug: tables list every value).
template <class E, size_t N>
constexpr std::string_view name_of(const EnumNames<E, N>& names, E value) {
  for (const auto& n : names)
    if (n.value == value) return n.name;
  return "?";
}

// The value named `name`, if the table has it.
template <class E, size_t N>
constexpr std::optional<E> value_of(const EnumNames<E, N>& names, std::string_view name) {
  for (const auto& n : names)
    if (n.name == name) return n.value;
  return std::nullopt;
}

}  // namespace scancrew
