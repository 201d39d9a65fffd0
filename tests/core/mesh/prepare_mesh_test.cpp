// SPDX-License-Identifier: MIT
// prepareMesh: each validation error and each repair triggered by its own generated case, volume
// and area against closed forms, progress and cancellation, the JSON report.
#include "mesh/prepare_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "test_meshes.h"
#include "test_support.h"

namespace omnislice {
namespace {

using test::makeBox;

bool hasLine(const std::vector<std::string>& lines, const std::string& prefix) {
  return std::any_of(lines.begin(), lines.end(),
                     [&](const std::string& l) { return l.rfind(prefix, 0) == 0; });
}

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += "[" + l + "] ";
  return s;
}

// A clean box: nothing to repair, closed-form volume and area.
TEST(PrepareMesh, CleanBoxIsSolid) {
  const PrepareMeshResult r = prepareMesh(makeBox(0, 0, 0, 1, 2, 3), {});
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_TRUE(r.solid.ok()) << r.solid.message;
  const MeshInfo& i = r.info;
  EXPECT_EQ(i.vertices, 8u);
  EXPECT_EQ(i.faces, 12u);
  EXPECT_EQ(i.shells, 1u);
  EXPECT_TRUE(i.closed);
  EXPECT_TRUE(i.manifold);
  EXPECT_TRUE(i.oriented);
  EXPECT_EQ(i.boundaryEdges, 0u);
  EXPECT_EQ(i.boundaryLoops, 0u);
  EXPECT_EQ(i.selfIntersections, 0u);
  EXPECT_NEAR(i.volumeMm3, 6.0, 1e-12);
  EXPECT_NEAR(i.areaMm2, 2 * (2 + 3 + 6), 1e-12);
  EXPECT_EQ(i.bbox.min, Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(i.bbox.max, Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(i.repairs.empty()) << joined(i.repairs);
  EXPECT_TRUE(i.errors.empty()) << joined(i.errors);
  EXPECT_TRUE(i.warnings.empty()) << joined(i.warnings);
  EXPECT_EQ(r.mesh.triangles, makeBox(0, 0, 0, 1, 2, 3).triangles);
}

// EmptyInput: no faces (vertices alone do not count).
TEST(PrepareMesh, EmptyInput) {
  Mesh m;
  EXPECT_EQ(prepareMesh(m, {}).status, Status::EmptyInput);
  m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const PrepareMeshResult r = prepareMesh(m, {});
  EXPECT_EQ(r.status, Status::EmptyInput);
  EXPECT_EQ(r.solid.status, Status::EmptyInput);
  EXPECT_FALSE(r.message.empty());
  EXPECT_TRUE(r.mesh.empty());
}

// NonFiniteVertex: NaN and infinity in referenced vertices are counted; an unreferenced NaN
// vertex is only dropped.
TEST(PrepareMesh, NonFiniteVertex) {
  Mesh m = makeBox(0, 0, 0, 1, 1, 1);
  m.positions[3 * 2 + 1] = std::numeric_limits<double>::quiet_NaN();
  m.positions[3 * 5 + 2] = std::numeric_limits<double>::infinity();
  const PrepareMeshResult r = prepareMesh(m, {});
  EXPECT_EQ(r.status, Status::NonFiniteVertex);
  EXPECT_EQ(r.info.nonFiniteVertices, 2u);
  EXPECT_NE(r.message.find("2 vertices"), std::string::npos) << r.message;

  Mesh unreferenced = makeBox(0, 0, 0, 1, 1, 1);
  unreferenced.positions.insert(unreferenced.positions.end(),
                                {std::numeric_limits<double>::quiet_NaN(), 0, 0});
  const PrepareMeshResult ok = prepareMesh(unreferenced, {});
  ASSERT_TRUE(ok.ok()) << ok.message;
  EXPECT_EQ(ok.info.vertices, 8u);
  EXPECT_TRUE(hasLine(ok.info.repairs, "dropped 1 unreferenced vertex")) << joined(ok.info.repairs);
  EXPECT_TRUE(ok.solid.ok());
}

// DegenerateInput: every face has a repeated vertex or zero area.
TEST(PrepareMesh, DegenerateInput) {
  Mesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0};
  m.triangles = {0, 1, 2,  // collinear
                 0, 0, 3,  // repeated index
                 3, 3, 3};
  const PrepareMeshResult r = prepareMesh(m, {});
  EXPECT_EQ(r.status, Status::DegenerateInput);
  EXPECT_NE(r.message.find("3 faces"), std::string::npos) << r.message;
  // A mesh whose points all coincide has a zero bounding box: degenerate too.
  Mesh point;
  point.positions = {1, 1, 1, 1, 1, 1, 1, 1, 1};
  point.triangles = {0, 1, 2};
  EXPECT_EQ(prepareMesh(point, {}).status, Status::DegenerateInput);
}

// Bad indices never crash.
TEST(PrepareMesh, IndexOutOfRange) {
  Mesh m = makeBox(0, 0, 0, 1, 1, 1);
  m.triangles[7] = 99;
  const PrepareMeshResult r = prepareMesh(m, {});
  EXPECT_EQ(r.status, Status::ParseError);
  EXPECT_NE(r.message.find("99"), std::string::npos);
  Mesh partial = makeBox(0, 0, 0, 1, 1, 1);
  partial.triangles.pop_back();
  EXPECT_EQ(prepareMesh(partial, {}).status, Status::ParseError);
}

// Repair: an STL-like soup (3 private vertices per face) welds back into the closed box.
TEST(PrepareMesh, MergesDuplicateVerticesOfSoup) {
  const Mesh soup = test::toSoup(makeBox(0, 0, 0, 1, 2, 3));
  ASSERT_EQ(soup.vertexCount(), 36u);
  const PrepareMeshResult r = prepareMesh(soup, {});
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.info.vertices, 8u);
  EXPECT_TRUE(hasLine(r.info.repairs, "merged 28 duplicate vertices")) << joined(r.info.repairs);
  EXPECT_TRUE(r.info.closed && r.info.manifold && r.info.oriented);
  EXPECT_TRUE(r.solid.ok()) << r.solid.message;
  EXPECT_NEAR(r.info.volumeMm3, 6.0, 1e-12);

  // Without repair the soup is 12 separate triangles: 36 boundary edges in 12 holes.
  PrepareOptions off;
  off.repair = false;
  const PrepareMeshResult raw = prepareMesh(soup, off);
  ASSERT_TRUE(raw.ok());
  EXPECT_EQ(raw.info.vertices, 36u);
  EXPECT_EQ(raw.info.shells, 12u);
  EXPECT_EQ(raw.info.boundaryEdges, 36u);
  EXPECT_EQ(raw.info.boundaryLoops, 12u);
  EXPECT_EQ(raw.solid.status, Status::OpenMesh);
  EXPECT_TRUE(raw.info.repairs.empty());
}

// Repair with a tolerance: coordinates jittered by 1e-6 mm weld only when mergeTolerance allows.
TEST(PrepareMesh, MergesWithinTolerance) {
  Mesh soup = test::toSoup(makeBox(0, 0, 0, 10, 10, 10));
  // Jitter of -2..2 um: copies straddle the grid cell boundaries at 0 and 10.
  for (size_t i = 0; i < soup.positions.size(); ++i) soup.positions[i] += 1e-6 * (double((i * 7) % 5) - 2);
  const PrepareMeshResult exact = prepareMesh(soup, {});
  ASSERT_TRUE(exact.ok());
  EXPECT_FALSE(exact.info.closed);
  PrepareOptions tol;
  tol.mergeTolerance = 1e-4;
  const PrepareMeshResult r = prepareMesh(soup, tol);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.info.vertices, 8u);
  EXPECT_TRUE(hasLine(r.info.repairs, "merged 28 duplicate vertices (within 0.0001 mm)")) << joined(r.info.repairs);
  EXPECT_TRUE(r.info.closed && r.info.manifold && r.info.oriented) << joined(r.info.errors);
  EXPECT_NEAR(r.info.volumeMm3, 1000.0, 1e-2);
  PrepareOptions bad;
  bad.mergeTolerance = -1;
  EXPECT_EQ(prepareMesh(soup, bad).status, Status::InvalidOption);
}

