// SPDX-License-Identifier: MIT
// Reader speed on large generated files. The 1M-triangle binary STL must parse well under 0.5 s
// in an optimised build (the read + validate budget is 1 s); times are printed for the record.
// OMNISLICE_SPEED_TRIANGLES overrides the text-format size (default 100k triangles).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "../test_support.h"
#include "mesh/read_mesh.h"
#include "read_mesh_writers.h"

namespace omnislice {
namespace {

// Speed is measured by `npm run bench`, never asserted in tests (a loaded CI machine would make a
// time bound flaky): these tests check large inputs read correctly and print the time taken.

// Random triangles; coordinates are floats, or (shortDecimals) multiples of 1/1024 whose
// decimal text has at most 13 significant digits, like typical exporters' output.
Mesh randomSoup(size_t faces, unsigned seed, bool shortDecimals = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-100.f, 100.f);
  Mesh m;
  m.positions.resize(9 * faces);
  for (double& v : m.positions) v = shortDecimals ? test::gridRound(u(rng)) : u(rng);
  m.triangles.resize(3 * faces);
  for (size_t i = 0; i < m.triangles.size(); ++i) m.triangles[i] = static_cast<uint32_t>(i);
  return m;
}

double secondsToRead(const std::vector<uint8_t>& bytes, const std::string& name, ReadMeshResult& out) {
  const auto t0 = std::chrono::steady_clock::now();
  out = readMesh(bytes.data(), bytes.size(), name);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(ReadMeshSpeed, BinaryStlMillionTriangles) {
  const size_t faces = 1000000;
  const Mesh m = randomSoup(faces, 1);
  const std::vector<uint8_t> bytes = test::writeBinaryStl(m, "solid speed test");
  ReadMeshResult r;
  double best = 1e9;
  for (int i = 0; i < 3; ++i) best = std::min(best, secondsToRead(bytes, "speed.stl", r));
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_EQ(r.mesh.faceCount(), faces);
  EXPECT_EQ(r.mesh.positions[12345], m.positions[12345]);
  std::printf("[ReadMeshSpeed] binary STL, %zu triangles (%.1f MB): %.3f s\n", faces, bytes.size() / 1e6, best);
}

TEST(ReadMeshSpeed, TextFormats) {
  size_t faces = 100000;
  if (const char* env = std::getenv("OMNISLICE_SPEED_TRIANGLES")) faces = std::strtoull(env, nullptr, 10);
  const Mesh m = randomSoup(faces, 2, true);
  test::PolyMesh poly;
  poly.positions = m.positions;
  for (size_t f = 0; f < faces; ++f) poly.polygons.push_back({m.triangles[3 * f], m.triangles[3 * f + 1], m.triangles[3 * f + 2]});
  struct Case {
    const char* label;
    std::vector<uint8_t> bytes;
    const char* name;
  };
  std::vector<Case> cases;
  cases.push_back({"ASCII STL", test::bytesOf(test::writeAsciiStl(m)), "s.stl"});
  // 17 significant digits (%.17g of float values): the parser's exact fast path does not apply
  // beyond 2^53, so these numbers go through strtod.
  cases.push_back({"ASCII STL, 17-digit numbers", test::bytesOf(test::writeAsciiStl(randomSoup(faces, 3))), "s.stl"});
  cases.push_back({"OBJ", test::bytesOf(test::writeObj(poly)), "s.obj"});
  cases.push_back({"PLY LE", test::writePly(poly, test::PlyKind::LittleEndian), "s.ply"});
  cases.push_back({"3MF deflated", test::write3mf(test::modelXml(test::objectXml(1, m), "<item objectid=\"1\"/>"), true), "s.3mf"});
  for (const Case& c : cases) {
    ReadMeshResult r;
    const double s = secondsToRead(c.bytes, c.name, r);
    ASSERT_TRUE(r.ok()) << c.label << ": " << r.message;
    EXPECT_EQ(r.mesh.faceCount(), faces) << c.label;
    std::printf("[ReadMeshSpeed] %s, %zu triangles (%.1f MB): %.3f s (%.3f s per million triangles)\n", c.label, faces,
                c.bytes.size() / 1e6, s, s * 1e6 / faces);
  }
}

}  // namespace
}  // namespace omnislice
