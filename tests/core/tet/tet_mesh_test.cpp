// SPDX-License-Identifier: MIT
// Tet meshes: the `.tet` reader on the shared models (counts against MANIFEST.md, boundary closed,
// edge-manifold, outward, of the listed genus, tet volumes summing to the enclosed volume), on
// generated cube grids (exact volumes, 12 n^2 boundary triangles, boundary equal to a brute-force
// one, orientation flips counted by permutation parity), quality figures on tets with known
// angles, every malformed input's status, and a 100k-tet parse (time printed, not asserted).
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "../test_support.h"
#include "mesh/mesh_topology.h"
#include "tet/tet_mesh.h"

namespace omnislice {
namespace {

// Independent signed volume of tet t (the determinant written out by components).
double signedVolume(const TetMesh& m, size_t t) {
  const double* p[4];
  for (int k = 0; k < 4; ++k) p[k] = &m.positions[3 * size_t(m.tets[4 * t + k])];
  double u[3], v[3], w[3];
  for (int i = 0; i < 3; ++i) {
    u[i] = p[1][i] - p[0][i];
    v[i] = p[2][i] - p[0][i];
    w[i] = p[3][i] - p[0][i];
  }
  return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
          u[2] * (v[0] * w[1] - v[1] * w[0])) / 6.0;
}

double sumVolumes(const TetMesh& m) {
  double s = 0;
  for (size_t t = 0; t < m.tetCount(); ++t) s += signedVolume(m, t);
  return s;
}

std::string writeTet(const TetMesh& m) {
  std::string s = std::to_string(m.vertexCount()) + " vertices\n" + std::to_string(m.tetCount()) + " tets\n";
  char buf[128];
  for (size_t i = 0; i < m.vertexCount(); ++i) {
    std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g\n", m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]);
    s += buf;
  }
  for (size_t t = 0; t < m.tetCount(); ++t) {
    std::snprintf(buf, sizeof buf, "4 %u %u %u %u\n", m.tets[4 * t], m.tets[4 * t + 1], m.tets[4 * t + 2], m.tets[4 * t + 3]);
    s += buf;
  }
  return s;
}

TetMeshResult readText(const std::string& s) {
  return readTetMesh(reinterpret_cast<const uint8_t*>(s.data()), s.size());
}

// n x n x n cubes of side h, each split into the 6 Kuhn tets around its main diagonal (a
// conforming split). The tets are listed as generated, half of them negatively oriented.
TetMesh kuhnGrid(int n, double h) {
  TetMesh m;
  const int s = n + 1;
  for (int z = 0; z <= n; ++z)
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x) m.positions.insert(m.positions.end(), {x * h, y * h, z * h});
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        for (const auto& p : perms) {
          int c[3] = {x, y, z};
          auto id = [&] { return static_cast<uint32_t>(c[0] + s * (c[1] + s * c[2])); };
          m.tets.push_back(id());
          for (int k = 0; k < 3; ++k) {
            ++c[p[k]];
            m.tets.push_back(id());
          }
        }
  return m;
}

// Boundary faces by a std::map of sorted triples (independent of the core's grouping).
std::set<std::array<uint32_t, 3>> bruteBoundary(const TetMesh& m) {
  std::map<std::array<uint32_t, 3>, int> uses;
  for (size_t t = 0; t < m.tetCount(); ++t)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<uint32_t, 3> f;
      int j = 0;
      for (int k = 0; k < 4; ++k)
        if (k != skip) f[j++] = m.tets[4 * t + k];
      std::sort(f.begin(), f.end());
      ++uses[f];
    }
  std::set<std::array<uint32_t, 3>> out;
  for (const auto& [f, n] : uses)
    if (n == 1) out.insert(f);
  return out;
}

struct SurfaceCheck {
  size_t usedVertices = 0, edges = 0;
  TopologyCounts topo;
  int euler = 0;
};

SurfaceCheck checkSurface(const Mesh& b) {
  SurfaceCheck c;
  const MeshEdges edges = buildEdges(b);
  c.topo = countTopology(b, edges);
  std::vector<char> used(b.vertexCount(), 0);
  for (uint32_t v : b.triangles) used[v] = 1;
  c.usedVertices = static_cast<size_t>(std::count(used.begin(), used.end(), 1));
  c.edges = edges.edgeCount();
  c.euler = static_cast<int>(c.usedVertices) - static_cast<int>(c.edges) + static_cast<int>(b.faceCount());
  return c;
}

