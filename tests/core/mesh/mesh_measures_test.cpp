// SPDX-License-Identifier: MIT
// signedVolume / surfaceArea against closed forms, independent of translation; splitComponents
// with and without cavity grouping.
#include "mesh/mesh_measures.h"

#include <gtest/gtest.h>

#include "test_meshes.h"
#include "mesh/mesh_topology.h"
#include "test_support.h"

namespace omnislice {
namespace {

TEST(MeshMeasures, BoxVolumeAndArea) {
  const Mesh box = test::makeBox(1, 2, 3, 3, 5, 7);
  EXPECT_NEAR(signedVolume(box), 2 * 3 * 4, 1e-12);
  EXPECT_NEAR(surfaceArea(box), 2 * (6 + 8 + 12), 1e-12);
  EXPECT_NEAR(signedVolume(test::flipped(box)), -24, 1e-12);
  EXPECT_EQ(signedVolume(Mesh{}), 0);
  EXPECT_EQ(surfaceArea(Mesh{}), 0);
}

// Far from the origin the sum about the box centre keeps full precision.
TEST(MeshMeasures, FarFromOrigin) {
  const double o = 1e7;
  const Mesh box = test::makeBox(o, o, o, o + 1, o + 1, o + 1);
  EXPECT_NEAR(signedVolume(box), 1, 1e-9);
  const Mesh sphere = test::makeIcosphere(2, 3, Eigen::Vector3d(-o, o, 3 * o));
  EXPECT_NEAR(signedVolume(sphere), signedVolume(test::makeIcosphere(2, 3)), 1e-6);
}

TEST(MeshMeasures, TorusNearClosedForm) {
  const Mesh torus = test::makeTorus(10, 3, 200, 100);
  EXPECT_NEAR(signedVolume(torus), 2 * M_PI * M_PI * 10 * 9, 0.005 * 2 * M_PI * M_PI * 90);
  EXPECT_NEAR(surfaceArea(torus), 4 * M_PI * M_PI * 30, 0.005 * 4 * M_PI * M_PI * 30);
}

TEST(SplitComponents, ShellsAndCavities) {
  const Mesh a = test::makeBox(0, 0, 0, 1, 1, 1);
  const Mesh b = test::makeBox(5, 0, 0, 6, 1, 1);
  const Mesh outer = test::makeBox(10, 0, 0, 14, 4, 4);
  const Mesh cavity = test::flipped(test::makeBox(11, 1, 1, 13, 3, 3));
  const Mesh all = test::append(test::append(test::append(a, cavity), b), outer);
  const std::vector<Mesh> shells = splitComponents(all);
  ASSERT_EQ(shells.size(), 4u);
  for (const Mesh& s : shells) {
    EXPECT_EQ(s.vertexCount(), 8u);
    EXPECT_EQ(s.faceCount(), 12u);
  }
  EXPECT_NEAR(signedVolume(shells[0]), 1, 1e-12);  // ordered by lowest face
  EXPECT_NEAR(signedVolume(shells[1]), -8, 1e-12);
  const std::vector<Mesh> solids = splitComponents(all, true);
  ASSERT_EQ(solids.size(), 3u);
  EXPECT_NEAR(signedVolume(solids[0]), 1, 1e-12);
  EXPECT_NEAR(signedVolume(solids[1]), 1, 1e-12);
  EXPECT_NEAR(signedVolume(solids[2]), 64 - 8, 1e-12);  // the box with its cavity
  EXPECT_EQ(solids[2].faceCount(), 24u);
  // A cavity inside no solid stays alone; an empty mesh gives nothing.
  EXPECT_EQ(splitComponents(test::append(a, test::flipped(b)), true).size(), 2u);
  EXPECT_TRUE(splitComponents(Mesh{}).empty());
}

}  // namespace
}  // namespace omnislice
