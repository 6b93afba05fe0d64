#include "fuzz/fuzz_input.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace scancrew::fuzz {

std::string as_file(const uint8_t* data, size_t size) {
  static const int fd = [] {
    const int created = memfd_create("scancrew-fuzz", 0);
    if (created < 0) {
      std::perror("memfd_create");
      std::abort();
    }
    return created;
  }();
  if (ftruncate(fd, 0) != 0 ||
      (size > 0 && pwrite(fd, data, size, 0) != static_cast<ssize_t>(size))) {
    std::perror("memfd write");
    std::abort();
  }
  return "/proc/self/fd/" + std::to_string(fd);
}

}  // namespace scancrew::fuzz