void expectClosedOutward(const Mesh& b, const std::string& label) {
  const SurfaceCheck c = checkSurface(b);
  EXPECT_EQ(c.topo.boundaryEdges, 0u) << label;
  EXPECT_EQ(c.topo.nonManifoldEdges, 0u) << label;
  EXPECT_EQ(c.topo.misorientedEdges, 0u) << label;
  EXPECT_GT(test::meshVolume(b), 0) << label;
}

TEST(TetMesh, KuhnCubeExactVolumeBoundaryAndFlips) {
  const TetMesh cube = kuhnGrid(1, 1.0);
  size_t negative = 0;
  for (size_t t = 0; t < 6; ++t) negative += signedVolume(cube, t) < 0;
  ASSERT_EQ(negative, 3u);  // odd permutations
  const TetMeshResult r = readText(writeTet(cube));
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.flipped, 3u);
  ASSERT_EQ(r.mesh.tetCount(), 6u);
  ASSERT_EQ(r.mesh.vertexCount(), 8u);
  for (size_t t = 0; t < 6; ++t) {
    EXPECT_NEAR(signedVolume(r.mesh, t), 1.0 / 6.0, 1e-15);
    // same vertex set as the input tet
    std::vector<uint32_t> a(&cube.tets[4 * t], &cube.tets[4 * t] + 4), b(&r.mesh.tets[4 * t], &r.mesh.tets[4 * t] + 4);
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b);
  }
  EXPECT_NEAR(sumVolumes(r.mesh), 1.0, 1e-15);
  const Mesh b = tetBoundary(r.mesh);
  EXPECT_EQ(b.faceCount(), 12u);
  EXPECT_EQ(b.vertexCount(), 8u);
  expectClosedOutward(b, "cube");
  EXPECT_DOUBLE_EQ(test::meshVolume(b), 1.0);
  const TetQuality q = tetQuality(r.mesh);
  EXPECT_DOUBLE_EQ(q.volume, 1.0);
  EXPECT_NEAR(q.minDihedralDegrees, 45.0, 1e-9);
  EXPECT_NEAR(q.maxDihedralDegrees, 90.0, 1e-9);
  // Kuhn tet: r_in = 3 (1/6) / (1 + sqrt 2), R = sqrt(3) / 2.
  EXPECT_NEAR(q.minRadiusRatio, std::sqrt(3.0) / (1 + std::sqrt(2.0)), 1e-12);
  // 19 distinct edges: 12 cube edges, 6 face diagonals, the main diagonal.
  EXPECT_NEAR(q.meanEdge, (12 + 6 * std::sqrt(2.0) + std::sqrt(3.0)) / 19.0, 1e-12);
  EXPECT_EQ(q.nonManifoldFaces, 0u);
}

TEST(TetMesh, RegularTetQuality) {
  TetMesh m;
  m.positions = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
  m.tets = {0, 1, 2, 3};
  const TetMeshResult r = validateTetMesh(m);
  ASSERT_TRUE(r.ok()) << r.message;
  const TetQuality q = tetQuality(r.mesh);
  EXPECT_NEAR(q.volume, 8.0 / 3.0, 1e-12);
  EXPECT_NEAR(q.meanEdge, std::sqrt(8.0), 1e-12);
  const double dihedral = std::acos(1.0 / 3.0) * 180.0 / M_PI;
  EXPECT_NEAR(q.minDihedralDegrees, dihedral, 1e-9);
  EXPECT_NEAR(q.maxDihedralDegrees, dihedral, 1e-9);
  EXPECT_NEAR(q.minRadiusRatio, 1.0, 1e-12);
  const Mesh b = tetBoundary(r.mesh);
  EXPECT_EQ(b.faceCount(), 4u);
  expectClosedOutward(b, "regular");
  EXPECT_NEAR(test::meshVolume(b), 8.0 / 3.0, 1e-12);
}