// Repair: degenerate faces (repeated index, zero area) are dropped; the box stays closed.
TEST(PrepareMesh, DropsDegenerateFaces) {
  Mesh m = makeBox(0, 0, 0, 1, 1, 1);
  m.positions.insert(m.positions.end(), {0.5, 0, 0});  // vertex 8: on edge 0-1
  m.triangles.insert(m.triangles.end(), {0, 1, 8});     // zero area
  m.triangles.insert(m.triangles.end(), {2, 2, 6});     // repeated index
  const PrepareMeshResult r = prepareMesh(m, {});
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.info.faces, 12u);
  EXPECT_EQ(r.info.vertices, 8u);
  EXPECT_TRUE(hasLine(r.info.repairs, "dropped 2 degenerate faces (1 with repeated vertices, 1 with zero area)"))
      << joined(r.info.repairs);
  EXPECT_TRUE(hasLine(r.info.repairs, "dropped 1 unreferenced vertex")) << joined(r.info.repairs);
  EXPECT_TRUE(r.solid.ok()) << r.solid.message;
}

// Repair: an exact copy of a face (same vertex set, either orientation) is dropped.
TEST(PrepareMesh, DropsDuplicateFaces) {
  Mesh m = makeBox(0, 0, 0, 1, 1, 1);
  m.triangles.insert(m.triangles.end(), {0, 2, 1});  // copy of face 0
  m.triangles.insert(m.triangles.end(), {5, 4, 6});  // face 2 reversed
  const PrepareMeshResult r = prepareMesh(m, {});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.info.faces, 12u);
  EXPECT_TRUE(hasLine(r.info.repairs, "dropped 2 duplicate faces")) << joined(r.info.repairs);
  EXPECT_TRUE(r.info.closed && r.info.manifold && r.info.oriented);
  EXPECT_TRUE(r.solid.ok());
  // Without repair the copies make non-manifold edges.
  PrepareOptions off;
  off.repair = false;
  const PrepareMeshResult raw = prepareMesh(m, off);
  EXPECT_GT(raw.info.nonManifoldEdges, 0u);
  EXPECT_FALSE(raw.solid.ok());
}

