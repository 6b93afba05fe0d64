// The dds_bridge over real Fast DDS on robot loss (bridge_harness.hpp): a destroyed launch,
// and a killed process (a child process of this binary), are reported lost; a restarted
// robot process takes over its id once the old one is lost.
//
// Waits are polls with generous bounds (a loaded 2-core machine), never fixed sleeps.

#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "components/dds_bridge/dds_bridge.hpp"
#include "tests/components/dds_bridge/bridge_harness.hpp"

namespace scancrew::dds_bridge {
namespace {

using namespace testing;  // NOLINT(google-build-using-namespace): the harness

TEST(DdsBridge, ADestroyedTeammateIsReportedLost) {
  auto r1 = std::make_unique<Robot>(1, "", "[robot_state]");
  Robot r2(2, "", "[robot_state]");
  wait_ready({r1.get(), &r2}, 2, {"robot_state"});
  ASSERT_TRUE(wait_until([&] { return r2.bridge().peers_alive() == 1; }));
  EXPECT_EQ(r2.sink().count(r2.sink().lost), 0u);

  const auto t0 = Clock::now();
  r1->destroy();
  ASSERT_TRUE(wait_until([&] { return r2.sink().count(r2.sink().lost) >= 1; }, 10.0));
  const double took_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const auto lost = r2.sink().copy(r2.sink().lost);
  EXPECT_EQ(lost[0].header.robot_id, 1u);
  EXPECT_EQ(lost[0].mode, msg::RobotState::Mode::kLost);
  EXPECT_EQ(r2.bridge().stats().peers_lost, 1u);
  EXPECT_EQ(r2.bridge().peers_alive(), 0u);
  std::printf("robot 1 reported lost %.3f s after its launch was destroyed\n", took_s);
}

// The child of the next test: a robot that runs until it is killed.
TEST(DdsBridgeChild, RunsARobotUntilKilled) {
  // NOLINTNEXTLINE(concurrency-mt-unsafe): getenv is read before any thread starts
  if (std::getenv("SCANCREW_DDS_TEST_CHILD") == nullptr)
    GTEST_SKIP() << "only run as the child process of AKilledRobotProcessIsReportedLost...";
  Robot r4(4, "", "[robot_state]");
  ASSERT_TRUE(wait_until([&] { return r4.active(); }));
  std::this_thread::sleep_for(std::chrono::seconds(60));  // the parent kills us long before
}

// Kills the child process on every exit path of the test.
struct ChildGuard {
  pid_t pid = -1;
  ~ChildGuard() { kill_now(); }
  void kill_now() {
    if (pid <= 0) return;
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    pid = -1;
  }
};

// Starts this binary's child test (robot 4) in our domain and partition.
void spawn_child_robot(ChildGuard& child) {
  std::vector<std::string> env_strings;
  for (char** e = environ; *e != nullptr; ++e)
    if (std::string_view(*e).substr(0, 24) != "SCANCREW_DDS_TEST_CHILD=")
      env_strings.emplace_back(*e);
  env_strings.push_back("SCANCREW_DDS_TEST_CHILD=" + std::to_string(::getpid()));
  std::vector<char*> envp;
  envp.reserve(env_strings.size() + 1);
  for (auto& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);
  std::string exe = "/proc/self/exe";
  std::string filter = "--gtest_filter=DdsBridgeChild.RunsARobotUntilKilled";
  std::vector<char*> argv = {exe.data(), filter.data(), nullptr};
  ASSERT_EQ(::posix_spawn(&child.pid, exe.c_str(), nullptr, nullptr, argv.data(), envp.data()), 0);
}

// Robot 3 stays alive beside it: Fast DDS 2.9's liveliness, asserted by any live writer for
// every one it tracks, never reported the killed robot lost with a live teammate in the
// domain (only the 20 s participant lease did; the bridge now sets that lease to its own).
TEST(DdsBridge, AKilledRobotProcessIsReportedLostWhenItsLeaseRunsOut) {
  Robot r2(2, "", "[robot_state]");
  Robot r3(3, "", "[robot_state]");
  ASSERT_TRUE(r2.ok());
  ASSERT_TRUE(wait_until([&] { return r2.active(); }));
  ChildGuard child;
  spawn_child_robot(child);
  ASSERT_TRUE(wait_until([&] { return r2.bridge().peers_alive() == 2; }, 30.0))
      << "the child robot never appeared";
  ASSERT_EQ(r2.sink().count(r2.sink().lost), 0u);
  const auto t0 = Clock::now();
  child.kill_now();  // no goodbye: only the liveliness lease can tell
  ASSERT_TRUE(wait_until([&] { return r2.sink().count(r2.sink().lost) >= 1; }, 10.0));
  const double took_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const auto lost = r2.sink().copy(r2.sink().lost);
  EXPECT_EQ(lost[0].header.robot_id, 4u);
  EXPECT_EQ(lost[0].mode, msg::RobotState::Mode::kLost);
  EXPECT_LT(took_s, 5.0) << "a 1 s participant lease (Fast DDS's default is 20 s)";
  std::printf("killed robot 4 reported lost %.3f s after SIGKILL (participant lease 1 s)\n",
              took_s);
}

// A restarted robot: its old process was killed (no goodbye) and the new one starts at once,
// while the old participant is still in the domain: refused until the old one leaves (its
// participant lease, 1 s at least), it then holds the robot's id and its samples count.
TEST(DdsBridge, ARestartedRobotProcessTakesOverItsIdOnceTheOldOneIsLost) {
  Robot r2(2, "", "[robot_state]");
  ASSERT_TRUE(r2.ok());
  ASSERT_TRUE(wait_until([&] { return r2.active(); }));
  ChildGuard child;
  spawn_child_robot(child);
  ASSERT_TRUE(wait_until([&] { return r2.bridge().peers_alive() == 1; }, 30.0))
      << "the child robot never appeared";
  child.kill_now();
  const auto t0 = Clock::now();
  Robot r4(4, "", "[robot_state]");  // the restarted process
  ASSERT_TRUE(wait_until(
      [&] { return r2.sink().count(r2.sink().lost) >= 1 && r2.bridge().peers_alive() == 1; }, 15.0))
      << "the old robot 4 was not reported lost, or the restarted one not taken for robot 4";
  const double took_s = std::chrono::duration<double>(Clock::now() - t0).count();
  EXPECT_LT(took_s, 5.0) << "a 1 s participant lease (Fast DDS's default is 20 s)";
  const auto heard = [&] {
    for (const msg::RobotState& s : r2.sink().copy(r2.sink().states))
      if (s.header.robot_id == 4 && s.path_index == 7) return true;
    return false;
  };
  ASSERT_TRUE(wait_until([&] {
    if (heard()) return true;
    (void)r4.source().send_state(7);
    return false;
  })) << "the restarted robot's samples are refused";
  EXPECT_EQ(r2.bridge().stats().peers_lost, 1u);
  std::printf("restarted robot 4 taken over %.3f s after it started\n", took_s);
}

}  // namespace
}  // namespace scancrew::dds_bridge
