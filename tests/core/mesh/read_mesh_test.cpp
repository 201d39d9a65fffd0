// SPDX-License-Identifier: MIT
// Mesh reader tests: the shared real models against MANIFEST.md, the same generated meshes
// written in every format and read back, and one block per malformed-input case.
#include "mesh/read_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "../test_meshes.h"
#include "../test_support.h"
#include "mesh/read_formats.h"
#include "mesh/zip_archive.h"
#include "read_mesh_writers.h"

namespace omnislice {
namespace {

using test::bytesOf;

ReadMeshResult readBytes(const std::vector<uint8_t>& b, const std::string& name) { return readMesh(b.data(), b.size(), name); }
ReadMeshResult readText(const std::string& s, const std::string& name) {
  return readMesh(reinterpret_cast<const uint8_t*>(s.data()), s.size(), name);
}

size_t distinctPositions(const Mesh& m) {
  std::set<std::tuple<double, double, double>> s;
  for (size_t i = 0; i < m.vertexCount(); ++i) s.insert({m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]});
  return s.size();
}

// ---- shared real models ------------------------------------------------------------------------

struct ManifestEntry {
  size_t vertices;    // for STL: distinct positions (MANIFEST merges bit-identical coordinates)
  size_t faces;
  bool hasBox[3];     // which axes MANIFEST gives a range for
  double lo[3], hi[3];
  double tol;         // MANIFEST rounds its bbox figures
};

const std::map<std::string, ManifestEntry>& manifest() {
  static const std::map<std::string, ManifestEntry> m = {
      {"pymdp_kitten.off", {5000, 10000, {true, true, true}, {-38.1, 0.0, -34.6}, {38.1, 116.3, 34.5}, 0.051}},
      {"voxelmaam_kitten.ply", {3444, 6888, {true, true, true}, {-32.1, -48.9, -29.2}, {32.2, 49.6, 29.2}, 0.051}},
      {"voxelmaam_platform.obj", {56, 108, {true, true, true}, {-63.75, -21.27, -63.75}, {63.75, 0.03, 63.75}, 0.0051}},
      {"compas_bunny_closed_low_res.obj", {938, 1872, {true, true, true}, {-101.4, -78.2, 0}, {101.4, 78.2, 200}, 0.051}},
      {"compas_bunny_closed_high_res.stl", {34801, 69598, {false, false, true}, {0, 0, 0}, {0, 0, 200}, 0.051}},
      // MANIFEST gives x,y[-105,105] here; an independent Python struct reader of the file gives
      // x[-105.356,105.356] y[-108.551,108.551], which is what is checked.
      {"compas_branches_70_closed_low_res.stl", {3118, 6232, {true, true, true}, {-105.356, -108.551, 0}, {105.356, 108.551, 200}, 0.0051}},
      {"compas_branches_16_closed_mid_res.stl", {25044, 50152, {true, true, true}, {-73.4, -73.4, 0}, {73.4, 73.4, 200}, 0.051}},
      {"compas_connection3legs_open_low_res.obj", {2831, 5519, {false, false, true}, {0, 0, 0}, {0, 0, 200}, 0.051}},
      {"compas_Y_shape_mesh.obj", {2014, 3942, {false, false, true}, {0, 0, 0}, {0, 0, 276.2}, 0.051}},
      {"compas_costa_surface_mesh.obj", {2695, 5135, {true, true, true}, {-200, -200, 0}, {200, 200, 340.6}, 0.051}},
      {"compas_overhang_coin_closed_low_res.stl", {80, 156, {true, true, true}, {-100, -18, 0}, {100, 18, 200}, 0.051}},
      {"nestedcages_fertility.off", {23188, 46388, {true, true, true}, {-0.22, -0.47, -0.30}, {1.0, 0.42, 0.14}, 0.0051}},
  };
  return m;
}

// Every mesh file of ../shared/models reads with MANIFEST's counts and bounding box.
TEST(ReadMeshSharedModels, EveryModelMatchesManifest) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  size_t checked = 0;
  for (const auto& de : std::filesystem::directory_iterator(test::sharedModelsDir())) {
    const std::string name = de.path().filename().string();
    const std::string ext = de.path().extension().string();
    if (ext != ".stl" && ext != ".obj" && ext != ".off" && ext != ".ply") continue;
    SCOPED_TRACE(name);
    const auto it = manifest().find(name);
    ASSERT_NE(it, manifest().end()) << "mesh file not listed in this test's copy of MANIFEST.md";
    const ManifestEntry& e = it->second;
    const ReadMeshResult r = readMeshFile(de.path().string());
    ASSERT_TRUE(r.ok()) << statusCode(r.status) << ": " << r.message;
    EXPECT_TRUE(test::indicesInRange(r.mesh));
    EXPECT_EQ(r.mesh.faceCount(), e.faces);
    if (ext == ".stl") {
      EXPECT_EQ(r.format, "stl-binary");
      EXPECT_EQ(r.mesh.vertexCount(), 3 * e.faces);  // raw STL: 3 vertices per face
      EXPECT_EQ(distinctPositions(r.mesh), e.vertices);
    } else {
      EXPECT_EQ(r.mesh.vertexCount(), e.vertices);
    }
    const BoundingBox box = boundingBox(r.mesh);
    for (int k = 0; k < 3; ++k) {
      if (!e.hasBox[k]) continue;
      EXPECT_NEAR(box.min[k], e.lo[k], e.tol) << "axis " << k;
      EXPECT_NEAR(box.max[k], e.hi[k], e.tol) << "axis " << k;
    }
    EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
    ++checked;
  }
  EXPECT_EQ(checked, manifest().size());
}

