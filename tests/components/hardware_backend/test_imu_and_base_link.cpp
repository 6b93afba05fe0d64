// The hardware backend's IMU and base links (the fixture: hardware_backend_fixture.hpp):
// the IMU is a pseudo-terminal whose master end the test writes, the base a UDP socket the
// test binds on 127.0.0.1; missing or wrong devices and bad parameters named, what was
// opened closed again on failure; the IMU line reader and the velocity datagram's layout.
// Every wait on the outside world is bounded (kWaitLimit: 2 s).

#include <gtest/gtest.h>
#include <pty.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "components/hardware_backend/base_command_link.hpp"
#include "components/hardware_backend/hardware_backend.hpp"
#include "components/hardware_backend/imu_line_reader.hpp"
#include "tests/components/hardware_backend/hardware_backend_fixture.hpp"

namespace scancrew::hardware_backend {
namespace {

using namespace fixture;  // NOLINT(google-build-using-namespace): the fixture
using namespace std::chrono_literals;

TEST_F(HardwareBackendTest, NamesAMissingImuDeviceAndOneThatIsNotASerialPort) {
  write_sequence(1);
  write_calibration({});
  const std::string missing = composition_error(camera_params() + ", imu_device: /dev/ttyNOPE7");
  EXPECT_NE(missing.find("imu_device '/dev/ttyNOPE7': cannot open (no such device)"),
            std::string::npos)
      << missing;
  const std::string not_a_tty =
      composition_error(camera_params() + ", imu_device: '" + dir_.file("stereo.yaml") + "'");
  EXPECT_NE(not_a_tty.find("imu_device '" + dir_.file("stereo.yaml") +
                           "': cannot open (not a serial port"),
            std::string::npos)
      << not_a_tty;
}

TEST_F(HardwareBackendTest, ClosesWhatItOpenedWhenALaterDeviceFails) {
  write_sequence(1);
  write_calibration({});
  int master = -1, slave = -1;
  char slave_path[256] = {};
  ASSERT_EQ(::openpty(&master, &slave, slave_path, nullptr, nullptr), 0);
  const size_t before = open_descriptors();
  // cameras and IMU open; the base cannot (a broadcast address needs SO_BROADCAST)
  const std::string error = composition_error(camera_params() + ", imu_device: '" + slave_path +
                                              "', base_host: 255.255.255.255, base_port: 5800");
  EXPECT_NE(error.find("base_host '255.255.255.255:5800': cannot open ("), std::string::npos)
      << error;
  EXPECT_EQ(open_descriptors(), before);  // the IMU port was closed again
  ::close(slave);
  ::close(master);
}

TEST_F(HardwareBackendTest, TurnsSerialImuLinesIntoImuMessages) {
  write_sequence(1);
  write_calibration({});
  int master = -1, slave = -1;
  char slave_path[256] = {};
  ASSERT_EQ(::openpty(&master, &slave, slave_path, nullptr, nullptr), 0);
  Run run = compose(camera_params() + ", imu_device: '" + slave_path +
                        "', imu_baud: 921600, imu_poll_hz: 100, imu_max_line_bytes: 64",
                    0.05);
  ASSERT_TRUE(run.launch);
  const auto write = [master](const std::string& text) {
    ASSERT_EQ(::write(master, text.data(), text.size()), static_cast<ssize_t>(text.size()));
  };
  // steps the graph until `n` samples are out or the wait limit passes
  const auto run_until_samples = [&run](size_t n) {
    const auto deadline = std::chrono::steady_clock::now() + kWaitLimit;
    while (run.recorder->imu.size() < n && std::chrono::steady_clock::now() < deadline) {
      run.launch->run();
      std::this_thread::sleep_for(1ms);
    }
  };

  write("IMU,0.1,-0.2,9.81,0.01,0.02,-0.03\nIMU,bad,line\nIMU,1,2,3,4,5,6\nIMU,1.5,2");
  run_until_samples(2);
  ASSERT_EQ(run.recorder->imu.size(), 2u);
  const msg::Imu& first = run.recorder->imu[0];
  EXPECT_EQ(first.linear_acceleration_mps2.x, 0.1);
  EXPECT_EQ(first.linear_acceleration_mps2.y, -0.2);
  EXPECT_EQ(first.linear_acceleration_mps2.z, 9.81);
  EXPECT_EQ(first.angular_velocity_radps.x, 0.01);
  EXPECT_EQ(first.angular_velocity_radps.y, 0.02);
  EXPECT_EQ(first.angular_velocity_radps.z, -0.03);
  EXPECT_EQ(first.header.robot_id, 7u);
  EXPECT_GT(first.header.stamp_ns, 0);
  EXPECT_EQ(first.header.stamp_ns % 10'000'000, 0);  // stamped by a poll on the sim clock
  EXPECT_EQ(run.recorder->imu[1].angular_velocity_radps.z, 6.0);
  EXPECT_EQ(run.backend->stats().imu_lines.malformed, 1u);

  // the split line completes; an overlong line is discarded; CRLF is accepted
  write(",3,4,5,6\n" + std::string(100, '7') + "\nIMU,+1e-3,0,0,0,0,-0\r\n");
  run_until_samples(4);
  ASSERT_EQ(run.recorder->imu.size(), 4u);
  EXPECT_EQ(run.recorder->imu[2].linear_acceleration_mps2.x, 1.5);
  EXPECT_EQ(run.recorder->imu[2].angular_velocity_radps.z, 6.0);
  EXPECT_EQ(run.recorder->imu[3].linear_acceleration_mps2.x, 1e-3);
  const auto stats = run.backend->stats();
  EXPECT_EQ(stats.imu_lines.samples, 4u);
  EXPECT_EQ(stats.imu_lines.malformed, 1u);
  EXPECT_EQ(stats.imu_lines.overlong, 1u);
  EXPECT_EQ(stats.imu_published, 4u);
  EXPECT_EQ(stats.imu_read_errors, 0u);
  ::close(slave);
  ::close(master);
}

TEST_F(HardwareBackendTest, SendsEachVelocityCommandAsOneDatagramAndAStopOnDeactivate) {
  write_sequence(1);
  write_calibration({});
  UdpReceiver base;
  Run run = compose(
      camera_params() + ", base_host: 127.0.0.1, base_port: " + std::to_string(base.port()), 0.05);
  ASSERT_TRUE(run.launch);
  auto topic = run.launch->graph().topic<msg::VelocityCommand>("/r1/cmd_vel", 4);
  ASSERT_TRUE(topic);
  Publisher<msg::VelocityCommand> cmd_vel(*topic, 0, &run.launch->graph().clock(), nullptr);
  const auto command = [&](double vx, double vy, double vz, double yaw_rate, int64_t stamp) {
    auto loan = cmd_vel.loan();
    ASSERT_TRUE(loan);
    (*loan)->linear_mps = {vx, vy, vz};
    (*loan)->yaw_rate_radps = yaw_rate;
    (*loan)->header.stamp_ns = stamp;
    ASSERT_TRUE(cmd_vel.publish(std::move(*loan)));
  };
  const auto next = [&base]() -> hardware_backend::VelocityDatagram {
    auto bytes = base.receive(std::chrono::duration_cast<std::chrono::milliseconds>(kWaitLimit));
    EXPECT_TRUE(bytes) << "no datagram";
    if (!bytes) return {};
    EXPECT_EQ(bytes->size(), hardware_backend::kVelocityDatagramBytes);
    auto d = hardware_backend::decode_velocity_datagram(*bytes);
    EXPECT_TRUE(d) << (d ? "" : hardware_backend::to_string(d.error()));
    return d ? *d : hardware_backend::VelocityDatagram{};
  };

  command(0.5, -0.25, 0.125, 0.3, 123'456'789);
  run.launch->run();  // delivers the command; deactivating at the end sends a stop
  command(-1.0, 0, 0, -0.7, 987'654'321);
  run.launch->run();

  const hardware_backend::VelocityDatagram d1 = next(), stop1 = next(), d2 = next(), stop2 = next();
  EXPECT_EQ(d1.robot_id, 7u);
  EXPECT_EQ(d1.seq, 1u);
  EXPECT_EQ(d1.stamp_ns, 123'456'789);
  EXPECT_EQ(d1.vx_mps, 0.5);
  EXPECT_EQ(d1.vy_mps, -0.25);
  EXPECT_EQ(d1.vz_mps, 0.125);
  EXPECT_EQ(d1.yaw_rate_radps, 0.3);
  EXPECT_EQ(stop1.seq, 2u);
  EXPECT_EQ(stop1.vx_mps, 0.0);
  EXPECT_EQ(stop1.yaw_rate_radps, 0.0);
  EXPECT_EQ(stop1.stamp_ns, 50'000'000);  // the sim clock at deactivation
  EXPECT_EQ(d2.seq, 3u);
  EXPECT_EQ(d2.stamp_ns, 987'654'321);
  EXPECT_EQ(d2.vx_mps, -1.0);
  EXPECT_EQ(d2.yaw_rate_radps, -0.7);
  EXPECT_EQ(stop2.seq, 4u);
  EXPECT_FALSE(base.receive(0ms)) << "one datagram per command";
  command(std::nan(""), 0.5, 0, 0, 555);  // never reaches the motors: a stop instead
  run.launch->run();
  const hardware_backend::VelocityDatagram instead = next(), stop3 = next();
  EXPECT_EQ(instead.seq, 5u);
  EXPECT_EQ(instead.stamp_ns, 555);
  EXPECT_EQ(instead.vx_mps, 0.0);
  EXPECT_EQ(instead.vy_mps, 0.0);
  EXPECT_EQ(stop3.seq, 6u);
  EXPECT_FALSE(base.receive(0ms)) << "one datagram per command";
  const auto stats = run.backend->stats();
  EXPECT_EQ(stats.commands_sent, 2u);
  EXPECT_EQ(stats.commands_not_finite, 1u);
  EXPECT_EQ(stats.stop_commands_sent, 3u);
  EXPECT_EQ(stats.command_send_errors, 0u);
}

TEST_F(HardwareBackendTest, RejectsBadParametersByKey) {
  write_sequence(1);
  write_calibration({});
  const std::string host = composition_error(camera_params() + ", base_host: robot.local");
  EXPECT_NE(host.find("params.base_host: 'robot.local' is not an IPv4 address"), std::string::npos)
      << host;
  const std::string port = composition_error(camera_params() + ", base_host: 10.0.0.2");
  EXPECT_NE(port.find("params.base_port: missing"), std::string::npos) << port;
  const std::string baud = composition_error(camera_params() + ", imu_baud: 12345");
  EXPECT_NE(baud.find("params.imu_baud: 12345 is not a termios baud rate"), std::string::npos)
      << baud;
  const std::string api = composition_error(camera_params() + ", camera_api: gphoto");
  EXPECT_NE(api.find("params.camera_api: 'gphoto' is not allowed"), std::string::npos) << api;
}

TEST(ImuLineReader, ParsesSplitLinesAndCountsMalformedAndOverlongOnes) {
  hardware_backend::ImuLineReader reader(40);
  std::vector<hardware_backend::ImuReading> out;
  const auto feed = [&](std::string_view bytes) {
    reader.feed(bytes, [&](const hardware_backend::ImuReading& r) { out.push_back(r); });
  };
  feed("IMU,1,2,3,4,5,6\nIMU,0.5,");
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(reader.buffered_bytes(), 8u);
  feed("0,0,0,0,-2.5e1\n\n");
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].linear_acceleration_mps2.x, 0.5);
  EXPECT_EQ(out[1].angular_velocity_radps.z, -25.0);
  for (const char* bad : {"IMU,1,2,3,4,5\n", "IMU,1,2,3,4,5,6,7\n", "IMU,1,2,3,4,5,nan\n",
                          "imu,1,2,3,4,5,6\n", "IMU, 1,2,3,4,5,6\n", "IMU,1,2,3,4,5,6 \n",
                          "IMU,1,,3,4,5,6\n", "IMU,+-1,2,3,4,5,6\n", "IMU,1,2,3,4,5,1e999\n"})
    feed(bad);
  EXPECT_EQ(out.size(), 2u);
  EXPECT_EQ(reader.stats().malformed, 9u);
  feed(std::string(100, 'x'));  // no newline: the buffer stays bounded
  EXPECT_LE(reader.buffered_bytes(), 40u);
  feed("still the same line\nIMU,9,9,9,9,9,9\n");
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(reader.stats().overlong, 1u);
  EXPECT_EQ(reader.stats().samples, 3u);
}

