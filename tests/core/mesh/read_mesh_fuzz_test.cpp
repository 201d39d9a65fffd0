// SPDX-License-Identifier: MIT
// Robustness of the mesh readers: random bytes, every truncation of a small file of each format,
// and random byte corruption. Each call must return a status (no crash, no hang; run under
// -DOMNISLICE_SANITIZE=ON as well), and an Ok result must be a well-formed mesh.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "../test_support.h"
#include "mesh/read_mesh.h"
#include "read_mesh_writers.h"

namespace omnislice {
namespace {

const char* const kNames[] = {"", "f.stl", "f.obj", "f.off", "f.ply", "f.3mf", "f.dat"};

void expectWellFormed(const ReadMeshResult& r, const std::string& what) {
  if (r.ok()) {
    EXPECT_FALSE(r.mesh.empty()) << what;
    EXPECT_TRUE(test::indicesInRange(r.mesh)) << what;
    EXPECT_TRUE(r.message.empty()) << what;
  } else {
    EXPECT_TRUE(r.mesh.empty()) << what;
    EXPECT_FALSE(r.message.empty()) << what << " status " << statusCode(r.status);
  }
}

struct Sample {
  std::string label;
  std::string name;
  std::vector<uint8_t> bytes;
  bool everyPrefixFails;  // formats whose end is declared up front (counts, sizes, zip directory)
};

std::vector<Sample> samples() {
  const test::PolyMesh box = test::makeBoxPoly(0, 0, 0, 1, 2, 3);
  const Mesh tri = box.triangulated();
  const std::string model = test::modelXml(test::objectXml(1, tri), "<item objectid=\"1\" transform=\"1 0 0 0 1 0 0 0 1 1 2 3\"/>");
  std::string offText = test::writeOff(box);
  offText.pop_back();  // no final newline: the last colour value ends the file
  return {
      {"binary STL", "f.stl", test::writeBinaryStl(tri, "solid header"), true},
      {"ASCII STL", "f.stl", test::bytesOf(test::writeAsciiStl(tri, 2)), false},
      {"OBJ", "f.obj", test::bytesOf(test::writeObj(box)), false},
      {"OFF", "f.off", test::bytesOf(offText), false},
      {"PLY ascii", "f.ply", test::writePly(box, test::PlyKind::Ascii), false},
      {"PLY LE", "f.ply", test::writePly(box, test::PlyKind::LittleEndian), true},
      {"PLY BE", "f.ply", test::writePly(box, test::PlyKind::BigEndian, "uint16", "uint8"), true},
      {"3MF stored", "f.3mf", test::write3mf(model, false), true},
      {"3MF deflated", "f.3mf", test::write3mf(model, true), true},
  };
}

// Random bytes under every name hint, and random bytes behind each format's magic.
TEST(ReadMeshFuzz, RandomBytes) {
  std::mt19937 rng(12345);
  const std::vector<std::string> prefixes = {"", "solid x\n", "ply\nformat binary_little_endian 1.0\n", "OFF\n",
                                             std::string("PK\x03\x04", 4), "v 1 2 3\nf "};
  for (int i = 0; i < 400; ++i) {
    std::vector<uint8_t> b = test::bytesOf(prefixes[i % prefixes.size()]);
    const size_t n = rng() % 600;
    for (size_t k = 0; k < n; ++k) b.push_back(static_cast<uint8_t>(rng()));
    for (const char* name : kNames) expectWellFormed(readMesh(b.data(), b.size(), name), "random " + std::to_string(i) + " " + name);
  }
}

// Every prefix of a small file of each format returns a status; for formats that declare their
// extent up front, every strict prefix fails.
TEST(ReadMeshFuzz, EveryTruncation) {
  for (const Sample& s : samples()) {
    SCOPED_TRACE(s.label);
    const ReadMeshResult full = readMesh(s.bytes.data(), s.bytes.size(), s.name);
    ASSERT_TRUE(full.ok()) << full.message;
    EXPECT_EQ(full.mesh.faceCount(), 12u);
    for (size_t n = 0; n < s.bytes.size(); ++n) {
      const ReadMeshResult r = readMesh(s.bytes.data(), n, s.name);
      expectWellFormed(r, s.label + " prefix " + std::to_string(n));
      if (s.everyPrefixFails) {
        EXPECT_FALSE(r.ok()) << "prefix " << n;
      }
      if (r.ok()) {
        EXPECT_LE(r.mesh.faceCount(), 12u);
      }
    }
  }
}

// Random corruption (byte flips, inserted and deleted bytes) of each format.
TEST(ReadMeshFuzz, Corruption) {
  std::mt19937 rng(777);
  for (const Sample& s : samples()) {
    SCOPED_TRACE(s.label);
    for (int i = 0; i < 300; ++i) {
      std::vector<uint8_t> b = s.bytes;
      const int edits = 1 + static_cast<int>(rng() % 4);
      for (int e = 0; e < edits && !b.empty(); ++e) {
        const size_t at = rng() % b.size();
        switch (rng() % 3) {
          case 0: b[at] = static_cast<uint8_t>(rng()); break;
          case 1: b.insert(b.begin() + at, static_cast<uint8_t>(rng())); break;
          default: b.erase(b.begin() + at); break;
        }
      }
      expectWellFormed(readMesh(b.data(), b.size(), s.name), s.label + " mutation " + std::to_string(i));
      expectWellFormed(readMesh(b.data(), b.size(), ""), s.label + " mutation (no name) " + std::to_string(i));
    }
  }
}

}  // namespace
}  // namespace omnislice