// The PLY kitten is binary little endian with float xyz and a uchar/int face list; the closed
// models have positive volume when read with the file's own orientation.
TEST(ReadMeshSharedModels, FormatsAndOrientation) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const ReadMeshResult ply = readMeshFile((test::sharedModelsDir() / "voxelmaam_kitten.ply").string());
  ASSERT_TRUE(ply.ok()) << ply.message;
  EXPECT_EQ(ply.format, "ply-binary-le");
  EXPECT_GT(test::meshVolume(ply.mesh), 0);
  const ReadMeshResult off = readMeshFile((test::sharedModelsDir() / "pymdp_kitten.off").string());
  ASSERT_TRUE(off.ok()) << off.message;
  EXPECT_EQ(off.format, "off");
  EXPECT_GT(test::meshVolume(off.mesh), 0);
  const ReadMeshResult stl = readMeshFile((test::sharedModelsDir() / "compas_bunny_closed_high_res.stl").string());
  ASSERT_TRUE(stl.ok()) << stl.message;
  EXPECT_GT(test::meshVolume(stl.mesh), 0);
}

// ---- generated round trips -----------------------------------------------------------------------

struct RoundTrip {
  std::string label;
  std::vector<uint8_t> bytes;
  std::string name;
  std::string format;
};

std::vector<RoundTrip> writeAllFormats(const test::PolyMesh& poly) {
  const Mesh tri = poly.triangulated();
  std::vector<RoundTrip> v;
  v.push_back({"binary STL", test::writeBinaryStl(tri), "m.stl", "stl-binary"});
  v.push_back({"binary STL with 'solid' header", test::writeBinaryStl(tri, "solid exported by a CAD tool"), "m.STL", "stl-binary"});
  v.push_back({"ASCII STL", bytesOf(test::writeAsciiStl(tri, 1)), "m.stl", "stl-ascii"});
  v.push_back({"ASCII STL, 3 solids", bytesOf(test::writeAsciiStl(tri, 3)), "m.stl", "stl-ascii"});
  v.push_back({"OBJ", bytesOf(test::writeObj(poly)), "m.obj", "obj"});
  v.push_back({"OFF", bytesOf(test::writeOff(poly)), "m.off", "off"});
  v.push_back({"PLY ascii", test::writePly(poly, test::PlyKind::Ascii), "m.ply", "ply-ascii"});
  v.push_back({"PLY LE", test::writePly(poly, test::PlyKind::LittleEndian), "m.ply", "ply-binary-le"});
  v.push_back({"PLY BE", test::writePly(poly, test::PlyKind::BigEndian, "ushort", "uint"), "m.ply", "ply-binary-be"});
  v.push_back({"PLY LE int8 count, uint16 index", test::writePly(poly, test::PlyKind::LittleEndian, "int8", "uint16"), "m.ply", "ply-binary-le"});
  v.push_back({"PLY BE uint count, short index", test::writePly(poly, test::PlyKind::BigEndian, "uint32", "short"), "m.ply", "ply-binary-be"});
  const std::string model = test::modelXml(test::objectXml(1, tri), "  <item objectid=\"1\"/>\n");
  v.push_back({"3MF stored", test::write3mf(model, false), "m.3mf", "3mf"});
  v.push_back({"3MF deflated", test::write3mf(model, true), "m.3mf", "3mf"});
  return v;
}

void expectSameMesh(const test::PolyMesh& poly, const RoundTrip& t) {
  SCOPED_TRACE(t.label);
  const Mesh expected = poly.triangulated();
  // Read with the file name, and with no name at all (content sniffing).
  for (const std::string& name : {t.name, std::string()}) {
    const ReadMeshResult r = readBytes(t.bytes, name);
    ASSERT_TRUE(r.ok()) << "name '" << name << "': " << statusCode(r.status) << ": " << r.message;
    EXPECT_EQ(r.format, t.format);
    EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
    EXPECT_TRUE(test::indicesInRange(r.mesh));
    EXPECT_EQ(r.mesh.faceCount(), expected.faceCount());
    // Coordinates lie on a 1/1024 grid, so every format reproduces them exactly.
    EXPECT_EQ(test::canonicalTriangles(r.mesh), test::canonicalTriangles(expected));
    EXPECT_DOUBLE_EQ(test::meshVolume(r.mesh), test::meshVolume(expected));
    if (t.format != "stl-binary" && t.format != "stl-ascii") {
      EXPECT_EQ(r.mesh.vertexCount(), expected.vertexCount());
    }
  }
}

// A few-hundred-face sphere (triangle fans at the poles, quads elsewhere) in every format.
TEST(ReadMeshRoundTrip, SphereInEveryFormat) {
  const test::PolyMesh sphere = test::makeSpherePoly(12, 16, 10.0, 3.0, -2.0, 10.0);
  const Mesh tri = sphere.triangulated();
  ASSERT_EQ(tri.faceCount(), 352u);
  // Independent check of the generator: the volume approaches 4/3 pi r^3 from below.
  const double v = test::meshVolume(tri);
  EXPECT_GT(v, 0.9 * 4.0 / 3.0 * M_PI * 1000);
  EXPECT_LT(v, 4.0 / 3.0 * M_PI * 1000);
  for (const RoundTrip& t : writeAllFormats(sphere)) expectSameMesh(sphere, t);
}

