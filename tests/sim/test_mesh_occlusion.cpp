// The mesh visibility test: rays blocked by triangles (both faces), points closed in by a
// mesh hidden, points with a way out exposed, whatever the winding.

#include <gtest/gtest.h>

#include "sim/mesh_occlusion.hpp"
#include "tests/sim/test_meshes.hpp"

namespace scancrew::sim {
namespace {

using test::cube;

TEST(MeshOcclusion, ATriangleBlocksARayFromEitherSide) {
  const MeshOcclusion occ({cube()}, 16);
  EXPECT_EQ(occ.triangle_count(), 12u);
  // through the top face, from above and from inside
  EXPECT_TRUE(occ.blocked({0.5, 0.5, 2}, {0, 0, -1}, 0, 10));
  EXPECT_TRUE(occ.blocked({0.5, 0.5, 0.5}, {0, 0, 1}, 0, 10));
  // beside the cube, and short of it
  EXPECT_FALSE(occ.blocked({1.5, 0.5, 2}, {0, 0, -1}, 0, 10));
  EXPECT_FALSE(occ.blocked({0.5, 0.5, 2}, {0, 0, -1}, 0, 0.9));
}

TEST(MeshOcclusion, APointClosedInIsHiddenAndOneOutsideIsExposed) {
  for (const bool flipped : {false, true}) {
    const MeshOcclusion occ({cube(flipped)}, 64);
    EXPECT_FALSE(occ.exposed({0.5, 0.5, 0.5}, {0, 0, 1})) << "flipped " << flipped;
    EXPECT_FALSE(occ.exposed({0.3, 0.6, 0.0}, {0, 0, 1})) << "the floor under it";
    // on the top face and on a side face, with the normal either way
    EXPECT_TRUE(occ.exposed({0.5, 0.5, 1.0}, {0, 0, flipped ? -1.0 : 1.0}));
    EXPECT_TRUE(occ.exposed({1.0, 0.4, 0.3}, {flipped ? -1.0 : 1.0, 0, 0}));
    // the floor beside it: within its bounding box's margin, and far outside it
    EXPECT_TRUE(occ.exposed({1.005, 0.5, 0.0}, {0, 0, 1}));
    EXPECT_TRUE(occ.exposed({5.0, 5.0, 0.0}, {0, 0, 1}));
  }
}

TEST(MeshOcclusion, AnOpenTopLetsTheInsideBeSeen) {
  const MeshOcclusion occ({cube(false, true)}, 64);
  EXPECT_TRUE(occ.exposed({0.5, 0.5, 0.5}, {1, 0, 0}));
  EXPECT_TRUE(occ.exposed({0.2, 0.7, 0.0}, {0, 0, 1}));
}

TEST(MeshOcclusion, NoTrianglesHideNothing) {
  TriangleMesh degenerate;
  degenerate.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  degenerate.triangles = {{0, 1, 2}};
  const MeshOcclusion occ({degenerate}, 8);
  EXPECT_TRUE(occ.empty());
  EXPECT_TRUE(occ.exposed({0.5, 0, 0}, {0, 0, 1}));
  EXPECT_FALSE(occ.blocked({0.5, 0, 1}, {0, 0, -1}, 0, 10));
}

}  // namespace
}  // namespace scancrew::sim
