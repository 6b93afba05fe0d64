// The message codec (interfaces/codec.hpp), as recordings and the DDS bridge use it: the
// first byte picks the wire message type, the rest is decoded as it. A decoded message must
// encode to bytes that decode to the same encoding (no state the codec cannot carry).
#include <cstdlib>
#include <span>
#include <vector>

#include "fuzz/fuzz_input.hpp"
#include "interfaces/codec.hpp"
#include "interfaces/message_fields.hpp"

namespace {

template <class... T>
constexpr size_t count(scancrew::msg::TypeList<T...> /*types*/) {
  return sizeof...(T);
}

template <class T>
void round_trip(std::span<const uint8_t> bytes) {
  T message;
  if (!scancrew::msg::decode(bytes, message)) return;
  const std::vector<uint8_t> once = scancrew::msg::encode(message);
  T again;
  if (!scancrew::msg::decode(std::span<const uint8_t>(once), again)) std::abort();
  if (scancrew::msg::encode(again) != once) std::abort();
}

template <class... T>
void decode_as(size_t index, std::span<const uint8_t> bytes,
               scancrew::msg::TypeList<T...> /*types*/) {
  size_t i = 0;
  ((i++ == index ? round_trip<T>(bytes) : void()), ...);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const scancrew::msg::WireMessages types;
  decode_as(data[0] % count(types), std::span<const uint8_t>(data + 1, size - 1), types);
  return 0;
}