// The quad box of the test support in every format: 12 triangles, volume 6.
TEST(ReadMeshRoundTrip, BoxInEveryFormat) {
  const test::PolyMesh box = test::makeBoxPoly(-1, 0, 2, 0, 2, 5);
  EXPECT_DOUBLE_EQ(test::meshVolume(box.triangulated()), 6.0);
  for (const RoundTrip& t : writeAllFormats(box)) expectSameMesh(box, t);
  // The triangle box of test_support.h, too.
  const Mesh m = test::makeBox(0, 0, 0, 1, 2, 3);
  const ReadMeshResult r = readBytes(test::writeBinaryStl(m), "box.stl");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(test::canonicalTriangles(r.mesh), test::canonicalTriangles(m));
  EXPECT_DOUBLE_EQ(test::meshVolume(r.mesh), 6.0);
}

// A cube with 6 x 6 quads per side, as makeGridBoxPoly in tests/fixtures/make_grid_box_3mf.py.
test::PolyMesh makeGridBoxPoly() {
  const int n = 6, s = 20;
  const int faces[6][3][3] = {{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}, {{0, 0, s}, {1, 0, 0}, {0, 1, 0}},
                              {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}, {{0, s, 0}, {0, 0, 1}, {1, 0, 0}},
                              {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}}, {{s, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  test::PolyMesh m;
  for (const auto& f : faces) {
    const uint32_t base = static_cast<uint32_t>(m.positions.size() / 3);
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; j <= n; ++j) {
        for (int k = 0; k < 3; ++k) m.positions.push_back(f[0][k] + (f[1][k] * i + f[2][k] * j) * s / n);
      }
    }
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const uint32_t a = base + i * (n + 1) + j, b = base + (i + 1) * (n + 1) + j;
        m.polygons.push_back({a, b, b + 1, a + 1});
      }
    }
  }
  return m;
}

// Committed fixture made by Info-ZIP `zip -9`: a real-world deflated 3MF whose model part uses
// dynamic Huffman blocks, with a build transform (rotate 90 degrees about z, move x by 5).
TEST(ReadMeshThreeMf, ZipToolFixtureWithDynamicHuffman) {
  const std::vector<uint8_t> bytes = test::readBytes(test::fixturesDir() / "grid_box_deflated.3mf");
  ASSERT_FALSE(bytes.empty());
  const ZipDirectory dir = readZipDirectory(bytes.data(), bytes.size());
  ASSERT_TRUE(dir.ok()) << dir.message;
  bool sawDynamic = false;
  for (const ZipEntry& e : dir.entries) {
    if (e.name != "3D/3dmodel.model") continue;
    EXPECT_EQ(e.method, 8);
    // The first DEFLATE block header: bit 0 final flag, bits 1-2 type (2 = dynamic Huffman).
    const uint64_t start = e.localHeaderOffset + 30 + (bytes[e.localHeaderOffset + 26] | bytes[e.localHeaderOffset + 27] << 8) +
                           (bytes[e.localHeaderOffset + 28] | bytes[e.localHeaderOffset + 29] << 8);
    sawDynamic = ((bytes[start] >> 1) & 3) == 2;
  }
  EXPECT_TRUE(sawDynamic);
  const ReadMeshResult r = readBytes(bytes, "grid_box_deflated.3mf");
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.format, "3mf");
  Mesh expected = makeGridBoxPoly().triangulated();
  ASSERT_EQ(expected.faceCount(), 432u);
  for (size_t i = 0; i < expected.vertexCount(); ++i) {
    const double x = expected.positions[3 * i], y = expected.positions[3 * i + 1];
    expected.positions[3 * i] = 5 - y;
    expected.positions[3 * i + 1] = x;
  }
  EXPECT_EQ(test::canonicalTriangles(r.mesh), test::canonicalTriangles(expected));
  EXPECT_DOUBLE_EQ(test::meshVolume(r.mesh), 8000.0);
  const BoundingBox box = boundingBox(r.mesh);
  EXPECT_EQ(box.min, Eigen::Vector3d(-15, 0, 0));
  EXPECT_EQ(box.max, Eigen::Vector3d(5, 20, 20));
}

