// SPDX-License-Identifier: MIT
// projectedSupports / supportMesh (paper 000 Section V): overhang sampling against the grid count,
// struts landing on the platform or on the model, progressive projection through a tilted
// subspace (pieces chained, each along -d of its own subspace and inside it), Eq. 13 against an
// independent torque sum, closed outward support meshes whose volume matches the primitives,
// bad options and cancellation.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <vector>

#include "common/math_constants.h"
#include "geometry/aabb_tree.h"
#include "multidir/projected_supports.h"
#include "test_meshes.h"
#include "test_support.h"

namespace omnislice {
namespace {

// test::makeLBracket(10): column [0,10]^2 x [0,30], arm [10,30] x [0,10] x [20,30]; underside
// 200 mm^2 at z = 20.

TEST(ProjectedSupports, FixedDirectionSamplesTheUndersideAndReachesThePlatform) {
  SupportOptions o;
  o.samplingMm = 2;
  o.mergeAngleDeg = 0;  // straight columns (trees: ProjectedSupports.TreesMerge...)
  const SupportResult r = projectedSupports(test::makeLBracket(10), {}, o);
  ASSERT_TRUE(r.ok()) << r.message;
  // Grid nodes (2i, 2j) inside the underside [10,30] x [0,10] (closed): 11 x 6, less the column
  // edge x = 10 which the column's own faces border (still in the closed face: counted).
  EXPECT_EQ(r.samples - r.pointOverhangs - r.patchSamples, 11u * 6u);
  EXPECT_EQ(r.blocked, 0u);
  EXPECT_EQ(r.landedOnPlatform, r.samples);
  EXPECT_NEAR(r.riskyAreaMm2, 200.0, 1e-9);
  for (const SupportStrut& s : r.struts) {
    EXPECT_EQ(s.subspace, 0);
    EXPECT_NEAR(s.top.z(), 20.0, 1e-9);
    EXPECT_NEAR(s.bottom.z(), 0.0, 1e-9);
    EXPECT_NEAR((s.top - s.bottom).normalized().dot(Eigen::Vector3d::UnitZ()), 1.0, 1e-12);
    EXPECT_GE(s.diameterMm, o.minDiameterMm);
    EXPECT_NEAR(s.diameterMm, std::max(o.minDiameterMm, o.samplingMm / 4), 1e-12);  // no torque along g
  }
}

TEST(ProjectedSupports, StrutsLandOnTheModelBelow) {
  // A step [0,31] x [0.5,9.5] x [0,5] under the arm: every strut stands on it (z = 5). (y off the
  // 2 mm grid, so no sample lies on the silhouette edge, where the ray grazes the step's side.)
  const Mesh m =
      test::makeBoxUnion({{0, 0.5, 0, 31, 9.5, 5}, {0, 0.5, 5, 10, 9.5, 30}, {10, 0.5, 20, 30, 9.5, 30}});
  SupportOptions o;
  o.mergeAngleDeg = 0;
  const SupportResult r = projectedSupports(m, {}, o);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_GT(r.samples, 0u);
  EXPECT_EQ(r.landedOnModel, r.samples);
  for (const SupportStrut& s : r.struts) EXPECT_NEAR(s.bottom.z(), 5.0, 1e-9);
}

// A plane tilted 30 deg about Y cutting the arm: samples above it go down along -n to the plane,
// then along -Z to the platform. Every trace is a chain of pieces, each along -d of its subspace
// with its midpoint inside that subspace, the last one on the platform or the surface.
TEST(ProjectedSupports, ProgressiveProjectionChainsPiecesThroughSubspaces) {
  const Mesh m = test::makeLBracket(10);
  const Eigen::Vector3d n = Eigen::Vector3d(std::sin(kPi / 6), 0, std::cos(kPi / 6));
  const std::vector<Plane> planes = {{n, n.dot(Eigen::Vector3d(20, 0, 20))}};
  SupportOptions o;
  o.lambda = 1e-3;  // large enough for Eq. 13 to matter
  o.mergeAngleDeg = 0;
  const SupportResult r = projectedSupports(m, planes, o);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_EQ(r.directions.size(), 2u);
  const AabbTree tree(m);
  std::map<int, std::vector<const SupportStrut*>> traces;
  for (const SupportStrut& s : r.struts) traces[s.trace].push_back(&s);
  size_t twoPiece = 0;
  for (const auto& [id, pieces] : traces) {
    for (size_t k = 0; k < pieces.size(); ++k) {
      const SupportStrut& s = *pieces[k];
      const Eigen::Vector3d d = r.directions[size_t(s.subspace)];
      EXPECT_NEAR((s.top - s.bottom).normalized().dot(d), 1.0, 1e-9);
      EXPECT_EQ(subspaceOf(0.5 * (s.top + s.bottom), planes), s.subspace);
      if (k > 0) {
        EXPECT_LT((pieces[k - 1]->bottom - s.top).norm(), 1e-9);
        EXPECT_GT(s.subspace, pieces[k - 1]->subspace);  // printed earlier
        EXPECT_NEAR(n.dot(s.top), planes[0].offset, 1e-9);  // continues from the base plane
      }
    }
    const Eigen::Vector3d end = pieces.back()->bottom;
    EXPECT_TRUE(std::abs(end.z()) < 1e-9 || tree.closest(end).distance < 1e-6) << end.transpose();
    if (pieces.size() == 2) {
      ++twoPiece;
      // Eq. 13 for the lower piece: the upper piece's volume at its centroid, gravity -9.81 n.
      const SupportStrut& up = *pieces[0];
      const SupportStrut& lo = *pieces[1];
      const double vol = kPi / 4 * up.diameterMm * up.diameterMm * (up.top - up.bottom).norm();
      const Eigen::Vector3d torque = vol * (0.5 * (up.top + up.bottom) - lo.top).cross(-9.81 * n);
      const double expect = std::max(o.minDiameterMm, (1 + o.lambda * torque.norm()) * o.samplingMm / 4);
      EXPECT_NEAR(lo.diameterMm, expect, 1e-12);
      EXPECT_NEAR(up.diameterMm, std::max(o.minDiameterMm, o.samplingMm / 4), 1e-12);
    }
  }
  EXPECT_GT(twoPiece, 0u);
  EXPECT_EQ(r.landedOnPlatform + r.landedOnModel + r.blocked, r.samples);
}

// A strut that would have to pass through a subspace printed later is refused (blocked).
TEST(ProjectedSupports, StrutIntoALaterSubspaceIsBlocked) {
  // Arm underside at z = 20; a plane x > 25 (subspace 0, printed last) beside it, and the arm's
  // risky samples in subspace 1 = the platform's. With the platform direction +Z nothing crosses
  // x = 25: nothing is blocked. Tilting subspace 0's plane so that it covers the space under the
  // arm (normal pointing down-left) makes the way down cross into it.
  const Mesh m = test::makeLBracket(10);
  const SupportResult free = projectedSupports(m, {{Eigen::Vector3d(1, 0, 0), 25}});
  ASSERT_TRUE(free.ok());
  EXPECT_EQ(free.blocked, 0u);
  const Eigen::Vector3d n = Eigen::Vector3d(1, 0, -1).normalized();
  const SupportResult blocked = projectedSupports(m, {{n, n.dot(Eigen::Vector3d(12, 0, 15))}});
  ASSERT_TRUE(blocked.ok());
  EXPECT_GT(blocked.blocked, 0u);
  for (const SupportStrut& s : blocked.struts) {
    EXPECT_EQ(subspaceOf(0.5 * (s.top + s.bottom), {{n, n.dot(Eigen::Vector3d(12, 0, 15))}}), s.subspace);
  }
}

TEST(ProjectedSupports, SupportMeshIsClosedOutwardAndHasThePrimitivesVolume) {
  SupportOptions o;
  o.roofMm = 0.4;
  const SupportResult r = projectedSupports(test::makeLBracket(10), {}, o);
  ASSERT_TRUE(r.ok());
  const int sides = 8;
  const Mesh mesh = supportMesh(r, 0, o, sides);
  ASSERT_FALSE(mesh.empty());
  // Every edge used once each way (closed, consistently oriented).
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    for (int e = 0; e < 3; ++e) {
      ++edges[{mesh.triangles[3 * f + size_t(e)], mesh.triangles[3 * f + size_t((e + 1) % 3)]}];
    }
  }
  for (const auto& [e, c] : edges) {
    EXPECT_EQ(c, 1);
    EXPECT_EQ(edges.count({e.second, e.first}), 1u);
  }
  double expect = 0;
  for (const SupportStrut& s : r.struts) {
    const double rin = s.diameterMm / 2;
    expect += sides * rin * rin * std::tan(kPi / sides) * (s.top - s.bottom).z();  // height along d
  }
  expect += r.roofVolumeMm3;
  EXPECT_NEAR(test::meshVolume(mesh), expect, 1e-6 * expect);
  EXPECT_NEAR(r.roofVolumeMm3, 200 * 0.4, 1e-9);
  EXPECT_TRUE(supportMesh(r, 1, o).empty());  // no such subspace
}

// Trees: the L's arm underside (50 samples at R = 2) merges into a few trunks. Every branch
// leans at most 30 degrees from -Z and keeps clear of the model below its start; every piece ends
// on the platform or at the top of another piece of its tree; trees use less strut volume than
// the straight columns and hold every sample.
TEST(ProjectedSupports, TreesMergeWithinThirtyDegreesAndSaveVolume) {
  const Mesh m = test::makeLBracket(10);
  SupportOptions columns;
  columns.mergeAngleDeg = 0;
  const SupportResult straight = projectedSupports(m, {}, columns);
  const SupportResult trees = projectedSupports(m, {});
  ASSERT_TRUE(straight.ok() && trees.ok()) << trees.message;
  EXPECT_EQ(straight.merges, 0u);
  EXPECT_GT(trees.merges, 10u);
  EXPECT_EQ(trees.samples, straight.samples);
  EXPECT_EQ(trees.blocked, 0u);
  EXPECT_EQ(trees.landedOnPlatform + trees.landedOnModel, trees.samples - trees.merges);  // roots
  EXPECT_LT(trees.strutVolumeMm3, 0.8 * straight.strutVolumeMm3);
  const AabbTree tree(m);
  const double clearance = 0.5 * SupportOptions{}.minDiameterMm + 0.2;
  size_t leaning = 0;
  for (const SupportStrut& s : trees.struts) {
    const Eigen::Vector3d axis = s.top - s.bottom;
    ASSERT_GT(axis.z(), 0);
    EXPECT_GE(axis.normalized().z(), std::cos(30 * kPi / 180) - 1e-9);
    EXPECT_GE(s.diameterMm, SupportOptions{}.minDiameterMm);
    bool joins = std::abs(s.bottom.z()) < 1e-9;
    for (const SupportStrut& t : trees.struts)
      joins = joins || (&t != &s && t.trace == s.trace && (t.top - s.bottom).norm() < 1e-9);
    EXPECT_TRUE(joins) << s.bottom.transpose();
    if (axis.normalized().z() < 1 - 1e-12) {
      ++leaning;
      for (double t = 2 * clearance; t <= axis.norm(); t += 0.1)
        EXPECT_GT(tree.closest(s.top - axis * (t / axis.norm())).distance, clearance - 1e-9);
    }
  }
  EXPECT_GT(leaning, 10u);
  std::printf("L arm: %zu samples, %zu merges, %zu pieces; strut volume %.1f mm^3 (columns %.1f)\n",
              trees.samples, trees.merges, trees.struts.size(), trees.strutVolumeMm3, straight.strutVolumeMm3);
}

TEST(ProjectedSupports, BadOptionsAndCancel) {
  const Mesh m = test::makeLBracket(10);
  SupportOptions o;
  o.samplingMm = 0;
  EXPECT_EQ(projectedSupports(m, {}, o).status, Status::InvalidOption);
  o = {};
  o.alphaMaxDeg = 90;
  EXPECT_EQ(projectedSupports(m, {}, o).status, Status::InvalidOption);
  o = {};
  o.mergeAngleDeg = 61;
  EXPECT_EQ(projectedSupports(m, {}, o).status, Status::InvalidOption);
  o = {};
  o.lambda = std::nan("");
  EXPECT_EQ(projectedSupports(m, {}, o).status, Status::InvalidOption);
  EXPECT_EQ(projectedSupports(m, {{Eigen::Vector3d::Zero(), 1}}).status, Status::InvalidOption);
  EXPECT_EQ(projectedSupports(Mesh{}, {}).status, Status::EmptyInput);
  Mesh bad = m;
  bad.positions[0] = std::nan("");
  EXPECT_EQ(projectedSupports(bad, {}).status, Status::NonFiniteVertex);
  const SupportResult c = projectedSupports(m, {}, {}, [](const char*, double f) { return f < 0.6; });
  EXPECT_EQ(c.status, Status::Cancelled);
}

}  // namespace
}  // namespace omnislice
