// SPDX-License-Identifier: MIT
// repair = auto (prepareMesh with closeSolid, mesh/repair_mesh.h): each repair by a generated case
// and by holes cut into closed shared models: after repair the mesh is closed and manifold, its
// volume and box match the intact one within stated tolerances; sheets are refused with a message
// that names the surface method.
#include "mesh/repair_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <string>

#include "mesh/prepare_mesh.h"
#include "mesh/read_mesh.h"
#include "test_meshes.h"
#include "test_support.h"

namespace omnislice {
namespace {

using test::makeBox;

PrepareMeshResult repaired(const Mesh& m) {
  PrepareOptions o;
  o.closeSolid = true;
  o.checkSelfIntersections = false;
  return prepareMesh(m, o);
}

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += "[" + l + "] ";
  return s;
}

void expectSolid(const PrepareMeshResult& r) {
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_TRUE(r.solid.ok()) << r.solid.message << " " << joined(r.info.errors);
  EXPECT_TRUE(r.info.closed);
  EXPECT_TRUE(r.info.manifold);
  EXPECT_TRUE(r.info.oriented);
  EXPECT_GT(r.info.volumeMm3, 0);
  // Independent recount: every edge in exactly two faces, running them opposite ways.
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (size_t f = 0; f < r.mesh.faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      ++directed[{r.mesh.triangles[3 * f + k], r.mesh.triangles[3 * f + (k + 1) % 3]}];
    }
  }
  for (const auto& [e, n] : directed) {
    EXPECT_EQ(n, 1) << "half-edge " << e.first << "->" << e.second << " used " << n << " times";
    EXPECT_EQ(directed.count({e.second, e.first}), 1u) << "edge " << e.first << "-" << e.second << " open";
  }
}

bool sameBox(const BoundingBox& a, const BoundingBox& b, double tol) {
  return (a.min - b.min).cwiseAbs().maxCoeff() <= tol && (a.max - b.max).cwiseAbs().maxCoeff() <= tol;
}

// A box with one side missing: the hole is flat, so the filled box is the box exactly.
TEST(RepairMesh, BoxWithAMissingSideIsTheBox) {
  Mesh m = makeBox(0, 0, 0, 10, 20, 30);
  m.triangles.erase(m.triangles.begin() + 4 * 3, m.triangles.begin() + 6 * 3);  // side y = 0
  const PrepareMeshResult r = repaired(m);
  expectSolid(r);
  EXPECT_NEAR(r.info.volumeMm3, 6000, 1e-9);
  EXPECT_EQ(r.info.faces, 12u);
  ASSERT_TRUE(r.info.solidRepaired);
  EXPECT_EQ(r.info.solidRepair.holesFilled, 1u);
  EXPECT_NEAR(r.info.solidRepair.filledAreaMm2, 300, 1e-9);
  EXPECT_NEAR(r.info.solidRepair.largestHoleMm, std::hypot(10.0, 30.0), 1e-9);
  EXPECT_NE(joined(r.info.repairs).find("filled 1 hole with 2 faces"), std::string::npos) << joined(r.info.repairs);
  // The filled faces are the last two, on the missing side (y = 0).
  ASSERT_EQ(r.info.firstFilledFace, 10u);
  for (size_t f = 10; f < 12; ++f) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(r.mesh.vertex(r.mesh.triangles[3 * f + k]).y(), 0);
  }
  // repair off for the solid (today's behaviour): refused.
  const PrepareMeshResult none = prepareMesh(m, {});
  EXPECT_EQ(none.solid.status, Status::OpenMesh);
}

// Two boxes sharing an edge (four faces on it) and two touching at a corner: each box keeps its
// own copy of the shared vertices, two closed shells of the right volume.
TEST(RepairMesh, BoxesTouchingAtAnEdgeOrACornerAreSplit) {
  for (const Mesh& m : {test::append(makeBox(0, 0, 0, 1, 1, 1), makeBox(1, 1, 0, 2, 2, 1)),
                        test::append(makeBox(0, 0, 0, 1, 1, 1), makeBox(1, 1, 1, 2, 2, 2))}) {
    const PrepareMeshResult r = repaired(m);
    expectSolid(r);
    EXPECT_EQ(r.info.shells, 2u);
    EXPECT_NEAR(r.info.volumeMm3, 2, 1e-12);
    EXPECT_GT(r.info.solidRepair.verticesSplit, 0u);
    EXPECT_EQ(r.info.solidRepair.holesFilled, 0u);
  }
  const PrepareMeshResult edge = repaired(test::append(makeBox(0, 0, 0, 1, 1, 1), makeBox(1, 1, 0, 2, 2, 1)));
  EXPECT_EQ(edge.info.solidRepair.edgesUnpaired, 1u);
  EXPECT_EQ(edge.info.solidRepair.verticesSplit, 2u);
}

