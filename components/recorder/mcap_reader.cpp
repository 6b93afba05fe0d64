#include "components/recorder/mcap_reader.hpp"

#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <system_error>

#include "components/recorder/mcap_format.hpp"

namespace scancrew::recorder {

using mcap::FieldReader;
using mcap::Opcode;

namespace {

// a record longer than this is corruption, not data (our largest message is a few MB)
constexpr uint64_t kMaxRecordBytes = 1ull << 30;
// the same for a chunk's records, uncompressed (our writer closes a chunk past 4 MB)
constexpr uint64_t kMaxChunkBytes = 256ull << 20;

std::string errno_text() {
  return std::error_code(errno, std::generic_category()).message();  // thread-safe strerror
}

// A string-to-string Map field.
bool read_map(FieldReader& r, std::map<std::string, std::string>& out) {
  std::span<const uint8_t> entries;
  if (!r.bytes<uint32_t>(entries)) return false;
  FieldReader m(entries);
  while (m.at() < entries.size()) {
    std::string key, value;
    if (!m.string(key) || !m.string(value)) return false;
    out[key] = std::move(value);
  }
  return true;
}

}  // namespace

void McapReader::FileCloser::operator()(std::FILE* f) const {
  (void)std::fclose(f);  // read only: nothing to lose
}

McapReader::McapReader(std::unique_ptr<std::FILE, FileCloser> file, std::string path, uint64_t size)
    : file_(std::move(file)), path_(std::move(path)), size_(size) {}

std::string McapReader::corrupt(uint64_t at, const std::string& what) const {
  return "'" + path_ + "': corrupt record at byte " + std::to_string(at) + ": " + what;
}

Result<McapReader, std::string> McapReader::open(const std::string& path) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) return make_unexpected("cannot open the recording '" + path + "': " + errno_text());
  if (std::fseek(file.get(), 0, SEEK_END) != 0)
    return make_unexpected("cannot read the recording '" + path + "': " + errno_text());
  const long size = std::ftell(file.get());
  std::rewind(file.get());
  std::array<uint8_t, mcap::kMagic.size()> magic{};
  const std::string not_mcap = "'" + path + "' is not an MCAP recording (.mcap)";
  if (size < static_cast<long>(magic.size()) ||
      std::fread(magic.data(), 1, magic.size(), file.get()) != magic.size() ||
      magic != mcap::kMagic)
    return make_unexpected(not_mcap);
  McapReader reader(std::move(file), path, static_cast<uint64_t>(size));
  reader.offset_ = magic.size();
  auto header = reader.read_record();
  if (!header) return make_unexpected(header.error());
  FieldReader r(reader.record_);
  std::string library;
  if (!*header || **header != static_cast<uint8_t>(Opcode::kHeader) || !r.string(reader.profile_) ||
      !r.string(library))
    return make_unexpected(not_mcap + ": no Header record after the magic");
  reader.data_start_ = reader.offset_;
  reader.truncated_ = false;
  return reader;
}

Result<std::optional<uint8_t>, std::string> McapReader::read_record() {
  const uint64_t at = offset_;
  std::array<uint8_t, mcap::kRecordHeaderBytes> head{};
  // a whole file ends with DataEnd: the end of the file before it is a cut
  if (size_ - at < head.size() ||
      std::fread(head.data(), 1, head.size(), file_.get()) != head.size()) {
    truncated_ = true;
    return std::optional<uint8_t>{};
  }
  uint64_t length = 0;
  std::memcpy(&length, head.data() + 1, sizeof length);
  if (length > kMaxRecordBytes)
    return make_unexpected(corrupt(at, "a record of " + std::to_string(length) + " bytes"));
  if (size_ - at - head.size() < length) {
    truncated_ = true;
    return std::optional<uint8_t>{};
  }
  record_.resize(length);
  if (std::fread(record_.data(), 1, length, file_.get()) != length)
    return make_unexpected("cannot read '" + path_ + "': " + errno_text());
  offset_ = at + head.size() + length;
  return std::optional<uint8_t>{head[0]};
}

Result<void, std::string> McapReader::open_chunk(uint64_t at) {
  FieldReader r(record_);
  uint64_t start_ns = 0, end_ns = 0, uncompressed = 0;
  uint32_t crc = 0;
  std::string compression;
  std::span<const uint8_t> records;
  if (!r.get(start_ns) || !r.get(end_ns) || !r.get(uncompressed) || !r.get(crc) ||
      !r.string(compression) || !r.bytes<uint64_t>(records))
    return make_unexpected(corrupt(at, "a malformed Chunk"));
  if (uncompressed > kMaxChunkBytes)
    return make_unexpected(corrupt(at, "a Chunk of " + std::to_string(uncompressed) +
                                           " bytes uncompressed (at most 256 MiB are read)"));
  if (compression == "zstd") {
    const unsigned long long content = ZSTD_getFrameContentSize(records.data(), records.size());
    if (content != ZSTD_CONTENTSIZE_UNKNOWN && content != uncompressed)
      return make_unexpected(corrupt(at, "the Chunk's zstd frame does not hold its size"));
    chunk_.resize(uncompressed);
    const size_t n = ZSTD_decompress(chunk_.data(), chunk_.size(), records.data(), records.size());
    if (ZSTD_isError(n) != 0 || n != uncompressed)
      return make_unexpected(
          corrupt(at, std::string("the Chunk does not decompress: ") +
                          (ZSTD_isError(n) != 0 ? ZSTD_getErrorName(n) : "its size differs")));
  } else if (compression.empty()) {
    if (records.size() != uncompressed)
      return make_unexpected(corrupt(at, "an uncompressed Chunk whose size differs"));
    chunk_.assign(records.begin(), records.end());
  } else {
    return make_unexpected("'" + path_ + "': the chunk at byte " + std::to_string(at) +
                           " is compressed with '" + compression.substr(0, 32) +
                           "'; this reader reads zstd and uncompressed chunks");
  }
  if (crc != 0 && mcap::crc32(chunk_) != crc)
    return make_unexpected(corrupt(at, "the Chunk's CRC does not match its records"));
  chunk_at_ = 0;
  chunk_offset_ = at;
  in_chunk_ = true;
  return {};
}

