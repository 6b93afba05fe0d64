#pragma once

// A decoded patch moved by a rigid correction (a teammate's frame drift, found by
// sdf_registration.hpp): its voxels resampled onto the map's lattice at T·p. Each destination
// voxel centre x takes the source's distance and weight at T⁻¹·x, trilinear over the 8
// source voxels around it (all observed, w > 0, else x stays unobserved; a corner of
// interpolation weight 0 need not be): a patch's border loses at most one voxel layer, and
// a translation by whole voxels moves every value exactly. The identity is not special-cased
// here: callers that want today's map bit for bit fuse the patch itself when there is no
// correction.

#include <Eigen/Geometry>

#include "core/tsdf/patch_codec.hpp"

namespace scancrew::tsdf {

DecodedPatch transform_patch(const DecodedPatch& patch, double voxel_m, const Eigen::Isometry3d& T);

}  // namespace scancrew::tsdf
