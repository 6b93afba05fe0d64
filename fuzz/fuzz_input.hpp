// The fuzz harnesses' shared pieces: readers that take a path get the input as an in-memory
// file (memfd), and the libFuzzer entry point's declaration.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace scancrew::fuzz {

// A path (/proc/self/fd/N) to a regular, seekable in-memory file that holds exactly the
// bytes; the same file is rewritten by each call (one input at a time).
std::string as_file(const uint8_t* data, size_t size);

}  // namespace scancrew::fuzz
