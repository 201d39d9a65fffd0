// SPDX-License-Identifier: MIT
// Tet mesher (isosurface stuffing): validity (positive tets, closed consistently oriented
// edge-manifold boundary), two-sided boundary conformity, volume and genus against the input on
// generated solids and the shared models, dihedral bounds before and after snapping, the cell size
// chosen from targetTets, every bad-input status, the heat method on the output, timings.
#include "common/math_constants.h"
#include "tet/tet_mesher.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "../test_meshes.h"
#include "../test_support.h"
#include "geodesic/heat_geodesic.h"
#include "geometry/aabb_tree.h"

namespace omnislice {
namespace {

using test::makeBox;
using test::makeTorus;
using test::makeUvSphere;
using test::meshVolume;

// Euler characteristic V - E + F of a triangle mesh over its referenced vertices.
long eulerCharacteristic(const Mesh& m) {
  std::vector<char> used(m.vertexCount(), 0);
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  for (size_t f = 0; f < m.faceCount(); ++f)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = m.triangles[3 * f + k], b = m.triangles[3 * f + (k + 1) % 3];
      used[a] = 1;
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  const long e = long(std::unique(edges.begin(), edges.end()) - edges.begin());
  return long(std::count(used.begin(), used.end(), 1)) - e + long(m.faceCount());
}

// Boundary vertices whose incident faces form more than one fan (pinch points): the number of
// extra fans. Expects an edge-manifold mesh.
size_t pinchedFans(const Mesh& m) {
  std::vector<std::vector<uint32_t>> faces(m.vertexCount());
  for (size_t f = 0; f < m.faceCount(); ++f)
    for (int k = 0; k < 3; ++k) faces[m.triangles[3 * f + k]].push_back(uint32_t(f));
  size_t extra = 0;
  for (size_t v = 0; v < m.vertexCount(); ++v) {
    const std::vector<uint32_t>& fs = faces[v];
    if (fs.empty()) continue;
    // Union faces sharing an edge through v (the other endpoint).
    std::vector<int> parent(fs.size());
    for (size_t i = 0; i < fs.size(); ++i) parent[i] = int(i);
    std::function<int(int)> find = [&](int x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
    std::map<uint32_t, int> seen;
    for (size_t i = 0; i < fs.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const uint32_t w = m.triangles[3 * fs[i] + k];
        if (w == v) continue;
        const auto it = seen.find(w);
        if (it == seen.end()) seen[w] = int(i); else parent[find(int(i))] = find(it->second);
      }
    size_t roots = 0;
    for (size_t i = 0; i < fs.size(); ++i) roots += find(int(i)) == int(i);
    extra += roots - 1;
  }
  return extra;
}

struct Report {
  double volumeRatio = 0, minDihedral = 0, maxDihedral = 0, maxBoundaryDistance = 0;
  double maxSurfaceToBoundary = 0;  // in cells
  long eulerIn = 0, eulerOut = 0;
  size_t pinched = 0;  // extra fans at pinched boundary vertices
};

// Every invariant of a mesher result against its input solid. Returns figures for the caller.
Report checkResult(const Mesh& solid, const TetMesherResult& r, const std::string& name) {
  Report rep;
  EXPECT_TRUE(r.ok()) << name << ": " << r.message;
  if (!r.ok()) return rep;
  const TetMesh& tm = r.mesh;
  // Positive orientation, checked here and by the core's validator (which flips nothing).
  size_t nonPositive = 0;
  for (size_t t = 0; t < tm.tetCount(); ++t) {
    const Eigen::Vector3d a = tm.vertex(tm.tets[4 * t]);
    const double v6 = (tm.vertex(tm.tets[4 * t + 1]) - a)
                          .dot((tm.vertex(tm.tets[4 * t + 2]) - a)
                                   .cross(tm.vertex(tm.tets[4 * t + 3]) - a));
    nonPositive += !(v6 > 0);
  }
  EXPECT_EQ(nonPositive, 0u) << name;
  const TetMeshResult v = validateTetMesh(tm);
  EXPECT_TRUE(v.ok()) << name << ": " << v.message;
  EXPECT_EQ(v.flipped, 0u) << name;
  EXPECT_EQ(r.quality.nonManifoldFaces, 0u) << name;
  // Boundary: every directed edge once, its reverse once (closed, edge-manifold, consistent).
  const Mesh boundary = tetBoundary(tm);
  EXPECT_GT(boundary.faceCount(), 0u) << name;
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (size_t f = 0; f < boundary.faceCount(); ++f)
    for (int k = 0; k < 3; ++k)
      ++directed[{boundary.triangles[3 * f + k], boundary.triangles[3 * f + (k + 1) % 3]}];
  size_t bad = 0;
  for (const auto& [e, n] : directed) {
    const auto it = directed.find({e.second, e.first});
    bad += n != 1 || it == directed.end() || it->second != 1;
  }
  EXPECT_EQ(bad, 0u) << name << ": boundary directed edges not paired exactly once";
  // Boundary vertices on the input surface within the tolerance.
  const AabbTree input(solid);
  const double tol = 0.05 * r.cellSize;
  std::vector<char> onBoundary(tm.vertexCount(), 0);
  for (uint32_t i : boundary.triangles) onBoundary[i] = 1;
  size_t boundaryCount = 0;
  for (size_t i = 0; i < tm.vertexCount(); ++i) {
    if (!onBoundary[i]) continue;
    ++boundaryCount;
    rep.maxBoundaryDistance = std::max(rep.maxBoundaryDistance, input.closest(tm.vertex(i)).distance);
  }
  EXPECT_EQ(boundaryCount, r.boundaryVertices) << name;
  EXPECT_LE(rep.maxBoundaryDistance, tol + 1e-9) << name;
  EXPECT_NEAR(rep.maxBoundaryDistance, r.maxBoundaryDistance, 1e-9) << name;
  EXPECT_EQ(r.unsnapped, 0u) << name;
  // Other side: input vertices and triangle centroids near the tet boundary (within a cell).
  const AabbTree out(boundary);
  for (size_t f = 0; f < solid.faceCount(); ++f) {
    const Eigen::Vector3d a = solid.vertex(solid.triangles[3 * f]);
    const Eigen::Vector3d g = (a + solid.vertex(solid.triangles[3 * f + 1]) +
                               solid.vertex(solid.triangles[3 * f + 2])) / 3;
    rep.maxSurfaceToBoundary = std::max({rep.maxSurfaceToBoundary, out.closest(a).distance / r.cellSize,
                                         out.closest(g).distance / r.cellSize});
  }
  EXPECT_LE(rep.maxSurfaceToBoundary, 1.5) << name;
  rep.volumeRatio = r.quality.volume / std::abs(meshVolume(solid));
  EXPECT_NEAR(rep.volumeRatio, r.volumeRatio, 1e-9) << name;
  rep.minDihedral = r.quality.minDihedralDegrees;
  rep.maxDihedral = r.quality.maxDihedralDegrees;
  rep.eulerIn = eulerCharacteristic(solid);
  rep.eulerOut = eulerCharacteristic(boundary);
  rep.pinched = pinchedFans(boundary);
  EXPECT_EQ(r.pinchedEdges, 0u) << name;
  std::printf("[tetmesh] %-36s cell %.3f mm, %zu tets, %zu verts (%zu boundary), volume ratio %.4f, "
              "dihedral [%.2f, %.2f] deg, boundary->surface %.2e mm, surface->boundary %.3f cells, "
              "euler %ld/%ld, pinched %zu, unwarped %zu, %.0f+%.0f+%.0f ms\n",
              name.c_str(), r.cellSize, tm.tetCount(), tm.vertexCount(), r.boundaryVertices,
              rep.volumeRatio, rep.minDihedral, rep.maxDihedral, rep.maxBoundaryDistance,
              rep.maxSurfaceToBoundary, rep.eulerIn, rep.eulerOut, rep.pinched, r.unwarped, r.classifyMs, r.stuffMs,
              r.snapMs);
  return rep;
}

// Bounds stated for the stuffed mesh (the paper proves [10.7, 164.8] degrees for its stencils
// and parity rule; our diagonal rule differs, these are the bounds measured with margin).
constexpr double kMinDihedralStuffed = 8.0, kMaxDihedralStuffed = 172.0;

TEST(TetMesher, GeneratedSolidsValidConformingVolumeGenus) {
  struct Case {
    std::string name;
    Mesh solid;
    double cellSize;
    double volumeTolerance;
  };
  std::vector<Case> cases;
  cases.push_back({"box 20x30x40", makeBox(0, 0, 0, 20, 30, 40), 2.0, 0.02});
  cases.push_back({"box 10 mm centred on the origin", makeBox(-5, -5, -5, 5, 5, 5), 1.0, 0.02});
  cases.push_back({"box 100 m from the origin",
                   makeBox(1e5, -1e5, 1e5, 1e5 + 20, -1e5 + 30, 1e5 + 40), 2.0, 0.02});
  cases.push_back({"sphere r=10", makeUvSphere(10, 96, 48), 0.8, 0.02});
  cases.push_back({"torus R=12 r=4", makeTorus(12, 4, 96, 48), 0.7, 0.03});
  cases.push_back({"sphere r=10 default size", makeUvSphere(10, 96, 48), 0, 0.02});
  for (const Case& c : cases) {
    TetMesherOptions o;
    o.cellSize = c.cellSize;
    const TetMesherResult r = tetrahedralize(c.solid, o);
    const Report rep = checkResult(c.solid, r, c.name);
    EXPECT_NEAR(rep.volumeRatio, 1.0, c.volumeTolerance) << c.name;
    EXPECT_EQ(rep.eulerIn, rep.eulerOut) << c.name;
    EXPECT_GE(rep.minDihedral, kMinDihedralStuffed) << c.name;
    EXPECT_LE(rep.maxDihedral, kMaxDihedralStuffed) << c.name;
  }
}

// Several shells: a cavity (inner sphere facing inward) stays empty and gives a second boundary
// component; overlapping shells are meshed as their union (winding number non-zero); an
// inward-facing solid is meshed the same as the outward one.
TEST(TetMesher, CavityUnionAndOrientation) {
  TetMesherOptions o;
  o.cellSize = 0.7;
  {
    const Mesh hollow = test::append(makeUvSphere(10, 96, 48), test::flipped(makeUvSphere(5, 64, 32)));
    const TetMesherResult r = tetrahedralize(hollow, o);
    const Report rep = checkResult(hollow, r, "hollow sphere");
    EXPECT_NEAR(rep.volumeRatio, 1.0, 0.02);
    EXPECT_EQ(rep.eulerOut, 4);  // two spheres
    // Nothing inside the cavity: every tet centroid at least 5 mm - one cell from the centre.
    for (size_t t = 0; t < r.mesh.tetCount(); ++t) {
      Eigen::Vector3d g(0, 0, 0);
      for (int k = 0; k < 4; ++k) g += r.mesh.vertex(r.mesh.tets[4 * t + k]) / 4;
      ASSERT_GT(g.norm(), 5 - r.cellSize) << t;
    }
  }
  {
    const Mesh a = makeUvSphere(10, 96, 48), b = makeUvSphere(10, 96, 48, {10, 0, 0});
    const Mesh both = test::append(a, b);
    const TetMesherResult r = tetrahedralize(both, o);
    ASSERT_TRUE(r.ok()) << r.message;
    // Union = two balls minus the lens pi (4R + d)(2R - d)^2 / 12, from the discrete volume.
    const double lens = kPi * (40 + 10) * 100 / 12 * (meshVolume(a) / (4.0 / 3 * kPi * 1000));
    const double unionVolume = 2 * meshVolume(a) - lens;
    EXPECT_NEAR(r.quality.volume / unionVolume, 1.0, 0.02);
    EXPECT_EQ(eulerCharacteristic(tetBoundary(r.mesh)), 2);  // one sphere-like boundary
    EXPECT_TRUE(validateTetMesh(r.mesh).ok());
  }
  {
    const Mesh out = makeUvSphere(10, 64, 32);
    const Mesh in = test::flipped(out);
    const TetMesherResult a = tetrahedralize(out, o), b = tetrahedralize(in, o);
    ASSERT_TRUE(a.ok() && b.ok()) << a.message << b.message;
    EXPECT_EQ(a.mesh.tetCount(), b.mesh.tetCount());
    EXPECT_NEAR(a.quality.volume, b.quality.volume, 1e-9 * a.quality.volume);
  }
}

TEST(TetMesher, SharedModelsAtDefaultSize) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  struct Model {
    const char* file;
    double scale;
  };
  // Smooth closed models: the full set of invariants, genus included.
  const Model models[] = {{"compas_bunny_closed_low_res.obj", 1},
                          {"pymdp_kitten.off", 1},
                          {"nestedcages_fertility.off", 100}};
  for (const Model& m : models) {
    const Mesh solid = test::loadModel(m.file, m.scale);
    const TetMesherResult r = tetrahedralize(solid);
    const Report rep = checkResult(solid, r, m.file);
    EXPECT_NEAR(rep.volumeRatio, 1.0, 0.015) << m.file;
    EXPECT_EQ(rep.eulerIn, rep.eulerOut) << m.file << " (genus changed)";
    EXPECT_EQ(rep.pinched, 0u) << m.file;
    EXPECT_EQ(r.unwarped, 0u) << m.file;
    EXPECT_GE(rep.minDihedral, kMinDihedralStuffed) << m.file;
    EXPECT_LE(rep.maxDihedral, kMaxDihedralStuffed) << m.file;
    EXPECT_LT(double(r.mesh.tetCount()), 1.5 * 60000) << m.file;
    EXPECT_GT(double(r.mesh.tetCount()), 60000 / 1.5) << m.file;
  }
}

// Branches (genus 17): struts of about 2.5 mm radius, two cells across at the default size, and
// 4 intersecting face pairs where struts touch, so the solid (union) differs in topology from
// its surface: genus is not comparable and crevices make the mesher un-warp vertices (slivers
// there). Still valid, closed, edge-manifold and conforming; volume within 10 % at the default
// size (thin struts lose their rims) and within 2 % at 1.2 mm cells.
TEST(TetMesher, BranchesValidDespiteThinStrutsAndTouchingParts) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Mesh solid = test::loadModel("compas_branches_16_closed_mid_res.stl");
  const TetMesherResult r = tetrahedralize(solid);
  const Report rep = checkResult(solid, r, "branches default");
  EXPECT_NEAR(rep.volumeRatio, 1.0, 0.10);
  EXPECT_GT(rep.minDihedral, 0.0);
  EXPECT_GT(r.unwarped, 0u);  // the crevices exercise the un-warping
  // At 5000 tets the first size estimate (volume-based) loses most struts (about 1.2k tets);
  // the retries on the measured count bring it within the 1.5x band.
  TetMesherOptions few;
  few.targetTets = 5000;
  const TetMesherResult rs = tetrahedralize(solid, few);
  ASSERT_TRUE(rs.ok()) << rs.message;
  EXPECT_GT(double(rs.mesh.tetCount()), 5000 / 1.5);
  EXPECT_LT(double(rs.mesh.tetCount()), 5000 * 1.5);
  EXPECT_TRUE(validateTetMesh(rs.mesh).ok());
  TetMesherOptions fine;
  fine.cellSize = 1.2;
  const TetMesherResult rf = tetrahedralize(solid, fine);
  const Report repf = checkResult(solid, rf, "branches 1.2 mm");
  EXPECT_NEAR(repf.volumeRatio, 1.0, 0.02);
}

// The Y-shape model of the manifest is an open shell (88 boundary edges): not a solid.
TEST(TetMesher, OpenShellModelIsRefused) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Mesh shell = test::loadModel("compas_Y_shape_mesh.obj", 1, test::Shell::MayBeOpen);
  const TetMesherResult r = tetrahedralize(shell);
  EXPECT_EQ(r.status, Status::OpenMesh) << r.message;
  EXPECT_NE(r.message.find("not closed"), std::string::npos) << r.message;
  EXPECT_EQ(r.mesh.tetCount(), 0u);
}