// Repair: one face of a box flipped is reoriented; exactly that face changes.
TEST(PrepareMesh, ReorientsFlippedFace) {
  Mesh m = makeBox(0, 0, 0, 1, 2, 3);
  std::swap(m.triangles[3 * 4 + 1], m.triangles[3 * 4 + 2]);
  PrepareOptions off;
  off.repair = false;
  const PrepareMeshResult raw = prepareMesh(m, off);
  EXPECT_FALSE(raw.info.oriented);
  EXPECT_TRUE(hasLine(raw.info.errors, "inconsistent_orientation: 3 edges")) << joined(raw.info.errors);
  EXPECT_EQ(raw.solid.status, Status::NonManifoldInput);

  const PrepareMeshResult r = prepareMesh(m, {});
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r.info.oriented);
  EXPECT_TRUE(hasLine(r.info.repairs, "reoriented 1 face")) << joined(r.info.repairs);
  EXPECT_EQ(r.mesh.triangles, makeBox(0, 0, 0, 1, 2, 3).triangles);
  EXPECT_NEAR(r.info.volumeMm3, 6.0, 1e-12);
  EXPECT_TRUE(r.solid.ok());
}

// Repair: an inside-out box is flipped to face outward (volume > 0).
TEST(PrepareMesh, FlipsInsideOutShell) {
  const Mesh m = test::flipped(makeBox(0, 0, 0, 1, 2, 3));
  PrepareOptions off;
  off.repair = false;
  const PrepareMeshResult raw = prepareMesh(m, off);
  EXPECT_NEAR(raw.info.volumeMm3, -6.0, 1e-12);
  EXPECT_TRUE(hasLine(raw.info.warnings, "inside_out")) << joined(raw.info.warnings);

  const PrepareMeshResult r = prepareMesh(m, {});
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(r.info.volumeMm3, 6.0, 1e-12);
  EXPECT_GT(test::meshVolume(r.mesh), 0);
  EXPECT_TRUE(hasLine(r.info.repairs, "flipped 1 closed shell (12 faces)")) << joined(r.info.repairs);
  EXPECT_TRUE(r.solid.ok());
}

