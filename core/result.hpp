#pragma once

// Result<T, E>: a value or a named error, for failures on the data path (a loan that
// cannot be served, a queue that is full, a launch file that is wrong). A stand-in for
// std::expected, which Debian 12's g++ only offers in C++23 mode.

#include <optional>
#include <type_traits>
#include <utility>
#include <variant>

#include "core/check.hpp"

namespace scancrew {

template <class E>
struct Unexpected {
  E error;
};

template <class E>
Unexpected<std::decay_t<E>> make_unexpected(E&& e) {
  return {std::forward<E>(e)};
}

template <class T, class E>
class [[nodiscard]] Result {
 public:
  // implicit from a value or an Unexpected, like std::expected
  Result(T value) : v_(std::in_place_index<0>, std::move(value)) {}
  template <class G>
  Result(Unexpected<G> e) : v_(std::in_place_index<1>, std::move(e.error)) {}

  bool has_value() const { return v_.index() == 0; }
  explicit operator bool() const { return has_value(); }

  T& value() & {
    SCANCREW_CHECK(has_value(), "Result::value() on an error");
    return std::get<0>(v_);
  }
  const T& value() const& {
    SCANCREW_CHECK(has_value(), "Result::value() on an error");
    return std::get<0>(v_);
  }
  T&& value() && {
    SCANCREW_CHECK(has_value(), "Result::value() on an error");
    return std::get<0>(std::move(v_));
  }
  const E& error() const {
    SCANCREW_CHECK(!has_value(), "Result::error() on a value");
    return std::get<1>(v_);
  }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T&& operator*() && { return std::move(*this).value(); }

 private:
  std::variant<T, E> v_;
};

// Result<void, E>: success or a named error.
template <class E>
class [[nodiscard]] Result<void, E> {
 public:
  Result() = default;
  template <class G>
  Result(Unexpected<G> e) : error_(std::move(e.error)) {}

  bool has_value() const { return !error_.has_value(); }
  explicit operator bool() const { return has_value(); }
  const E& error() const {
    SCANCREW_CHECK(error_.has_value(), "Result::error() on a success");
    return *error_;
  }

 private:
  std::optional<E> error_;
};

}  // namespace scancrew
