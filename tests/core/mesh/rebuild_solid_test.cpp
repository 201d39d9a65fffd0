// SPDX-License-Identifier: MIT
// rebuildSolid (ray-parity samples and a surface net) and prepareMesh's use of it: a box whose
// faces were tessellated apart (T-junctions on every edge), which the face-by-face repair closes
// into the wrong shape; a cell-by-cell export whose inner walls are triangulated differently on
// each side; a sphere with every face turned at random; and what must not be rebuilt (sheets).
#include "mesh/rebuild_solid.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "mesh/prepare_mesh.h"
#include "pipeline/pipeline_fixtures.h"
#include "pipeline/settings.h"
#include "pipeline/slice_and_verify.h"
#include "test_meshes.h"
#include "test_support.h"

namespace omnislice {
namespace {

// A grid of nu x nv quads over the parallelogram o + s u + t v (s, t in [0, 1]), normal u x v.
void addPatch(Mesh& m, const Eigen::Vector3d& o, const Eigen::Vector3d& u, const Eigen::Vector3d& v, int nu, int nv) {
  const uint32_t base = uint32_t(m.vertexCount());
  for (int i = 0; i <= nu; ++i) {
    for (int j = 0; j <= nv; ++j) {
      const Eigen::Vector3d p = o + u * double(i) / nu + v * double(j) / nv;
      m.positions.insert(m.positions.end(), {p.x(), p.y(), p.z()});
    }
  }
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const uint32_t a = base + uint32_t(i * (nv + 1) + j), b = a + uint32_t(nv + 1), c = b + 1, d = a + 1;
      m.triangles.insert(m.triangles.end(), {a, b, c, a, c, d});
    }
  }
}

// A box [x0, x1] x [y0, y1] x [z0, z1] whose six faces are gridded independently (3x5, 7x4, ...):
// no two faces share a vertex along their common edge but the corners, so every edge is a crack
// of T-junctions. Faces outward. With shrink > 0 each face is scaled about its centre by
// 1 - shrink: the cracks open (no vertex lies on another face's edge any more).
Mesh tJunctionBox(double x0 = 0, double y0 = 0, double z0 = 0, double x1 = 30, double y1 = 20, double z1 = 10,
                  double shrink = 0) {
  Mesh m;
  const double X = x1 - x0, Y = y1 - y0, Z = z1 - z0;
  auto face = [&](const Eigen::Vector3d& o, const Eigen::Vector3d& u, const Eigen::Vector3d& v, int nu, int nv) {
    const size_t first = m.vertexCount();
    addPatch(m, o, u, v, nu, nv);
    const Eigen::Vector3d c = o + 0.5 * (u + v);
    for (size_t i = first; i < m.vertexCount(); ++i) {
      const Eigen::Vector3d p = c + (1 - shrink) * (m.vertex(i) - c);
      for (int k = 0; k < 3; ++k) m.positions[3 * i + k] = p[k];
    }
  };
  face({x0, y0, z0}, {0, Y, 0}, {X, 0, 0}, 3, 5);  // bottom, normal -z
  face({x0, y0, z1}, {X, 0, 0}, {0, Y, 0}, 7, 4);  // top
  face({x0, y0, z0}, {X, 0, 0}, {0, 0, Z}, 6, 2);  // y = y0, normal -y
  face({x0, y1, z0}, {0, 0, Z}, {X, 0, 0}, 2, 5);  // y = y1
  face({x0, y0, z0}, {0, 0, Z}, {0, Y, 0}, 3, 3);  // x = x0, normal -x
  face({x1, y0, z0}, {0, Y, 0}, {0, 0, Z}, 5, 2);  // x = x1
  return m;
}

double netVolume(const Mesh& m) {
  double v = 0;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    v += m.vertex(m.triangles[3 * f]).dot(m.vertex(m.triangles[3 * f + 1]).cross(m.vertex(m.triangles[3 * f + 2]))) / 6;
  }
  return v;
}

PrepareMeshResult prepareSolid(const Mesh& m, bool zip = true, bool rebuild = true) {
  PrepareOptions o;
  o.closeSolid = true;
  o.uniteShells = true;
  o.rebuild = rebuild;
  o.solidRepair.zipTJunctions = zip;
  return prepareMesh(m, o);
}

// T-junctions are zipped: the box closes exactly, sharp, with no face added beyond the splits.
TEST(RebuildSolid, TJunctionBoxIsZippedExactly) {
  const PrepareMeshResult r = prepareSolid(tJunctionBox());
  ASSERT_TRUE(r.ok() && r.solid.ok()) << r.solid.message;
  EXPECT_TRUE(r.info.closed && r.info.manifold && r.info.oriented);
  EXPECT_NEAR(r.info.volumeMm3, 6000, 1e-9);
  EXPECT_NEAR(r.info.areaMm2, 2200, 1e-9);
  EXPECT_EQ(r.info.solidRepair.rebuiltPitchMm, 0);
  EXPECT_EQ(r.info.solidRepair.holesFilled, 0u);
  // Every vertex on a face's edge but the 8 corners is a T-vertex on the other side: 54 here.
  EXPECT_EQ(r.info.solidRepair.tJunctionsZipped, 54u);
  EXPECT_EQ(r.info.selfIntersections, 0u);
}

