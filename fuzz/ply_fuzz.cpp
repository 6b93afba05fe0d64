// The PLY mesh reader (core/io/ply.hpp), ASCII and binary: its cost must stay bounded by
// the file's size (a count of 2^62 in a 300-byte file once looped for centuries).
#include "core/io/ply.hpp"
#include "fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)scancrew::io::read_ply_mesh(scancrew::fuzz::as_file(data, size));
  return 0;
}