TEST(TetMesh, GridOfCubes) {
  for (int n : {2, 3, 5}) {
    const double h = 0.7;
    const TetMesh g = kuhnGrid(n, h);
    const TetMeshResult r = readText(writeTet(g));
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_EQ(r.flipped, 3u * n * n * n);
    EXPECT_EQ(r.mesh.tetCount(), 6u * n * n * n);
    const double exact = n * n * n * h * h * h;
    EXPECT_NEAR(sumVolumes(r.mesh), exact, 1e-12 * exact);
    for (size_t t = 0; t < r.mesh.tetCount(); ++t) ASSERT_GT(signedVolume(r.mesh, t), 0);
    const Mesh b = tetBoundary(r.mesh);
    EXPECT_EQ(b.faceCount(), 12u * n * n);
    expectClosedOutward(b, "grid");
    const SurfaceCheck c = checkSurface(b);
    EXPECT_EQ(c.usedVertices, 6u * n * n + 2);
    EXPECT_EQ(c.euler, 2);
    EXPECT_NEAR(test::meshVolume(b), exact, 1e-12 * exact);
    // Same face set as the brute-force boundary.
    std::set<std::array<uint32_t, 3>> mine;
    for (size_t f = 0; f < b.faceCount(); ++f) {
      std::array<uint32_t, 3> t = {b.triangles[3 * f], b.triangles[3 * f + 1], b.triangles[3 * f + 2]};
      std::sort(t.begin(), t.end());
      mine.insert(t);
    }
    EXPECT_EQ(mine, bruteBoundary(r.mesh));
    const TetQuality q = tetQuality(r.mesh);
    EXPECT_NEAR(q.volume, exact, 1e-12 * exact);
    EXPECT_NEAR(q.minDihedralDegrees, 45.0, 1e-9);
    EXPECT_NEAR(q.maxDihedralDegrees, 90.0, 1e-9);
    EXPECT_EQ(q.nonManifoldFaces, 0u);
    // Distinct edges: 3 n (n+1)^2 axis edges of length h, 3 n^2 (n+1) face diagonals, n^3 main diagonals.
    const double e1 = 3.0 * n * (n + 1) * (n + 1), e2 = 3.0 * n * n * (n + 1), e3 = double(n) * n * n;
    EXPECT_NEAR(q.meanEdge, h * (e1 + e2 * std::sqrt(2.0) + e3 * std::sqrt(3.0)) / (e1 + e2 + e3), 1e-12);
  }
}

TEST(TetMesh, ShuffledOrientationsFlippedByParity) {
  TetMesh g = kuhnGrid(3, 1.5);
  // Make every tet positive, then apply random permutations: odd ones must be flipped.
  for (size_t t = 0; t < g.tetCount(); ++t)
    if (signedVolume(g, t) < 0) std::swap(g.tets[4 * t], g.tets[4 * t + 1]);
  std::mt19937 rng(7);
  size_t odd = 0;
  for (size_t t = 0; t < g.tetCount(); ++t) {
    std::array<int, 4> p = {0, 1, 2, 3};
    std::shuffle(p.begin(), p.end(), rng);
    int inversions = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) inversions += p[i] > p[j];
    odd += inversions % 2;
    std::array<uint32_t, 4> old;
    for (int k = 0; k < 4; ++k) old[k] = g.tets[4 * t + k];
    for (int k = 0; k < 4; ++k) g.tets[4 * t + k] = old[p[k]];
  }
  ASSERT_GT(odd, 0u);
  const TetMeshResult r = readText(writeTet(g));
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.flipped, odd);
  for (size_t t = 0; t < r.mesh.tetCount(); ++t) ASSERT_GT(signedVolume(r.mesh, t), 0);
  const TetMeshResult v = validateTetMesh(g);
  ASSERT_TRUE(v.ok()) << v.message;
  EXPECT_EQ(v.flipped, odd);
  EXPECT_EQ(v.mesh.tets, r.mesh.tets);
  EXPECT_EQ(validateTetMesh(v.mesh).flipped, 0u);
}