// Outward repair flips whole nesting trees: a cavity facing inward stays a cavity, an inside-out
// hollow box is turned as a whole, and a shell nested with the same orientation (a union under
// the non-zero rule) is kept as it is, with a warning.
TEST(PrepareMesh, NestedShellsKeepTheirMeaning) {
  const Mesh outer = makeBox(0, 0, 0, 10, 10, 10);
  const Mesh inner = makeBox(2, 2, 2, 8, 8, 8);
  struct Case {
    Mesh mesh;
    double volume;
    size_t flippedShells;
    bool nestedWarning;
  };
  const Case cases[] = {
      {test::append(outer, test::flipped(inner)), 1000.0 - 216.0, 0, false},                // hollow box
      {test::append(test::flipped(outer), inner), 1000.0 - 216.0, 2, false},                // inside out
      {test::append(outer, inner), 1000.0 + 216.0, 0, true},                                // union
      {test::append(test::flipped(outer), test::flipped(inner)), 1000.0 + 216.0, 2, true},  // union, inside out
  };
  for (const Case& c : cases) {
    const PrepareMeshResult r = prepareMesh(c.mesh, {});
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(r.info.shells, 2u);
    EXPECT_NEAR(r.info.volumeMm3, c.volume, 1e-9);
    EXPECT_TRUE(r.solid.ok());
    EXPECT_EQ(hasLine(r.info.repairs, "flipped 2 closed shells (24 faces)"), c.flippedShells == 2)
        << joined(r.info.repairs);
    if (c.flippedShells == 0) {
      EXPECT_TRUE(r.info.repairs.empty()) << joined(r.info.repairs);
    }
    EXPECT_EQ(hasLine(r.info.warnings, "nested_shells: 1 closed shell lies inside another with the same "
                                       "orientation; slicing fills it (union)"),
              c.nestedWarning)
        << joined(r.info.warnings);
  }
  // Three levels: an island inside the cavity, whole model inside out: all three turn.
  const Mesh island = makeBox(4, 4, 4, 6, 6, 6);
  const PrepareMeshResult r3 = prepareMesh(
      test::append(test::append(test::flipped(outer), inner), test::flipped(island)), {});
  EXPECT_NEAR(r3.info.volumeMm3, 1000.0 - 216.0 + 8.0, 1e-9);
  EXPECT_TRUE(hasLine(r3.info.repairs, "flipped 3 closed shells (36 faces)")) << joined(r3.info.repairs);
}

// open_mesh: a box with one triangle removed has one hole of 3 edges.
TEST(PrepareMesh, OpenMeshOneHole) {
  Mesh m = makeBox(0, 0, 0, 1, 1, 1);
  m.triangles.erase(m.triangles.begin() + 3 * 5, m.triangles.begin() + 3 * 6);
  const PrepareMeshResult r = prepareMesh(m, {});
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(r.info.closed);
  EXPECT_TRUE(r.info.manifold);
  EXPECT_TRUE(r.info.oriented);
  EXPECT_EQ(r.info.boundaryEdges, 3u);
  EXPECT_EQ(r.info.boundaryLoops, 1u);
  EXPECT_TRUE(hasLine(r.info.errors, "open_mesh: 3 boundary edges in 1 hole; the solid is not closed"))
      << joined(r.info.errors);
  EXPECT_EQ(r.solid.status, Status::OpenMesh);
  EXPECT_NE(r.solid.message.find("3 boundary edges"), std::string::npos);
}

// open_mesh: two holes (a whole side of the box and one triangle of the opposite side).
TEST(PrepareMesh, OpenMeshTwoHoles) {
  Mesh m = makeBox(0, 0, 0, 1, 1, 1);
  // Faces 0,1: bottom (z = 0); faces 2,3: top; remove both bottom faces and one top face.
  m.triangles.erase(m.triangles.begin() + 3 * 2, m.triangles.begin() + 3 * 3);
  m.triangles.erase(m.triangles.begin(), m.triangles.begin() + 3 * 2);
  const PrepareMeshResult r = prepareMesh(m, {});
  EXPECT_EQ(r.info.boundaryEdges, 4u + 3u);
  EXPECT_EQ(r.info.boundaryLoops, 2u);
  EXPECT_EQ(r.info.shells, 1u);
}

