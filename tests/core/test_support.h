// SPDX-License-Identifier: MIT
// Shared helpers for the C++ tests: locating ../shared/models (skip when absent, fail under CI=true),
// reading files, temp paths, independent volume and area sums, and loading a shared model read,
// prepared and placed as the pipeline does. Generated meshes are in test_meshes.h.
#pragma once
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "mesh/mesh.h"
#include "mesh/place_mesh.h"
#include "mesh/prepare_mesh.h"
#include "mesh/read_mesh.h"

namespace omnislice::test {

inline std::filesystem::path sharedModelsDir() { return OMNISLICE_SHARED_MODELS_DIR; }
inline std::filesystem::path fixturesDir() { return OMNISLICE_FIXTURES_DIR; }
inline std::filesystem::path tempDir() {
  std::filesystem::path p = OMNISLICE_TEST_TMP;
  std::filesystem::create_directories(p);
  return p;
}

inline bool underCi() {
  const char* ci = std::getenv("CI");
  return ci && std::string(ci) == "true";
}

// Use at the top of a test that needs ../shared/models: skips with a message when the folder is
// absent (a user's clone), fails when it is absent under CI=true.
#define OMNISLICE_REQUIRE_SHARED_MODELS()                                                  \
  do {                                                                                     \
    if (!std::filesystem::exists(::omnislice::test::sharedModelsDir() / "MANIFEST.md")) { \
      if (::omnislice::test::underCi()) {                                                  \
        FAIL() << "../shared/models is absent under CI=true: " << OMNISLICE_SHARED_MODELS_DIR; \
      }                                                                                    \
      GTEST_SKIP() << "../shared/models absent (" << OMNISLICE_SHARED_MODELS_DIR          \
                   << "): skipping test that needs the shared models";                     \
    }                                                                                      \
  } while (0)

inline std::vector<uint8_t> readBytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

inline std::vector<uint8_t> bytesOf(const std::string& s) {
  return std::vector<uint8_t>(s.begin(), s.end());
}

// Signed volume by the divergence theorem (sum of signed tetrahedra against the origin), written
// independently of the core's so tests can check it.
inline double meshVolume(const Mesh& m) {
  double v = 0;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    const Eigen::Vector3d a = m.vertex(m.triangles[3 * f]), b = m.vertex(m.triangles[3 * f + 1]),
                          c = m.vertex(m.triangles[3 * f + 2]);
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

// Surface area (sum of triangle areas), written independently of the core's.
inline double surfaceArea(const Mesh& m) {
  double a = 0;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    const Eigen::Vector3d p = m.vertex(m.triangles[3 * f]);
    a += (m.vertex(m.triangles[3 * f + 1]) - p).cross(m.vertex(m.triangles[3 * f + 2]) - p).norm() / 2;
  }
  return a;
}

// Whether loadModel insists on a closed manifold.
enum class Shell { Closed, MayBeOpen };

// A shared model (../shared/models/<file>) read and prepared as the pipeline does (vertices welded,
// degenerate and duplicate faces dropped, shells oriented outward; the self-intersection search,
// which only warns, is skipped), every coordinate then multiplied by `scale`. Fails the calling
// test when the file cannot be read or prepared, and with Shell::Closed when the result is not a
// closed manifold. Call OMNISLICE_REQUIRE_SHARED_MODELS() first.
inline Mesh loadModel(const std::string& file, double scale = 1.0, Shell shell = Shell::Closed) {
  const ReadMeshResult raw = readMeshFile((sharedModelsDir() / file).string());
  EXPECT_TRUE(raw.ok()) << file << ": " << raw.message;
  PrepareOptions options;
  options.checkSelfIntersections = false;
  PrepareMeshResult prepared = prepareMesh(raw.mesh, options);
  EXPECT_TRUE(prepared.ok()) << file << ": " << prepared.message;
  if (shell == Shell::Closed) {
    EXPECT_TRUE(prepared.solid.ok()) << file << ": " << prepared.solid.message;
  }
  for (double& c : prepared.mesh.positions) c *= scale;
  return prepared.mesh;
}

// loadModel(file) put on the platform as the pipeline does (placeMesh: scale or fit, up axis,
// rotations, lowest point at z = 0, centred in x and y unless placement.center is false).
inline Mesh loadPlaced(const std::string& file, const PlaceOptions& placement = {}) {
  const PlaceMeshResult placed = placeMesh(loadModel(file), placement);
  EXPECT_TRUE(placed.ok()) << file << ": " << placed.message;
  return placed.mesh;
}

// The same with the up axis and, when fitMm > 0, the largest side fitted to fitMm.
inline Mesh loadPlaced(const std::string& file, UpAxis up, double fitMm = 0) {
  PlaceOptions placement;
  placement.up = up;
  placement.fitMm = fitMm;
  return loadPlaced(file, placement);
}

}  // namespace omnislice::test
