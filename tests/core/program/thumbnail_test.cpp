// SPDX-License-Identifier: MIT
// Thumbnails for printer hosts (issue 30 item 4): the PNG encoder against an independent decoder
// written here (chunk CRCs by a bitwise CRC-32, the zlib stream through the 3MF inflater, Adler-32
// recomputed, all five PNG row filters undone), the rasteriser against projected areas computed
// from the geometry, and the G-code block against PrusaSlicer's format, with the rest of the
// program unchanged.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "../test_meshes.h"
#include "../pipeline/pipeline_fixtures.h"
#include "../test_support.h"
#include "mesh/inflate.h"
#include "pipeline/pipeline.h"
#include "program/png.h"
#include "program/read_program.h"
#include "program/thumbnail.h"

namespace omnislice {
namespace {

uint32_t bitwiseCrc(const uint8_t* d, size_t n) {
  uint32_t c = 0xffffffffu;
  for (size_t i = 0; i < n; ++i) {
    c ^= d[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return ~c;
}

uint32_t be32(const uint8_t* p) { return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | p[3]; }

// The zlib stream's payload, checked: header, then the raw DEFLATE inflated, then its Adler-32.
std::vector<uint8_t> unzlib(const std::vector<uint8_t>& z, size_t expected) {
  EXPECT_GE(z.size(), 6u);
  if (z.size() < 6) return {};
  EXPECT_EQ(z[0] & 0x0f, 8) << "deflate";
  EXPECT_EQ((z[0] * 256 + z[1]) % 31, 0) << "FCHECK";
  const InflateResult r = inflateRaw(z.data() + 2, z.size() - 6, expected + 1);
  EXPECT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.consumed, z.size() - 6);
  uint64_t a = 1, b = 0;
  for (uint8_t v : r.data) {
    a = (a + v) % 65521;
    b = (b + a) % 65521;
  }
  EXPECT_EQ(be32(z.data() + z.size() - 4), uint32_t((b << 16) | a)) << "Adler-32";
  return r.data;
}

struct Decoded {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

// PNG (8-bit RGBA, no interlace) to pixels.
Decoded decodePng(const std::vector<uint8_t>& png) {
  Decoded d;
  const uint8_t sig[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  EXPECT_TRUE(png.size() > 8 && std::equal(sig, sig + 8, png.begin()));
  std::vector<uint8_t> idat;
  bool ended = false;
  for (size_t at = 8; at + 12 <= png.size();) {
    const uint32_t len = be32(&png[at]);
    EXPECT_LE(at + 12 + len, png.size());
    if (at + 12 + len > png.size()) break;
    const std::string type(png.begin() + long(at) + 4, png.begin() + long(at) + 8);
    EXPECT_EQ(be32(&png[at + 8 + len]), bitwiseCrc(&png[at + 4], len + 4)) << type;
    const uint8_t* data = &png[at + 8];
    if (type == "IHDR") {
      EXPECT_EQ(len, 13u);
      d.width = int(be32(data));
      d.height = int(be32(data + 4));
      EXPECT_EQ(data[8], 8);   // bits
      EXPECT_EQ(data[9], 6);   // RGBA
      EXPECT_EQ(data[12], 0);  // not interlaced
    } else if (type == "IDAT") {
      idat.insert(idat.end(), data, data + len);
    } else if (type == "IEND") {
      ended = true;
    }
    at += 12 + len;
  }
  EXPECT_TRUE(ended);
  const size_t stride = size_t(d.width) * 4;
  const std::vector<uint8_t> raw = unzlib(idat, (stride + 1) * size_t(d.height));
  EXPECT_EQ(raw.size(), (stride + 1) * size_t(d.height));
  if (raw.size() != (stride + 1) * size_t(d.height)) return d;
  d.rgba.assign(stride * size_t(d.height), 0);
  for (int y = 0; y < d.height; ++y) {
    const uint8_t type = raw[size_t(y) * (stride + 1)];
    const uint8_t* in = &raw[size_t(y) * (stride + 1) + 1];
    uint8_t* row = &d.rgba[size_t(y) * stride];
    const uint8_t* up = y > 0 ? row - stride : nullptr;
    EXPECT_LE(type, 4);
    for (size_t k = 0; k < stride; ++k) {
      const int a = k >= 4 ? row[k - 4] : 0, b = up ? up[k] : 0, c = (up && k >= 4) ? up[k - 4] : 0;
      int pred = 0;
      if (type == 1) pred = a;
      if (type == 2) pred = b;
      if (type == 3) pred = (a + b) / 2;
      if (type == 4) {
        const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
        pred = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      row[k] = uint8_t(in[k] + pred);
    }
  }
  return d;
}

std::vector<uint8_t> base64Decode(const std::string& s) {
  std::vector<uint8_t> out;
  uint32_t acc = 0;
  int bits = 0;
  for (char ch : s) {
    int v;
    if (ch >= 'A' && ch <= 'Z') v = ch - 'A';
    else if (ch >= 'a' && ch <= 'z') v = ch - 'a' + 26;
    else if (ch >= '0' && ch <= '9') v = ch - '0' + 52;
    else if (ch == '+') v = 62;
    else if (ch == '/') v = 63;
    else if (ch == '=') break;
    else {
      ADD_FAILURE() << "not base64: " << ch;
      return {};
    }
    acc = (acc << 6) | uint32_t(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(uint8_t((acc >> bits) & 0xff));
    }
  }
  return out;
}

TEST(Png, ZlibStreamsInflateToTheirInput) {
  std::mt19937 rng(7);
  std::vector<std::vector<uint8_t>> inputs = {{}, {42}, std::vector<uint8_t>(1000, 0), std::vector<uint8_t>(70000, 9)};
  std::vector<uint8_t> noise(50000), pattern, mixed;
  for (uint8_t& v : noise) v = uint8_t(rng());
  for (int i = 0; i < 100000; ++i) pattern.push_back(uint8_t((i * 7) % 251));  // period 251
  for (int i = 0; i < 80000; ++i) mixed.push_back(i % 40000 < 300 ? noise[size_t(i % 300)] : uint8_t(i / 1000));
  inputs.push_back(noise);
  inputs.push_back(pattern);
  inputs.push_back(mixed);
  for (const auto& in : inputs) {
    const std::vector<uint8_t> z = zlibCompress(in.data(), in.size());
    EXPECT_EQ(unzlib(z, in.size()), in) << "input of " << in.size() << " bytes";
  }
  // Runs and repeats compress (a match covers up to 258 bytes in about 20 bits): runs under 1 %,
  // the 251-byte period under 1.5 % of the input.
  EXPECT_LT(zlibCompress(inputs[3].data(), inputs[3].size()).size(), 700u);
  EXPECT_LT(zlibCompress(pattern.data(), pattern.size()).size(), 1500u);
}

TEST(Png, EncodedImagesDecodeToTheSamePixels) {
  std::mt19937 rng(11);
  for (const auto& [w, h] : {std::pair<int, int>{1, 1}, {16, 16}, {220, 124}, {7, 300}}) {
    std::vector<uint8_t> rgba(size_t(w) * size_t(h) * 4);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        uint8_t* p = &rgba[(size_t(y) * size_t(w) + size_t(x)) * 4];
        // Gradients (Sub/Up pay), flat areas and a noisy band.
        p[0] = uint8_t(x * 3);
        p[1] = uint8_t(y * 2);
        p[2] = (y / 10) % 3 == 0 ? uint8_t(rng()) : 128;
        p[3] = x < w / 2 ? 255 : uint8_t(x + y);
      }
    }
    const std::vector<uint8_t> png = encodePngRgba(rgba, w, h);
    const Decoded d = decodePng(png);
    EXPECT_EQ(d.width, w);
    EXPECT_EQ(d.height, h);
    EXPECT_EQ(d.rgba, rgba) << w << "x" << h;
  }
}

// Pixels at least half covered, in mm^2 of the projection.
double coveredArea(const ThumbnailImage& img) {
  size_t n = 0;
  for (size_t i = 3; i < img.rgba.size(); i += 4) n += img.rgba[i] >= 128;
  return double(n) * img.mmPerPixel * img.mmPerPixel;
}

// A convex solid's orthographic projection along e has area (1/2) sum |n . e| A over its faces.
double projectedArea(const Mesh& m, const Eigen::Vector3d& e) {
  double a = 0;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    const Eigen::Vector3d p0 = m.vertex(m.triangles[3 * f]), p1 = m.vertex(m.triangles[3 * f + 1]),
                          p2 = m.vertex(m.triangles[3 * f + 2]);
    a += 0.5 * std::abs((p1 - p0).cross(p2 - p0).dot(e));
  }
  return 0.5 * a;
}

TEST(Thumbnail, TheDrawnPartCoversItsProjectedArea) {
  const Mesh box = test::makeBox(-3, 5, 0, 17, 15, 5);
  const Mesh ball = test::makeIcosphere(8, 4, {2, -4, 8});
  for (const Mesh* m : {&box, &ball}) {
    for (const auto& [w, h] : {std::pair<int, int>{220, 124}, {300, 300}, {600, 600}}) {
      const ThumbnailImage img = renderThumbnail(*m, w, h);
      ASSERT_EQ(img.rgba.size(), size_t(w) * size_t(h) * 4);
      const double expected = projectedArea(*m, img.view);
      EXPECT_NEAR(coveredArea(img), expected, 0.03 * expected) << w << "x" << h;
      // Centred and filling 90 % of the image in its tighter direction.
      int x0 = w, x1 = -1, y0 = h, y1 = -1;
      for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
          if (img.rgba[(size_t(y) * size_t(w) + size_t(x)) * 4 + 3] < 128) continue;
          x0 = std::min(x0, x);
          x1 = std::max(x1, x);
          y0 = std::min(y0, y);
          y1 = std::max(y1, y);
        }
      }
      EXPECT_NEAR(x0 + x1, w - 1, 2.5);
      EXPECT_NEAR(y0 + y1, h - 1, 2.5);
      const double fill = std::max(double(x1 - x0 + 1) / w, double(y1 - y0 + 1) / h);
      EXPECT_NEAR(fill, 0.9, 0.02);
    }
  }
  // The top of the box faces up and the light: brighter than its front.
  const ThumbnailImage img = renderThumbnail(test::makeBox(0, 0, 0, 10, 10, 10), 200, 200);
  auto blue = [&](int x, int y) { return img.rgba[(size_t(y) * 200 + size_t(x)) * 4 + 2]; };
  auto alpha = [&](int x, int y) { return img.rgba[(size_t(y) * 200 + size_t(x)) * 4 + 3]; };
  EXPECT_EQ(alpha(0, 0), 0) << "the corner is background";
  int top = 0, bottom = 199;
  while (top < 200 && alpha(100, top) < 255) ++top;
  while (bottom > 0 && alpha(100, bottom) < 255) --bottom;
  ASSERT_LT(top + 20, bottom);
  EXPECT_GT(blue(100, top + 5), blue(100, bottom - 5)) << "the top face is lit more than the sides";
  // An empty mesh: a clear image of the asked size.
  const ThumbnailImage none = renderThumbnail(Mesh{}, 16, 16);
  EXPECT_EQ(none.rgba, std::vector<uint8_t>(16 * 16 * 4, 0));
}

TEST(Thumbnail, SizesParseAndRefuse) {
  ThumbnailSizes s = parseThumbnailSizes(" 16x16, 220X124 ");
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(s.sizes, (std::vector<std::pair<int, int>>{{16, 16}, {220, 124}}));
  EXPECT_TRUE(parseThumbnailSizes("").ok());
  for (const char* bad : {"16", "x16", "16x", "0x10", "10x2000", "axb", "16x16x2", "1x1,2x2,3x3,4x4,5x5,6x6,7x7,8x8,9x9"}) {
    const ThumbnailSizes r = parseThumbnailSizes(bad);
    EXPECT_EQ(r.status, Status::InvalidOption) << bad;
    EXPECT_FALSE(r.message.empty());
  }
}

// Slices with and without thumbnails: the blocks follow PrusaSlicer's format, decode to PNGs of
// the sizes asked, and the program apart from them is byte for byte the one without.
TEST(Thumbnail, GcodeCarriesPrusaSlicerBlocksAndIsOtherwiseUnchanged) {
  const auto bytes = test::binaryStl(test::makeLBracket(10));
  Settings plain;
  ASSERT_TRUE(setSetting(plain, "machine", "table5").ok());
  ASSERT_TRUE(setSetting(plain, "method", "multidir").ok());
  Settings with = plain;
  ASSERT_TRUE(setSetting(with, "thumbnails", "16x16,220x124").ok());
  const SliceOutput a = runSlice(bytes.data(), bytes.size(), "bracket.stl", plain);
  const SliceOutput b = runSlice(bytes.data(), bytes.size(), "bracket.stl", with);
  ASSERT_TRUE(a.ok() && b.ok()) << a.message << b.message;

  std::istringstream in(b.program);
  std::string rest, line;
  std::vector<std::pair<int, int>> sizes;
  int beforeFirstMove = 1;
  while (std::getline(in, line)) {
    if (line.rfind("G1 ", 0) == 0 || line.rfind("G0 ", 0) == 0) beforeFirstMove = 0;
    int w = 0, h = 0;
    size_t len = 0;
    if (std::sscanf(line.c_str(), "; thumbnail begin %dx%d %zu", &w, &h, &len) == 3) {
      EXPECT_EQ(beforeFirstMove, 1) << "thumbnails come before the moves";
      std::string b64;
      while (std::getline(in, line) && line != "; thumbnail end") {
        ASSERT_EQ(line.rfind("; ", 0), 0u) << line;
        EXPECT_LE(line.size(), 80u);
        b64 += line.substr(2);
      }
      EXPECT_EQ(line, "; thumbnail end");
      EXPECT_EQ(b64.size(), len) << "the begin line gives the base64 length";
      const Decoded d = decodePng(base64Decode(b64));
      EXPECT_EQ(d.width, w);
      EXPECT_EQ(d.height, h);
      size_t opaque = 0;
      for (size_t i = 3; i < d.rgba.size(); i += 4) opaque += d.rgba[i] > 0;
      EXPECT_GT(opaque, d.rgba.size() / 4 / 10) << "the part is drawn";
      sizes.emplace_back(w, h);
      continue;
    }
    rest += line + "\n";
  }
  EXPECT_EQ(sizes, (std::vector<std::pair<int, int>>{{16, 16}, {220, 124}}));
  // The headers' dates may differ by a second: compare from the second line.
  auto fromSecondLine = [](const std::string& t) { return t.substr(t.find('\n')); };
  EXPECT_EQ(fromSecondLine(rest), fromSecondLine(a.program));
  // Readers skip the blocks (comments): the same moves.
  const ParsedProgram pa = readProgram(a.program), pb = readProgram(b.program);
  ASSERT_TRUE(pa.ok() && pb.ok()) << pa.message << pb.message;
  ASSERT_EQ(pa.moves.size(), pb.moves.size());
  for (size_t i = 0; i < pa.moves.size(); ++i) ASSERT_EQ(pa.moves[i].axes, pb.moves[i].axes) << i;

  // Robot programs have no printer host: none.
  Settings robot = with;
  ASSERT_TRUE(setSetting(robot, "machine", "robot6-ur5").ok());
  const SliceOutput r = runSlice(bytes.data(), bytes.size(), "bracket.stl", robot);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.program.find("thumbnail"), std::string::npos);
  // A bad size is a setting error.
  Settings bad;
  EXPECT_EQ(setSetting(bad, "thumbnails", "220x").status, Status::InvalidOption);
}

}  // namespace
}  // namespace omnislice