// Without the zipping, the face-by-face repair "closes" the same box into another solid (loose
// faces dropped as sheets, a hole capped across the box): the volume check against the rebuild
// catches it and the rebuilt surface is taken instead.
TEST(RebuildSolid, RepairThatChangesTheVolumeGivesWayToTheRebuild) {
  const Mesh box = tJunctionBox();
  const PrepareMeshResult faceByFace = prepareSolid(box, false, false);
  ASSERT_TRUE(faceByFace.solid.ok());
  EXPECT_GT(std::abs(faceByFace.info.volumeMm3 - 6000), 0.05 * 6000);
  const PrepareMeshResult r = prepareSolid(box, false, true);
  ASSERT_TRUE(r.ok() && r.solid.ok()) << r.solid.message;
  EXPECT_GT(r.info.solidRepair.rebuiltPitchMm, 0);
  EXPECT_TRUE(r.info.closed && r.info.manifold && r.info.oriented);
  EXPECT_NEAR(r.info.volumeMm3, 6000, 0.005 * 6000);
  const double h = r.info.solidRepair.rebuiltPitchMm;
  EXPECT_NEAR(r.info.bbox.min.x(), 0, h);
  EXPECT_NEAR(r.info.bbox.max.x(), 30, h);
  EXPECT_NEAR(r.info.bbox.max.y(), 20, h);
  EXPECT_NEAR(r.info.bbox.max.z(), 10, h);
  EXPECT_EQ(r.info.firstFilledFace, 0u);
}

// Opened cracks (each face shrunk by 1e-4 about its centre: gaps of ~1 um, wider than the zip
// tolerance) cannot be closed face by face: the box is rebuilt.
TEST(RebuildSolid, CrackedBoxIsRebuilt) {
  const PrepareMeshResult r = prepareSolid(tJunctionBox(0, 0, 0, 30, 20, 10, 1e-4));
  ASSERT_TRUE(r.ok() && r.solid.ok()) << r.solid.message;
  EXPECT_GT(r.info.solidRepair.rebuiltPitchMm, 0);
  EXPECT_NEAR(r.info.volumeMm3, 6000, 0.005 * 6000);
}

// Two such boxes overlapping (an L of two bodies exported face by face): the winding rule fills
// their overlap, where parity would leave it empty.
TEST(RebuildSolid, OverlappingTJunctionBodiesAreRebuiltAsTheirUnion) {
  const Mesh m = test::append(tJunctionBox(0, 0, 0, 30, 10, 10), tJunctionBox(20, 0, 0, 30, 10, 40));
  const RebuildResult r = rebuildSolid(m);
  ASSERT_TRUE(r.ok() && r.accepted);
  EXPECT_TRUE(r.winding);
  const double union_ = 3000 + 4000 - 1000;
  EXPECT_NEAR(netVolume(r.mesh), union_, 0.01 * union_);
  const PrepareMeshResult p = prepareSolid(m);
  ASSERT_TRUE(p.ok() && p.solid.ok()) << p.solid.message;
  EXPECT_GT(p.info.solidRepair.rebuiltPitchMm, 0);
  EXPECT_NEAR(p.info.volumeMm3, union_, 0.01 * union_);
}

// Every cell of a 4 x 4 x 4 grid exported with its own six faces, each quad split along the
// diagonal through its lowest-index corner as seen by that cell: the two copies of an inner wall
// are the same square triangulated along the other diagonal. Parity cancels them.
TEST(RebuildSolid, CellByCellExportRebuildsTheOuterSolid) {
  Mesh soup;
  const int n = 4;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const Mesh cell = test::makeBox(i, j, k, i + 1, j + 1, k + 1);
        // Odd cells split each square along its other diagonal, so a wall between two cells is
        // the same square triangulated two ways.
        Mesh turned = cell;
        if ((i + j + k) % 2 == 1) {
          for (size_t f = 0; f + 1 < cell.faceCount(); f += 2) {
            const uint32_t* t = &cell.triangles[3 * f];
            const uint32_t* u = &cell.triangles[3 * f + 3];
            auto inU = [&](uint32_t v) { return v == u[0] || v == u[1] || v == u[2]; };
            int r = 0;
            while (inU(t[r])) ++r;
            const uint32_t p = t[r], a = t[(r + 1) % 3], b = t[(r + 2) % 3];  // shared edge a b
            uint32_t q = u[0];
            for (int k2 = 0; k2 < 3; ++k2) {
              if (u[k2] != a && u[k2] != b) q = u[k2];
            }
            // The square p a q b, split along p q instead of a b.
            const uint32_t tri[6] = {p, a, q, p, q, b};
            std::copy(tri, tri + 6, turned.triangles.begin() + 3 * f);
          }
        }
        soup = test::append(soup, turned);
      }
    }
  }
  const RebuildResult r = rebuildSolid(soup);
  ASSERT_TRUE(r.ok());
  ASSERT_TRUE(r.accepted);
  EXPECT_EQ(r.disagreeing, 0u);
  EXPECT_FALSE(r.touchesBorder);
  EXPECT_NEAR(netVolume(r.mesh), 64, 0.01 * 64);
}