// Robustness over orientations and sizes (the lattice meets the surface differently each time):
// valid, closed, edge-manifold, conforming, volume close, genus kept at 60k tets (not at 20k:
// with 10 mm cells a bunny ear can come off or pinch). Where no vertex had to be put back
// (unwarped = 0) the dihedral angles stay above 10 deg (measured >= 11.0 over bunny, kitten,
// fertility at 5k-150k tets and 4 rotations); where the ears come within a cell of the body
// the put-back vertices leave slivers, improved by the interior moves but only bounded > 1 deg.
TEST(TetMesher, RotatedModelsAtSeveralSizes) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  for (const char* file : {"compas_bunny_closed_low_res.obj", "pymdp_kitten.off"}) {
    const Mesh base = test::loadModel(file);
    for (int rot = 0; rot < 4; ++rot) {
      const Eigen::Matrix3d rotation =
          Eigen::AngleAxisd(0.37 * rot, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
      const Mesh solid = test::transformed(base, rotation, Eigen::Vector3d::Zero());
      for (size_t target : {20000u, 60000u}) {
        TetMesherOptions o;
        o.targetTets = target;
        const TetMesherResult r = tetrahedralize(solid, o);
        const std::string name = std::string(file) + " rot " + std::to_string(rot) + " " +
                                 std::to_string(target);
        const Report rep = checkResult(solid, r, name);
        EXPECT_NEAR(rep.volumeRatio, 1.0, 0.02) << name;
        if (target == 60000) {
          EXPECT_EQ(rep.eulerIn, rep.eulerOut) << name;
        }
        EXPECT_GT(rep.minDihedral, r.unwarped == 0 ? 10.0 : 1.0) << name;
        EXPECT_LT(rep.maxDihedral, r.unwarped == 0 ? 165.0 : 179.0) << name;
      }
    }
  }
}

