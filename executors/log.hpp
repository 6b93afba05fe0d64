#pragma once

// Minimal levelled logging to stderr, printf-style (the runtime keeps its dependencies
// small). Thread safe: one fprintf per message. Level from SCANCREW_LOG (error, warn,
// info, debug; default info).

#include <cstdarg>
#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace scancrew::log {

enum class Level { kError = 0, kWarn = 1, kInfo = 2, kDebug = 3 };

Level threshold();
// The whole message (no length limit up to kMaxMessageBytes), made printable.
void write(Level level, const char* format, ...) __attribute__((format(printf, 2, 3)));

// A message is cut here, with the count of bytes left out.
inline constexpr size_t kMaxMessageBytes = size_t{64} * 1024;
// Text from files and links made safe for a terminal: control bytes other than tab (an escape
// sequence, a carriage return that overwrites the line) and UTF-8's C1 controls become \xNN, a
// newline \n (a record stays one line); cut at kMaxMessageBytes. Every log line goes through
// it; print other untrusted text with it too.
std::string printable(std::string_view text);

}  // namespace scancrew::log

#define SCANCREW_LOG_ERROR(...) ::scancrew::log::write(::scancrew::log::Level::kError, __VA_ARGS__)
#define SCANCREW_LOG_WARN(...) ::scancrew::log::write(::scancrew::log::Level::kWarn, __VA_ARGS__)
#define SCANCREW_LOG_INFO(...) ::scancrew::log::write(::scancrew::log::Level::kInfo, __VA_ARGS__)
#define SCANCREW_LOG_DEBUG(...) ::scancrew::log::write(::scancrew::log::Level::kDebug, __VA_ARGS__)
