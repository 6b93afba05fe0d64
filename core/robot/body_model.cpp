#include "core/robot/body_model.hpp"

namespace scancrew::robot {

BodyModel BodyModel::of(RobotKind kind) {
  BodyModel b;
  b.kind = kind;
  if (kind == RobotKind::kMultirotor) {
    b.frame_half_m = Eigen::Vector3d(0.25, 0.25, 0.10);
    b.safety_radii_m = Eigen::Vector3d::Constant(1.0);  // table 2.1's collision radius
    b.safety_center_z_m = 0;  // a multirotor's volume is centred on its position
    b.height_m = 2 * b.frame_half_m.z();
    b.underside_m = 0;
  }
  return b;
}

Eigen::Vector3d BodyModel::aabb_half_extents(const Eigen::Matrix3d& R) const {
  Eigen::Vector3d h;
  for (int i = 0; i < 3; ++i) h[i] = R.row(i).cwiseProduct(safety_radii_m.transpose()).norm();
  return h;
}

BodyModel BodyModel::inflated(double margin_m) const {
  BodyModel b = *this;
  b.safety_radii_m.array() += margin_m;
  return b;
}

}  // namespace scancrew::robot