// Two boxes glued face to face on the same triangles: the pair of opposite faces between them is an
// internal wall; both go, one closed box of twice the volume is left.
TEST(RepairMesh, BoxesGluedFaceToFaceBecomeOne) {
  Mesh a = makeBox(0, 0, 0, 1, 1, 1);
  // The second box is the first mirrored through x = 1, so their x = 1 faces use the same triangles.
  Mesh b = a;
  for (size_t v = 0; v < b.vertexCount(); ++v) b.positions[3 * v] = 2 - b.positions[3 * v];
  b = test::flipped(b);
  const PrepareMeshResult r = repaired(test::append(a, b));
  expectSolid(r);
  EXPECT_EQ(r.info.shells, 1u);
  EXPECT_EQ(r.info.faces, 20u);
  EXPECT_NEAR(r.info.volumeMm3, 2, 1e-12);
  EXPECT_NE(joined(r.info.repairs).find("2 pairs of opposite faces"), std::string::npos) << joined(r.info.repairs);
}

// A fin (one triangle) glued to a box edge: it hangs by one edge, it goes; the box is left.
TEST(RepairMesh, FinOnAnEdgeIsDropped) {
  Mesh m = makeBox(0, 0, 0, 1, 1, 1);
  m.positions.insert(m.positions.end(), {2, 2, 0.5});
  m.triangles.insert(m.triangles.end(), {2, 6, 8});
  const PrepareMeshResult r = repaired(m);
  expectSolid(r);
  EXPECT_NEAR(r.info.volumeMm3, 1, 1e-12);
  EXPECT_EQ(r.info.faces, 12u);
}

// Holes cut into a sphere (faces removed around random points, some holes touching at a vertex)
// and tiny debris beside it: closed, volume within 1 % of the intact sphere, the same box.
TEST(RepairMesh, SphereWithHolesAndDebris) {
  const Mesh intact = test::makeUvSphere(10, 48, 24);
  const PrepareMeshResult whole = repaired(intact);
  std::mt19937 rng(5);
  Mesh m = intact;
  std::vector<uint32_t> kept;
  std::vector<uint8_t> cut(intact.faceCount(), 0);
  for (int h = 0; h < 15; ++h) cut[rng() % intact.faceCount()] = 1;
  for (size_t f = 0; f < intact.faceCount(); ++f) {
    if (!cut[f]) kept.insert(kept.end(), intact.triangles.begin() + 3 * f, intact.triangles.begin() + 3 * f + 3);
  }
  m.triangles = kept;
  // Debris: one loose triangle and a tiny open box (a side missing), away from the sphere; and a
  // tiny closed box, which is the model's and stays.
  Mesh speck = makeBox(30, 0, 0, 30.1, 0.1, 0.1);
  speck.triangles.resize(speck.triangles.size() - 6);
  m = test::append(m, speck);
  m = test::append(m, makeBox(-30, 5, 0, -29.9, 5.1, 0.1));
  const uint32_t base = static_cast<uint32_t>(m.vertexCount());
  m.positions.insert(m.positions.end(), {-30, 0, 0, -30.2, 0, 0, -30, 0.2, 0});
  m.triangles.insert(m.triangles.end(), {base, base + 1, base + 2});
  const PrepareMeshResult r = repaired(m);
  expectSolid(r);
  EXPECT_EQ(r.info.shells, 2u);                     // the sphere and the closed box
  EXPECT_EQ(r.info.solidRepair.debrisPieces, 2u);  // the open box and the loose triangle
  EXPECT_GE(r.info.solidRepair.holesFilled, 10u);
  EXPECT_NEAR(r.info.volumeMm3, whole.info.volumeMm3 + 0.001, 0.01 * whole.info.volumeMm3);
  EXPECT_NEAR(r.info.bbox.min.x(), -30, 1e-12);
  EXPECT_EQ(r.info.firstFilledFace, r.info.faces - r.info.solidRepair.filledFaces);
}