// non_manifold: three faces on one edge (a fin glued to a box edge).
TEST(PrepareMesh, NonManifoldEdgeThreeFaces) {
  Mesh m = makeBox(0, 0, 0, 1, 1, 1);
  m.positions.insert(m.positions.end(), {2, 2, 0.5});    // vertex 8
  m.triangles.insert(m.triangles.end(), {2, 6, 8});       // edge 2-6 now has 3 faces
  const PrepareMeshResult r = prepareMesh(m, {});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.info.nonManifoldEdges, 1u);
  EXPECT_FALSE(r.info.manifold);
  EXPECT_TRUE(hasLine(r.info.errors, "non_manifold: 1 edge shared by more than two faces"))
      << joined(r.info.errors);
  // The fin also leaves two boundary edges: open_mesh comes first in errors and in solid.
  EXPECT_EQ(r.info.boundaryEdges, 2u);
  EXPECT_EQ(r.solid.status, Status::OpenMesh);
}

// non_manifold: two closed boxes sharing one edge (4 faces on it), no boundary.
TEST(PrepareMesh, NonManifoldEdgeClosed) {
  const Mesh m = test::append(makeBox(0, 0, 0, 1, 1, 1), makeBox(1, 1, 0, 2, 2, 1));
  const PrepareMeshResult r = prepareMesh(m, {});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.info.vertices, 14u);
  EXPECT_TRUE(r.info.closed);
  EXPECT_EQ(r.info.nonManifoldEdges, 1u);
  EXPECT_EQ(r.info.shells, 1u);
  EXPECT_EQ(r.solid.status, Status::NonManifoldInput);
  EXPECT_NE(r.solid.message.find("1 edge shared by more than two faces"), std::string::npos);
  EXPECT_NEAR(r.info.volumeMm3, 2.0, 1e-12);
}

// non_manifold: two boxes touching at one corner: a bow-tie vertex, two shells.
TEST(PrepareMesh, NonManifoldVertex) {
  const Mesh m = test::append(makeBox(0, 0, 0, 1, 1, 1), makeBox(1, 1, 1, 2, 2, 2));
  const PrepareMeshResult r = prepareMesh(m, {});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.info.vertices, 15u);
  EXPECT_EQ(r.info.shells, 2u);
  EXPECT_EQ(r.info.nonManifoldEdges, 0u);
  EXPECT_EQ(r.info.nonManifoldVertices, 1u);
  EXPECT_FALSE(r.info.manifold);
  EXPECT_TRUE(hasLine(r.info.errors, "non_manifold: 1 vertex")) << joined(r.info.errors);
  EXPECT_EQ(r.solid.status, Status::NonManifoldInput);
}

// Two overlapping boxes: 2 shells, self-intersections found, a warning only.
TEST(PrepareMesh, OverlappingShellsWarnSelfIntersection) {
  const Mesh m = test::append(makeBox(0, 0, 0, 2, 2, 2), makeBox(1, 1, 1, 3, 3.5, 4));
  const PrepareMeshResult r = prepareMesh(m, {});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.info.shells, 2u);
  EXPECT_GT(r.info.selfIntersections, 0u);
  EXPECT_FALSE(r.info.selfIntersectionsCapped);
  EXPECT_TRUE(hasLine(r.info.warnings, "self_intersecting: " + std::to_string(r.info.selfIntersections) +
                                           " face pairs intersect; slicing uses the union"))
      << joined(r.info.warnings);
  EXPECT_TRUE(r.info.errors.empty()) << joined(r.info.errors);
  EXPECT_TRUE(r.solid.ok());
  // Both shells stay outward (overlap is not nesting): volume is the plain sum.
  EXPECT_NEAR(r.info.volumeMm3, 8.0 + 2 * 2.5 * 3, 1e-9);
  // The cap stops the count.
  PrepareOptions capped;
  capped.selfIntersectionCap = 2;
  const PrepareMeshResult c = prepareMesh(m, capped);
  EXPECT_EQ(c.info.selfIntersections, 2u);
  EXPECT_TRUE(c.info.selfIntersectionsCapped);
  EXPECT_TRUE(hasLine(c.info.warnings, "self_intersecting: at least 2")) << joined(c.info.warnings);
  // Switched off: nothing reported.
  PrepareOptions unchecked;
  unchecked.checkSelfIntersections = false;
  EXPECT_EQ(prepareMesh(m, unchecked).info.selfIntersections, 0u);
}

