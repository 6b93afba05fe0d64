// The hardware backend's stereo cameras against image sequences written with cv::imwrite
// (the fixture: hardware_backend_fixture.hpp): frames published unchanged under identity
// rectification and rectified like OpenCV otherwise, bad frames dropped, missing cameras
// and calibration problems named; the calibration file's parser.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "components/hardware_backend/hardware_backend.hpp"
#include "components/hardware_backend/stereo_calibration.hpp"
#include "tests/components/hardware_backend/hardware_backend_fixture.hpp"

namespace scancrew::hardware_backend {
namespace {

using namespace fixture;  // NOLINT(google-build-using-namespace): the fixture
using hardware_backend::FrameStatus;

TEST_F(HardwareBackendTest, PublishesTheImageSequenceUnchangedUnderIdentityRectification) {
  const auto pairs = write_sequence(3);
  write_calibration({});
  Run run = compose(camera_params());
  ASSERT_TRUE(run.launch);
  run.launch->run();  // ticks at 0.1 .. 0.4 s: three frames, then the sequence has ended

  ASSERT_EQ(run.recorder->frames.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const HwRecorder::Frame& f = run.recorder->frames[i];
    EXPECT_EQ(f.stamp_ns, static_cast<int64_t>(i + 1) * 100'000'000);  // capture time, sim clock
    EXPECT_EQ(f.intrinsics.width, 64u);
    EXPECT_EQ(f.intrinsics.height, 48u);
    EXPECT_NEAR(f.intrinsics.fx, 50.0, 1e-6);
    EXPECT_NEAR(f.intrinsics.fy, 50.0, 1e-6);
    EXPECT_NEAR(f.intrinsics.cx, 31.5, 1e-6);
    EXPECT_NEAR(f.intrinsics.cy, 23.5, 1e-6);
    EXPECT_DOUBLE_EQ(f.baseline_m, 0.26);
    // identity rotation, no distortion: the rectified pair is the input pair
    EXPECT_EQ(f.left, bytes_of(pairs[i].left)) << "frame " << i;
    EXPECT_EQ(f.right, bytes_of(pairs[i].right)) << "frame " << i;
    // and still a rectified pair: each right row is its left row shifted by the disparity
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x + kDisparityPx < 64; ++x)
        ASSERT_EQ(f.right[y * 64 + x], f.left[y * 64 + x + kDisparityPx]) << y << "," << x;
  }
  const auto stats = run.backend->stats();
  EXPECT_EQ(stats.frames_published, 3u);
  EXPECT_EQ(stats.frames_dropped[static_cast<size_t>(FrameStatus::kGrabFailed)], 1u);
}

TEST_F(HardwareBackendTest, RectifiesWithTheCalibrationsDistortionAndRotationLikeOpenCv) {
  const auto pairs = write_sequence(1);
  Calibration c;
  c.left_d = {-0.08, 0.01, 0.001, -0.001, 0};
  c.right_d = {-0.06, 0.005, 0, 0, 0};
  const double a = 1.5 * M_PI / 180;  // the right camera yawed by 1.5 degrees
  c.r = {std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a)};
  c.t = {-0.2, 0.004, 0.002};
  write_calibration(c);
  Run run = compose(camera_params(), 0.15);
  ASSERT_TRUE(run.launch);
  run.launch->run();
  ASSERT_EQ(run.recorder->frames.size(), 1u);
  const HwRecorder::Frame& f = run.recorder->frames[0];