TEST(TetMesh, NonManifoldFaceCountedAndNotBoundary) {
  // Triangle (0,1,2) in z=0 with apexes above (3), below (4) and above again (5): face shared by 3.
  TetMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, 1, 0.2, 0.2, -1, 0.3, 0.3, 2};
  m.tets = {0, 1, 2, 3, 0, 1, 2, 4, 0, 1, 2, 5};
  const TetMeshResult r = validateTetMesh(m);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.flipped, 1u);
  EXPECT_EQ(tetQuality(r.mesh).nonManifoldFaces, 1u);
  const Mesh b = tetBoundary(r.mesh);
  EXPECT_EQ(b.faceCount(), 9u);
  for (size_t f = 0; f < b.faceCount(); ++f) {
    std::array<uint32_t, 3> t = {b.triangles[3 * f], b.triangles[3 * f + 1], b.triangles[3 * f + 2]};
    std::sort(t.begin(), t.end());
    EXPECT_NE(t, (std::array<uint32_t, 3>{0, 1, 2}));
  }
}

TEST(TetMesh, TolerantSyntax) {
  const std::string text =
      "# a comment\r\n\r\n  4   vertices  # trailing comment\r\n"
      "1 TETRAHEDRA\r\n"
      "0 0 0\r\n\t1.0e0 0 0\r\n0 1 0 # v2\r\n\n0 0 +1\r\n"
      "4 0 1 2 3\r\n";
  const TetMeshResult r = readText(text);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.mesh.vertexCount(), 4u);
  EXPECT_EQ(r.flipped, 0u);
  EXPECT_NEAR(sumVolumes(r.mesh), 1.0 / 6.0, 1e-15);
  // Bare counts, on one line.
  const TetMeshResult r2 = readText("4 1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n4 0 2 1 3\n");
  ASSERT_TRUE(r2.ok()) << r2.message;
  EXPECT_EQ(r2.flipped, 1u);
  // A UTF-8 byte order mark.
  const TetMeshResult bom = readText("\xEF\xBB\xBF" "4 1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n4 0 1 2 3\n");
  ASSERT_TRUE(bom.ok()) << bom.message;
  // An unused vertex and trailing lines are warnings.
  const TetMeshResult r3 = readText("5\n1\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n9 9 9\n4 0 1 2 3\nextra\n");
  ASSERT_TRUE(r3.ok()) << r3.message;
  EXPECT_EQ(r3.warnings.size(), 2u);
}