// Components, nested transforms, several build items and units: expected positions computed
// here from the 3MF row-vector convention x' = x*m00 + y*m10 + z*m20 + m30.
TEST(ReadMeshThreeMf, ComponentsTransformsAndUnits) {
  const Mesh box = test::makeBox(0, 0, 0, 1, 2, 3);
  // Object 1: the box. Object 2: two instances of 1 (identity, and scaled by 2 then moved).
  // Object 3: one instance of 2, rotated 90 degrees about z. Build: 3 moved, and 1 as it is.
  const std::string resources = test::objectXml(1, box) +
                                "  <object id=\"2\"><components>\n"
                                "   <component objectid=\"1\"/>\n"
                                "   <component objectid=\"1\" transform=\"2 0 0 0 2 0 0 0 2 10 0 0\"/>\n"
                                "  </components></object>\n"
                                "  <object id=\"3\"><components><component objectid=\"2\" "
                                "transform=\"0 1 0 -1 0 0 0 0 1 0 0 0\"/></components></object>\n";
  const std::string build = "  <item objectid=\"3\" transform=\"1 0 0 0 1 0 0 0 1 0 0 100\"/>\n  <item objectid=\"1\"/>\n";
  auto transformed = [](const Mesh& m, const double t[12]) {
    Mesh out = m;
    for (size_t i = 0; i < m.vertexCount(); ++i) {
      const double x = m.positions[3 * i], y = m.positions[3 * i + 1], z = m.positions[3 * i + 2];
      for (int c = 0; c < 3; ++c) out.positions[3 * i + c] = x * t[c] + y * t[3 + c] + z * t[6 + c] + t[9 + c];
    }
    return out;
  };
  const double identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  const double scaleMove[12] = {2, 0, 0, 0, 2, 0, 0, 0, 2, 10, 0, 0};
  const double rotate[12] = {0, 1, 0, -1, 0, 0, 0, 0, 1, 0, 0, 0};
  const double lift[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 100};
  std::vector<Mesh> parts = {transformed(transformed(transformed(box, identity), rotate), lift),
                             transformed(transformed(transformed(box, scaleMove), rotate), lift), box};
  for (const char* unit : {"millimeter", "inch", "micron", "centimeter", "foot", "meter"}) {
    SCOPED_TRACE(unit);
    const double scale = std::string(unit) == "inch" ? 25.4 : std::string(unit) == "micron" ? 0.001
                       : std::string(unit) == "centimeter" ? 10 : std::string(unit) == "foot" ? 304.8
                       : std::string(unit) == "meter" ? 1000 : 1;
    const ReadMeshResult r = readBytes(test::write3mf(test::modelXml(resources, build, unit), true), "scene.3mf");
    ASSERT_TRUE(r.ok()) << r.message;
    ASSERT_EQ(r.mesh.faceCount(), 36u);
    Mesh expected;
    for (const Mesh& p : parts) {
      const uint32_t base = static_cast<uint32_t>(expected.vertexCount());
      for (double v : p.positions) expected.positions.push_back(v * scale);
      for (uint32_t t : p.triangles) expected.triangles.push_back(base + t);
    }
    const auto got = test::canonicalTriangles(r.mesh), want = test::canonicalTriangles(expected);
    ASSERT_EQ(got.size(), want.size());
    for (size_t i = 0; i < got.size(); ++i) {
      for (int k = 0; k < 9; ++k) EXPECT_NEAR(got[i][k], want[i][k], 1e-9 * scale);
    }
    // Volume: 6 + 6 * 8 + 6 mm3 (rotations keep it), times the unit scale cubed.
    EXPECT_NEAR(test::meshVolume(r.mesh), 60.0 * scale * scale * scale, 1e-9 * 60 * scale * scale * scale);
  }
}

// The model part may have another name; it is found through _rels/.rels.
TEST(ReadMeshThreeMf, ModelPartFoundThroughRelationships) {
  const Mesh box = test::makeBox(0, 0, 0, 1, 1, 1);
  const std::string model = test::modelXml(test::objectXml(7, box), "<item objectid=\"7\"/>");
  const ReadMeshResult r = readBytes(test::write3mf(model, false, "3D/Objects/thing.model"), "x.3mf");
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.mesh.faceCount(), 12u);
  // Without relationships, the single .model entry is still found.
  const ReadMeshResult bare = readBytes(test::writeZip({{"meshes/only.model", model, true}}), "x.3mf");
  ASSERT_TRUE(bare.ok()) << bare.message;
  EXPECT_EQ(bare.mesh.faceCount(), 12u);
}

// Production extension: a component may reference an object in another model part (p:path).
TEST(ReadMeshThreeMf, ComponentInAnotherPart) {
  const Mesh box = test::makeBox(0, 0, 0, 1, 1, 1);
  const std::string other = test::modelXml(test::objectXml(1, box), "");
  const std::string root = test::modelXml(
      "<object id=\"5\"><components><component xmlns:p=\"http://schemas.microsoft.com/3dmanufacturing/production/2015/06\" "
      "p:path=\"/3D/Objects/other.model\" objectid=\"1\" transform=\"1 0 0 0 1 0 0 0 1 0 0 7\"/></components></object>",
      "<item objectid=\"5\"/>");
  const std::vector<uint8_t> bytes = test::writeZip({{"[Content_Types].xml", test::kContentTypes, true},
                                                     {"_rels/.rels", test::relsFor("/3D/3dmodel.model"), false},
                                                     {"3D/3dmodel.model", root, true},
                                                     {"3D/Objects/other.model", other, true}});
  const ReadMeshResult r = readBytes(bytes, "p.3mf");
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.mesh.faceCount(), 12u);
  const BoundingBox b = boundingBox(r.mesh);
  EXPECT_EQ(b.min, Eigen::Vector3d(0, 0, 7));
  EXPECT_EQ(b.max, Eigen::Vector3d(1, 1, 8));
}

