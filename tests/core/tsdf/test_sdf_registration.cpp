// SDF-to-map registration (core/tsdf/sdf_registration.hpp) on analytic scenes: a room corner
// with a box, written into a reference map and, seen from a frame off by a known drift, into a
// source map; the registration must find the drift.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/tsdf/sdf_registration.hpp"
#include "tests/core/tsdf/sdf_scenes.hpp"

namespace scancrew::tsdf {
namespace {

// floor z = 0, walls x = 3 and y = 2.5 (solid beyond), a box on the floor
double corner_sdf(const Eigen::Vector3d& p) {
  const test::Box box{.centre = {1.0, 0.5, 0.4}, .half = {0.5, 0.4, 0.4}};
  return std::min({p.z(), 3.0 - p.x(), 2.5 - p.y(), box.sdf(p)});
}

const Eigen::Vector3d kLo{-1.0, -1.0, -0.4}, kHi{3.4, 2.9, 1.6};

Eigen::Isometry3d drift(double x, double y, double z, double yaw_deg) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

// The scene as a robot whose frame is off by T_reference_source maps it: its point p is the
// reference's T·p.
template <class Sdf>
std::shared_ptr<const MapSnapshot> seen_through(const Sdf& sdf, const Eigen::Isometry3d& T) {
  TsdfMap map(test::config(0.1));
  test::fill(
      map, [&](const Eigen::Vector3d& p) { return sdf(T * p); }, kLo, kHi);
  return map.snapshot();
}

double yaw_deg_of(const Eigen::Isometry3d& T) {
  return std::atan2(T.linear()(1, 0), T.linear()(0, 0)) * 180.0 / M_PI;
}

TEST(SdfRegistration, TrilinearSamplingOfAPlaneIsExactWithItsGradient) {
  const auto map = seen_through([](const Eigen::Vector3d& p) { return 0.4 * p.x() + 0.3 * p.z(); },
                                Eigen::Isometry3d::Identity());
  const auto v = sample_sdf(*map, {0.537, 0.21, 0.113});
  ASSERT_TRUE(v.has_value());
  EXPECT_NEAR(v->distance_m, 0.4 * 0.537 + 0.3 * 0.113, 1e-6);
  EXPECT_NEAR(v->gradient.x(), 0.4, 1e-5);
  EXPECT_NEAR(v->gradient.y(), 0.0, 1e-5);
  EXPECT_NEAR(v->gradient.z(), 0.3, 1e-5);
  EXPECT_FALSE(sample_sdf(*map, {20.0, 0, 0}).has_value());  // nothing observed there
}

TEST(SdfRegistration, FindsATeammatesDriftOnARoomCorner) {
  const auto reference = seen_through(corner_sdf, Eigen::Isometry3d::Identity());
  const Eigen::Isometry3d truth = drift(0.15, -0.10, 0.05, 3.0);
  const auto source = seen_through(corner_sdf, truth);
  const double band = 0.5 * reference->config().truncation_m;
  const auto r = register_to_map(*reference, surface_samples(*source, band));
  ASSERT_TRUE(r.has_value()) << r.error();
  const Eigen::Isometry3d& T = r->T_reference_source;
  EXPECT_LT((T.translation() - truth.translation()).norm(), 0.01);
  EXPECT_NEAR(yaw_deg_of(T), 3.0, 0.2);
  EXPECT_GT(r->rms_before_m, 0.03);
  EXPECT_LT(r->rms_after_m, 0.005);
  EXPECT_GE(r->overlap, RegistrationConfig{}.min_overlap);
}

TEST(SdfRegistration, AlignedMapsStayWhereTheyAre) {
  const auto reference = seen_through(corner_sdf, Eigen::Isometry3d::Identity());
  const auto r = register_to_map(*reference, surface_samples(*reference, 0.15));
  ASSERT_TRUE(r.has_value()) << r.error();
  EXPECT_LT(r->T_reference_source.translation().norm(), 1e-3);
  EXPECT_NEAR(yaw_deg_of(r->T_reference_source), 0.0, 0.01);
  EXPECT_LT(r->rms_after_m, 1e-4);
}

TEST(SdfRegistration, TheFloorAloneIsRefusedAsUnconstrained) {
  const auto floor = [](const Eigen::Vector3d& p) { return p.z(); };
  const auto reference = seen_through(floor, Eigen::Isometry3d::Identity());
  const auto source = seen_through(floor, drift(0.2, 0.1, 0.03, 2.0));
  const auto r = register_to_map(*reference, surface_samples(*source, 0.15));
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().find("does not constrain"), std::string::npos) << r.error();
}

TEST(SdfRegistration, MapsThatDoNotOverlapAreRefused) {
  const auto reference = seen_through(corner_sdf, Eigen::Isometry3d::Identity());
  const auto far = seen_through(corner_sdf, drift(-30.0, 0, 0, 0));  // a room 30 m away
  const auto r = register_to_map(*reference, surface_samples(*far, 0.15),
                                 drift(30.0, 0, 0, 0) * drift(30.0, 0, 0, 0));
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().find("min_overlap"), std::string::npos) << r.error();
}

}  // namespace
}  // namespace scancrew::tsdf