TEST(TetMesh, MalformedInputStatuses) {
  const std::string v4 = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  struct Case {
    const char* label;
    std::string text;
    Status status;
    int line;  // expected line named in the message, 0 = none
  };
  const std::vector<Case> cases = {
      {"empty", "", Status::EmptyInput, 0},
      {"blank and comments", "\n  \n# nothing\n", Status::EmptyInput, 0},
      {"counts missing", v4 + "4 0 1 2 3\n", Status::ParseError, 1},
      {"tet count missing, file ends", "4 vertices\n", Status::TruncatedFile, 1},
      {"tet count missing", "4 vertices\n" + v4 + "4 0 1 2 3\n", Status::ParseError, 2},
      {"bad count", "four vertices\n1 tets\n" + v4, Status::ParseError, 1},
      {"negative count", "-4 vertices\n1 tets\n" + v4, Status::ParseError, 1},
      {"wrong count word", "4 faces\n1 tets\n" + v4, Status::ParseError, 1},
      {"no tets", "4 vertices\n0 tets\n" + v4, Status::DegenerateInput, 2},
      {"truncated vertices", "4 vertices\n1 tets\n0 0 0\n1 0 0\n", Status::TruncatedFile, 4},
      {"truncated tets", "4 vertices\n2 tets\n" + v4 + "4 0 1 2 3\n", Status::TruncatedFile, 7},
      {"truncated mid-line", "4 vertices\n1 tets\n" + v4 + "4 0 1 2", Status::ParseError, 7},
      {"bad number", "4 vertices\n1 tets\n0 0 0\n1 0x 0\n0 1 0\n0 0 1\n4 0 1 2 3\n", Status::ParseError, 4},
      {"comma decimal", "4 vertices\n1 tets\n0 0 0\n1,0 0 0\n0 1 0\n0 0 1\n4 0 1 2 3\n", Status::ParseError, 4},
      {"NaN", "4 vertices\n1 tets\n0 0 0\n1 0 0\n0 nan 0\n0 0 1\n4 0 1 2 3\n", Status::NonFiniteVertex, 5},
      {"infinity", "4 vertices\n1 tets\n0 0 0\n1 0 0\n0 1 0\n0 0 -inf\n4 0 1 2 3\n", Status::NonFiniteVertex, 6},
      {"vertex arity 2", "4 vertices\n1 tets\n0 0 0\n1 0\n0 1 0\n0 0 1\n4 0 1 2 3\n", Status::ParseError, 4},
      {"vertex arity 4", "4 vertices\n1 tets\n0 0 0\n1 0 0 1\n0 1 0\n0 0 1\n4 0 1 2 3\n", Status::ParseError, 4},
      {"tet arity 3", "4 vertices\n1 tets\n" + v4 + "3 0 1 2\n", Status::ParseError, 7},
      {"tet without leading 4", "4 vertices\n1 tets\n" + v4 + "0 1 2 3\n", Status::ParseError, 7},
      {"tet with 5 indices", "4 vertices\n1 tets\n" + v4 + "4 0 1 2 3 0\n", Status::ParseError, 7},
      {"bad index", "4 vertices\n1 tets\n" + v4 + "4 0 1 two 3\n", Status::ParseError, 7},
      {"fractional index", "4 vertices\n1 tets\n" + v4 + "4 0 1 2.0 3\n", Status::ParseError, 7},
      {"index out of range", "4 vertices\n1 tets\n" + v4 + "4 0 1 2 4\n", Status::DegenerateInput, 7},
      {"1-based indices", "4 vertices\n1 tets\n" + v4 + "4 1 2 3 4\n", Status::DegenerateInput, 7},
      {"negative index", "4 vertices\n1 tets\n" + v4 + "4 0 1 -2 3\n", Status::DegenerateInput, 7},
      {"huge index", "4 vertices\n1 tets\n" + v4 + "4 0 1 2 99999999999999999999\n", Status::ParseError, 7},
      {"repeated vertex", "4 vertices\n1 tets\n" + v4 + "4 0 1 1 3\n", Status::DegenerateInput, 7},
      {"zero volume", "4 vertices\n1 tets\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n4 0 1 2 3\n", Status::DegenerateInput, 7},
      {"coincident points", "4 vertices\n1 tets\n0 0 0\n1 0 0\n0 1 0\n0 0 0\n4 0 1 2 3\n", Status::DegenerateInput, 7},
      {"binary junk", std::string("\x01\x02\xff\x00\x7f", 5), Status::ParseError, 1},
  };
  for (const Case& c : cases) {
    const TetMeshResult r = readText(c.text);
    EXPECT_EQ(r.status, c.status) << c.label << ": " << r.message;
    EXPECT_FALSE(r.message.empty()) << c.label;
    EXPECT_TRUE(r.mesh.tets.empty() && r.mesh.positions.empty()) << c.label;
    if (c.line > 0) {
      EXPECT_NE(r.message.find("line " + std::to_string(c.line) + ":"), std::string::npos) << c.label << ": " << r.message;
    }
  }
  const TetMeshResult nul = readTetMesh(nullptr, 0);
  EXPECT_EQ(nul.status, Status::EmptyInput);
}

TEST(TetMesh, ValidateInMemoryStatuses) {
  TetMesh good;
  good.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  good.tets = {0, 1, 2, 3};
  EXPECT_TRUE(validateTetMesh(good).ok());
  EXPECT_EQ(validateTetMesh(TetMesh()).status, Status::EmptyInput);
  TetMesh m = good;
  m.tets.push_back(1);
  EXPECT_EQ(validateTetMesh(m).status, Status::ParseError);
  m = good;
  m.positions.push_back(1);
  EXPECT_EQ(validateTetMesh(m).status, Status::ParseError);
  m = good;
  m.positions[4] = std::nan("");
  EXPECT_EQ(validateTetMesh(m).status, Status::NonFiniteVertex);
  m = good;
  m.tets[3] = 4;
  EXPECT_EQ(validateTetMesh(m).status, Status::DegenerateInput);
  m = good;
  m.tets[3] = 0;
  EXPECT_EQ(validateTetMesh(m).status, Status::DegenerateInput);
  m = good;
  m.positions[11] = 0;  // flat
  EXPECT_EQ(validateTetMesh(m).status, Status::DegenerateInput);
  m = good;
  m.tets.clear();
  EXPECT_EQ(validateTetMesh(m).status, Status::DegenerateInput);
  // Invalid meshes never crash boundary or quality.
  m = good;
  m.tets[3] = 40;
  EXPECT_TRUE(tetBoundary(m).empty());
  EXPECT_EQ(tetQuality(m).volume, 0.0);
  EXPECT_EQ(tetQuality(TetMesh()).meanEdge, 0.0);
}