// Non-finite coordinates are read as they are (validation reports them later).
TEST(ReadMeshValues, NonFiniteCoordinatesKept) {
  const std::string stl = "solid s\nfacet normal 0 0 1\nouter loop\nvertex nan 0 0\nvertex 1 inf 0\nvertex 0 1 -INF\n"
                          "endloop\nendfacet\nendsolid s\n";
  const ReadMeshResult a = readText(stl, "nan.stl");
  ASSERT_TRUE(a.ok()) << a.message;
  EXPECT_TRUE(std::isnan(a.mesh.positions[0]));
  EXPECT_EQ(a.mesh.positions[4], std::numeric_limits<double>::infinity());
  EXPECT_EQ(a.mesh.positions[8], -std::numeric_limits<double>::infinity());
  Mesh m = test::makeBox(0, 0, 0, 1, 1, 1);
  m.positions[0] = std::numeric_limits<double>::quiet_NaN();
  const ReadMeshResult b = readBytes(test::writeBinaryStl(m), "nan.stl");
  ASSERT_TRUE(b.ok());
  size_t nans = 0;
  for (double v : b.mesh.positions) nans += std::isnan(v);
  EXPECT_EQ(nans, 5u);  // vertex 0 of makeBox is used by 5 triangles
  const ReadMeshResult c = readText("v NaN 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "nan.obj");
  ASSERT_TRUE(c.ok());
  EXPECT_TRUE(std::isnan(c.mesh.positions[0]));
}

// Text numbers are correctly rounded, whatever their spelling.
TEST(ReadMeshValues, NumberSpellings) {
  const std::string obj = "v 0.1 -2.5e-3 1E+2\nv .5 7. +3\nv 123456789012345678901234 1e-310 -0.0\nf 1 2 3\n";
  const ReadMeshResult r = readText(obj, "n.obj");
  ASSERT_TRUE(r.ok()) << r.message;
  const std::vector<double> want = {0.1, -2.5e-3, 100, 0.5, 7, 3, 123456789012345678901234.0, 1e-310, -0.0};
  for (size_t i = 0; i < want.size(); ++i) EXPECT_EQ(r.mesh.positions[i], want[i]) << i;
  EXPECT_TRUE(std::signbit(r.mesh.positions[8]));
}

// The extension picks the format; clearly different content wins, with a warning.
TEST(ReadMeshFormat, ExtensionAndSniffing) {
  const test::PolyMesh box = test::makeBoxPoly(0, 0, 0, 1, 1, 1);
  const std::vector<uint8_t> ply = test::writePly(box, test::PlyKind::LittleEndian);
  const ReadMeshResult a = readBytes(ply, "model.stl");
  ASSERT_TRUE(a.ok()) << a.message;
  EXPECT_EQ(a.format, "ply-binary-le");
  ASSERT_FALSE(a.warnings.empty());
  EXPECT_NE(a.warnings[0].find("content is PLY"), std::string::npos) << a.warnings[0];
  // An ASCII STL named .stl is ASCII whatever its header, and a binary STL named .obj is STL.
  const Mesh tri = box.triangulated();
  EXPECT_EQ(readText(test::writeAsciiStl(tri), "x.STL").format, "stl-ascii");
  const ReadMeshResult b = readBytes(test::writeBinaryStl(tri, "solid looks like text"), "x.obj");
  EXPECT_EQ(b.format, "stl-binary");
  EXPECT_TRUE(b.ok());
  // OBJ text named .stl is read as OBJ, with a warning.
  const ReadMeshResult c = readText(test::writeObj(box), "model.stl");
  ASSERT_TRUE(c.ok()) << c.message;
  EXPECT_EQ(c.format, "obj");
  EXPECT_EQ(c.mesh.faceCount(), 12u);
  EXPECT_FALSE(c.warnings.empty());
  // Extension in any case, path with dots in folder names.
  EXPECT_EQ(readText(test::writeOff(box), "/tmp/a.b/c.OfF").format, "off");
  // No extension: sniffed from content.
  EXPECT_EQ(readText(test::writeObj(box), "noext").format, "obj");
  EXPECT_EQ(readText(test::writeOff(box), "").format, "off");
  EXPECT_EQ(readBytes(test::write3mf(test::modelXml(test::objectXml(1, tri), "<item objectid=\"1\"/>"), false), "").format, "3mf");
}

// ---- malformed input: one block per case ---------------------------------------------------------

TEST(ReadMeshMalformed, General) {
  // No bytes at all.
  EXPECT_EQ(readMesh(nullptr, 0, "a.stl").status, Status::EmptyInput);
  EXPECT_EQ(readText("", "").status, Status::EmptyInput);
  // Content of no known format, without and with an unknown extension.
  EXPECT_EQ(readText("hello world, this is not a mesh\n", "").status, Status::UnsupportedFormat);
  EXPECT_EQ(readText("hello world, this is not a mesh\n", "notes.txt").status, Status::UnsupportedFormat);
  std::vector<uint8_t> noise(300);
  for (size_t i = 0; i < noise.size(); ++i) noise[i] = static_cast<uint8_t>((i * 7919 + 13) % 251);
  EXPECT_EQ(readBytes(noise, "blob.bin").status, Status::UnsupportedFormat);
  // A missing file: IoError naming the path.
  const ReadMeshResult r = readMeshFile("/nonexistent/dir/model.stl");
  EXPECT_EQ(r.status, Status::IoError);
  EXPECT_NE(r.message.find("/nonexistent/dir/model.stl"), std::string::npos);
  // A folder is not a readable file.
  EXPECT_EQ(readMeshFile(test::tempDir().string()).status, Status::IoError);
}

TEST(ReadMeshMalformed, Stl) {
  const Mesh box = test::makeBox(0, 0, 0, 1, 1, 1);
  const std::vector<uint8_t> good = test::writeBinaryStl(box);
  {  // Binary: header declares 12 triangles, only 10 present -> TruncatedFile.
    std::vector<uint8_t> b(good.begin(), good.end() - 100);
    const ReadMeshResult r = readBytes(b, "t.stl");
    EXPECT_EQ(r.status, Status::TruncatedFile);
    EXPECT_NE(r.message.find("12"), std::string::npos) << r.message;
    EXPECT_TRUE(r.mesh.empty());
  }
  {  // Binary: more data than declared -> the declared count is read, with a warning.
    std::vector<uint8_t> b = good;
    b[80] = 10;
    const ReadMeshResult r = readBytes(b, "t.stl");
    ASSERT_EQ(r.status, Status::Ok);
    EXPECT_EQ(r.mesh.faceCount(), 10u);
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_NE(r.warnings[0].find("10"), std::string::npos);
  }
  {  // Binary: header only, zero triangles -> EmptyInput.
    std::vector<uint8_t> b(good.begin(), good.begin() + 84);
    b[80] = 0;
    EXPECT_EQ(readBytes(b, "t.stl").status, Status::EmptyInput);
  }
  {  // Binary: shorter than the 84-byte header -> TruncatedFile.
    std::vector<uint8_t> b(good.begin(), good.begin() + 50);
    EXPECT_EQ(readBytes(b, "t.stl").status, Status::TruncatedFile);
  }
  const std::string ascii = test::writeAsciiStl(box);
  {  // ASCII: cut inside a facet -> TruncatedFile.
    EXPECT_EQ(readText(ascii.substr(0, ascii.find("outer loop", ascii.size() / 2) + 6), "t.stl").status, Status::TruncatedFile);
    EXPECT_EQ(readText(ascii.substr(0, ascii.find("vertex", ascii.size() / 2) + 9), "t.stl").status, Status::TruncatedFile);
  }
  {  // ASCII: a bad number -> ParseError naming the line.
    const ReadMeshResult r = readText("solid x\nfacet normal 0 0 1\nouter loop\nvertex 1 2 3\nvertex 1 2 abc\n", "t.stl");
    EXPECT_EQ(r.status, Status::ParseError);
    EXPECT_NE(r.message.find("line 5"), std::string::npos) << r.message;
  }
  {  // ASCII: unknown keyword where a facet should start -> ParseError.
    EXPECT_EQ(readText("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
                       "endfacet\nbanana\nendsolid\n", "t.stl").status,
              Status::ParseError);
  }
  {  // ASCII: a loop with two vertices -> ParseError.
    EXPECT_EQ(readText("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n",
                       "t.stl").status,
              Status::ParseError);
  }
  {  // ASCII: a solid without facets -> EmptyInput.
    EXPECT_EQ(readText("solid empty\nendsolid empty\n", "t.stl").status, Status::EmptyInput);
  }
  {  // ASCII: missing endsolid after complete facets -> read, with a warning.
    const ReadMeshResult r = readText(ascii.substr(0, ascii.rfind("endsolid")), "t.stl");
    EXPECT_EQ(r.status, Status::Ok);
    EXPECT_EQ(r.mesh.faceCount(), 12u);
    EXPECT_FALSE(r.warnings.empty());
  }
  {  // Binary garbage named .stl, not a multiple of the record size -> TruncatedFile or ParseError, never Ok.
    std::vector<uint8_t> b(1000, 0xAB);
    EXPECT_NE(readBytes(b, "t.stl").status, Status::Ok);
  }
}

TEST(ReadMeshMalformed, Obj) {
  {  // Index beyond the vertices -> ParseError with the line number.
    const ReadMeshResult r = readText("v 0 0 0\nv 1 0 0\nv 0 1 0\n# comment\nf 1 2 4\n", "t.obj");
    EXPECT_EQ(r.status, Status::ParseError);
    EXPECT_NE(r.message.find("line 5"), std::string::npos) << r.message;
  }
  {  // Forward reference resolved by vertices defined later is accepted; a dangling one is not.
    EXPECT_EQ(readText("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "t.obj").status, Status::Ok);
    const ReadMeshResult r = readText("f 1 2 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "t.obj");
    EXPECT_EQ(r.status, Status::ParseError);
    EXPECT_NE(r.message.find("line 1"), std::string::npos) << r.message;
  }
  {  // A line continuation joins lines, and later errors still name the physical line.
    const ReadMeshResult ok = readText("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 \\\n 2 3\n", "t.obj");
    ASSERT_TRUE(ok.ok()) << ok.message;
    EXPECT_EQ(ok.mesh.faceCount(), 1u);
    const ReadMeshResult r = readText("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 \\\r\n 2 3\nf 1 2 9\n", "t.obj");
    EXPECT_EQ(r.status, Status::ParseError);
    EXPECT_NE(r.message.find("line 6"), std::string::npos) << r.message;
  }
  {  // Index 0 -> ParseError.
    EXPECT_EQ(readText("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "t.obj").status, Status::ParseError);
  }
  {  // Relative index reaching before the first vertex -> ParseError.
    EXPECT_EQ(readText("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", "t.obj").status, Status::ParseError);
  }
  {  // Bad coordinate, missing coordinate, bad index text -> ParseError.
    EXPECT_EQ(readText("v 0 0 x\n", "t.obj").status, Status::ParseError);
    EXPECT_EQ(readText("v 0 0\n", "t.obj").status, Status::ParseError);
    EXPECT_EQ(readText("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3a\n", "t.obj").status, Status::ParseError);
  }
  {  // Only vertices -> EmptyInput.
    EXPECT_EQ(readText("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "t.obj").status, Status::EmptyInput);
  }
  {  // Binary bytes named .obj -> ParseError.
    std::vector<uint8_t> b = {0x01, 0x02, 0xff, 0x00, '\n', 'v'};
    EXPECT_EQ(readBytes(b, "t.obj").status, Status::ParseError);
  }
}

TEST(ReadMeshMalformed, Off) {
  {  // Fewer vertices than declared -> TruncatedFile.
    EXPECT_EQ(readText("OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n", "t.off").status, Status::TruncatedFile);
  }
  {  // Fewer faces than declared -> TruncatedFile.
    EXPECT_EQ(readText("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "t.off").status, Status::TruncatedFile);
  }
  {  // A face cut short -> TruncatedFile.
    EXPECT_EQ(readText("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1", "t.off").status, Status::TruncatedFile);
  }
  {  // Index out of range -> ParseError naming the line.
    const ReadMeshResult r = readText("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "t.off");
    EXPECT_EQ(r.status, Status::ParseError);
    EXPECT_NE(r.message.find("line 6"), std::string::npos) << r.message;
  }
  {  // Bad counts and bad coordinates -> ParseError.
    EXPECT_EQ(readText("OFF\nthree 1 0\n", "t.off").status, Status::ParseError);
    EXPECT_EQ(readText("OFF\n3 1 0\n0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", "t.off").status, Status::ParseError);
  }
  {  // No faces -> EmptyInput; header-less OFF with comments is accepted.
    EXPECT_EQ(readText("OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", "t.off").status, Status::EmptyInput);
    EXPECT_EQ(readText("# comment\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "t.off").status, Status::Ok);
  }
  {  // 4D OFF and binary OFF are recognised but not supported.
    EXPECT_EQ(readText("4OFF\n1 0 0\n0 0 0 0\n", "t.off").status, Status::UnsupportedFormat);
    EXPECT_EQ(readText("OFF BINARY\n", "t.off").status, Status::UnsupportedFormat);
  }
}

TEST(ReadMeshMalformed, Ply) {
  const test::PolyMesh box = test::makeBoxPoly(0, 0, 0, 1, 1, 1);
  {  // Binary data cut short -> TruncatedFile.
    const std::vector<uint8_t> b = test::writePly(box, test::PlyKind::LittleEndian);
    EXPECT_EQ(readBytes(std::vector<uint8_t>(b.begin(), b.end() - 7), "t.ply").status, Status::TruncatedFile);
  }
  {  // ASCII data cut short -> TruncatedFile.
    const std::vector<uint8_t> b = test::writePly(box, test::PlyKind::Ascii);
    EXPECT_EQ(readBytes(std::vector<uint8_t>(b.begin(), b.end() - 15), "t.ply").status, Status::TruncatedFile);
  }
  {  // Header without end_header -> TruncatedFile.
    EXPECT_EQ(readText("ply\nformat ascii 1.0\nelement vertex 3\n", "t.ply").status, Status::TruncatedFile);
  }
  {  // Unknown property type, unknown format -> ParseError.
    EXPECT_EQ(readText("ply\nformat ascii 1.0\nelement vertex 1\nproperty real x\nend_header\n1\n", "t.ply").status,
              Status::ParseError);
    EXPECT_EQ(readText("ply\nformat binary_middle_endian 1.0\nend_header\n", "t.ply").status, Status::ParseError);
  }
  {  // Face element without vertex_indices, vertex element without z -> ParseError.
    EXPECT_EQ(readText("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                       "element face 1\nproperty list uchar int corners\nend_header\n3 0 1 2\n", "t.ply").status,
              Status::ParseError);
    EXPECT_EQ(readText("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
                       "t.ply").status,
              Status::ParseError);
  }
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  {  // A header keyword the standard does not define is skipped with a warning; the mesh reads.
    const ReadMeshResult r = readText("ply\nformat ascii 1.0\ntexturefile skin.png\nelement vertex 3\nproperty float x\n"
                                      "property float y\nproperty float z\nelement face 1\n"
                                      "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                                      "t.ply");
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_EQ(r.mesh.faceCount(), 1u);
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_EQ(r.warnings[0], "PLY header line 3: skipped the unknown keyword 'texturefile'");
  }
  {  // Index out of range, and a negative index -> ParseError.
    EXPECT_EQ(readText(head + "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
                       "t.ply").status,
              Status::ParseError);
    EXPECT_EQ(readText(head + "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n",
                       "t.ply").status,
              Status::ParseError);
  }
  {  // Point cloud (no faces) -> EmptyInput.
    EXPECT_EQ(readText(head + "end_header\n0 0 0\n1 0 0\n0 1 0\n", "t.ply").status, Status::EmptyInput);
  }
  {  // Binary list with a huge count -> TruncatedFile, without a huge allocation.
    std::string h = "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n";
    std::vector<uint8_t> b = bytesOf(h);
    test::putLe(b, 0xFFFFFFF0u, 4);
    test::putLe(b, 0, 4);
    EXPECT_EQ(readBytes(b, "t.ply").status, Status::TruncatedFile);
  }
  {  // An element without properties and a gigantic count holds no data: no hang, faces still read.
    const ReadMeshResult r = readText(head + "element nothing 999999999999999\nelement face 1\n"
                                      "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "t.ply");
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_EQ(r.mesh.faceCount(), 1u);
  }
  {  // Element count far beyond the data -> TruncatedFile.
    std::string h = "ply\nformat binary_big_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
                    "property float z\nend_header\n";
    EXPECT_EQ(readText(h + "abcdefghijkl", "t.ply").status, Status::TruncatedFile);
  }
}

TEST(ReadMeshMalformed, ThreeMf) {
  const Mesh box = test::makeBox(0, 0, 0, 1, 1, 1);
  const std::string model = test::modelXml(test::objectXml(1, box), "<item objectid=\"1\"/>");
  const std::vector<uint8_t> good = test::write3mf(model, true);
  {  // Zip cut short (end of central directory lost) -> TruncatedFile.
    EXPECT_EQ(readBytes(std::vector<uint8_t>(good.begin(), good.begin() + good.size() / 2), "t.3mf").status,
              Status::TruncatedFile);
  }
  {  // Not a zip at all -> ParseError.
    EXPECT_EQ(readText("<model></model>", "t.3mf").status, Status::ParseError);
  }
  {  // Mismatched XML tags -> ParseError.
    std::string bad = model;
    bad.replace(bad.find("</vertices>"), 11, "</vertexes>");
    EXPECT_EQ(readBytes(test::write3mf(bad, false), "t.3mf").status, Status::ParseError);
  }
  {  // Unterminated attribute -> ParseError.
    std::string bad = model;
    bad.erase(bad.rfind("</model>"));
    bad += "<x a=\"1";
    EXPECT_EQ(readBytes(test::write3mf(bad, true), "t.3mf").status, Status::ParseError);
  }
  {  // Corrupted compressed data -> ParseError (invalid code or CRC mismatch), not a crash.
    std::vector<uint8_t> b = good;
    const size_t modelAt = std::string(b.begin(), b.end()).find("3D/3dmodel.model") + 16;
    for (size_t i = modelAt + 20; i < modelAt + 60; ++i) b[i] ^= 0x5A;
    const Status s = readBytes(b, "t.3mf").status;
    EXPECT_TRUE(s == Status::ParseError || s == Status::TruncatedFile) << statusCode(s);
  }
  {  // Triangle index out of range -> ParseError.
    std::string bad = model;
    bad.replace(bad.find("v3=\"1\""), 6, "v3=\"8\"");
    const ReadMeshResult r = readBytes(test::write3mf(bad, false), "t.3mf");
    EXPECT_EQ(r.status, Status::ParseError);
    EXPECT_NE(r.message.find("out of range"), std::string::npos) << r.message;
  }
  {  // Vertex without z -> ParseError.
    std::string bad = model;
    bad.replace(bad.find(" z=\"0\""), 6, "");
    EXPECT_EQ(readBytes(test::write3mf(bad, false), "t.3mf").status, Status::ParseError);
  }
  {  // Build item naming an unknown object, and a component cycle -> ParseError.
    EXPECT_EQ(readBytes(test::write3mf(test::modelXml(test::objectXml(1, box), "<item objectid=\"5\"/>"), false), "t.3mf").status,
              Status::ParseError);
    const std::string cycle = "<object id=\"2\"><components><component objectid=\"3\"/></components></object>"
                              "<object id=\"3\"><components><component objectid=\"2\"/></components></object>";
    EXPECT_EQ(readBytes(test::write3mf(test::modelXml(cycle, "<item objectid=\"2\"/>"), false), "t.3mf").status,
              Status::ParseError);
  }
  {  // Zip without any model part -> ParseError.
    EXPECT_EQ(readBytes(test::writeZip({{"readme.txt", "hello", false}}), "t.3mf").status, Status::ParseError);
  }
  {  // Unsupported compression method (e.g. 12 = bzip2) -> UnsupportedFormat.
    std::vector<uint8_t> b = test::write3mf(model, false);
    for (size_t i = 0; i + 4 < b.size(); ++i) {
      if (b[i] == 'P' && b[i + 1] == 'K' && b[i + 2] == 1 && b[i + 3] == 2) b[i + 10] = 12;  // central entries
    }
    EXPECT_EQ(readBytes(b, "t.3mf").status, Status::UnsupportedFormat);
  }
  {  // An object without triangles -> EmptyInput.
    const std::string empty = test::modelXml("<object id=\"1\"><mesh><vertices/><triangles/></mesh></object>",
                                             "<item objectid=\"1\"/>");
    EXPECT_EQ(readBytes(test::write3mf(empty, true), "t.3mf").status, Status::EmptyInput);
  }
}

}  // namespace
}  // namespace omnislice
