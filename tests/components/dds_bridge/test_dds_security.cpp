// DDS-Security on the bridge (docs/security.md): a team's keys (scancrew keys' library), bridges
// that run authenticated and encrypted with a launch file's security block. A participant
// without a certificate, or with another team's, neither reads nor injects; robot 2's
// identity cannot write a topic its permissions do not grant, nor send as robot 1; a capture
// of the loopback traffic (in a network namespace of the test's own) holds the plaintext of a
// plain run and none of a secure one.

#include <arpa/inet.h>
#include <linux/if_packet.h>
#include <net/ethernet.h>
#include <net/if.h>
#include <sched.h>
#include <sys/ioctl.h>
#include <sys/socket.h>

#include <algorithm>
#include <filesystem>

#include "components/dds_bridge/team_keys.hpp"
#include "tests/components/dds_bridge/bridge_harness.hpp"

namespace scancrew::dds_bridge {
namespace {

using namespace testing;  // NOLINT(google-build-using-namespace): the harness

namespace fs = std::filesystem;

// A key folder of team `team` with these places, each allowed the harness's topics (and
// robot_1 also sc/r1/plan, which no other place is granted).
std::string make_keys(const std::string& team, const std::vector<std::string>& places) {
  const std::string dir =
      (fs::temp_directory_path() / ("scancrew_keys_" + team + "_" + std::to_string(test_pid())))
          .string();
  fs::remove_all(dir);
  const auto init = init_team_keys(dir, team);
  EXPECT_TRUE(init) << (init ? "" : init.error());
  for (const std::string& place : places) {
    PlaceGrant g;
    g.place = place;
    g.publish = {"sc/robot_state", "sc/plan", "sc/patch", std::string(kPresenceTopic)};
    if (place == "robot_1") g.publish.emplace_back("sc/r1/plan");
    g.subscribe = g.publish;
    const auto added = add_place_keys(dir, g);
    EXPECT_TRUE(added) << (added ? "" : added.error());
  }
  return dir;
}

std::vector<std::pair<std::string, std::string>> properties(const std::string& dir,
                                                            const std::string& place) {
  auto p = security_properties(dir, place);
  EXPECT_TRUE(p) << (p ? "" : p.error());
  return p ? *p : std::vector<std::pair<std::string, std::string>>{};
}

std::string security_block(const std::string& dir) {
  return "security: {keys: " + dir + "}\n";
}

TEST(DdsSecurity, TeamKeysNameEachPlaceAndRefuseASecondAuthority) {
  const std::string dir = make_keys("alpha", {"robot_1", "station"});
  for (const char* f : {"ca.pem", "ca.key", "governance.p7s", "robot_1.pem", "robot_1.key",
                        "permissions_robot_1.p7s", "station.pem", "permissions_station.p7s"})
    EXPECT_TRUE(fs::is_regular_file(fs::path(dir) / f)) << f;
  EXPECT_EQ(fs::status(fs::path(dir) / "robot_1.key").permissions() & fs::perms::others_read,
            fs::perms::none);
  auto team = team_of_keys(dir);
  ASSERT_TRUE(team);
  EXPECT_EQ(*team, "alpha");
  EXPECT_FALSE(init_team_keys(dir, "alpha"));         // would orphan the places' certificates
  EXPECT_FALSE(security_properties(dir, "robot_9"));  // no such place: named error
  EXPECT_FALSE(add_place_keys(dir, PlaceGrant{.place = "Robot 1"}));
  EXPECT_EQ(place_name(3, 65535), "robot_3");
  EXPECT_EQ(place_name(0, 65535), "station");
  EXPECT_EQ(place_name(65535, 65535), "sim");
  // the GUID prefix of a place's participants: 0x80 set, distinct per place and team
  const auto a = place_guid_prefix("alpha", "robot_1");
  EXPECT_NE(a[0] & 0x80, 0);
  EXPECT_NE(a, place_guid_prefix("alpha", "robot_2"));
  EXPECT_NE(a, place_guid_prefix("beta", "robot_1"));
  fs::remove_all(dir);
}

TEST(DdsSecurity, OutsidersNeitherReadNorInjectAndAnIdentitySendsOnlyAsItself) {
  const std::string keys = make_keys("alpha", {"robot_1", "robot_2", "robot_3"});
  const std::string foreign = make_keys("beta", {"robot_3"});
  Robot r1(1, "", "[robot_state]", security_block(keys));
  Robot r2(2, "", "[robot_state]", security_block(keys));
  wait_ready({&r1, &r2}, 2, {"robot_state"});
  ASSERT_TRUE(r1.source().send_state(1));
  ASSERT_TRUE(wait_until([&] { return r2.sink().count(r2.sink().states) == 1; })) << describe(r2);

  // control: robot 3 of the team authenticates and is matched, its samples flow
  const auto t0 = Clock::now();
  RawPeer member(3, properties(keys, "robot_3"));
  ASSERT_TRUE(member.ok());
  ASSERT_TRUE(wait_until([&] { return member.matched() >= 2; }, 30.0));
  const double match_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const uint32_t v = msg::kMessageFormatVersion;
  const std::string type = msg::RobotState::kTypeName;
  ASSERT_TRUE(member.write(v, 3, 1, type, state_bytes(3, 30)));
  ASSERT_TRUE(wait_until([&] { return r2.sink().count(r2.sink().states) == 2; }));

  // outsiders: no certificate (a plain bridge and a raw writer), another team's certificate
  Robot plain(4, "", "[robot_state]");
  RawPeer anonymous(std::nullopt), stranger(3, properties(foreign, "robot_3"));
  ASSERT_TRUE(plain.ok());
  ASSERT_TRUE(wait_until([&] { return plain.active(); }));
  ASSERT_TRUE(anonymous.ok());
  // robot 2's identity claiming robot 1, and writing a topic robot 2 is not granted
  RawPeer impostor(1, properties(keys, "robot_2"));
  RawPeer plan_writer(2, properties(keys, "robot_2"), "sc/r1/plan");
  EXPECT_FALSE(plan_writer.ok()) << "robot 2's permissions do not grant sc/r1/plan";
  ASSERT_TRUE(impostor.ok());
  ASSERT_TRUE(wait_until([&] { return impostor.matched() >= 2; }, 30.0));
  // given four times the control's matching time, the outsiders matched nobody of the team
  std::this_thread::sleep_for(std::chrono::duration<double>(std::max(2.0, 4 * match_s)));
  EXPECT_LE(anonymous.matched(), 1u) << "matched more than the plain bridge, a fellow outsider";
  EXPECT_EQ(stranger.matched(), 0u);

  ASSERT_TRUE(anonymous.write(v, 3, 1, type, state_bytes(3, 40)));
  ASSERT_TRUE(stranger.write(v, 3, 2, type, state_bytes(3, 41)));
  ASSERT_TRUE(impostor.write(v, 1, 1000, type, state_bytes(1, 42)));  // robot 2 as robot 1
  ASSERT_TRUE(r1.source().send_state(2));
  ASSERT_TRUE(wait_until([&] {
    return counters(r2.bridge().stats(), "robot_state", false)
               .rejected[static_cast<size_t>(Reject::kForgedSender)] == 1;
  })) << describe(r2);
  ASSERT_TRUE(wait_until([&] { return r2.sink().count(r2.sink().states) == 3; }));
  std::vector<uint32_t> got;
  for (const auto& s : r2.sink().copy(r2.sink().states)) got.push_back(s.path_index);
  EXPECT_EQ(got, (std::vector<uint32_t>{1, 30, 2}));
  EXPECT_EQ(plain.sink().count(plain.sink().states), 0u) << "a plain bridge read the team";
  fs::remove_all(keys);
  fs::remove_all(foreign);
}

// A raw capture of every frame on the loopback interface of a network namespace.
class LoopbackCapture {
 public:
  LoopbackCapture() {
    fd_ = ::socket(AF_PACKET, SOCK_RAW, htons(ETH_P_ALL));
    if (fd_ < 0) return;
    sockaddr_ll at{};
    at.sll_family = AF_PACKET;
    at.sll_protocol = htons(ETH_P_ALL);
    at.sll_ifindex = static_cast<int>(::if_nametoindex("lo"));
    timeval timeout{0, 100'000};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&at), sizeof at) != 0) return;
    thread_ = std::thread([this] {
      std::vector<uint8_t> frame(65536);
      while (!stop_.load()) {
        const ssize_t n = ::recv(fd_, frame.data(), frame.size(), 0);
        if (n <= 0) continue;
        std::lock_guard lock(mutex_);
        bytes_.insert(bytes_.end(), frame.begin(), frame.begin() + n);
        bytes_.push_back(0);  // frames apart: a match never spans two
      }
    });
  }
  ~LoopbackCapture() {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
    if (fd_ >= 0) ::close(fd_);
  }
  LoopbackCapture(const LoopbackCapture&) = delete;
  LoopbackCapture& operator=(const LoopbackCapture&) = delete;
  bool ok() const { return thread_.joinable(); }
  size_t size() const {
    std::lock_guard lock(mutex_);
    return bytes_.size();
  }
  bool contains(const std::vector<uint8_t>& needle) const {
    std::lock_guard lock(mutex_);
    return std::search(bytes_.begin(), bytes_.end(), needle.begin(), needle.end()) != bytes_.end();
  }

 private:
  int fd_ = -1;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;
  std::vector<uint8_t> bytes_;
};

// The test process's own network namespace, its loopback up: nothing else on the machine
// shares the capture. Needs root (CAP_SYS_ADMIN, CAP_NET_RAW).
bool own_network_namespace() {
  if (::unshare(CLONE_NEWNET) != 0) return false;
  const int s = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (s < 0) return false;
  ifreq ifr{};
  std::snprintf(ifr.ifr_name, sizeof ifr.ifr_name, "lo");
  bool up = ::ioctl(s, SIOCGIFFLAGS, &ifr) == 0;
  ifr.ifr_flags = static_cast<short>(ifr.ifr_flags | IFF_UP);
  up = up && ::ioctl(s, SIOCSIFFLAGS, &ifr) == 0;
  ::close(s);
  return up;
}

// What a patch of robot 1 (Source::send_patch) carries: 64 bytes of its payload, and its
// type's name in the envelope; found in the capture of a plain run. (Topic names are not
// secret: the permissions documents that the authentication handshake carries, signed but
// not encrypted, list them; docs/security.md.)
std::vector<std::vector<uint8_t>> plaintext_of_patch(uint32_t index) {
  std::vector<uint8_t> data(64);
  for (size_t i = 0; i < data.size(); ++i) data[i] = static_cast<uint8_t>((i + 4096) * 31 + index);
  const std::string type = msg::TsdfPatch::kTypeName;
  return {data, {type.begin(), type.end()}};
}

TEST(DdsSecurity, ACaptureOfTheLoopbackTrafficHoldsNoPlaintext) {
  if (!own_network_namespace())
    GTEST_SKIP() << "needs root: a network namespace of its own and a raw capture (CI runs it)";
  LoopbackCapture capture;
  ASSERT_TRUE(capture.ok()) << "no raw socket on lo";
  const std::string keys = make_keys("alpha", {"robot_1", "robot_2"});
  const auto exchange = [&](const std::string& top, uint32_t index) {
    Robot r1(1, "", "[robot_state, patch]", top), r2(2, "", "[robot_state, patch]", top);
    wait_ready({&r1, &r2}, 2, {"patch"});
    ASSERT_TRUE(r1.source().send_patch(index, 300'000));  // fragmented by DDS
    ASSERT_TRUE(wait_until([&] {
      std::lock_guard lock(r2.sink().mutex);
      return r2.sink().patches.size() == 1;
    }));
  };
  // secure: the patch crossed, and neither its payload nor its type is in clear
  exchange(security_block(keys), 1);
  EXPECT_GT(capture.size(), 300'000u);
  const char* what[] = {"the patch's payload", "its type name"};
  const auto texts = plaintext_of_patch(1);
  for (size_t i = 0; i < texts.size(); ++i)
    EXPECT_FALSE(capture.contains(texts[i])) << what[i] << " in clear";
  // the control, after: a plain run's capture holds both
  exchange("", 1);
  for (size_t i = 0; i < texts.size(); ++i)
    EXPECT_TRUE(capture.contains(texts[i])) << what[i] << " not found in a plain run's capture";
  fs::remove_all(keys);
}

}  // namespace
}  // namespace scancrew::dds_bridge
