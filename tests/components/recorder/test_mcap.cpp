// The MCAP writer and reader (components/recorder/mcap_{writer,reader}.hpp): what is written
// reads back the same, a file cut anywhere reads up to the cut, corrupt chunks are errors
// naming their offset, and the scancrew view of a recording passes over foreign channels.
// web/tests/read_mcap.mjs checks the same files with @mcap/core (test recorder.mcap_core).

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "components/recorder/mcap_format.hpp"
#include "components/recorder/mcap_reader.hpp"
#include "components/recorder/mcap_writer.hpp"
#include "components/recorder/recording.hpp"
#include "interfaces/message_fields.hpp"

namespace scancrew::recorder {
namespace {

namespace fs = std::filesystem;

std::span<const uint8_t> bytes_of(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

std::vector<uint8_t> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void write_file(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
}

struct Written {
  uint16_t channel;
  uint64_t log_ns;
  std::vector<uint8_t> data;
};

class Mcap : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ =
        (fs::temp_directory_path() / ("scancrew_mcap_test_" + std::to_string(::getpid()) + ".mcap"))
            .string();
  }
  void TearDown() override { fs::remove(path_); }

  // Two scancrew topics and a JSON channel, 60 messages in chunks of about 300 bytes.
  std::vector<Written> write_sample() {
    auto writer = RecordingWriter::open(path_, {.chunk_bytes = 300});
    EXPECT_TRUE(writer) << writer.error();
    const uint16_t imu = writer->add_topic({"/r1/imu", "scancrew/Imu"});
    const uint16_t odom = writer->add_topic({"/r1/odom", "scancrew/Odometry"});
    const uint16_t json_schema =
        writer->mcap().add_schema("foxglove.Log", "jsonschema", bytes_of(R"({"type":"object"})"));
    const uint16_t json = writer->mcap().add_channel("/log", "json", json_schema, {{"k", "v"}});
    std::vector<Written> written;
    for (uint8_t i = 0; i < 60; ++i) {
      const uint16_t channel = i % 3 == 0 ? imu : (i % 3 == 1 ? odom : json);
      Written w{channel, uint64_t{1000} * i, std::vector<uint8_t>(10 + i, i)};
      if (channel == json)
        EXPECT_TRUE(writer->mcap().write(json, w.log_ns, w.log_ns + 1, w.data));
      else
        EXPECT_TRUE(writer->write(channel, static_cast<int64_t>(w.log_ns), w.data));
      written.push_back(std::move(w));
    }
    EXPECT_TRUE(writer->close());
    return written;
  }