  // the reference: OpenCV called directly on the same calibration
  const cv::Mat k = (cv::Mat_<double>(3, 3) << c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
  const cv::Mat r = cv::Mat(c.r).reshape(1, 3), t = cv::Mat(c.t);
  cv::Mat r1, r2, p1, p2, q, lm1, lm2, rm1, rm2, left, right;
  const cv::Size size(64, 48);
  cv::stereoRectify(k, cv::Mat(c.left_d), k, cv::Mat(c.right_d), size, r, t, r1, r2, p1, p2, q,
                    cv::CALIB_ZERO_DISPARITY, 0.0, size);
  cv::initUndistortRectifyMap(k, cv::Mat(c.left_d), r1, p1, size, CV_16SC2, lm1, lm2);
  cv::initUndistortRectifyMap(k, cv::Mat(c.right_d), r2, p2, size, CV_16SC2, rm1, rm2);
  cv::remap(pairs[0].left, left, lm1, lm2, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
  cv::remap(pairs[0].right, right, rm1, rm2, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);

  EXPECT_EQ(f.intrinsics.width, 64u);
  EXPECT_EQ(f.intrinsics.height, 48u);
  EXPECT_DOUBLE_EQ(f.intrinsics.fx, p1.at<double>(0, 0));
  EXPECT_DOUBLE_EQ(f.intrinsics.fy, p1.at<double>(1, 1));
  EXPECT_DOUBLE_EQ(f.intrinsics.cx, p1.at<double>(0, 2));
  EXPECT_DOUBLE_EQ(f.intrinsics.cy, p1.at<double>(1, 2));
  EXPECT_DOUBLE_EQ(f.baseline_m, std::sqrt(0.2 * 0.2 + 0.004 * 0.004 + 0.002 * 0.002));
  // rectified: the right camera's projection differs from the left by the baseline only
  EXPECT_NEAR(-p2.at<double>(0, 3) / p2.at<double>(0, 0), f.baseline_m, 1e-9);
  EXPECT_EQ(f.left, bytes_of(left));
  EXPECT_EQ(f.right, bytes_of(right));
  EXPECT_NE(f.left, bytes_of(pairs[0].left));  // the calibration did change the images
  EXPECT_NE(f.right, bytes_of(pairs[0].right));
}

TEST_F(HardwareBackendTest, DropsAFrameWhoseLeftAndRightSizesDifferAndKeepsRunning) {
  write_sequence(3);
  // frame 1 of the right camera comes in at another size
  const cv::Mat small = make_pair(32, 24, kDisparityPx, 9).right;
  ASSERT_TRUE(cv::imwrite(dir_.file("right_001.png"), small));
  write_calibration({});
  Run run = compose(camera_params(), 0.35);
  ASSERT_TRUE(run.launch);
  run.launch->run();
  ASSERT_EQ(run.recorder->frames.size(), 2u);
  EXPECT_EQ(run.recorder->frames[0].stamp_ns, 100'000'000);
  EXPECT_EQ(run.recorder->frames[1].stamp_ns, 300'000'000);
  const auto stats = run.backend->stats();
  EXPECT_EQ(stats.frames_dropped[static_cast<size_t>(FrameStatus::kSizeMismatch)], 1u);
  EXPECT_EQ(stats.frames_published, 2u);
}

TEST_F(HardwareBackendTest, RefusesCamerasWhoseImageSizeDiffersFromTheCalibration) {
  write_sequence(1, 80, 60);
  write_calibration({});  // 64x48
  const std::string error = composition_error(camera_params());
  EXPECT_NE(error.find("left_device '" + dir_.file("left_%03d.png") +
                       "': delivers 80x60 px, but the calibration '" + dir_.file("stereo.yaml") +
                       "' is for 64x48 px"),
            std::string::npos)
      << error;
  // and a requested size that is not the calibrated one
  write_sequence(1);
  const std::string requested = composition_error(camera_params() + ", width: 640, height: 480");
  EXPECT_NE(requested.find("width x height 640x480 px differs from the image size 64x48 px"),
            std::string::npos)
      << requested;
}

TEST_F(HardwareBackendTest, NamesAMissingCamera) {
  write_sequence(1);
  write_calibration({});
  const std::string missing_left =
      composition_error("left_device: /dev/video77, right_device: '" + dir_.file("right_%03d.png") +
                        "', calibration: '" + dir_.file("stereo.yaml") + "'");
  EXPECT_NE(missing_left.find("left_device '/dev/video77': cannot open (no such device)"),
            std::string::npos)
      << missing_left;
  const std::string missing_right = composition_error(
      "left_device: '" + dir_.file("left_%03d.png") + "', right_device: '" +
      dir_.file("nothing_%03d.png") + "', calibration: '" + dir_.file("stereo.yaml") + "'");
  EXPECT_NE(missing_right.find("right_device '" + dir_.file("nothing_%03d.png") +
                               "': cannot open (no image matches the pattern"),
            std::string::npos)
      << missing_right;
}

TEST_F(HardwareBackendTest, NamesTheCalibrationProblem) {
  write_sequence(1);
  Calibration c;
  c.left_k_override = "[50, 0, 31.5, 0, 50, 23.5, 0, 0]";
  write_calibration(c);
  const std::string malformed = composition_error(camera_params());
  EXPECT_NE(malformed.find(dir_.file("stereo.yaml") + ":4: left.K: has 8 numbers; allowed: 9"),
            std::string::npos)
      << malformed;

  std::filesystem::remove(dir_.file("stereo.yaml"));
  const std::string missing = composition_error(camera_params());
  EXPECT_NE(missing.find("calibration: " + dir_.file("stereo.yaml") +
                         ": cannot read the calibration file (no such file)"),
            std::string::npos)
      << missing;

  c = {};
  c.t = {0, 0, 0};
  write_calibration(c);
  const std::string zero = composition_error(camera_params());
  EXPECT_NE(zero.find("T: zero baseline"), std::string::npos) << zero;
}

TEST(StereoCalibration, ReadsTheExampleFile) {
  auto c = hardware_backend::load_stereo_calibration(SCANCREW_SOURCE_DIR
                                                     "/launch_cfg/calibration/example_stereo.yaml");
  ASSERT_TRUE(c) << c.error().front();
  EXPECT_EQ(c->left.width, 640u);
  EXPECT_EQ(c->left.height, 480u);
  EXPECT_NEAR(c->left.K[0], 320.0, 5.0);
  EXPECT_NEAR(c->baseline_m(), 0.26, 1e-3);
}

TEST(StereoCalibration, ListsEveryProblemWithItsKey) {
  const std::string text = R"(left:
  image_width: 640
  image_height: 480
  K: [320, 0, 319.5, 0, 320, 239.5, 0, 0, 2]
  D: [0, 0, 0]
right:
  image_width: 640
  image_height: 480.5
  K: [320, 0, 319.5, 0, 320, 239.5, 0, 0, 1]
  lens: fisheye
R: [1, 0, 0, 0, 1, 0, 0, 0, 2]
T: [0.26, 0, 0]
)";
  auto c = hardware_backend::parse_stereo_calibration(text, "calib.yaml");
  ASSERT_FALSE(c);
  std::string all;
  for (const auto& e : c.error()) all += e + "\n";
  for (const char* expected :
       {"calib.yaml:4: left.K: not a camera matrix", "calib.yaml:5: left.D: has 3 numbers",
        "calib.yaml:8: right.image_height: '480.5' is invalid",
        "calib.yaml:10: right.lens: unknown key", "calib.yaml:11: R: not a rotation",
        "calib.yaml:12: T: T.x > 0: the right camera is to the left of the left one"})
    EXPECT_NE(all.find(expected), std::string::npos) << expected << "\nin:\n" << all;
}

}  // namespace
}  // namespace scancrew::hardware_backend
