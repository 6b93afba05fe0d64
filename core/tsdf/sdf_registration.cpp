#include "core/tsdf/sdf_registration.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>

namespace scancrew::tsdf {

namespace {

using Vector4 = Eigen::Matrix<double, 4, 1>;
using Matrix4 = Eigen::Matrix<double, 4, 4>;

// The normal equations of the robust cost at one correction.
struct Normal {
  Matrix4 H = Matrix4::Zero();
  Vector4 g = Vector4::Zero();
  double cost = 0;     // Σ Huber(r)
  double squared = 0;  // Σ r²
  size_t overlap = 0;
  double mean_cost() const { return overlap > 0 ? cost / static_cast<double>(overlap) : 0; }
  double rms() const { return overlap > 0 ? std::sqrt(squared / static_cast<double>(overlap)) : 0; }
};

Normal evaluate(const MapSnapshot& reference, const std::vector<SdfSample>& source,
                const Eigen::Isometry3d& T, const Eigen::Vector3d& centroid, double huber_m) {
  Normal n;
  for (const SdfSample& s : source) {
    const Eigen::Vector3d q = T * s.position;
    const std::optional<SdfValue> v = sample_sdf(reference, q);
    if (!v) continue;
    const double r = v->distance_m - s.distance_m;
    const double a = std::abs(r);
    const double w = a <= huber_m ? 1.0 : huber_m / a;
    const Eigen::Vector3d arm = q - centroid;
    Vector4 jac;
    jac << v->gradient, v->gradient.x() * -arm.y() + v->gradient.y() * arm.x();  // ∂/∂yaw
    n.H.noalias() += w * jac * jac.transpose();
    n.g.noalias() += w * jac * r;
    n.cost += a <= huber_m ? 0.5 * r * r : huber_m * (a - 0.5 * huber_m);
    n.squared += r * r;
    ++n.overlap;
  }
  return n;
}

// The step δ = (x, y, z, yaw about the centroid) applied before T.
Eigen::Isometry3d apply(const Vector4& delta, const Eigen::Vector3d& centroid,
                        const Eigen::Isometry3d& T) {
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  step.linear() = Eigen::AngleAxisd(delta(3), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  step.translation() = centroid - step.linear() * centroid + delta.head<3>();
  return step * T;
}

// Smallest over largest eigenvalue of H, the yaw row and column scaled by the samples'
// spread so that a turn and a shift of the same size at the samples weigh alike.
double conditioning(const Matrix4& H, double spread_m) {
  Matrix4 scale = Matrix4::Identity();
  scale(3, 3) = 1.0 / std::max(spread_m, 1e-6);
  const Eigen::SelfAdjointEigenSolver<Matrix4> eig(scale * H * scale);
  const Vector4& values = eig.eigenvalues();  // ascending
  return values(3) > 0 ? values(0) / values(3) : 0;
}

}  // namespace

std::vector<SdfSample> surface_samples(const MapSnapshot& map, double band_m, size_t stride) {
  stride = std::max<size_t>(stride, 1);
  std::vector<BlockIndex> order;
  order.reserve(map.blocks().size());
  for (const auto& [index, block] : map.blocks()) order.push_back(index);
  std::sort(order.begin(), order.end(), [](const BlockIndex& a, const BlockIndex& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  const auto w_th = static_cast<float>(map.config().w_th);
  std::vector<SdfSample> samples;
  size_t k = 0;
  for (const BlockIndex& index : order) {
    const Block& block = *map.blocks().at(index);
    for (int z = 0; z < kBlockSide; ++z)
      for (int y = 0; y < kBlockSide; ++y)
        for (int x = 0; x < kBlockSide; ++x) {
          const Voxel& v = block.at(x, y, z);
          if (!(v.weight >= w_th) || std::abs(v.distance_m) >= band_m) continue;
          if (k++ % stride != 0) continue;
          const VoxelIndex g = index * kBlockSide + Eigen::Vector3i(x, y, z);
          samples.push_back({voxel_center(g, map.voxel_m()), v.distance_m});
        }
  }
  return samples;
}

std::optional<SdfValue> sample_sdf(const MapSnapshot& map, const Eigen::Vector3d& p) {
  const double voxel = map.voxel_m();
  const Eigen::Vector3d u = p / voxel - Eigen::Vector3d::Constant(0.5);
  const Eigen::Vector3d floor_u = u.array().floor();
  const Eigen::Vector3i base = floor_u.cast<int>();
  const Eigen::Vector3d f = u - floor_u;
  const auto w_th = static_cast<float>(map.config().w_th);
  SdfValue out;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3i d(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    const Voxel* v = map.voxel(base + d);
    if (v == nullptr || !(v->weight >= w_th)) return std::nullopt;
    // the corner's trilinear weight along each axis, and its derivative
    Eigen::Vector3d w, dw;
    for (int a = 0; a < 3; ++a) {
      w(a) = d(a) == 1 ? f(a) : 1.0 - f(a);
      dw(a) = d(a) == 1 ? 1.0 : -1.0;
    }
    const double phi = v->distance_m;
    out.distance_m += w.prod() * phi;
    out.gradient += phi / voxel *
                    Eigen::Vector3d(dw(0) * w(1) * w(2), w(0) * dw(1) * w(2), w(0) * w(1) * dw(2));
  }
  return out;
}

Result<Registration, std::string> register_to_map(const MapSnapshot& reference,
                                                  const std::vector<SdfSample>& source,
                                                  const Eigen::Isometry3d& initial,
                                                  const RegistrationConfig& config) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const SdfSample& s : source) centroid += initial * s.position;
  if (!source.empty()) centroid /= static_cast<double>(source.size());
  double spread = 0;
  for (const SdfSample& s : source) spread += (initial * s.position - centroid).squaredNorm();
  spread = source.empty() ? 0 : std::sqrt(spread / static_cast<double>(source.size()));

  Registration out;
  out.T_reference_source = initial;
  Normal n = evaluate(reference, source, initial, centroid, config.huber_m);
  if (n.overlap < config.min_overlap)
    return make_unexpected("registration: " + std::to_string(n.overlap) +
                           " samples overlap the reference, fewer than min_overlap " +
                           std::to_string(config.min_overlap));
  if (conditioning(n.H, spread) < config.min_conditioning)
    return make_unexpected(
        "registration: the overlap does not constrain x, y, z and yaw (a single plane in view?)");
  out.rms_before_m = n.rms();
  double lambda = 1e-3;
  for (out.iterations = 0; out.iterations < config.max_iterations; ++out.iterations) {
    bool accepted = false;
    Vector4 delta = Vector4::Zero();
    for (int attempt = 0; attempt < 10 && !accepted; ++attempt) {
      Matrix4 lhs = n.H;
      lhs.diagonal() += lambda * n.H.diagonal() + Vector4::Constant(1e-12);
      delta = -lhs.ldlt().solve(n.g);
      const Eigen::Isometry3d candidate = apply(delta, centroid, out.T_reference_source);
      const Normal next = evaluate(reference, source, candidate, centroid, config.huber_m);
      if (next.overlap >= config.min_overlap && next.mean_cost() <= n.mean_cost()) {
        out.T_reference_source = candidate;
        n = next;
        lambda = std::max(lambda / 3.0, 1e-7);
        accepted = true;
      } else {
        lambda *= 4.0;
      }
    }
    if (!accepted || (delta.head<3>().norm() < 1e-5 && std::abs(delta(3)) < 1e-6)) break;
  }
  out.overlap = n.overlap;
  out.rms_after_m = n.rms();
  return out;
}

}  // namespace scancrew::tsdf
