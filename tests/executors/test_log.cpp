// Log lines: whole (not cut at a fixed buffer) and safe for a terminal.

#include <gtest/gtest.h>

#include <string>

#include "executors/log.hpp"

namespace scancrew::log {
namespace {

TEST(Log, PrintableEscapesControlBytesAndKeepsText) {
  EXPECT_EQ(printable("plain text, tab\there"), "plain text, tab\there");
  // a newline would let a file forge a log line of its own: "[error] ..."
  EXPECT_EQ(printable("name\n[error] forged"), "name\\n[error] forged");
  // U+009B (CSI in UTF-8) starts an escape sequence on a terminal too; U+00E9 and U+2014 pass
  EXPECT_EQ(printable("a\xc2\x9b"
                      "2Jb \xe2\x80\x94"),
            "a\\xc2\\x9b2Jb \xe2\x80\x94");
  // an escape sequence (clear the screen), a carriage return, a NUL and DEL from a hostile file
  EXPECT_EQ(printable(std::string("a\x1b[2Jb\rc\0d\x7f", 11)), "a\\x1b[2Jb\\x0dc\\x00d\\x7f");
  EXPECT_EQ(printable("h\xc3\xa9llo"), "h\xc3\xa9llo");  // UTF-8 passes
  const std::string huge(kMaxMessageBytes + 10, 'x');
  EXPECT_EQ(printable(huge), std::string(kMaxMessageBytes, 'x') + " ... (10 bytes more)");
}

// Messages were cut at 1 KiB, and the error's end (what to do) was lost.
TEST(Log, AWholeLongMessageReachesStderr) {
  const std::string reason(3000, 'r');
  ::testing::internal::CaptureStderr();
  write(Level::kError, "%s: %s", "x.yaml", (reason + " end").c_str());
  const std::string out = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(out, "[error] x.yaml: " + reason + " end\n");
}

}  // namespace
}  // namespace scancrew::log
