#pragma once

// The binary codec of messages, for recordings and links between robots: every field of
// visit_fields() in order, little-endian, no padding; a vector is its u32 element count then
// its elements. Decoding checks every length against the bytes left, so a malformed,
// truncated or hostile buffer is an error, never an overread or a huge allocation.
//
// encode(message, bytes) appends; decode(bytes, message) fills message (reusing its vector
// capacity) and fails unless it consumes exactly all the bytes.

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "core/result.hpp"
#include "interfaces/message_fields.hpp"

namespace scancrew::msg {

static_assert(std::endian::native == std::endian::little,
              "the codec writes memory as is: a big-endian port must byte-swap here");

namespace codec_detail {

template <class T>
struct IsVector : std::false_type {};
template <class T, class A>
struct IsVector<std::vector<T, A>> : std::true_type {};
template <class T>
struct IsArray : std::false_type {};
template <class T, size_t N>
struct IsArray<std::array<T, N>> : std::true_type {};

template <class T>
constexpr bool kPlain = std::is_arithmetic_v<T> || std::is_enum_v<T>;

struct Writer {
  std::vector<uint8_t>& out;

  void append(const void* data, size_t n) {
    if (n == 0) return;
    const size_t at = out.size();
    out.resize(at + n);
    std::memcpy(out.data() + at, data, n);
  }

  template <class T>
  void put(const T& v) {
    if constexpr (kPlain<T>) {
      append(&v, sizeof(T));
    } else if constexpr (IsVector<T>::value) {
      put(static_cast<uint32_t>(v.size()));
      if constexpr (kPlain<typename T::value_type>) {
        append(v.data(), v.size() * sizeof(typename T::value_type));
      } else {
        for (const auto& e : v) put(e);
      }
    } else if constexpr (IsArray<T>::value) {
      for (const auto& e : v) put(e);
    } else {
      visit_fields(v, [this](const auto&... f) { (put(f), ...); });
    }
  }
};

// Bytes of the smallest encoding of T (all its vectors empty).
template <class T>
size_t min_wire_size() {
  static const size_t size = [] {
    std::vector<uint8_t> out;
    Writer{out}.put(T{});
    return out.size();
  }();
  return size;
}

struct Reader {
  std::span<const uint8_t> in;
  size_t at = 0;
  bool ok = true;

  bool take(void* dst, size_t n) {
    if (!ok || in.size() - at < n) return ok = false;
    if (n > 0) std::memcpy(dst, in.data() + at, n);
    at += n;
    return true;
  }

  template <class T>
  void get(T& v) {
    if constexpr (kPlain<T>) {
      take(&v, sizeof(T));
    } else if constexpr (IsVector<T>::value) {
      uint32_t n = 0;
      if (!take(&n, sizeof n)) return;
      using E = typename T::value_type;
      // a count the bytes left cannot hold is malformed (checked before allocating)
      if (n > (in.size() - at) / min_wire_size<E>()) {
        ok = false;
        return;
      }
      v.resize(n);
      if constexpr (kPlain<E>) {
        take(v.data(), size_t{n} * sizeof(E));
      } else {
        for (auto& e : v)
          if (ok) get(e);
      }
    } else if constexpr (IsArray<T>::value) {
      for (auto& e : v) get(e);
    } else {
      visit_fields(v, [this](auto&... f) { (get(f), ...); });
    }
  }
};

}  // namespace codec_detail

template <class T>
void encode(const T& message, std::vector<uint8_t>& out) {
  codec_detail::Writer{out}.put(message);
}

template <class T>
std::vector<uint8_t> encode(const T& message) {
  std::vector<uint8_t> out;
  encode(message, out);
  return out;
}

template <class T>
Result<void, std::string> decode(std::span<const uint8_t> bytes, T& message) {
  codec_detail::Reader reader{bytes};
  reader.get(message);
  if (!reader.ok)
    return make_unexpected(std::string("truncated or malformed ") + T::kTypeName + " (" +
                           std::to_string(bytes.size()) + " bytes)");
  if (reader.at != bytes.size())
    return make_unexpected(std::string(T::kTypeName) + ": " +
                           std::to_string(bytes.size() - reader.at) + " trailing bytes");
  return {};
}

}  // namespace scancrew::msg