  std::string path_;
};

TEST_F(Mcap, WhatIsWrittenReadsBackTheSame) {
  const auto written = write_sample();
  auto reader = McapReader::open(path_);
  ASSERT_TRUE(reader) << reader.error();
  EXPECT_EQ(reader->profile(), "scancrew");
  size_t n = 0;
  for (;; ++n) {
    auto m = reader->next();
    ASSERT_TRUE(m) << m.error();
    if (!*m) break;
    ASSERT_LT(n, written.size());
    EXPECT_EQ((*m)->channel_id, written[n].channel);
    EXPECT_EQ((*m)->log_time_ns, written[n].log_ns);
    EXPECT_EQ(std::vector<uint8_t>((*m)->data.begin(), (*m)->data.end()), written[n].data);
  }
  EXPECT_EQ(n, written.size());
  EXPECT_FALSE(reader->truncated());
  ASSERT_EQ(reader->schemas().size(), 3u);
  EXPECT_EQ(reader->schemas().at(1).name, "scancrew/Imu");
  EXPECT_EQ(reader->schemas().at(1).encoding, kSchemaEncoding);
  EXPECT_EQ(std::string(reader->schemas().at(1).data.begin(), reader->schemas().at(1).data.end()),
            schema_text("scancrew/Imu"));
  ASSERT_EQ(reader->channels().size(), 3u);
  EXPECT_EQ(reader->channels().at(3).message_encoding, "json");
  EXPECT_EQ(reader->channels().at(3).metadata.at("k"), "v");
  EXPECT_EQ(reader->channels().at(1).metadata.at("format_version"),
            std::to_string(msg::kMessageFormatVersion));

  // the file ends with a Footer whose summary CRC covers the summary, then the magic
  const std::vector<uint8_t> file = read_file(path_);
  ASSERT_GT(file.size(), 8u + 29u);
  EXPECT_TRUE(std::equal(mcap::kMagic.begin(), mcap::kMagic.end(), file.end() - 8));
  const size_t footer = file.size() - 8 - 29;
  EXPECT_EQ(file[footer], static_cast<uint8_t>(mcap::Opcode::kFooter));
  uint64_t summary_start = 0;
  uint32_t summary_crc = 0;
  std::memcpy(&summary_start, &file[footer + 9], 8);
  std::memcpy(&summary_crc, &file[footer + 25], 4);
  ASSERT_GT(summary_start, 0u);
  ASSERT_LT(summary_start, footer);
  // DataEnd (13 bytes) closes the data section with the CRC of every byte before it
  ASSERT_EQ(file[summary_start - 13], static_cast<uint8_t>(mcap::Opcode::kDataEnd));
  uint32_t data_crc = 0;
  std::memcpy(&data_crc, &file[summary_start - 4], 4);
  EXPECT_EQ(mcap::crc32(std::span(file).first(summary_start - 13)), data_crc);
  EXPECT_EQ(mcap::crc32(std::span(file).subspan(summary_start, footer + 25 - summary_start)),
            summary_crc);
}

TEST_F(Mcap, TheRecordingViewPassesOverForeignChannels) {
  const auto written = write_sample();
  auto reader = RecordingReader::open(path_);
  ASSERT_TRUE(reader) << reader.error();
  ASSERT_TRUE(reader->scan_topics());
  ASSERT_EQ(reader->topics().size(), 2u);
  EXPECT_EQ(reader->topics()[1].name, "/r1/odom");
  EXPECT_EQ(reader->topics()[1].type, "scancrew/Odometry");
  size_t n = 0;
  for (const Written& w : written) {
    if (w.channel == 3) continue;
    auto e = reader->next();
    ASSERT_TRUE(e && *e);
    EXPECT_EQ((*e)->topic, w.channel - 1);
    EXPECT_EQ((*e)->receive_ns, static_cast<int64_t>(w.log_ns));
    EXPECT_EQ(std::vector<uint8_t>((*e)->message.begin(), (*e)->message.end()), w.data);
    ++n;
  }
  auto end = reader->next();
  ASSERT_TRUE(end);
  EXPECT_FALSE(*end);
  EXPECT_EQ(n, 40u);
}

// Cut at every byte: never an error; the messages read are a prefix, and all of them once the
// data section is whole.
TEST_F(Mcap, AFileCutAnywhereReadsUpToTheCut) {
  const auto written = write_sample();
  const size_t header_end = 8 + 9 + 2 * (4 + std::string("scancrew").size());
  size_t more = written.size();  // read at the next longer cut
  for (size_t size = fs::file_size(path_); size >= header_end; --size) {
    fs::resize_file(path_, size);
    auto reader = McapReader::open(path_);
    ASSERT_TRUE(reader) << size << ": " << reader.error();
    size_t n = 0;
    for (;; ++n) {
      auto m = reader->next();
      ASSERT_TRUE(m) << size << ": " << m.error();
      if (!*m) break;
      ASSERT_EQ((*m)->log_time_ns, written[n].log_ns);
    }
    ASSERT_LE(n, more) << size;
    more = n;
    if (!reader->truncated()) {
      EXPECT_EQ(n, written.size()) << size;
    }
  }
  EXPECT_EQ(more, 0u);
}

TEST_F(Mcap, ACorruptChunkIsAnErrorNamingItsOffset) {
  (void)write_sample();
  std::vector<uint8_t> file = read_file(path_);
  // walk the records outside chunks to the second chunk
  size_t at = mcap::kMagic.size(), chunks = 0;
  for (;;) {
    ASSERT_LT(at + 9, file.size());
    uint64_t length = 0;
    std::memcpy(&length, &file[at + 1], 8);
    if (file[at] == static_cast<uint8_t>(mcap::Opcode::kChunk) && ++chunks == 2) break;
    at += 9 + length;
  }
  file[at + 9 + 44 + 20] ^= 0x55;  // in the compressed records (after 44 bytes of fields)
  write_file(path_, file);
  auto reader = McapReader::open(path_);
  ASSERT_TRUE(reader) << reader.error();
  for (int i = 0; i < 1000; ++i) {
    auto m = reader->next();
    if (!m) {
      EXPECT_NE(m.error().find("corrupt record at byte " + std::to_string(at)), std::string::npos)
          << m.error();
      return;
    }
    ASSERT_TRUE(*m) << "read to the end through a corrupt chunk";
  }
  FAIL() << "no error";
}

// CRC-32 as zlib's (the check value of the ISO-HDLC CRC), byte by byte and 8 at a time.
TEST(McapCrc, IsTheIsoHdlcCrc) {
  EXPECT_EQ(mcap::crc32(bytes_of("123456789")), 0xCBF43926u);
  EXPECT_EQ(mcap::crc32(bytes_of("")), 0u);
  std::string text;
  for (int i = 0; i < 100; ++i) text += "The quick brown fox jumps over the lazy dog ";
  uint32_t crc = mcap::kCrcInit;
  for (size_t at = 0; at < text.size(); at += 7)
    crc = mcap::crc32_update(crc, bytes_of(text.substr(at, 7)));
  EXPECT_EQ(mcap::crc32_final(crc), mcap::crc32(bytes_of(text)));
  EXPECT_EQ(mcap::crc32(bytes_of("The quick brown fox jumps over the lazy dog")), 0x414FA339u);
}

TEST_F(Mcap, NotMcapIsRefusedByName) {
  write_file(path_, std::vector<uint8_t>(100, 'x'));
  auto reader = McapReader::open(path_);
  ASSERT_FALSE(reader);
  EXPECT_NE(reader.error().find("is not an MCAP recording"), std::string::npos) << reader.error();
}

}  // namespace
}  // namespace scancrew::recorder
