// Record -> replay reproduces the messages exactly: a simulated robot's sensors recorded,
// then played into the same ports, arrive with identical contents (headers included; only
// publish_mono_ns, the local monotonic publish time, is new). Bad recordings are refused
// or played up to the damage.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "components/recorder/log_file.hpp"
#include "components/recorder/recorder.hpp"
#include "components/recorder/recording.hpp"
#include "components/recorder/replay.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"
#include "interfaces/codec.hpp"

namespace scancrew::recorder {
namespace {

namespace fs = std::filesystem;

// Keeps the encoding of every message received on its ports, publish_mono_ns zeroed.
class Collector final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: keeps every message it receives";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  Collector(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

  std::map<std::string, std::vector<std::vector<uint8_t>>> received;

 private:
  template <class T>
  void keep(const char* port) {
    create_subscription<T>(port, {.depth = 64}, [this, port](Sample<T>&& s) {
      T copy = *s;
      copy.header.publish_mono_ns = 0;
      received[port].push_back(msg::encode(copy));
    });
  }
  Result<void, std::string> on_configure() override {
    keep<msg::StereoFrame>("stereo");
    keep<msg::DepthImage>("depth");
    keep<msg::Imu>("imu");
    keep<msg::Odometry>("pose_gt");
    return {};
  }
};
SCANCREW_REGISTER_COMPONENT(Collector, "test_collector")

class RecordReplay : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("scancrew_record_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    log_ = (dir_ / "session.mcap").string();
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs a launch file and returns its collector (kept alive by launch_).
  Collector* run(const std::string& text) {
    auto launch = Launch::from_string(text, "test.yaml");
    EXPECT_TRUE(launch) << (launch ? "" : launch.error().front());
    if (!launch) return nullptr;
    launch_ = std::move(launch).value();
    launch_->run();
    return find<Collector>();
  }
  template <class T>
  T* find() {
    return launch_->find_component<T>();
  }

  std::string record_launch() const {
    return R"(
clock: sim
executor: {type: step}
run: {duration_s: 1.0, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1, kind: ground, start: [-1.0, -1.0, 0, 0]}
components:
  - name: sim
    type: team_simulator
    per_robot: false
    params:
      scene: )" SCANCREW_SOURCE_DIR R"(/launch_cfg/scenes/tiny.yaml
      ground_camera_width: 96
      ground_camera_height: 56
      ground_camera_rate_hz: 5
      imu_rate_hz: 50
  - {name: recorder, type: recorder, params: {path: )" +
           log_ + R"(, flush_period_s: 0.1, topics: [stereo, depth, imu, pose_gt]}}
  - {name: collector, type: test_collector}
)";
  }
  std::string replay_launch(const std::string& extra = "") const {
    return R"(
clock: sim
executor: {type: step}
run: {duration_s: 1.5, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1, kind: ground}
components:
  - {name: replay, type: replay, per_robot: false, params: {path: )" +
           log_ + extra + R"(}}
  - {name: collector, type: test_collector}
)";
  }

  fs::path dir_;
  std::string log_;
  std::unique_ptr<Launch> launch_;
};

TEST_F(RecordReplay, ReplayReproducesTheRecordedMessagesExactly) {
  Collector* live = run(record_launch());
  ASSERT_NE(live, nullptr);
  const auto recorded = live->received;
  ASSERT_EQ(recorded.at("stereo").size(), 5u);
  ASSERT_EQ(recorded.at("depth").size(), 5u);
  ASSERT_NEAR(static_cast<double>(recorded.at("imu").size()), 50.0, 1.0);
  ASSERT_EQ(recorded.at("pose_gt").size(), 5u);
  size_t total = 0;
  for (const auto& [port, messages] : recorded) total += messages.size();
  ASSERT_NE(find<Recorder>(), nullptr);
  EXPECT_EQ(find<Recorder>()->messages_written(), total);
  EXPECT_EQ(find<Recorder>()->write_errors(), 0u);

  Collector* played = run(replay_launch());
  ASSERT_NE(played, nullptr);
  auto* replay = find<Replay>();
  ASSERT_NE(replay, nullptr);
  EXPECT_TRUE(replay->finished());
  EXPECT_FALSE(replay->truncated());
  EXPECT_EQ(replay->decode_errors(), 0u);
  for (const auto& [port, messages] : recorded) {
    ASSERT_EQ(played->received[port].size(), messages.size()) << port;
    for (size_t i = 0; i < messages.size(); ++i)
      EXPECT_EQ(played->received[port][i], messages[i]) << port << " message " << i;
  }
}

// A recording cut in the middle (a crash: chunks are flushed every 0.1 s here) plays the
// messages of its whole chunks, each topic's a prefix of what was recorded, and says so.
TEST_F(RecordReplay, ACutRecordingPlaysUpToTheCut) {
  Collector* live = run(record_launch());
  ASSERT_NE(live, nullptr);
  const auto recorded = live->received;
  const uint64_t total = find<Recorder>()->messages_written();
  fs::resize_file(log_, fs::file_size(log_) / 2);
  Collector* played = run(replay_launch());
  ASSERT_NE(played, nullptr);
  auto* replay = find<Replay>();
  EXPECT_TRUE(replay->finished());
  EXPECT_TRUE(replay->truncated());
  EXPECT_GT(replay->published(), 10u);
  EXPECT_LT(replay->published(), total);
  for (const auto& [port, messages] : played->received) {
    ASSERT_LE(messages.size(), recorded.at(port).size()) << port;
    for (size_t i = 0; i < messages.size(); ++i)
      EXPECT_EQ(messages[i], recorded.at(port)[i]) << port << " message " << i;
  }
}

TEST_F(RecordReplay, BadRecordingsAndBadTopicsAreClearErrors) {
  { std::ofstream(log_) << "not a recording at all"; }
  auto launch = Launch::from_string(replay_launch(), "replay.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("is not an MCAP recording"), std::string::npos)
      << launch.error().front();

  {  // another format version
    auto writer = RecordingWriter::open(log_);
    ASSERT_TRUE(writer) << writer.error();
    const std::string text = schema_text("scancrew/Imu");
    const uint16_t schema =
        writer->mcap().add_schema("scancrew/Imu", kSchemaEncoding,
                                  {reinterpret_cast<const uint8_t*>(text.data()), text.size()});
    (void)writer->mcap().add_channel(
        "/r1/imu", kMessageEncoding, schema,
        {{"format_version", std::to_string(msg::kMessageFormatVersion + 1)}});
    ASSERT_TRUE(writer->close());
  }
  launch = Launch::from_string(replay_launch(), "replay.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("format version"), std::string::npos)
      << launch.error().front();

  {  // the retired format: the error says how to convert it
    std::ofstream out(log_, std::ios::binary);
    out.write(kLogMagic, sizeof kLogMagic);
  }
  launch = Launch::from_string(replay_launch(), "replay.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("is a .sclog recording (retired): convert it with "
                                        "`scancrew convert "),
            std::string::npos)
      << launch.error().front();

  std::string text = record_launch();
  const std::string stereo = "topics: [stereo";
  text.replace(text.find(stereo), stereo.size(), "topics: [nowhere");
  launch = Launch::from_string(text, "record.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("topic '/r1/nowhere' does not exist yet"),
            std::string::npos)
      << launch.error().front();

  text = record_launch();
  text.replace(text.find("path: "), std::string("path: ").size(), "path: /nonexistent/dir/");
  launch = Launch::from_string(text, "record.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("cannot create the recording"), std::string::npos)
      << launch.error().front();
}

// A recording's topic names become topics and are echoed: a name with control bytes (an
// escape sequence) is a corrupt file, refused before anything plays (Step 12's review).
TEST_F(RecordReplay, ATopicNameThatIsNoTopicNameIsRefused) {
  {
    auto writer = RecordingWriter::open(log_);
    ASSERT_TRUE(writer) << writer.error();
    const uint16_t t = writer->add_topic({"/r1/\x1b[2Jimu", "scancrew/Imu"});
    ASSERT_TRUE(writer->write(t, 1, std::vector<uint8_t>(4, 0)));
    ASSERT_TRUE(writer->close());
  }
  auto launch = Launch::from_string(replay_launch(), "replay.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("'/r1/\\x1b[2Jimu' is not a topic name"), std::string::npos)
      << launch.error().front();
}

// A forged receive time far in the future held the rest of the recording back and the run
// ended as if it had played it all; the replay now says it stopped short, and where.
TEST_F(RecordReplay, AReplayStoppedShortSaysWhere) {
  {
    auto writer = RecordingWriter::open(log_);
    ASSERT_TRUE(writer) << writer.error();
    const uint16_t t = writer->add_topic({"/r1/imu", "scancrew/Imu"});
    const std::vector<uint8_t> imu = msg::encode(msg::Imu{});
    ASSERT_TRUE(writer->write(t, 1'000, imu));
    ASSERT_TRUE(writer->write(t, INT64_MAX, imu));
    ASSERT_TRUE(writer->close());
  }
  auto launch = Launch::from_string(replay_launch(), "replay.yaml");
  ASSERT_TRUE(launch) << launch.error().front();
  ::testing::internal::CaptureStderr();
  (*launch)->run();
  const std::string err = ::testing::internal::GetCapturedStderr();
  auto* replay = (*launch)->find_component<Replay>();
  ASSERT_NE(replay, nullptr);
  EXPECT_EQ(replay->published(), 1U);
  EXPECT_FALSE(replay->finished());
  EXPECT_NE(err.find("not played to its end: 1 messages played; the next (in the record ending "
                     "at byte"),
            std::string::npos)
      << err;
}

// A message that did not decode was skipped and counted, and the run looked whole (exit 0);
// the replay now reports it as lost data (scancrew run exits 4).
TEST_F(RecordReplay, MessagesThatDoNotDecodeAreReportedAsLost) {
  {
    auto writer = RecordingWriter::open(log_);
    ASSERT_TRUE(writer) << writer.error();
    const uint16_t t = writer->add_topic({"/r1/imu", "scancrew/Imu"});
    std::vector<uint8_t> imu = msg::encode(msg::Imu{});
    ASSERT_TRUE(writer->write(t, 1'000, imu));
    imu.push_back(0);  // a trailing byte: not an Imu
    ASSERT_TRUE(writer->write(t, 2'000, imu));
    ASSERT_TRUE(writer->close());
  }
  auto launch = Launch::from_string(replay_launch(), "replay.yaml");
  ASSERT_TRUE(launch) << launch.error().front();
  ::testing::internal::CaptureStderr();
  (*launch)->run();
  (void)::testing::internal::GetCapturedStderr();
  auto* replay = (*launch)->find_component<Replay>();
  ASSERT_NE(replay, nullptr);
  EXPECT_TRUE(replay->finished());
  EXPECT_EQ(replay->decode_errors(), 1U);
  const auto failures = (*launch)->graph().failures();
  ASSERT_EQ(failures.size(), 1U);
  EXPECT_NE(failures.front().find("1 message(s)"), std::string::npos) << failures.front();
}

// Channels of other encodings (the Foxglove JSON channels beside ours) are passed over.
TEST_F(RecordReplay, ReplayPassesOverChannelsThatAreNotOurs) {
  {
    auto writer = RecordingWriter::open(log_);
    ASSERT_TRUE(writer) << writer.error();
    const uint16_t t = writer->add_topic({"/r1/imu", "scancrew/Imu"});
    const std::string schema = R"({"type":"object"})", json = R"({"message":"hello"})";
    const auto bytes = [](const std::string& text) {
      return std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size());
    };
    const uint16_t log = writer->mcap().add_channel(
        "/r1/log", "json", writer->mcap().add_schema("foxglove.Log", "jsonschema", bytes(schema)));
    const std::vector<uint8_t> imu = msg::encode(msg::Imu{});
    ASSERT_TRUE(writer->write(t, 1'000, imu));
    ASSERT_TRUE(writer->mcap().write(log, 1'500, 1'500, bytes(json)));
    ASSERT_TRUE(writer->write(t, 2'000, imu));
    ASSERT_TRUE(writer->close());
  }
  Collector* played = run(replay_launch());
  ASSERT_NE(played, nullptr);
  auto* replay = find<Replay>();
  EXPECT_TRUE(replay->finished());
  EXPECT_EQ(replay->published(), 2U);
  EXPECT_EQ(replay->decode_errors(), 0U);
  EXPECT_EQ(played->received["imu"].size(), 2U);
}

struct Stored {
  uint16_t topic;
  int64_t receive_ns;
  std::vector<uint8_t> message;
};

// Every scancrew topic and message of a recording.
std::pair<std::vector<LogTopic>, std::vector<Stored>> read_all(const std::string& path) {
  auto reader = RecordingReader::open(path);
  EXPECT_TRUE(reader) << reader.error();
  EXPECT_TRUE(reader->scan_topics());
  std::vector<Stored> entries;
  for (;;) {
    auto e = reader->next();
    EXPECT_TRUE(e) << e.error();
    if (!e || !*e) break;
    entries.push_back(
        {(*e)->topic, (*e)->receive_ns, {(*e)->message.begin(), (*e)->message.end()}});
  }
  EXPECT_FALSE(reader->truncated());
  return {reader->topics(), entries};
}

// The retired .sclog layout (components/recorder/log_file.hpp), as the recorder wrote it.
void write_sclog(const std::string& path, const std::vector<LogTopic>& topics,
                 const std::vector<Stored>& entries) {
  std::vector<uint8_t> out(std::begin(kLogMagic), std::end(kLogMagic));
  const auto put = [&out]<class T>(T v) {
    const auto* b = reinterpret_cast<const uint8_t*>(&v);
    out.insert(out.end(), b, b + sizeof v);
  };
  const auto record = [&](uint8_t kind, const std::vector<uint8_t>& payload) {
    out.push_back(kind);
    put(static_cast<uint32_t>(payload.size()));
    out.insert(out.end(), payload.begin(), payload.end());
  };
  put(msg::kMessageFormatVersion);
  for (size_t i = 0; i < topics.size(); ++i) {
    std::vector<uint8_t> payload = {static_cast<uint8_t>(i), 0};
    for (const std::string* s : {&topics[i].name, &topics[i].type}) {
      payload.push_back(static_cast<uint8_t>(s->size()));
      payload.push_back(0);
      payload.insert(payload.end(), s->begin(), s->end());
    }
    record(1, payload);
  }
  for (const Stored& e : entries) {
    std::vector<uint8_t> payload = {static_cast<uint8_t>(e.topic), 0};
    const auto* t = reinterpret_cast<const uint8_t*>(&e.receive_ns);
    payload.insert(payload.end(), t, t + sizeof e.receive_ns);
    payload.insert(payload.end(), e.message.begin(), e.message.end());
    record(2, payload);
  }
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(out.size()));
}

// `scancrew convert` of an old recording gives what the recorder now writes directly: the
// same topics, types, receive times and message bytes, in the same order.
TEST_F(RecordReplay, ConvertingAnSclogGivesTheDirectRecording) {
  ASSERT_NE(run(record_launch()), nullptr);
  const auto [topics, entries] = read_all(log_);
  ASSERT_EQ(topics.size(), 4U);
  ASSERT_GT(entries.size(), 60U);
  const std::string old = (dir_ / "old.sclog").string(), converted = (dir_ / "new.mcap").string();
  write_sclog(old, topics, entries);
  const auto summary = convert_sclog(old, converted);
  ASSERT_TRUE(summary) << summary.error();
  EXPECT_EQ(summary->topics, 4U);
  EXPECT_EQ(summary->messages, entries.size());
  EXPECT_FALSE(summary->truncated);
  const auto [topics2, entries2] = read_all(converted);
  ASSERT_EQ(topics2.size(), topics.size());
  for (size_t i = 0; i < topics.size(); ++i) {
    EXPECT_EQ(topics2[i].name, topics[i].name);
    EXPECT_EQ(topics2[i].type, topics[i].type);
  }
  ASSERT_EQ(entries2.size(), entries.size());
  for (size_t i = 0; i < entries.size(); ++i) {
    EXPECT_EQ(entries2[i].topic, entries[i].topic) << i;
    EXPECT_EQ(entries2[i].receive_ns, entries[i].receive_ns) << i;
    EXPECT_EQ(entries2[i].message, entries[i].message) << i;
  }
}

}  // namespace
}  // namespace scancrew::recorder