// The sphere with its bottom cap cut off (an open base, as scans come): capped flat.
TEST(RepairMesh, OpenBaseIsCapped) {
  const Mesh intact = test::makeUvSphere(10, 48, 24);
  const Mesh m = test::withoutFaces(intact, [](const Eigen::Vector3d& c) { return c.z() <= -8; });
  const PrepareMeshResult r = repaired(m);
  expectSolid(r);
  EXPECT_EQ(r.info.solidRepair.holesFilled, 1u);
  // The cap is the flat regular 48-gon of the last ring kept, at latitude -52.5 degrees.
  const double ring = 10 * std::cos(52.5 * kPi / 180);
  EXPECT_NEAR(r.info.solidRepair.filledAreaMm2, 24 * ring * ring * std::sin(2 * kPi / 48), 1e-6);
}

// A sheet (a wavy height field) cannot bound a solid: refused, the message names the surface method.
TEST(RepairMesh, SheetIsRefusedWithAReason) {
  Mesh m;
  const int n = 12;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      m.positions.insert(m.positions.end(), {double(i), double(j), 0.3 * std::sin(0.7 * i)});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i;
      m.triangles.insert(m.triangles.end(), {a, a + 1, a + n + 2, a, a + n + 2, a + n + 1});
    }
  }
  const PrepareMeshResult r = repaired(m);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.solid.status, Status::OpenMesh);
  EXPECT_NE(r.solid.message.find("method surface"), std::string::npos) << r.solid.message;
  EXPECT_EQ(r.info.solidRepair.sheets, 1u);
  EXPECT_EQ(r.info.solidRepair.holesLeft, 1u);
  EXPECT_FALSE(r.info.closed);
}

// A band of faces cut around the north pole leaves the polar cap as an island of surface in the
// hole: the island (a sheet of a small share of the area) is dropped, the hole closed.
TEST(RepairMesh, IslandInAHoleIsDropped) {
  const Mesh intact = test::makeUvSphere(10, 48, 24);
  const Mesh m = test::withoutFaces(intact, [](const Eigen::Vector3d& c) { return c.z() >= 9.2 && c.z() <= 9.85; });
  const PrepareMeshResult r = repaired(m);
  expectSolid(r);
  EXPECT_EQ(r.info.shells, 1u);
  EXPECT_EQ(r.info.solidRepair.debrisPieces, 1u);
  EXPECT_EQ(r.info.solidRepair.sheets, 0u);  // the island was dropped, not refused
  EXPECT_EQ(r.info.solidRepair.holesFilled, 1u);
}

// A single-sided panel beside a box (as CAD exports have them) is dropped and the box prints; a
// small box beside a large sheet does not make the sheet printable: refused.
TEST(RepairMesh, SheetsBesideASolidAreDropped) {
  auto panel = [](double x, double size) {
    Mesh p;
    p.positions = {x, 0, 0, x + size, 0, 0, x + size, size, 0.5, x, size, 0.5};
    p.triangles = {0, 1, 2, 0, 2, 3};
    return p;
  };
  const PrepareMeshResult r = repaired(test::append(makeBox(0, 0, 0, 10, 10, 10), panel(12, 5)));
  expectSolid(r);
  EXPECT_EQ(r.info.solidRepair.sheetsDropped, 1u);
  EXPECT_NEAR(r.info.volumeMm3, 1000, 1e-9);
  EXPECT_NE(joined(r.info.repairs).find("dropped 1 open sheet (2 faces"), std::string::npos) << joined(r.info.repairs);
  const PrepareMeshResult refused = repaired(test::append(makeBox(0, 0, 0, 1, 1, 1), panel(3, 40)));
  EXPECT_EQ(refused.solid.status, Status::OpenMesh);
  EXPECT_NE(refused.solid.message.find("method surface"), std::string::npos) << refused.solid.message;
}