// Pure stuffing (snap = false) keeps the stated dihedral bounds; snapping (which moves only the
// cut points kept 1e-3 of an edge away from a lattice vertex, and with a tolerance of 1e-9 mm
// must bring every boundary vertex onto the surface) leaves no tet flatter than the bound.
TEST(TetMesher, DihedralBoundsBeforeAndAfterSnapping) {
  std::vector<std::pair<std::string, Mesh>> solids;
  solids.emplace_back("sphere", makeUvSphere(10, 64, 32));
  solids.emplace_back("torus", makeTorus(12, 4, 64, 32));
  solids.emplace_back("box", makeBox(0, 0, 0, 10, 12, 14));
  for (const auto& [name, solid] : solids) {
    for (double cell : {1.0, 0.77}) {
      TetMesherOptions off;
      off.cellSize = cell;
      off.snap = false;
      const TetMesherResult a = tetrahedralize(solid, off);
      ASSERT_TRUE(a.ok()) << a.message;
      EXPECT_GE(a.quality.minDihedralDegrees, kMinDihedralStuffed) << name;
      EXPECT_LE(a.quality.maxDihedralDegrees, kMaxDihedralStuffed) << name;
      EXPECT_LE(a.maxBoundaryDistance, 1e-3 * cell) << name;  // cut points' clamp
      TetMesherOptions tight;
      tight.cellSize = cell;
      tight.boundaryTolerance = 1e-9;
      const TetMesherResult b = tetrahedralize(solid, tight);
      ASSERT_TRUE(b.ok()) << b.message;
      EXPECT_EQ(b.mesh.tetCount(), a.mesh.tetCount());
      EXPECT_EQ(b.unsnapped, 0u) << name;
      EXPECT_LE(b.maxBoundaryDistance, 1e-9) << name;
      EXPECT_GE(b.quality.minDihedralDegrees, kMinDihedralStuffed) << name;  // after snapping
      EXPECT_TRUE(validateTetMesh(b.mesh).ok());
      EXPECT_EQ(validateTetMesh(b.mesh).flipped, 0u);
      std::printf("[tetmesh] %s cell %.2f: max distance %.2e -> %.2e mm, dihedral [%.2f, %.2f] -> "
                  "[%.2f, %.2f]\n",
                  name.c_str(), cell, a.maxBoundaryDistance, b.maxBoundaryDistance,
                  a.quality.minDihedralDegrees, a.quality.maxDihedralDegrees,
                  b.quality.minDihedralDegrees, b.quality.maxDihedralDegrees);
    }
  }
}

