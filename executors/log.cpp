#include "executors/log.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>

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

std::string printable(std::string_view text) {
  std::string out;
  const size_t n = std::min(text.size(), kMaxMessageBytes);
  out.reserve(n);
  const auto escape = [&out](unsigned char c) {
    char hex[8];
    std::snprintf(hex, sizeof hex, "\\x%02x", c);
    out += hex;
  };
  for (size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\n') {
      out += "\\n";  // one record per line: a file cannot forge a log line of its own
    } else if ((c < 0x20 && c != '\t') || c == 0x7f) {
      escape(c);
    } else if (c == 0xc2 && i + 1 < n && static_cast<unsigned char>(text[i + 1]) >= 0x80 &&
               static_cast<unsigned char>(text[i + 1]) <= 0x9f) {
      // a C1 control in UTF-8 (U+0080..U+009F: U+009B is CSI, an escape sequence's start)
      escape(c);
      escape(static_cast<unsigned char>(text[++i]));
    } else {
      out += static_cast<char>(c);
    }
  }
  if (text.size() > n) out += " ... (" + std::to_string(text.size() - n) + " bytes more)";
  return out;
}

void write(Level level, const char* format, ...) {
  if (level > threshold()) return;
  static constexpr const char* kNames[] = {"error", "warn", "info", "debug"};
  va_list args;
  va_start(args, format);
  va_list again;
  va_copy(again, args);
  const int length = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  std::string message(length > 0 ? static_cast<size_t>(length) : 0, '\0');
  if (length > 0) std::vsnprintf(message.data(), message.size() + 1, format, again);
  va_end(again);
  std::fprintf(stderr, "[%s] %s\n", kNames[static_cast<int>(level)], printable(message).c_str());
}

}  // namespace scancrew::log