// A hole in a sphere is refined and faired to continue the sphere: the new points lie near it,
// and the volume is closer to the intact one than with a flat fill. A hole in a box side stays flat.
TEST(RepairMesh, FairedHoleFollowsTheSurface) {
  const Mesh intact = test::makeIcosphere(10, 4);
  const double volume = test::meshVolume(intact);
  const Eigen::Vector3d at = Eigen::Vector3d(1, 2, 3).normalized() * 10;
  const Mesh m = test::withoutFaces(intact, [&](const Eigen::Vector3d& c) { return (c - at).norm() <= 4; });
  PrepareOptions flatOptions;
  flatOptions.closeSolid = true;
  flatOptions.solidRepair.fair = false;
  const PrepareMeshResult flat = prepareMesh(m, flatOptions);
  const PrepareMeshResult faired = repaired(m);
  expectSolid(flat);
  expectSolid(faired);
  EXPECT_EQ(faired.info.solidRepair.holesFaired, 1u);
  EXPECT_EQ(flat.info.solidRepair.holesFaired, 0u);
  EXPECT_GT(faired.info.solidRepair.filledFaces, flat.info.solidRepair.filledFaces);
  // The sphere's own points are on it; the points the fairing added lie closer to it than the flat
  // fill's middle (the cap's height over a rim of about 4 mm radius, 10 - sqrt(100 - 16) = 0.83 mm).
  double worst = 0;
  for (size_t v = 0; v < faired.mesh.vertexCount(); ++v) {
    worst = std::max(worst, std::abs(faired.mesh.vertex(v).norm() - 10));
  }
  EXPECT_LT(worst, 0.6);
  const double flatError = std::abs(flat.info.volumeMm3 - volume), fairedError = std::abs(faired.info.volumeMm3 - volume);
  std::printf("[ repair ] hole of 4 mm radius in a 10 mm sphere: volume error flat %.3f mm3, faired %.3f mm3; "
              "faired points off the sphere by at most %.3f mm\n", flatError, fairedError, worst);
  EXPECT_LT(fairedError, 0.6 * flatError);
  // A flat hole (a box side) is left flat.
  Mesh box = makeBox(0, 0, 0, 10, 20, 30);
  box.triangles.erase(box.triangles.begin() + 4 * 3, box.triangles.begin() + 6 * 3);
  EXPECT_EQ(repaired(box).info.solidRepair.holesFaired, 0u);
}

// A loop too long to triangulate is capped by a fan from its centroid: still closed.
TEST(RepairMesh, LongLoopIsCappedFromItsCentre) {
  const Mesh intact = test::makeUvSphere(10, 48, 24);
  const Mesh m = test::withoutFaces(intact, [](const Eigen::Vector3d& c) { return c.z() <= -8; });
  PrepareOptions o;
  o.closeSolid = true;
  o.solidRepair.maxTriangulatedLoop = 10;
  const PrepareMeshResult r = prepareMesh(m, o);
  expectSolid(r);
  EXPECT_EQ(r.info.solidRepair.holesCapped, 1u);
  EXPECT_EQ(r.info.solidRepair.filledFaces, 48u);
}

// Random damage to a sphere (faces deleted, flipped, doubled the other way round, a fin glued to an
// edge, two distant vertices made one): whatever repair returns as a solid is closed and manifold
// by an independent recount, anything else is refused with a message, and most come back solid.
TEST(RepairMesh, RandomDamageNeverGivesABrokenSolid) {
  const Mesh intact = test::makeUvSphere(10, 24, 12);
  std::mt19937 rng(17);
  int solid = 0;
  const int trials = 60;
  for (int trial = 0; trial < trials; ++trial) {
    Mesh m = intact;
    std::vector<uint32_t> t;
    for (size_t f = 0; f < m.faceCount(); ++f) {
      const uint32_t* tri = m.triangles.data() + 3 * f;
      const unsigned roll = rng() % 100;
      if (roll < 6) continue;                                                      // deleted
      if (roll < 9) t.insert(t.end(), {tri[0], tri[2], tri[1]});                   // flipped
      else t.insert(t.end(), tri, tri + 3);
      if (roll == 99) t.insert(t.end(), {tri[0], tri[2], tri[1]});                  // doubled
    }
    if (trial % 3 == 0) {  // a fin on an edge
      const uint32_t v = static_cast<uint32_t>(m.vertexCount());
      m.positions.insert(m.positions.end(), {0, 0, 25});
      t.insert(t.end(), {t[0], t[1], v});
    }
    if (trial % 4 == 1) {  // two distant vertices made one: a pinch
      const uint32_t a = static_cast<uint32_t>(rng() % m.vertexCount()), b = static_cast<uint32_t>(rng() % m.vertexCount());
      for (uint32_t& i : t) i = i == b ? a : i;
    }
    m.triangles = t;
    SCOPED_TRACE("trial " + std::to_string(trial));
    PrepareOptions o;
    o.closeSolid = true;
    const PrepareMeshResult r = prepareMesh(m, o);
    ASSERT_TRUE(r.ok()) << r.message;
    if (r.solid.ok()) {
      ++solid;
      expectSolid(r);
    } else {
      EXPECT_FALSE(r.solid.message.empty());
      std::printf("[ repair ] trial %d refused: %s: %s\n", trial, statusCode(r.solid.status), r.solid.message.c_str());
    }
  }
  std::printf("[ repair ] %d of %d damaged spheres repaired into a closed manifold\n", solid, trials);
  EXPECT_GE(solid, trials * 9 / 10);
}