TEST(TetMesher, CellSizeFromTargetTets) {
  std::vector<std::pair<std::string, Mesh>> solids;
  solids.emplace_back("sphere", makeUvSphere(10, 64, 32));
  solids.emplace_back("torus", makeTorus(12, 4, 64, 32));
  solids.emplace_back("box", makeBox(0, 0, 0, 10, 20, 80));
  for (const auto& [name, solid] : solids)
    for (size_t target : {3000u, 20000u, 100000u}) {
      TetMesherOptions o;
      o.targetTets = target;
      const TetMesherResult r = tetrahedralize(solid, o);
      ASSERT_TRUE(r.ok()) << r.message;
      const double ratio = double(r.mesh.tetCount()) / double(target);
      EXPECT_GT(ratio, 1 / 1.5) << name << " " << target;
      EXPECT_LT(ratio, 1.5) << name << " " << target;
    }
}

TEST(TetMesher, BadInput) {
  const Mesh box = makeBox(0, 0, 0, 10, 10, 10);
  // Empty mesh.
  EXPECT_EQ(tetrahedralize(Mesh{}).status, Status::EmptyInput);
  // A NaN coordinate.
  Mesh nan = box;
  nan.positions[4] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(tetrahedralize(nan).status, Status::NonFiniteVertex);
  // An index out of range.
  Mesh bad = box;
  bad.triangles[5] = 99;
  EXPECT_EQ(tetrahedralize(bad).status, Status::DegenerateInput);
  // Absurd cell sizes.
  for (double c : {-1.0, std::numeric_limits<double>::quiet_NaN(),
                   std::numeric_limits<double>::infinity()}) {
    TetMesherOptions o;
    o.cellSize = c;
    const TetMesherResult r = tetrahedralize(box, o);
    EXPECT_EQ(r.status, Status::InvalidOption) << c;
    EXPECT_NE(r.message.find("cellSize"), std::string::npos) << r.message;
  }
  // Too fine: about 12e6 tets in a 10 mm cube at 0.02 mm, refused with the count and a size.
  {
    TetMesherOptions o;
    o.cellSize = 0.02;
    const TetMesherResult r = tetrahedralize(box, o);
    EXPECT_EQ(r.status, Status::InvalidOption);
    EXPECT_NE(r.message.find("more than maxTets 3000000"), std::string::npos) << r.message;
    const size_t about = r.message.find("about ");
    ASSERT_NE(about, std::string::npos) << r.message;
    const double count = std::stod(r.message.substr(about + 6));
    EXPECT_GE(count, 12 * 1000 / (0.02 * 0.02 * 0.02)) << r.message;  // 12 per interior cube
    EXPECT_LT(count, 1.1 * 12 * 1000 / (0.02 * 0.02 * 0.02)) << r.message;
    EXPECT_NE(r.message.find("at least"), std::string::npos) << r.message;
    o.cellSize = 0;
    o.maxTets = 1000;
    EXPECT_EQ(tetrahedralize(box, o).status, Status::InvalidOption);  // target 60000 > 1000
    o.targetTets = 0;
    EXPECT_EQ(tetrahedralize(box, o).status, Status::InvalidOption);
    TetMesherOptions neg;
    neg.boundaryTolerance = -1;
    EXPECT_EQ(tetrahedralize(box, neg).status, Status::InvalidOption);
  }
  // Two small spheres 1.7 m apart at 0.1 mm cells: few tets (about 0.1 M) but a lattice of
  // about 1e13 vertices, refused before anything is allocated.
  {
    const Mesh two = test::append(makeUvSphere(1, 16, 8), makeUvSphere(1, 16, 8, {1000, 1000, 1000}));
    TetMesherOptions o;
    o.cellSize = 0.1;
    const TetMesherResult r = tetrahedralize(two, o);
    EXPECT_EQ(r.status, Status::InvalidOption);
    EXPECT_NE(r.message.find("lattice"), std::string::npos) << r.message;
  }
  // A plate thinner than the lattice: no lattice vertex inside.
  {
    TetMesherOptions o;
    o.cellSize = 1;
    const TetMesherResult r = tetrahedralize(makeBox(0, 0, 0, 10, 10, 0.1), o);
    EXPECT_EQ(r.status, Status::DegenerateInput) << r.message;
    EXPECT_NE(r.message.find("thinner"), std::string::npos) << r.message;
  }
  // A flat (zero-volume) "solid".
  EXPECT_EQ(tetrahedralize(makeBox(0, 0, 0, 10, 10, 0)).status, Status::DegenerateInput);
  // An open box (one top triangle removed: vertical columns through it enter and never leave).
  Mesh open = box;
  open.triangles.erase(open.triangles.begin() + 9, open.triangles.begin() + 12);
  EXPECT_EQ(tetrahedralize(open).status, Status::OpenMesh);
  // Cancellation, at the start and midway; the stage is "tetmesh".
  for (double at : {0.0, 0.5}) {
    bool stageOk = true;
    const TetMesherResult r =
        tetrahedralize(makeUvSphere(10, 64, 32), {}, [&](const char* stage, double f) {
          stageOk = stageOk && std::string(stage) == "tetmesh";
          return f < at || (at == 0 && false);
        });
    EXPECT_EQ(r.status, Status::Cancelled) << at;
    EXPECT_TRUE(stageOk);
    EXPECT_EQ(r.mesh.tetCount(), 0u);
  }
}