Result<std::optional<McapMessage>, std::string> McapReader::take(uint8_t opcode,
                                                                 std::span<const uint8_t> content,
                                                                 uint64_t at) {
  using None = std::optional<McapMessage>;
  FieldReader r(content);
  switch (static_cast<Opcode>(opcode)) {
    case Opcode::kSchema: {
      McapSchema s;
      std::span<const uint8_t> data;
      if (!r.get(s.id) || !r.string(s.name) || !r.string(s.encoding) || !r.bytes<uint32_t>(data) ||
          s.id == 0)
        return make_unexpected(corrupt(at, "a malformed Schema"));
      s.data.assign(data.begin(), data.end());
      auto [it, added] = schemas_.try_emplace(s.id, s);
      if (!added && (it->second.name != s.name || it->second.encoding != s.encoding ||
                     it->second.data != s.data))
        return make_unexpected(
            corrupt(at, "schema " + std::to_string(s.id) + " is declared twice, differently"));
      return None{};
    }
    case Opcode::kChannel: {
      McapChannel c;
      if (!r.get(c.id) || !r.get(c.schema_id) || !r.string(c.topic) ||
          !r.string(c.message_encoding) || !read_map(r, c.metadata))
        return make_unexpected(corrupt(at, "a malformed Channel"));
      if (c.schema_id != 0 && !schemas_.contains(c.schema_id))
        return make_unexpected(corrupt(at, "channel " + std::to_string(c.id) + " is on schema " +
                                               std::to_string(c.schema_id) +
                                               ", not declared before it"));
      auto [it, added] = channels_.try_emplace(c.id, c);
      if (!added && (it->second.topic != c.topic || it->second.schema_id != c.schema_id ||
                     it->second.message_encoding != c.message_encoding))
        return make_unexpected(
            corrupt(at, "channel " + std::to_string(c.id) + " is declared twice, differently"));
      return None{};
    }
    case Opcode::kMessage: {
      McapMessage m;
      if (!r.get(m.channel_id) || !r.get(m.sequence) || !r.get(m.log_time_ns) ||
          !r.get(m.publish_time_ns))
        return make_unexpected(corrupt(at, "a malformed Message"));
      if (!channels_.contains(m.channel_id))
        return make_unexpected(corrupt(at, "a message on channel " + std::to_string(m.channel_id) +
                                               ", not declared before it"));
      m.data = r.rest();
      return std::optional<McapMessage>{m};
    }
    default:
      return None{};  // indexes, attachments, metadata, records of later versions
  }
}

Result<std::optional<McapMessage>, std::string> McapReader::next() {
  using None = std::optional<McapMessage>;
  while (!ended_) {
    if (in_chunk_) {
      if (chunk_at_ == chunk_.size()) {
        in_chunk_ = false;
        continue;
      }
      uint64_t length = 0;
      if (chunk_.size() - chunk_at_ < mcap::kRecordHeaderBytes ||
          (std::memcpy(&length, chunk_.data() + chunk_at_ + 1, sizeof length),
           chunk_.size() - chunk_at_ - mcap::kRecordHeaderBytes < length))
        return make_unexpected(corrupt(chunk_offset_, "a record runs past the end of its Chunk"));
      const uint8_t opcode = chunk_[chunk_at_];
      const auto content = std::span<const uint8_t>(chunk_).subspan(
          chunk_at_ + mcap::kRecordHeaderBytes, static_cast<size_t>(length));
      chunk_at_ += mcap::kRecordHeaderBytes + static_cast<size_t>(length);
      if (opcode == static_cast<uint8_t>(Opcode::kChunk))
        return make_unexpected(corrupt(chunk_offset_, "a Chunk inside a Chunk"));
      auto taken = take(opcode, content, chunk_offset_);
      if (!taken || *taken) return taken;
      continue;
    }
    const uint64_t at = offset_;
    auto opcode = read_record();
    if (!opcode) return make_unexpected(opcode.error());
    if (!*opcode) {
      ended_ = true;  // cut short
      return None{};
    }
    switch (static_cast<Opcode>(**opcode)) {
      case Opcode::kChunk:
        if (auto opened = open_chunk(at); !opened) return make_unexpected(opened.error());
        break;
      case Opcode::kDataEnd:
      case Opcode::kFooter:  // a file without DataEnd: the spec asks for one; end here anyway
        ended_ = true;
        break;
      case Opcode::kHeader:
        return make_unexpected(corrupt(at, "a second Header"));
      default:
        if (auto taken = take(**opcode, record_, at); !taken || *taken) return taken;
    }
  }
  return None{};
}

Result<void, std::string> McapReader::rewind() {
  if (std::fseek(file_.get(), static_cast<long>(data_start_), SEEK_SET) != 0)
    return make_unexpected("cannot read '" + path_ + "': " + errno_text());
  offset_ = data_start_;
  in_chunk_ = ended_ = truncated_ = false;
  return {};
}

Result<void, std::string> McapReader::scan() {
  for (;;) {
    auto m = next();
    if (!m) return make_unexpected(m.error());
    if (!*m) break;
  }
  return rewind();
}

}  // namespace scancrew::recorder
