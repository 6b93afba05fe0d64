// Open3D's headers are included here only (see open3d_peer.hpp).
#include "bench/tsdf/open3d_peer.hpp"

#include <open3d/Open3DConfig.h>
#include <open3d/camera/PinholeCameraIntrinsic.h>
#include <open3d/geometry/Image.h>
#include <open3d/geometry/RGBDImage.h>
#include <open3d/geometry/TriangleMesh.h>
#include <open3d/pipelines/integration/ScalableTSDFVolume.h>
#include <open3d/pipelines/integration/UniformTSDFVolume.h>
#include <open3d/utility/Logging.h>
#include <open3d/utility/Parallel.h>

#include <chrono>
#include <cmath>
#include <exception>

namespace scancrew::bench {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The ScalableTSDFVolume constructor's defaults.
constexpr int kUnitResolution = 16;
constexpr int kDepthStride = 4;

}  // namespace

std::string open3d_description() {
  return std::string("Open3D ") + OPEN3D_VERSION + " ScalableTSDFVolume (volume units of " +
         std::to_string(kUnitResolution) + "^3 voxels, depth sampling stride " +
         std::to_string(kDepthStride) + ")";
}

int open3d_threads() {
  return open3d::utility::EstimateMaxThreads();
}

Result<PeerRun, std::string> run_open3d(const PeerCamera& camera, std::span<const PeerFrame> frames,
                                        const PeerConfig& config) {
  namespace o3d = open3d;
  o3d::utility::SetVerbosityLevel(o3d::utility::VerbosityLevel::Error);
  const auto w = static_cast<int>(camera.width), h = static_cast<int>(camera.height);
  PeerRun run;
  try {
    o3d::pipelines::integration::ScalableTSDFVolume volume(
        config.voxel_m, config.truncation_m,
        o3d::pipelines::integration::TSDFVolumeColorType::NoColor, kUnitResolution, kDepthStride);
    const o3d::camera::PinholeCameraIntrinsic intrinsic(w, h, camera.fx, camera.fy, camera.cx,
                                                        camera.cy);
    // a colour image is required by the RGBDImage; with NoColor the volume never reads it
    o3d::geometry::Image color;
    color.Prepare(w, h, 3, 1);
    o3d::geometry::Image depth;
    depth.Prepare(w, h, 1, 4);
    run.integrate_ms.reserve(frames.size());
    run.prepare_ms.reserve(frames.size());
    for (const PeerFrame& frame : frames) {
      auto t0 = Clock::now();
      auto* out = depth.PointerAs<float>();
      for (size_t i = 0; i < static_cast<size_t>(w) * h; ++i) {
        const float d = frame.depth_m[i];
        out[i] = std::isnan(d) ? 0.0f : d;  // Open3D's "no measurement" is 0
      }
      const auto rgbd = o3d::geometry::RGBDImage::CreateFromColorAndDepth(
          color, depth, /*depth_scale=*/1.0, /*depth_trunc=*/config.max_range_m,
          /*convert_rgb_to_intensity=*/false);
      Eigen::Matrix4d extrinsic;
      for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
          extrinsic(r, c) = frame.T_cam_world[static_cast<size_t>(4 * r + c)];
      run.prepare_ms.push_back(ms_since(t0));
      t0 = Clock::now();
      volume.Integrate(*rgbd, intrinsic, extrinsic);
      run.integrate_ms.push_back(ms_since(t0));
    }
    const auto t0 = Clock::now();
    const std::shared_ptr<o3d::geometry::TriangleMesh> mesh = volume.ExtractTriangleMesh();
    run.mesh_ms = ms_since(t0);
    run.mesh.vertices.reserve(mesh->vertices_.size());
    for (const Eigen::Vector3d& v : mesh->vertices_)
      run.mesh.vertices.push_back({v.x(), v.y(), v.z()});
    run.mesh.triangles.reserve(mesh->triangles_.size());
    for (const Eigen::Vector3i& t : mesh->triangles_)
      run.mesh.triangles.push_back({static_cast<uint32_t>(t.x()), static_cast<uint32_t>(t.y()),
                                    static_cast<uint32_t>(t.z())});
    run.volume_units = volume.volume_units_.size();
    run.voxels_per_unit = size_t{kUnitResolution} * kUnitResolution * kUnitResolution;
    run.memory_bytes = run.volume_units * run.voxels_per_unit * sizeof(o3d::geometry::TSDFVoxel);
  } catch (const std::exception& e) {
    return make_unexpected(std::string("Open3D: ") + e.what());
  }
  return run;
}

}  // namespace scancrew::bench
