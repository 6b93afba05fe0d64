#pragma once

// Minimal levelled logging to stderr, printf-style (the runtime keeps its dependencies
// small). Thread safe: one fprintf per message. Level from SCANCREW_LOG (error, warn,
// info, debug; default info).

#include <cstdarg>
#include <cstdio>

namespace scancrew::log {

enum class Level { kError = 0, kWarn = 1, kInfo = 2, kDebug = 3 };

Level threshold();
void write(Level level, const char* format, ...) __attribute__((format(printf, 2, 3)));

}  // namespace scancrew::log

#define SCANCREW_LOG_ERROR(...) ::scancrew::log::write(::scancrew::log::Level::kError, __VA_ARGS__)
#define SCANCREW_LOG_WARN(...) ::scancrew::log::write(::scancrew::log::Level::kWarn, __VA_ARGS__)
#define SCANCREW_LOG_INFO(...) ::scancrew::log::write(::scancrew::log::Level::kInfo, __VA_ARGS__)
#define SCANCREW_LOG_DEBUG(...) ::scancrew::log::write(::scancrew::log::Level::kDebug, __VA_ARGS__)