// The heat method runs on the mesher's output: distance from the bottom face of a meshed box
// equals the height (measured at 1.5 mm cells: mean error 0.32 mm, max 0.96 mm; asserted under
// 1.5 % and 5 % of the 30 mm height).
TEST(TetMesher, HeatGeodesicOnMeshedBox) {
  const double height = 30;
  const Mesh solid = makeBox(0, 0, 0, 20, 20, height);
  TetMesherOptions o;
  o.cellSize = 1.5;
  const TetMesherResult r = tetrahedralize(solid, o);
  ASSERT_TRUE(r.ok()) << r.message;
  const std::vector<uint32_t> sources = platformVertices(r.mesh, 1e-9);
  EXPECT_GT(sources.size(), 100u);
  // Every boundary vertex is on a face of the box to roundoff (the bottom ones at z = 0 exactly
  // enough for platformVertices' default tolerance).
  const AabbTree input(solid);
  for (size_t v = 0; v < r.mesh.vertexCount(); ++v) {
    const Eigen::Vector3d p = r.mesh.vertex(v);
    if (std::find(sources.begin(), sources.end(), uint32_t(v)) != sources.end()) continue;
    EXPECT_GT(p.z(), 1e-6) << v;  // not a missed platform vertex
  }
  EXPECT_LT(r.maxBoundaryDistance, 1e-9);
  const HeatGeodesic hg(r.mesh);
  ASSERT_TRUE(hg.status().ok()) << hg.status().message;
  const GeodesicField f = hg.distanceFrom(sources);
  ASSERT_TRUE(f.ok()) << f.message;
  double sum = 0, worst = 0;
  for (size_t v = 0; v < r.mesh.vertexCount(); ++v) {
    const double e = std::abs(f.distance[v] - r.mesh.vertex(v).z());
    sum += e;
    worst = std::max(worst, e);
  }
  const double mean = sum / double(r.mesh.vertexCount());
  std::printf("[tetmesh] heat on meshed box (%zu tets, %zu sources): mean |d - z| %.3f mm, max %.3f "
              "mm (height %.0f mm)\n",
              r.mesh.tetCount(), sources.size(), mean, worst, height);
  EXPECT_LT(mean, 0.015 * height);
  EXPECT_LT(worst, 0.05 * height);
}

// Native timings at the default targetTets (60k); printed, not asserted.
TEST(TetMesher, TimingsAtSixtyThousandTets) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  for (const char* file : {"compas_bunny_closed_low_res.obj", "pymdp_kitten.off"}) {
    const Mesh solid = test::loadModel(file);
    double best = 1e300;
    TetMesherResult r;
    for (int rep = 0; rep < 3; ++rep) {
      const auto t0 = std::chrono::steady_clock::now();
      r = tetrahedralize(solid);
      best = std::min(best, std::chrono::duration<double, std::milli>(
                                std::chrono::steady_clock::now() - t0).count());
    }
    ASSERT_TRUE(r.ok()) << r.message;
    std::printf("[tetmesh] timing %s: %zu tets in %.1f ms (best of 3; classify %.1f, stuff %.1f, "
                "snap %.1f)\n",
                file, r.mesh.tetCount(), best, r.classifyMs, r.stuffMs, r.snapMs);
  }
}

}  // namespace
}  // namespace omnislice