TEST(TetMesh, MutatedInputNeverCrashes) {
  const std::string base = writeTet(kuhnGrid(1, 2.0));
  std::mt19937 rng(11);
  size_t okCount = 0;
  // Every prefix, then random byte edits.
  for (size_t cut = 0; cut <= base.size(); ++cut) {
    const TetMeshResult r = readText(base.substr(0, cut));
    if (r.ok()) {
      ++okCount;
      EXPECT_EQ(r.mesh.tetCount(), 6u);  // only when the last index is complete
    } else {
      EXPECT_FALSE(r.message.empty());
    }
  }
  EXPECT_GE(okCount, 1u);
  const char alphabet[] = "0123456789 -+.eE\n#x\tn";
  for (int trial = 0; trial < 3000; ++trial) {
    std::string s = base;
    const int edits = 1 + trial % 4;
    for (int k = 0; k < edits; ++k) {
      const size_t at = rng() % s.size();
      switch (rng() % 3) {
        case 0: s[at] = alphabet[rng() % (sizeof alphabet - 1)]; break;
        case 1: s.erase(at, 1); break;
        default: s.insert(at, 1, alphabet[rng() % (sizeof alphabet - 1)]); break;
      }
    }
    const TetMeshResult r = readText(s);
    if (!r.ok()) {
      EXPECT_FALSE(r.message.empty());
      continue;
    }
    for (size_t t = 0; t < r.mesh.tetCount(); ++t) ASSERT_GT(signedVolume(r.mesh, t), 0) << s;
    const TetMeshResult v = validateTetMesh(r.mesh);
    ASSERT_TRUE(v.ok()) << v.message;
    EXPECT_EQ(v.flipped, 0u);
  }
}

struct SharedTet {
  const char* file;
  size_t vertices, tets, boundaryVertices, boundaryTriangles;
  int genus;
};

// From MANIFEST.md.
const SharedTet kSharedTets[] = {
    {"reinforcedfdm_YogaNew.tet", 11000, 52446, 4646, 9296, 2},
    {"reinforcedfdm_bunnyhead.tet", 12000, 60375, 4101, 8198, 0},
    {"reinforcedfdm_topopt_new.tet", 15000, 70505, 6735, 13490, 6},
};

