#pragma once

// SDF-to-map registration: the rigid correction that puts one robot's TSDF (a teammate's
// patches, in its own drifting odometry frame) onto another's map, so that a surface both
// have seen is one surface (Step 14, "drift between robots"; thesis 5.5 and its conclusion
// name the drift and leave collaborative SLAM open).
//
// Method: the source's near-surface voxels (|φ| under half the truncation) are samples
// (p, d). For a correction T, each residual is r = φ_ref(T·p) − d, with φ_ref the reference
// map's distance, trilinear over the 8 voxel centres around T·p (all known, else the sample
// does not overlap). Levenberg-Marquardt on the 4 degrees of freedom that drift in a
// visual-inertial odometry (x, y, z, yaw: gravity is observed, thesis 1.2.2), the yaw about
// the samples' centroid, with Huber weights (KinectFusion-style SDF alignment; Bylow et al.,
// "Real-time camera tracking and 3D reconstruction using signed distance functions", RSS
// 2013, do the same on one image's points).
//
// Refused, with the reason: fewer overlapping samples than min_overlap, or a problem that
// does not constrain all 4 degrees of freedom (only the floor in view: x, y and yaw free;
// one wall: its direction free), judged by the normalised Hessian's smallest eigenvalue.
//
// Plain functions on immutable snapshots; thread safe.

#include <Eigen/Geometry>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "core/tsdf/tsdf_map.hpp"

namespace scancrew::tsdf {

struct SdfSample {
  Eigen::Vector3d position;  // voxel centre, in the source's frame
  double distance_m = 0;
};

// A map's known voxels with |φ| < band_m, every `stride`-th (≥ 1) in a fixed order.
std::vector<SdfSample> surface_samples(const MapSnapshot& map, double band_m, size_t stride = 1);

// The reference's distance at p and its gradient, trilinear; nullopt where one of the 8
// voxel centres around p is unknown.
struct SdfValue {
  double distance_m = 0;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
};
std::optional<SdfValue> sample_sdf(const MapSnapshot& map, const Eigen::Vector3d& p);

struct RegistrationConfig {
  int max_iterations = 20;
  size_t min_overlap = 200;  // samples with a known reference distance
  double huber_m = 0.05;     // residuals beyond count linearly
  // the smallest eigenvalue of the Hessian (yaw scaled by the samples' spread), over the
  // largest: below it a degree of freedom is unconstrained
  double min_conditioning = 1e-3;
};

struct Registration {
  Eigen::Isometry3d T_reference_source = Eigen::Isometry3d::Identity();
  size_t overlap = 0;  // samples used at the last iteration
  double rms_before_m = 0, rms_after_m = 0;
  int iterations = 0;
};

// The correction that carries source samples onto the reference, starting from `initial`.
Result<Registration, std::string> register_to_map(
    const MapSnapshot& reference, const std::vector<SdfSample>& source,
    const Eigen::Isometry3d& initial = Eigen::Isometry3d::Identity(),
    const RegistrationConfig& config = {});

}  // namespace scancrew::tsdf
