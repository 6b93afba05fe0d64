#pragma once

// Message types of the runtime tests.

#include <cstdint>
#include <vector>

#include "interfaces/header.hpp"

namespace scancrew::test {

struct Counter {
  static constexpr const char* kTypeName = "scancrew/test/Counter";
  msg::Header header;
  uint64_t value = 0;
};

struct Blob {
  static constexpr const char* kTypeName = "scancrew/test/Blob";
  msg::Header header;
  std::vector<uint8_t> bytes;
};

}  // namespace scancrew::test