TEST(TetMesh, SharedModels) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  for (const SharedTet& s : kSharedTets) {
    const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / s.file);
    ASSERT_FALSE(bytes.empty()) << s.file;
    TetMeshResult r;
    double best = 1e9;
    for (int i = 0; i < 3; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      r = readTetMesh(bytes.data(), bytes.size());
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    ASSERT_TRUE(r.ok()) << s.file << ": " << r.message;
    EXPECT_EQ(r.mesh.vertexCount(), s.vertices) << s.file;
    EXPECT_EQ(r.mesh.tetCount(), s.tets) << s.file;
    for (size_t t = 0; t < r.mesh.tetCount(); ++t) ASSERT_GT(signedVolume(r.mesh, t), 0) << s.file;
    // Independent parse with iostreams: the same coordinates (bit for bit) and tets.
    {
      std::istringstream in(std::string(bytes.begin(), bytes.end()));
      size_t nv = 0, nt = 0;
      std::string word;
      in >> nv >> word >> nt >> word;
      ASSERT_EQ(nv, s.vertices);
      ASSERT_EQ(nt, s.tets);
      std::vector<double> xyz(3 * nv);
      for (double& x : xyz) in >> x;
      ASSERT_EQ(xyz, r.mesh.positions) << s.file;
      std::vector<uint32_t> tets(4 * nt);
      for (size_t t = 0; t < nt; ++t) {
        int four = 0;
        in >> four >> tets[4 * t] >> tets[4 * t + 1] >> tets[4 * t + 2] >> tets[4 * t + 3];
        ASSERT_EQ(four, 4);
      }
      ASSERT_TRUE(in) << s.file;
      EXPECT_EQ(tets, r.mesh.tets) << s.file << " (no tet flipped, so the same order)";
    }
    const auto t0 = std::chrono::steady_clock::now();
    const Mesh b = tetBoundary(r.mesh);
    const double boundarySeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const SurfaceCheck c = checkSurface(b);
    EXPECT_EQ(b.faceCount(), s.boundaryTriangles) << s.file;
    EXPECT_EQ(c.usedVertices, s.boundaryVertices) << s.file;
    EXPECT_EQ(c.topo.boundaryEdges, 0u) << s.file;
    EXPECT_EQ(c.topo.nonManifoldEdges, 0u) << s.file;
    EXPECT_EQ(c.topo.misorientedEdges, 0u) << s.file;
    EXPECT_EQ(c.topo.shells, 1u) << s.file;
    EXPECT_EQ(c.euler, 2 - 2 * s.genus) << s.file;
    std::set<std::array<uint32_t, 3>> mine;
    for (size_t f = 0; f < b.faceCount(); ++f) {
      std::array<uint32_t, 3> t = {b.triangles[3 * f], b.triangles[3 * f + 1], b.triangles[3 * f + 2]};
      std::sort(t.begin(), t.end());
      mine.insert(t);
    }
    EXPECT_EQ(mine, bruteBoundary(r.mesh)) << s.file;
    const double tetVolume = sumVolumes(r.mesh), enclosed = test::meshVolume(b);
    EXPECT_GT(enclosed, 0) << s.file;
    EXPECT_NEAR(tetVolume, enclosed, 1e-9 * enclosed) << s.file;
    const auto t1 = std::chrono::steady_clock::now();
    const TetQuality q = tetQuality(r.mesh);
    const double qualitySeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    EXPECT_NEAR(q.volume, tetVolume, 1e-9 * tetVolume) << s.file;
    EXPECT_EQ(q.nonManifoldFaces, 0u) << s.file;
    EXPECT_GT(q.minDihedralDegrees, 0) << s.file;
    EXPECT_LT(q.maxDihedralDegrees, 180) << s.file;
    EXPECT_GT(q.minRadiusRatio, 0) << s.file;
    EXPECT_LE(q.minRadiusRatio, 1) << s.file;
    EXPECT_GT(q.meanEdge, 0) << s.file;
    std::printf("[TetMesh] %s: %zu V, %zu tets, flipped %zu, boundary %zu V / %zu tris (genus %d), volume %.6g mm^3 "
                "(boundary %.6g, rel diff %.2g), mean edge %.4g mm, dihedral [%.3f, %.3f] deg, min radius ratio %.4g; "
                "read %.1f ms (%.2f MB), boundary %.1f ms, quality %.1f ms\n",
                s.file, r.mesh.vertexCount(), r.mesh.tetCount(), r.flipped, c.usedVertices, b.faceCount(),
                (2 - c.euler) / 2, q.volume, enclosed, std::abs(tetVolume - enclosed) / enclosed, q.meanEdge,
                q.minDihedralDegrees, q.maxDihedralDegrees, q.minRadiusRatio, best * 1e3, bytes.size() / 1e6,
                boundarySeconds * 1e3, qualitySeconds * 1e3);
  }
}

// Speed is printed, never asserted (a loaded machine would make a bound flaky).
TEST(TetMesh, HundredThousandTetsParse) {
  const int n = 26;  // 105,456 tets
  TetMesh g = kuhnGrid(n, 1.0 / 3.0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.03, 0.03);
  for (double& x : g.positions) x += jitter(rng);  // full-precision coordinates
  const std::string text = writeTet(g);
  TetMeshResult r;
  double best = 1e9;
  for (int i = 0; i < 3; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    r = readText(text);
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_EQ(r.mesh.tetCount(), 6u * n * n * n);
  EXPECT_EQ(r.mesh.positions, g.positions);  // %.17g round-trips exactly
  const Mesh b = tetBoundary(r.mesh);
  EXPECT_EQ(b.faceCount(), 12u * n * n);
  expectClosedOutward(b, "jittered grid");
  EXPECT_NEAR(sumVolumes(r.mesh), test::meshVolume(b), 1e-9 * test::meshVolume(b));
  std::printf("[TetMesh] %zu tets, %zu vertices (%.2f MB, 17-digit coordinates): read %.1f ms\n", r.mesh.tetCount(),
              r.mesh.vertexCount(), text.size() / 1e6, best * 1e3);
}

}  // namespace
}  // namespace omnislice