// Holes cut into closed shared models (balls of faces removed around random vertices): closed and
// manifold after repair, volume within 0.5 % of the intact model's, and its box within what the cut
// can take away (a hole over an extreme point, an ear's tip, loses it: the cut's radius plus the
// longest edge).
TEST(RepairMesh, HolesCutIntoSharedModels) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  for (const char* file : {"pymdp_kitten.off", "compas_bunny_closed_low_res.obj", "nestedcages_fertility.off"}) {
    const Mesh intact = test::loadModel(file);
    const PrepareMeshResult whole = repaired(intact);
    const double diagonal = (whole.info.bbox.max - whole.info.bbox.min).norm();
    double longestEdge = 0;
    for (size_t f = 0; f < intact.faceCount(); ++f) {
      for (int k = 0; k < 3; ++k) {
        longestEdge = std::max(longestEdge, (intact.vertex(intact.triangles[3 * f + k]) -
                                             intact.vertex(intact.triangles[3 * f + (k + 1) % 3])).norm());
      }
    }
    std::mt19937 rng(11);
    for (int trial = 0; trial < 3; ++trial) {
      const double radius = (0.01 + 0.01 * trial) * diagonal;
      const Mesh m = test::withHolesCut(intact, 12, radius, rng());
      SCOPED_TRACE(std::string(file) + " trial " + std::to_string(trial));
      ASSERT_LT(m.faceCount(), intact.faceCount());
      const PrepareMeshResult r = repaired(m);
      expectSolid(r);
      EXPECT_GE(r.info.solidRepair.holesFilled, 1u);
      EXPECT_NEAR(r.info.volumeMm3, whole.info.volumeMm3, 0.005 * whole.info.volumeMm3);
      EXPECT_TRUE(sameBox(r.info.bbox, whole.info.bbox, radius + longestEdge));
      std::printf("[ repair ] %s, 12 holes of radius %.1f%% of the diagonal: %s; volume %+.3f%%\n", file,
                  100 * (0.01 + 0.01 * trial), joined(r.info.repairs).c_str(),
                  100 * (r.info.volumeMm3 / whole.info.volumeMm3 - 1));
    }
  }
}

// The open shells in ../shared/models: the three-legged connection and the Y are tubes with open
// ends (closed by repair); the Costa surface is a sheet (refused).
TEST(RepairMesh, SharedOpenModels) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  for (const char* file : {"compas_connection3legs_open_low_res.obj", "compas_Y_shape_mesh.obj"}) {
    const Mesh m = test::loadModel(file, 1.0, test::Shell::MayBeOpen);
    const PrepareMeshResult r = repaired(m);
    SCOPED_TRACE(file);
    expectSolid(r);
    std::printf("[ repair ] %s: %s\n", file, joined(r.info.repairs).c_str());
  }
  const PrepareMeshResult costa =
      repaired(test::loadModel("compas_costa_surface_mesh.obj", 1.0, test::Shell::MayBeOpen));
  EXPECT_EQ(costa.solid.status, Status::OpenMesh);
  EXPECT_NE(costa.solid.message.find("method surface"), std::string::npos) << costa.solid.message;
}

}  // namespace
}  // namespace omnislice
