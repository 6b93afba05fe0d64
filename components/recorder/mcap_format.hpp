#pragma once

// The pieces of the MCAP format (https://mcap.dev/spec, major version 0) that the writer
// (mcap_writer.hpp) and the reader (mcap_reader.hpp) share: the magic, the record opcodes,
// CRC-32 and little-endian field encoding.
//
// A record is <u8 opcode><u64 content length><content>. Field types: integers little-endian;
// String = u32 byte length + UTF-8; Bytes = a u32 or u64 length + bytes (per field); Map and
// Array = u32 byte length of the entries + the entries.

#include <array>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace scancrew::recorder::mcap {

inline constexpr std::array<uint8_t, 8> kMagic = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};
inline constexpr size_t kRecordHeaderBytes = 1 + sizeof(uint64_t);

enum class Opcode : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// CRC-32 (ISO-HDLC, as zlib's crc32): crc32_update(kCrcInit, ...) over the bytes, then
// crc32_final. Thread safe; allocates nothing.
inline constexpr uint32_t kCrcInit = 0xFFFFFFFFu;
uint32_t crc32_update(uint32_t crc, std::span<const uint8_t> bytes);
inline uint32_t crc32_final(uint32_t crc) {
  return crc ^ 0xFFFFFFFFu;
}
inline uint32_t crc32(std::span<const uint8_t> bytes) {
  return crc32_final(crc32_update(kCrcInit, bytes));
}

// Appends fields to a byte buffer.
class Fields {
 public:
  explicit Fields(std::vector<uint8_t>& out) : out_(out) {}
  template <class T>
  Fields& put(T v) {
    const size_t at = out_.size();
    out_.resize(at + sizeof(T));
    std::memcpy(out_.data() + at, &v, sizeof(T));  // little-endian hosts only (x86, arm64)
    return *this;
  }
  Fields& bytes(std::span<const uint8_t> b) {
    out_.insert(out_.end(), b.begin(), b.end());
    return *this;
  }
  Fields& string(std::string_view s) {
    put(static_cast<uint32_t>(s.size()));
    out_.insert(out_.end(), s.begin(), s.end());
    return *this;
  }
  size_t size() const { return out_.size(); }
  // Writes a u32 at `at` (a length prefix reserved with put(uint32_t{0})).
  void patch_u32(size_t at, uint32_t v) { std::memcpy(out_.data() + at, &v, sizeof v); }

 private:
  std::vector<uint8_t>& out_;
};

// Reads fields from a record's content; every getter returns false past the end.
class FieldReader {
 public:
  explicit FieldReader(std::span<const uint8_t> in) : in_(in) {}
  template <class T>
  bool get(T& v) {
    if (in_.size() - at_ < sizeof(T)) return false;
    std::memcpy(&v, in_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return true;
  }
  bool string(std::string& s);
  // Bytes with a length prefix of type L.
  template <class L>
  bool bytes(std::span<const uint8_t>& b) {
    L n = 0;
    if (!get(n) || in_.size() - at_ < n) return false;
    b = in_.subspan(at_, static_cast<size_t>(n));
    at_ += static_cast<size_t>(n);
    return true;
  }
  std::span<const uint8_t> rest() const { return in_.subspan(at_); }
  size_t at() const { return at_; }

 private:
  std::span<const uint8_t> in_;
  size_t at_ = 0;
};

}  // namespace scancrew::recorder::mcap