// Two disjoint boxes: 2 shells, no self-intersection, solid.
TEST(PrepareMesh, DisjointShells) {
  const Mesh m = test::append(makeBox(0, 0, 0, 1, 1, 1), makeBox(3, 0, 0, 4, 2, 1));
  const PrepareMeshResult r = prepareMesh(m, {});
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.info.shells, 2u);
  EXPECT_EQ(r.info.selfIntersections, 0u);
  EXPECT_TRUE(r.info.warnings.empty()) << joined(r.info.warnings);
  EXPECT_TRUE(r.solid.ok());
  EXPECT_NEAR(r.info.volumeMm3, 3.0, 1e-12);
}

// inconsistent_orientation: a Moebius strip cannot be oriented; it is also open (one boundary
// curve of 2n edges).
TEST(PrepareMesh, MoebiusStripIsNotOrientable) {
  const Mesh m = test::makeMoebius(10, 2, 24);
  const PrepareMeshResult r = prepareMesh(m, {});
  ASSERT_TRUE(r.ok());
  EXPECT_FALSE(r.info.oriented);
  EXPECT_EQ(r.info.shells, 1u);
  EXPECT_EQ(r.info.boundaryEdges, 48u);
  EXPECT_TRUE(hasLine(r.info.errors, "inconsistent_orientation: 1 component is not orientable"))
      << joined(r.info.errors);
  EXPECT_TRUE(hasLine(r.info.errors, "open_mesh: 48 boundary edges")) << joined(r.info.errors);
  EXPECT_EQ(r.solid.status, Status::OpenMesh);
  // An orientable strip (no twist) of the same size is fine apart from being open.
  Mesh band = m;
  band.triangles.resize(band.triangles.size() - 6);
  const uint32_t n = 24, a = 2 * (n - 1), b = a + 1;
  band.triangles.insert(band.triangles.end(), {a, 0, 1, a, 1, b});
  const PrepareMeshResult rb = prepareMesh(band, {});
  EXPECT_TRUE(rb.info.oriented) << joined(rb.info.errors);
  EXPECT_EQ(rb.info.boundaryLoops, 2u);
}

// Closed forms: an icosphere's volume and area approach the sphere's from below; a torus has
// genus 1 (V - E + F = 0).
TEST(PrepareMesh, SphereAndTorusMeasures) {
  const double r = 20;
  const PrepareMeshResult s = prepareMesh(test::toSoup(test::makeIcosphere(r, 5)), {});
  ASSERT_TRUE(s.ok());
  EXPECT_TRUE(s.solid.ok()) << s.solid.message;
  EXPECT_EQ(s.info.faces, 20480u);
  EXPECT_EQ(s.info.vertices, 10242u);
  const double exactVolume = 4.0 / 3.0 * M_PI * r * r * r;
  const double exactArea = 4 * M_PI * r * r;
  EXPECT_LT(s.info.volumeMm3, exactVolume);
  EXPECT_GT(s.info.volumeMm3, exactVolume * (1 - 2e-3));
  EXPECT_LT(s.info.areaMm2, exactArea);
  EXPECT_GT(s.info.areaMm2, exactArea * (1 - 2e-3));
  EXPECT_EQ(s.info.selfIntersections, 0u);

  const PrepareMeshResult t = prepareMesh(test::makeTorus(30, 10, 96, 48), {});
  ASSERT_TRUE(t.ok());
  EXPECT_TRUE(t.solid.ok()) << t.solid.message;
  const long chi = long(t.info.vertices) - long(3 * t.info.faces / 2) + long(t.info.faces);
  EXPECT_EQ(chi, 0);
  // Polyhedral torus volume: 2 pi R * (polygon cross-section area), the polygon inscribed.
  const double section = 0.5 * 48 * 10 * 10 * std::sin(2 * M_PI / 48);
  const double ringCorrection = std::sin(2 * M_PI / 96) / (2 * M_PI / 96);
  EXPECT_NEAR(t.info.volumeMm3, 2 * M_PI * 30 * section * ringCorrection, 1e-6 * t.info.volumeMm3);
  EXPECT_NEAR(t.info.volumeMm3, test::meshVolume(t.mesh), 1e-9 * t.info.volumeMm3);
  EXPECT_NEAR(t.info.areaMm2, test::surfaceArea(t.mesh), 1e-9 * t.info.areaMm2);
}

