#include "executors/log.hpp"

#include <cstdlib>
#include <cstring>

namespace scancrew::log {

Level threshold() {
  static const Level level = [] {
    // NOLINTNEXTLINE(concurrency-mt-unsafe): read once, in a static initialiser
    const char* env = std::getenv("SCANCREW_LOG");
    if (env == nullptr) return Level::kInfo;
    if (std::strcmp(env, "error") == 0) return Level::kError;
    if (std::strcmp(env, "warn") == 0) return Level::kWarn;
    if (std::strcmp(env, "debug") == 0) return Level::kDebug;
    return Level::kInfo;
  }();
  return level;
}

void write(Level level, const char* format, ...) {
  if (level > threshold()) return;
  static constexpr const char* kNames[] = {"error", "warn", "info", "debug"};
  char message[1024];
  va_list args;
  va_start(args, format);
  std::vsnprintf(message, sizeof(message), format, args);
  va_end(args);
  std::fprintf(stderr, "[%s] %s\n", kNames[static_cast<int>(level)], message);
}

}  // namespace scancrew::log
