// SPDX-License-Identifier: MIT
// DEFLATE decoder tests: stored and fixed-Huffman streams from the test-side encoder, dynamic
// Huffman streams from the committed zip fixture and (when the tool exists) from gzip, and
// one block per kind of corrupt stream.
#include "mesh/inflate.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "../test_support.h"
#include "mesh/zip_archive.h"
#include "read_mesh_writers.h"

namespace omnislice {
namespace {

std::vector<uint8_t> sampleText(size_t n, unsigned seed) {
  // Words from a small vocabulary: compressible, with matches at many distances and lengths.
  static const char* words[] = {"vertex", "triangle", "<", "/>", " x=\"", "\"", "0.125", "12", "-3.5", "\n", "  ", "object"};
  std::mt19937 rng(seed);
  std::string s;
  while (s.size() < n) s += words[rng() % 12];
  s.resize(n);
  return std::vector<uint8_t>(s.begin(), s.end());
}

std::vector<uint8_t> randomBytes(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> v(n);
  for (uint8_t& b : v) b = static_cast<uint8_t>(rng());
  return v;
}

TEST(ReadMeshInflate, Crc32KnownValue) {
  const std::string s = "123456789";
  EXPECT_EQ(crc32(reinterpret_cast<const uint8_t*>(s.data()), s.size()), 0xCBF43926u);
  EXPECT_EQ(crc32(nullptr, 0), 0u);
}

// Stored and fixed-Huffman blocks (with overlapping copies: runs of one byte) round trip.
TEST(ReadMeshInflate, FixedAndStoredBlocksRoundTrip) {
  std::vector<std::vector<uint8_t>> inputs = {sampleText(50000, 1), randomBytes(20000, 2), std::vector<uint8_t>(9000, 'a'),
                                              std::vector<uint8_t>{'x'}};
  std::vector<uint8_t> mixed = sampleText(10000, 3);
  const std::vector<uint8_t> noise = randomBytes(5000, 4);
  mixed.insert(mixed.end(), noise.begin(), noise.end());
  inputs.push_back(mixed);
  for (const auto& in : inputs) {
    for (size_t block : {size_t{100}, size_t{4000}, size_t{70000}}) {
      const std::vector<uint8_t> z = test::deflateFixed(in, block);
      const InflateResult r = inflateRaw(z.data(), z.size(), in.size());
      ASSERT_TRUE(r.ok()) << r.message << " (input " << in.size() << " bytes, block " << block << ")";
      EXPECT_EQ(r.data, in);
      EXPECT_EQ(r.consumed, z.size());
    }
  }
  // Compression really happened on the repetitive inputs (so matches were decoded).
  EXPECT_LT(test::deflateFixed(std::vector<uint8_t>(9000, 'a'), 70000).size(), 200u);
}

// Dynamic-Huffman streams written by gzip, when the tool is installed.
TEST(ReadMeshInflate, GzipDynamicBlocks) {
  if (std::system("command -v gzip > /dev/null 2>&1") != 0) GTEST_SKIP() << "gzip not installed";
  const std::string in = (test::tempDir() / "inflate_sample.txt").string();
  const std::vector<uint8_t> text = sampleText(300000, 7);
  {
    std::FILE* f = std::fopen(in.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    std::fwrite(text.data(), 1, text.size(), f);
    std::fclose(f);
  }
  for (const char* level : {"-1", "-6", "-9"}) {
    const std::string out = in + level + ".gz";
    ASSERT_EQ(std::system(("gzip -n -c " + std::string(level) + " " + in + " > " + out).c_str()), 0);
    const std::vector<uint8_t> gz = test::readBytes(out);
    // gzip member: 10-byte header (no name with -n), DEFLATE data, CRC-32, size.
    ASSERT_GT(gz.size(), 18u);
    ASSERT_EQ(gz[0], 0x1f);
    ASSERT_EQ(gz[3] & 0x1e, 0);  // no extra fields, name or comment
    EXPECT_EQ((gz[10] >> 1) & 3, 2) << "expected a dynamic Huffman first block";
    const InflateResult r = inflateRaw(gz.data() + 10, gz.size() - 18, text.size());
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_EQ(r.data, text);
    EXPECT_EQ(r.consumed, gz.size() - 18);
    const uint32_t crc = gz[gz.size() - 8] | gz[gz.size() - 7] << 8 | gz[gz.size() - 6] << 16 | uint32_t{gz[gz.size() - 5]} << 24;
    EXPECT_EQ(crc32(r.data.data(), r.data.size()), crc);
  }
}

// The zip fixture's entries inflate to the sizes and CRCs its directory declares.
TEST(ReadMeshInflate, ZipFixtureEntries) {
  const std::vector<uint8_t> zip = test::readBytes(test::fixturesDir() / "grid_box_deflated.3mf");
  const ZipDirectory dir = readZipDirectory(zip.data(), zip.size());
  ASSERT_TRUE(dir.ok()) << dir.message;
  ASSERT_EQ(dir.entries.size(), 3u);
  for (const ZipEntry& e : dir.entries) {
    const ZipExtractResult x = extractZipEntry(zip.data(), zip.size(), e);
    ASSERT_TRUE(x.ok()) << x.message;
    EXPECT_EQ(x.data.size(), e.uncompressedSize);
    EXPECT_EQ(crc32(x.data.data(), x.data.size()), e.crc);
  }
}

TEST(ReadMeshInflate, CorruptStreams) {
  const std::vector<uint8_t> text = sampleText(20000, 5);
  const std::vector<uint8_t> z = test::deflateFixed(text, 5000);
  {  // Every truncation: never Ok, and never a crash.
    for (size_t n = 0; n < z.size(); ++n) {
      const InflateResult r = inflateRaw(z.data(), n, text.size());
      ASSERT_FALSE(r.ok()) << "prefix " << n;
      EXPECT_TRUE(r.status == Status::TruncatedFile || r.status == Status::ParseError) << statusCode(r.status);
      EXPECT_TRUE(r.data.empty());
    }
  }
  {  // Block type 3 is reserved -> ParseError.
    const uint8_t b[] = {0x07, 0, 0, 0};
    EXPECT_EQ(inflateRaw(b, sizeof b, 100).status, Status::ParseError);
  }
  {  // Stored block whose LEN and NLEN disagree -> ParseError.
    const uint8_t b[] = {0x01, 0x05, 0x00, 0x00, 0x00, 'h', 'e', 'l', 'l', 'o'};
    EXPECT_EQ(inflateRaw(b, sizeof b, 100).status, Status::ParseError);
  }
  {  // Stored block longer than the data -> TruncatedFile.
    const uint8_t b[] = {0x01, 0x05, 0x00, 0xFA, 0xFF, 'h', 'e'};
    EXPECT_EQ(inflateRaw(b, sizeof b, 100).status, Status::TruncatedFile);
  }
  {  // A match reaching before the start of the output -> ParseError.
    test::BitWriter w;
    w.bits(1, 1);
    w.bits(1, 2);
    test::fixedLiteral(w, 'a');
    test::fixedLiteral(w, 257);  // length 3
    w.huffman(4, 5);             // distance code 4: 5..6
    w.bits(1, 1);                // distance 6 > 1 byte of output
    test::fixedLiteral(w, 256);
    EXPECT_EQ(inflateRaw(w.out.data(), w.out.size(), 100).status, Status::ParseError);
  }
  {  // More output than the declared maximum -> ParseError.
    EXPECT_EQ(inflateRaw(z.data(), z.size(), text.size() - 1).status, Status::ParseError);
  }
  {  // Random bytes -> some status, no crash.
    for (unsigned seed = 0; seed < 300; ++seed) {
      const std::vector<uint8_t> b = randomBytes(1 + seed % 97, seed);
      const InflateResult r = inflateRaw(b.data(), b.size(), 1 << 16);
      if (r.ok()) {
        EXPECT_LE(r.data.size(), size_t{1} << 16);
      }
    }
  }
}

}  // namespace
}  // namespace omnislice