// Progress: stage "validate", fractions non-decreasing in [0, 1], ending at 1; a false return
// cancels at every point it is asked.
TEST(PrepareMesh, ProgressAndCancel) {
  const Mesh m = test::toSoup(test::makeIcosphere(5, 3));
  std::vector<double> fractions;
  const PrepareMeshResult r = prepareMesh(m, {}, [&](const char* stage, double f) {
    EXPECT_STREQ(stage, "validate");
    fractions.push_back(f);
    return true;
  });
  ASSERT_TRUE(r.ok());
  ASSERT_GE(fractions.size(), 5u);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_EQ(fractions.front(), 0.0);
  EXPECT_EQ(fractions.back(), 1.0);
  for (size_t stop = 0; stop < fractions.size(); ++stop) {
    size_t calls = 0;
    const PrepareMeshResult c = prepareMesh(m, {}, [&](const char*, double) { return calls++ < stop; });
    EXPECT_EQ(c.status, Status::Cancelled) << "stop at call " << stop;
    EXPECT_EQ(calls, stop + 1);
    EXPECT_TRUE(c.mesh.empty());
  }
}

// Above selfIntersectionMaxFaces the CGAL test is skipped with a warning.
TEST(PrepareMesh, SelfIntersectionSkippedAboveLimit) {
  PrepareOptions o;
  o.selfIntersectionMaxFaces = 10;
  const PrepareMeshResult r =
      prepareMesh(test::append(makeBox(0, 0, 0, 2, 2, 2), makeBox(1, 1, 1, 3, 3, 3)), o);
  EXPECT_EQ(r.info.selfIntersections, 0u);
  EXPECT_TRUE(hasLine(r.info.warnings, "self_intersections not checked above 10 faces (24 here)"))
      << joined(r.info.warnings);
}