TEST(VelocityDatagram, HasTheDocumentedLittleEndianLayoutAndRejectsOthers) {
  hardware_backend::VelocityDatagram d;
  d.robot_id = 0x01020304;
  d.seq = 0xA0B0C0D0;
  d.stamp_ns = -2;
  d.vx_mps = 1.0;
  d.vy_mps = -0.5;
  d.vz_mps = 0.25;
  d.yaw_rate_radps = 3.0;
  const auto bytes = hardware_backend::encode_velocity_datagram(d);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "SCVC");
  EXPECT_EQ(bytes[4], 1);
  EXPECT_EQ(bytes[5] | bytes[6] | bytes[7], 0);
  EXPECT_EQ(bytes[8], 0x04);   // robot id, least significant byte first
  EXPECT_EQ(bytes[15], 0xA0);  // seq's most significant byte
  EXPECT_EQ(bytes[16], 0xFE);  // stamp -2
  EXPECT_EQ(bytes[23], 0xFF);
  EXPECT_EQ(bytes[31], 0x3F);  // 1.0 = 0x3FF0000000000000
  EXPECT_EQ(bytes[30], 0xF0);
  auto back = hardware_backend::decode_velocity_datagram(bytes);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->robot_id, d.robot_id);
  EXPECT_EQ(back->seq, d.seq);
  EXPECT_EQ(back->stamp_ns, d.stamp_ns);
  EXPECT_EQ(back->vx_mps, 1.0);
  EXPECT_EQ(back->vy_mps, -0.5);
  EXPECT_EQ(back->vz_mps, 0.25);
  EXPECT_EQ(back->yaw_rate_radps, 3.0);

  auto wrong = bytes;
  wrong[0] = 'X';
  EXPECT_EQ(hardware_backend::decode_velocity_datagram(wrong).error(),
            hardware_backend::DatagramError::kBadMagic);
  wrong = bytes;
  wrong[4] = 2;
  EXPECT_EQ(hardware_backend::decode_velocity_datagram(wrong).error(),
            hardware_backend::DatagramError::kUnsupportedVersion);
  EXPECT_EQ(hardware_backend::decode_velocity_datagram(std::span(bytes).first(40)).error(),
            hardware_backend::DatagramError::kWrongSize);
}

}  // namespace
}  // namespace scancrew::hardware_backend
