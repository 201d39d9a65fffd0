// SPDX-License-Identifier: MIT
// prepareMesh on the real models of ../shared/models, checked against MANIFEST.md (closed or
// open with the listed boundary edge count, genus, shells, outward volume), and a measurement on a
// generated 1M-triangle torus (printed, not timed).
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <map>
#include <cstdio>
#include <ctime>
#include <string>

#include "cgal/self_intersections.h"
#include "test_meshes.h"
#include "mesh/prepare_mesh.h"
#include "mesh/read_mesh.h"
#include "pipeline/pipeline_fixtures.h"
#include "test_support.h"

namespace omnislice {
namespace {

// Holes counted independently of OpenMesh: connected components of the graph of boundary edges
// (equal to the number of boundary loops when no vertex lies on two holes).
size_t boundaryComponents(const Mesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> uses;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      ++uses[std::minmax(m.triangles[3 * f + k], m.triangles[3 * f + (k + 1) % 3])];
    }
  }
  std::map<uint32_t, uint32_t> parent;
  std::function<uint32_t(uint32_t)> root = [&](uint32_t v) {
    return parent[v] == v ? v : parent[v] = root(parent[v]);
  };
  for (const auto& [edge, n] : uses) {
    if (n != 1) continue;
    for (uint32_t v : {edge.first, edge.second}) parent.emplace(v, v);
    parent[root(edge.first)] = root(edge.second);
  }
  size_t roots = 0;
  for (const auto& [v, p] : parent) roots += root(v) == v ? 1 : 0;
  return roots;
}

struct Expected {
  const char* file;
  size_t vertices, faces;
  bool closed;
  size_t boundaryEdges;  // open models
  int genus;             // closed models
};

// From MANIFEST.md.
const Expected kModels[] = {
    {"pymdp_kitten.off", 5000, 10000, true, 0, 1},
    {"voxelmaam_kitten.ply", 3444, 6888, true, 0, 1},
    {"voxelmaam_platform.obj", 56, 108, true, 0, 0},
    {"compas_bunny_closed_low_res.obj", 938, 1872, true, 0, 0},
    {"compas_bunny_closed_high_res.stl", 34801, 69598, true, 0, 0},
    {"compas_branches_70_closed_low_res.stl", 3118, 6232, true, 0, 0},
    {"compas_branches_16_closed_mid_res.stl", 25044, 50152, true, 0, 17},
    {"compas_overhang_coin_closed_low_res.stl", 80, 156, true, 0, 0},
    {"nestedcages_fertility.off", 23188, 46388, true, 0, 4},
    {"compas_connection3legs_open_low_res.obj", 2831, 5519, false, 147, 0},
    {"compas_Y_shape_mesh.obj", 2014, 3942, false, 88, 0},
    {"compas_costa_surface_mesh.obj", 2695, 5135, false, 261, 0},
};

TEST(PrepareMeshModels, MatchManifest) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  // Every mesh file in the folder is covered by the table.
  size_t meshFiles = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::sharedModelsDir())) {
    const std::string ext = entry.path().extension().string();
    if (ext == ".stl" || ext == ".obj" || ext == ".off" || ext == ".ply") ++meshFiles;
  }
  EXPECT_EQ(meshFiles, std::size(kModels));
  for (const Expected& e : kModels) {
    SCOPED_TRACE(e.file);
    const ReadMeshResult read = readMeshFile((test::sharedModelsDir() / e.file).string());
    ASSERT_TRUE(read.ok()) << read.message;
    const Mesh& raw = read.mesh;
    ASSERT_EQ(raw.faceCount(), e.faces);
    const PrepareMeshResult r = prepareMesh(raw, {});
    ASSERT_TRUE(r.ok()) << r.message;
    const MeshInfo& i = r.info;
    EXPECT_EQ(i.vertices, e.vertices);
    EXPECT_EQ(i.faces, e.faces);
    EXPECT_EQ(i.shells, 1u);
    EXPECT_TRUE(i.manifold);
    EXPECT_TRUE(i.oriented);
    EXPECT_EQ(i.closed, e.closed);
    EXPECT_GT(i.areaMm2, 0);
    if (e.closed) {
      EXPECT_TRUE(r.solid.ok()) << r.solid.message;
      EXPECT_GT(i.volumeMm3, 0);
      const long chi = long(i.vertices) - long(3 * i.faces / 2) + long(i.faces);
      EXPECT_EQ((2 - chi) / 2, e.genus);
      EXPECT_EQ(i.boundaryEdges, 0u);
    } else {
      EXPECT_EQ(i.boundaryEdges, e.boundaryEdges);
      EXPECT_GE(i.boundaryLoops, 1u);
      EXPECT_EQ(i.boundaryLoops, boundaryComponents(r.mesh));
      EXPECT_EQ(r.solid.status, Status::OpenMesh);
    }
    std::string lines;
    for (const auto& s : i.repairs) lines += " [" + s + "]";
    for (const auto& s : i.warnings) lines += " [" + s + "]";
    std::printf("%-42s V %6zu F %6zu loops %zu self-int %zu%s\n", e.file, i.vertices, i.faces,
                i.boundaryLoops, i.selfIntersections, lines.c_str());
  }
}

// Measurement (printed): binary STL of a 1M-triangle torus -> parse -> prepareMesh, and the cost of
// the CGAL self-intersection test at that size. Wall and CPU time (the machine may be shared).
// Asserts only correctness.
TEST(PrepareMeshModels, MillionTriangleMeasurement) {
  struct Stopwatch {
    std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
    std::clock_t cpu = std::clock();
    std::string lap() {
      const auto w = std::chrono::steady_clock::now();
      const std::clock_t c = std::clock();
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.0f ms wall, %.0f ms CPU",
                    std::chrono::duration<double, std::milli>(w - wall).count(),
                    1000.0 * double(c - cpu) / CLOCKS_PER_SEC);
      wall = w;
      cpu = c;
      return buf;
    }
  };
  const Mesh torus = test::makeTorus(60, 20, 1000, 500);
  ASSERT_EQ(torus.faceCount(), 1000000u);
  const std::vector<uint8_t> stl = test::binaryStl(torus);
  Stopwatch watch;
  const ReadMeshResult read = readMesh(stl.data(), stl.size(), "torus.stl");
  const std::string parse = watch.lap();
  ASSERT_TRUE(read.ok()) << read.message;
  const Mesh& soup = read.mesh;
  const PrepareMeshResult r = prepareMesh(soup, {});
  const std::string prepare = watch.lap();
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r.solid.ok()) << r.solid.message;
  EXPECT_EQ(r.info.vertices, 500000u);
  EXPECT_EQ(r.info.faces, 1000000u);
  EXPECT_EQ(r.info.shells, 1u);
  EXPECT_EQ(r.info.nonManifoldEdges + r.info.nonManifoldVertices + r.info.boundaryEdges, 0u);
  std::printf("1M-triangle torus: parse binary STL %s\n", parse.c_str());
  std::printf("1M-triangle torus: prepareMesh (weld 3M corners, repair, report; self-intersections %s) %s\n",
              r.info.faces > PrepareOptions{}.selfIntersectionMaxFaces ? "skipped" : "checked", prepare.c_str());
  SelfIntersectionOptions so;
  so.collectPairs = false;
  watch.lap();
  const SelfIntersectionResult si = findSelfIntersections(r.mesh, so);
  const std::string cgal = watch.lap();
  EXPECT_TRUE(si.ok());
  EXPECT_EQ(si.count, 0u);
  std::printf("1M-triangle torus: CGAL self-intersection test %s\n", cgal.c_str());
}

}  // namespace
}  // namespace omnislice