// A sphere with every face turned at random: orientation does not matter to parity. With holes
// cut in it, rays through a hole flip the parity beyond it: where two directions pass through the
// same hole the vote goes wrong and the net bulges there (by up to the hole's size); the volume
// stays close.
TEST(RebuildSolid, ScrambledSphereIsRebuiltAndHolesBulgeLocally) {
  const double ball = 4.0 / 3.0 * M_PI * 1000;  // the icosphere is inside the ball by ~0.5 %
  for (int holes : {0, 5}) {
    SCOPED_TRACE(std::to_string(holes) + " holes");
    Mesh sphere = test::withHolesCut(test::makeIcosphere(10, 4), holes, 1.0, 9);
    std::mt19937 rng(4);
    for (size_t f = 0; f < sphere.faceCount(); ++f) {
      if (rng() % 2) std::swap(sphere.triangles[3 * f + 1], sphere.triangles[3 * f + 2]);
    }
    const RebuildResult r = rebuildSolid(sphere);
    ASSERT_TRUE(r.ok() && r.accepted) << r.disagreeing << " disagree, " << r.insideSamples << " inside, border "
                                      << r.touchesBorder << " invented " << r.inventedVertices << " of " << r.netVertices;
    EXPECT_NEAR(netVolume(r.mesh), ball, (holes == 0 ? 0.01 : 0.03) * ball);
    size_t near = 0;
    for (size_t v = 0; v < r.mesh.vertexCount(); ++v) near += std::abs(r.mesh.vertex(v).norm() - 10) <= 2 * r.pitchMm;
    EXPECT_FALSE(r.winding);  // the faces' orientation means nothing here
    if (holes == 0) {
      EXPECT_EQ(r.disagreeing, 0u);
      EXPECT_EQ(r.inventedVertices, 0u);
      EXPECT_EQ(near, r.mesh.vertexCount());
    } else {
      EXPECT_GT(r.inventedVertices, 0u);
      EXPECT_GE(double(near), 0.95 * double(r.mesh.vertexCount()));
    }
  }
}

// Sheets bound nothing: a bowl (a hemisphere without its cap) and a flat square are not accepted.
TEST(RebuildSolid, SheetsAreNotRebuilt) {
  const Mesh bowl = test::withoutFaces(test::makeIcosphere(10, 3), [](const Eigen::Vector3d& c) { return c.z() > 0; });
  const RebuildResult a = rebuildSolid(bowl);
  ASSERT_TRUE(a.ok());
  EXPECT_FALSE(a.accepted);
  Mesh square;
  addPatch(square, {0, 0, 0}, {10, 0, 0}, {0, 10, 0}, 4, 4);
  const RebuildResult b = rebuildSolid(square);
  ASSERT_TRUE(b.ok());
  EXPECT_FALSE(b.accepted);
  EXPECT_EQ(rebuildSolid(Mesh{}).status, Status::EmptyInput);
}

// The zipped box and the rebuilt (cracked) box print: planar and multidir programs verify
// against them.
TEST(RebuildSolid, ZippedAndRebuiltBoxesPrint) {
  for (double shrink : {0.0, 1e-4}) {
    const std::vector<uint8_t> bytes = test::binaryStl(tJunctionBox(0, 0, 0, 30, 20, 10, shrink));
    for (const auto& [method, machine] : {std::pair{"planar", "cartesian3"}, std::pair{"multidir", "table5"}}) {
      SCOPED_TRACE(std::string(method) + (shrink > 0 ? " cracked" : " zipped"));
      Settings s;
      ASSERT_TRUE(setSetting(s, "method", method).ok());
      ASSERT_TRUE(setSetting(s, "machine", machine).ok());
      ASSERT_TRUE(setSetting(s, "infill", "100").ok());
      const test::Sliced r = test::sliceAndVerify(bytes, "tbox.stl", s);
      ASSERT_TRUE(r.out.ok());
      const nlohmann::json& repair = r.report["mesh"]["repair"];
      if (shrink > 0) {
        EXPECT_GT(repair["rebuilt_mm"].get<double>(), 0);
      } else {
        EXPECT_EQ(repair["t_junctions"].get<int>(), 54);
      }
      EXPECT_GE(r.verify["inside"].get<double>(), 0.99);
      EXPECT_GE(r.verify["coverage"].get<double>(), 0.95);
      EXPECT_GE(r.verify["surface_reached"].get<double>(), 0.99);
      EXPECT_EQ(r.verify["collisions"].get<int>(), 0);
    }
  }
}

}  // namespace
}  // namespace omnislice