// JSON report: all keys, numbers as computed, strings preserved.
TEST(PrepareMesh, InfoJson) {
  Mesh m = makeBox(0, 0, 0, 1, 2, 3);
  m.triangles.erase(m.triangles.begin(), m.triangles.begin() + 3);
  const PrepareMeshResult r = prepareMesh(test::toSoup(m), {});
  const nlohmann::json j = nlohmann::json::parse(meshInfoJson(r.info));
  for (const char* key : {"vertices", "faces", "shells", "closed", "manifold", "oriented", "volume_mm3",
                          "area_mm2", "bbox", "boundary_edges", "boundary_loops", "non_manifold_edges",
                          "non_manifold_vertices", "self_intersections", "repairs", "errors", "warnings"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["vertices"], 8);
  EXPECT_EQ(j["faces"], 11);
  EXPECT_EQ(j["closed"], false);
  EXPECT_EQ(j["boundary_edges"], 3);
  EXPECT_EQ(j["boundary_loops"], 1);
  EXPECT_DOUBLE_EQ(j["area_mm2"].get<double>(), r.info.areaMm2);
  EXPECT_DOUBLE_EQ(j["volume_mm3"].get<double>(), r.info.volumeMm3);
  EXPECT_EQ(j["bbox"]["max"][2], 3.0);
  EXPECT_EQ(j["errors"].size(), r.info.errors.size());
  EXPECT_EQ(j["errors"][0].get<std::string>(), r.info.errors[0]);
  EXPECT_EQ(j["repairs"][0].get<std::string>(), r.info.repairs[0]);
  MeshInfo bad;
  bad.volumeMm3 = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(nlohmann::json::parse(meshInfoJson(bad))["volume_mm3"].is_null());
}

// Random small meshes on a coarse grid (coincident points, coplanar and folded faces, shared and
// non-manifold edges, repeated indices) never crash, and the report agrees with an independent
// recount on the returned mesh.
TEST(PrepareMesh, RandomMeshesAgreeWithRecount) {
  std::mt19937 rng(12345);
  for (int round = 0; round < 300; ++round) {
    Mesh m;
    const int nv = 4 + int(rng() % 12);
    for (int i = 0; i < 3 * nv; ++i) m.positions.push_back(double(rng() % 3));
    const int nf = 1 + int(rng() % 20);
    for (int i = 0; i < 3 * nf; ++i) m.triangles.push_back(rng() % nv);
    if (round % 3 == 0) m = test::append(makeBox(0, 0, 0, 2, 2, 2), m);
    if (round % 5 == 0) m = test::toSoup(m);
    for (bool repair : {true, false}) {
      SCOPED_TRACE("round " + std::to_string(round) + (repair ? " repair" : " no repair"));
      PrepareOptions o;
      o.repair = repair;
      const PrepareMeshResult r = prepareMesh(m, o);
      if (!r.ok()) {
        EXPECT_EQ(r.status, Status::DegenerateInput) << r.message;
        continue;
      }
      const Mesh& out = r.mesh;
      ASSERT_EQ(r.info.faces, out.faceCount());
      ASSERT_EQ(r.info.vertices, out.vertexCount());
      for (uint32_t v : out.triangles) ASSERT_LT(v, out.vertexCount());
      std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edgeFaces;  // -> halfedges
      for (uint32_t h = 0; h < out.triangles.size(); ++h) {
        const uint32_t a = out.triangles[h], b = out.triangles[h - h % 3 + (h % 3 + 1) % 3];
        edgeFaces[std::minmax(a, b)].push_back(h);
      }
      size_t boundary = 0, nonManifold = 0, misoriented = 0;
      std::vector<uint32_t> parent(out.faceCount());
      std::iota(parent.begin(), parent.end(), 0u);
      std::function<uint32_t(uint32_t)> root = [&](uint32_t x) { return parent[x] == x ? x : parent[x] = root(parent[x]); };
      for (const auto& [edge, hs] : edgeFaces) {
        boundary += hs.size() == 1;
        nonManifold += hs.size() > 2;
        if (hs.size() == 2) misoriented += out.triangles[hs[0]] == out.triangles[hs[1]];
        for (uint32_t h : hs) parent[root(h / 3)] = root(hs[0] / 3);
      }
      size_t shells = 0;
      for (uint32_t f = 0; f < out.faceCount(); ++f) shells += root(f) == f;
      EXPECT_EQ(r.info.boundaryEdges, boundary);
      EXPECT_EQ(r.info.nonManifoldEdges, nonManifold);
      EXPECT_EQ(r.info.shells, shells);
      EXPECT_EQ(r.info.closed, boundary == 0);
      EXPECT_EQ(r.info.oriented, misoriented == 0);
      EXPECT_EQ(r.solid.ok(), r.info.closed && r.info.manifold && r.info.oriented);
      EXPECT_NEAR(r.info.areaMm2, test::surfaceArea(out), 1e-9);
      if (r.info.closed && r.info.oriented && r.info.manifold) {  // volume independent of origin
        EXPECT_NEAR(r.info.volumeMm3, test::meshVolume(out), 1e-9);
      }
      if (repair) {
        std::set<std::array<uint32_t, 3>> faces;
        std::vector<uint8_t> used(out.vertexCount(), 0);
        for (size_t f = 0; f < out.faceCount(); ++f) {
          std::array<uint32_t, 3> t = {out.triangles[3 * f], out.triangles[3 * f + 1], out.triangles[3 * f + 2]};
          for (uint32_t v : t) used[v] = 1;
          std::sort(t.begin(), t.end());
          EXPECT_TRUE(t[0] != t[1] && t[1] != t[2]) << "degenerate face left";
          EXPECT_TRUE(faces.insert(t).second) << "duplicate face left";
        }
        EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << "unreferenced vertex left";
        // Nothing orientable is left misoriented, and outward shells have positive volume.
        if (r.info.closed && r.info.manifold && r.info.oriented && r.info.shells == 1) {
          EXPECT_GE(r.info.volumeMm3, 0);
        }
      }
    }
  }
}

}  // namespace
}  // namespace omnislice
