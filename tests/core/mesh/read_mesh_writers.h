// SPDX-License-Identifier: MIT
// Test-side writers for the mesh reader tests: polygon meshes written as binary/ASCII STL, OBJ,
// OFF, PLY (ascii, little and big endian) and 3MF (ZIP with stored entries or entries compressed
// by a small fixed-Huffman DEFLATE encoder written here independently of the decoder), plus
// geometric comparison helpers.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "mesh/inflate.h"
#include "mesh/mesh.h"

#include "../test_support.h"

namespace omnislice::test {

// Positions plus polygons (3 or more vertex indices each, counter-clockwise from outside).
struct PolyMesh {
  std::vector<double> positions;
  std::vector<std::vector<uint32_t>> polygons;

  Eigen::Vector3d vertex(size_t i) const { return {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]}; }
  // Fan triangulation (v0, vk, vk+1), the convention the readers use.
  Mesh triangulated() const {
    Mesh m;
    m.positions = positions;
    for (const auto& p : polygons) {
      for (size_t k = 1; k + 1 < p.size(); ++k) m.triangles.insert(m.triangles.end(), {p[0], p[k], p[k + 1]});
    }
    return m;
  }
};

// Coordinates on a 1/1024 grid: exact in float and in any decimal text written with %.17g,
// so every format must reproduce them bit for bit.
inline double gridRound(double v) { return std::round(v * 1024.0) / 1024.0; }

// UV sphere: triangles at the poles, quads elsewhere. rings * segments small -> few hundred faces.
inline PolyMesh makeSpherePoly(int rings, int segments, double radius, double cx, double cy, double cz) {
  PolyMesh m;
  auto add = [&m](double x, double y, double z) {
    // push_back, not insert of a list: GCC 12 warns (stringop-overflow) when inlined.
    m.positions.push_back(gridRound(x));
    m.positions.push_back(gridRound(y));
    m.positions.push_back(gridRound(z));
    return static_cast<uint32_t>(m.positions.size() / 3 - 1);
  };
  const uint32_t north = add(cx, cy, cz + radius);
  for (int r = 1; r < rings; ++r) {
    const double theta = M_PI * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * M_PI * s / segments;
      add(cx + radius * std::sin(theta) * std::cos(phi), cy + radius * std::sin(theta) * std::sin(phi),
          cz + radius * std::cos(theta));
    }
  }
  const uint32_t south = add(cx, cy, cz - radius);
  auto ring = [segments](int r, int s) { return static_cast<uint32_t>(1 + (r - 1) * segments + (s % segments)); };
  for (int s = 0; s < segments; ++s) m.polygons.push_back({north, ring(1, s), ring(1, s + 1)});
  for (int r = 1; r + 1 < rings; ++r) {
    for (int s = 0; s < segments; ++s) m.polygons.push_back({ring(r, s), ring(r + 1, s), ring(r + 1, s + 1), ring(r, s + 1)});
  }
  for (int s = 0; s < segments; ++s) m.polygons.push_back({south, ring(rings - 1, s + 1), ring(rings - 1, s)});
  return m;
}

// Axis-aligned box as 6 outward quads.
inline PolyMesh makeBoxPoly(double x0, double y0, double z0, double x1, double y1, double z1) {
  PolyMesh m;
  m.positions = {x0, y0, z0, x1, y0, z0, x1, y1, z0, x0, y1, z0, x0, y0, z1, x1, y0, z1, x1, y1, z1, x0, y1, z1};
  m.polygons = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  return m;
}

// Triangles as coordinate 9-tuples, each rotated to start at its smallest vertex (orientation
// kept), sorted: equal lists mean the same oriented triangles whatever the vertex sharing.
inline std::vector<std::array<double, 9>> canonicalTriangles(const Mesh& m) {
  std::vector<std::array<double, 9>> out;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    std::array<std::array<double, 3>, 3> v;
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) v[k][c] = m.positions[3 * m.triangles[3 * f + k] + c];
    }
    const int first = static_cast<int>(std::min_element(v.begin(), v.end()) - v.begin());
    std::array<double, 9> t;
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) t[3 * k + c] = v[(first + k) % 3][c];
    }
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

inline bool indicesInRange(const Mesh& m) {
  for (uint32_t i : m.triangles) {
    if (i >= m.vertexCount()) return false;
  }
  return m.positions.size() % 3 == 0 && m.triangles.size() % 3 == 0;
}

inline std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

inline void putLe(std::vector<uint8_t>& out, uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
inline void putBe(std::vector<uint8_t>& out, uint64_t v, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
inline void putFloat(std::vector<uint8_t>& out, float f, bool bigEndian) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  bigEndian ? putBe(out, u, 4) : putLe(out, u, 4);
}
inline void putDouble(std::vector<uint8_t>& out, double d, bool bigEndian) {
  uint64_t u;
  std::memcpy(&u, &d, 8);
  bigEndian ? putBe(out, u, 8) : putLe(out, u, 8);
}
inline void append(std::vector<uint8_t>& out, const std::string& s) { out.insert(out.end(), s.begin(), s.end()); }

// Binary STL; the 80-byte header starts with `header` (e.g. "solid name" as many exporters do).
inline std::vector<uint8_t> writeBinaryStl(const Mesh& m, const std::string& header = "binary test") {
  std::vector<uint8_t> out(80, ' ');
  std::memcpy(out.data(), header.data(), std::min<size_t>(80, header.size()));
  putLe(out, m.faceCount(), 4);
  for (size_t f = 0; f < m.faceCount(); ++f) {
    const Eigen::Vector3d a = m.vertex(m.triangles[3 * f]), b = m.vertex(m.triangles[3 * f + 1]),
                          c = m.vertex(m.triangles[3 * f + 2]);
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    for (int k = 0; k < 3; ++k) putFloat(out, static_cast<float>(n[k]), false);
    for (const Eigen::Vector3d& v : {a, b, c}) {
      for (int k = 0; k < 3; ++k) putFloat(out, static_cast<float>(v[k]), false);
    }
    putLe(out, 0, 2);
  }
  return out;
}

// ASCII STL split into `solids` solids, with mixed keyword case and whitespace and CRLF lines.
inline std::string writeAsciiStl(const Mesh& m, int solids = 1) {
  std::string s;
  const size_t per = (m.faceCount() + solids - 1) / solids;
  for (int part = 0; part < solids; ++part) {
    s += part % 2 ? "SOLID Part" + std::to_string(part) + "\r\n" : "solid part" + std::to_string(part) + "\n";
    for (size_t f = part * per; f < std::min(m.faceCount(), (part + 1) * per); ++f) {
      s += f % 3 == 0 ? "  facet normal 0 0 0\n    outer loop\n" : "facet NORMAL 1e-3 -0 +0.5\r\n\touter   loop\r\n";
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d v = m.vertex(m.triangles[3 * f + k]);
        s += (f % 2 ? "\t  Vertex " : "      vertex ") + num(v.x()) + "  " + num(v.y()) + "\t" + num(v.z()) + "\n";
      }
      s += f % 3 == 0 ? "    endloop\n  endfacet\n" : "ENDLOOP\nendFacet\n";
    }
    s += "endsolid part" + std::to_string(part) + "\n";
  }
  return s;
}

// OBJ using every face-index form, negative (relative) indices for some faces, quads, and the
// statements a reader must skip. Vertices are written in two batches, faces after each batch.
inline std::string writeObj(const PolyMesh& m) {
  std::string s = "# test OBJ\nmtllib test.mtl\no shape\n";
  const size_t nv = m.positions.size() / 3;
  const size_t half = nv / 2;
  auto vertexLine = [&](size_t i) {
    std::string l = "v " + num(m.positions[3 * i]) + " " + num(m.positions[3 * i + 1]) + " " + num(m.positions[3 * i + 2]);
    if (i % 3 == 1) l += " 1.0";                 // optional w
    if (i % 3 == 2) l += " 0.5 0.25 1";          // vertex colour
    return l + (i % 4 == 0 ? "\r\n" : "\n");
  };
  for (size_t i = 0; i < half; ++i) s += vertexLine(i);
  s += "vt 0 0\nvt 1 0\nvn 0 0 1\ng first\ns off\nusemtl red\n";
  size_t written = half;
  auto faceLine = [&](const std::vector<uint32_t>& p, size_t fi) {
    std::string l = "f";
    for (size_t k = 0; k < p.size(); ++k) {
      const long long idx = fi % 2 ? static_cast<long long>(p[k]) - static_cast<long long>(written) : p[k] + 1;
      const std::string i = std::to_string(idx);
      switch ((fi + k) % 4) {
        case 0: l += " " + i; break;
        case 1: l += " " + i + "/1"; break;
        case 2: l += " " + i + "//1"; break;
        default: l += " " + i + "/2/1"; break;
      }
      if (fi == 5 && k == 1) l += " \\\n ";  // a line continuation inside one face
    }
    return l + " # trailing comment\n";
  };
  std::vector<bool> done(m.polygons.size(), false);
  for (size_t f = 0; f < m.polygons.size(); ++f) {
    const auto& p = m.polygons[f];
    if (std::all_of(p.begin(), p.end(), [&](uint32_t v) { return v < written; })) {
      s += faceLine(p, f);
      done[f] = true;
    }
  }
  s += "g second\nl 1 2\n";
  for (size_t i = half; i < nv; ++i) s += vertexLine(i);
  written = nv;
  for (size_t f = 0; f < m.polygons.size(); ++f) {
    if (!done[f]) s += faceLine(m.polygons[f], f);
  }
  return s;
}

// OFF (COFF-like: colours after vertices and faces), comments, polygons as they are.
inline std::string writeOff(const PolyMesh& m) {
  std::string s = "COFF\n# generated for the reader test\n\n";
  s += std::to_string(m.positions.size() / 3) + " " + std::to_string(m.polygons.size()) + " 0  # counts\n";
  for (size_t i = 0; i < m.positions.size() / 3; ++i) {
    s += num(m.positions[3 * i]) + " " + num(m.positions[3 * i + 1]) + " " + num(m.positions[3 * i + 2]) + " 255 128 0 255\n";
  }
  for (const auto& p : m.polygons) {
    s += std::to_string(p.size());
    for (uint32_t v : p) s += " " + std::to_string(v);
    s += " 0.5 0.5 0.5\n";
  }
  return s;
}

enum class PlyKind { Ascii, LittleEndian, BigEndian };

// PLY with extra vertex properties of several types, an extra element (with a list) between
// vertex and face, scalar and list properties around vertex_indices, and the given list types.
inline std::vector<uint8_t> writePly(const PolyMesh& m, PlyKind kind, const std::string& countType = "uchar",
                                     const std::string& indexType = "int") {
  const size_t nv = m.positions.size() / 3;
  std::string h = "ply\n";
  h += kind == PlyKind::Ascii ? "format ascii 1.0\n"
       : kind == PlyKind::LittleEndian ? "format binary_little_endian 1.0\n"
                                       : "format binary_big_endian 1.0\n";
  h += "comment written by the omnislice reader test\nobj_info extra words here\n";
  h += "element vertex " + std::to_string(nv) + "\n";
  h += "property uchar flags\nproperty double x\nproperty float y\nproperty short pad\nproperty double z\n";
  h += "property list uchar int16 neighbours\nproperty uint8 red\n";
  h += "element material 2\nproperty list ushort float coeffs\nproperty int id\n";
  h += "element face " + std::to_string(m.polygons.size()) + "\n";
  h += "property uchar intensity\nproperty list " + countType + " " + indexType + " vertex_indices\n";
  h += "property list uchar float texcoord\n";
  h += "end_header\n";
  std::vector<uint8_t> out(h.begin(), h.end());
  const bool be = kind == PlyKind::BigEndian;
  auto sizeOf = [](const std::string& t) -> int {
    if (t == "uchar" || t == "char" || t == "uint8" || t == "int8") return 1;
    if (t == "ushort" || t == "short" || t == "uint16" || t == "int16") return 2;
    return 4;
  };
  auto putInt = [&](uint64_t v, int bytes) { be ? putBe(out, v, bytes) : putLe(out, v, bytes); };
  if (kind == PlyKind::Ascii) {
    std::string s;
    for (size_t i = 0; i < nv; ++i) {
      s += std::to_string(i % 7) + " " + num(m.positions[3 * i]) + " " + num(m.positions[3 * i + 1]) + " -3 " +
           num(m.positions[3 * i + 2]) + " 2 5 -6 200\n";
    }
    s += "3 0.5 1.5 2.5 7\n0 8\n";
    for (const auto& p : m.polygons) {
      s += "9 " + std::to_string(p.size());
      for (uint32_t v : p) s += " " + std::to_string(v);
      s += " 2 0.25 0.75\n";
    }
    append(out, s);
    return out;
  }
  for (size_t i = 0; i < nv; ++i) {
    out.push_back(static_cast<uint8_t>(i % 7));
    putDouble(out, m.positions[3 * i], be);
    putFloat(out, static_cast<float>(m.positions[3 * i + 1]), be);
    putInt(static_cast<uint16_t>(-3), 2);
    putDouble(out, m.positions[3 * i + 2], be);
    out.push_back(2);
    putInt(5, 2);
    putInt(static_cast<uint16_t>(-6), 2);
    out.push_back(200);
  }
  putInt(3, 2);
  for (float f : {0.5f, 1.5f, 2.5f}) putFloat(out, f, be);
  putInt(7, 4);
  putInt(0, 2);
  putInt(8, 4);
  for (const auto& p : m.polygons) {
    out.push_back(9);
    putInt(p.size(), sizeOf(countType));
    for (uint32_t v : p) putInt(v, sizeOf(indexType));
    out.push_back(2);
    putFloat(out, 0.25f, be);
    putFloat(out, 0.75f, be);
  }
  return out;
}

// ---- ZIP and DEFLATE (encoder side, for 3MF tests) ---------------------------------------------

class BitWriter {
 public:
  void bits(uint32_t value, int n) {  // least significant bit first
    for (int i = 0; i < n; ++i) {
      if (count_ == 0) out.push_back(0);
      out.back() |= static_cast<uint8_t>(((value >> i) & 1u) << count_);
      count_ = (count_ + 1) % 8;
    }
  }
  void huffman(uint32_t code, int n) {  // Huffman codes go most significant bit first
    for (int i = n - 1; i >= 0; --i) bits((code >> i) & 1u, 1);
  }
  void align() { count_ = 0; }
  std::vector<uint8_t> out;

 private:
  int count_ = 0;
};

inline void fixedLiteral(BitWriter& w, int sym) {
  if (sym < 144) w.huffman(0x30 + sym, 8);
  else if (sym < 256) w.huffman(0x190 + sym - 144, 9);
  else if (sym < 280) w.huffman(sym - 256, 7);
  else w.huffman(0xC0 + sym - 280, 8);
}

// Raw DEFLATE of data: alternating fixed-Huffman blocks (greedy LZ77, hash of 3 bytes) and stored
// blocks, so both block kinds and the switch between them are exercised.
inline std::vector<uint8_t> deflateFixed(const std::vector<uint8_t>& data, size_t blockSize = 4000) {
  static const int lenBase[29] = {3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
  static const int lenExtra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
  static const int distBase[30] = {1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193, 257, 385, 513, 769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577};
  static const int distExtra[30] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13};
  BitWriter w;
  std::vector<int64_t> head(1 << 15, -1);
  auto hash = [&](size_t i) { return ((data[i] << 10) ^ (data[i + 1] << 5) ^ data[i + 2]) & 0x7FFF; };
  size_t pos = 0;
  int block = 0;
  do {
    const size_t end = std::min(data.size(), pos + blockSize);
    const bool last = end == data.size();
    if (block % 3 == 2) {  // stored block
      w.bits(last ? 1 : 0, 1);
      w.bits(0, 2);
      w.align();
      const uint32_t len = static_cast<uint32_t>(end - pos);
      putLe(w.out, len, 2);
      putLe(w.out, len ^ 0xFFFF, 2);
      w.out.insert(w.out.end(), data.begin() + pos, data.begin() + end);
      for (size_t i = pos; i < end && i + 2 < data.size(); ++i) head[hash(i)] = static_cast<int64_t>(i);
      pos = end;
    } else {
      w.bits(last ? 1 : 0, 1);
      w.bits(1, 2);
      while (pos < end) {
        size_t bestLen = 0, bestDist = 0;
        if (pos + 2 < data.size()) {
          const int64_t cand = head[hash(pos)];
          if (cand >= 0 && pos - cand <= 32768) {
            size_t l = 0;
            while (l < 258 && pos + l < end && data[cand + l] == data[pos + l]) ++l;
            if (l >= 3) bestLen = l, bestDist = pos - cand;
          }
          head[hash(pos)] = static_cast<int64_t>(pos);
        }
        if (bestLen == 0) {
          fixedLiteral(w, data[pos]);
          ++pos;
          continue;
        }
        int li = 28;
        while (lenBase[li] > static_cast<int>(bestLen)) --li;
        fixedLiteral(w, 257 + li);
        w.bits(static_cast<uint32_t>(bestLen - lenBase[li]), lenExtra[li]);
        int di = 29;
        while (distBase[di] > static_cast<int>(bestDist)) --di;
        w.huffman(di, 5);
        w.bits(static_cast<uint32_t>(bestDist - distBase[di]), distExtra[di]);
        for (size_t i = pos + 1; i < pos + bestLen && i + 2 < data.size(); ++i) head[hash(i)] = static_cast<int64_t>(i);
        pos += bestLen;
      }
      fixedLiteral(w, 256);
    }
    ++block;
  } while (pos < data.size());
  return w.out;
}

struct ZipInput {
  std::string name;
  std::string content;
  bool deflate = false;
};

// ZIP archive with local headers, central directory and end record.
inline std::vector<uint8_t> writeZip(const std::vector<ZipInput>& files) {
  std::vector<uint8_t> out, central;
  for (const ZipInput& f : files) {
    const std::vector<uint8_t> raw(f.content.begin(), f.content.end());
    const std::vector<uint8_t> body = f.deflate ? deflateFixed(raw) : raw;
    const uint32_t crc = crc32(raw.data(), raw.size());
    const size_t offset = out.size();
    putLe(out, 0x04034b50, 4);
    putLe(out, 20, 2);
    putLe(out, 0, 2);
    putLe(out, f.deflate ? 8 : 0, 2);
    putLe(out, 0, 4);  // time, date
    putLe(out, crc, 4);
    putLe(out, body.size(), 4);
    putLe(out, raw.size(), 4);
    putLe(out, f.name.size(), 2);
    putLe(out, 0, 2);
    append(out, f.name);
    out.insert(out.end(), body.begin(), body.end());
    putLe(central, 0x02014b50, 4);
    putLe(central, 20, 2);
    putLe(central, 20, 2);
    putLe(central, 0, 2);
    putLe(central, f.deflate ? 8 : 0, 2);
    putLe(central, 0, 4);
    putLe(central, crc, 4);
    putLe(central, body.size(), 4);
    putLe(central, raw.size(), 4);
    putLe(central, f.name.size(), 2);
    putLe(central, 0, 2);  // extra
    putLe(central, 0, 2);  // comment
    putLe(central, 0, 2);  // disk
    putLe(central, 0, 2);  // internal attributes
    putLe(central, 0, 4);  // external attributes
    putLe(central, offset, 4);
    append(central, f.name);
  }
  const size_t dirOffset = out.size();
  out.insert(out.end(), central.begin(), central.end());
  putLe(out, 0x06054b50, 4);
  putLe(out, 0, 2);
  putLe(out, 0, 2);
  putLe(out, files.size(), 2);
  putLe(out, files.size(), 2);
  putLe(out, central.size(), 4);
  putLe(out, dirOffset, 4);
  putLe(out, 0, 2);
  return out;
}

inline const char* kContentTypes =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    "<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\">"
    "<Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/>"
    "<Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/></Types>\n";

inline std::string relsFor(const std::string& target) {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">"
         "<Relationship Target=\"" + target + "\" Id=\"rel0\" "
         "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>\n";
}

// <object> element with a mesh, in the 3MF core schema.
inline std::string objectXml(int id, const Mesh& m) {
  std::string s = "  <object id=\"" + std::to_string(id) + "\" type=\"model\">\n   <mesh>\n    <vertices>\n";
  for (size_t i = 0; i < m.vertexCount(); ++i) {
    s += "     <vertex x=\"" + num(m.positions[3 * i]) + "\" y=\"" + num(m.positions[3 * i + 1]) + "\" z=\"" +
         num(m.positions[3 * i + 2]) + "\" />\n";
  }
  s += "    </vertices>\n    <triangles>\n";
  for (size_t f = 0; f < m.faceCount(); ++f) {
    s += "     <triangle v1=\"" + std::to_string(m.triangles[3 * f]) + "\" v2=\"" + std::to_string(m.triangles[3 * f + 1]) +
         "\" v3=\"" + std::to_string(m.triangles[3 * f + 2]) + "\"/>\n";
  }
  return s + "    </triangles>\n   </mesh>\n  </object>\n";
}

inline std::string modelXml(const std::string& resources, const std::string& build, const std::string& unit = "millimeter") {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!-- written by the reader test -->\n"
         "<model unit=\"" + unit + "\" xml:lang=\"en-US\" xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n"
         " <metadata name=\"Title\">test &amp; more</metadata>\n <resources>\n" + resources +
         " </resources>\n <build>\n" + build + " </build>\n</model>\n";
}

// A 3MF package holding one model part.
inline std::vector<uint8_t> write3mf(const std::string& model, bool deflate, const std::string& part = "3D/3dmodel.model") {
  return writeZip({{"[Content_Types].xml", kContentTypes, deflate},
                   {"_rels/.rels", relsFor("/" + part), deflate},
                   {part, model, deflate}});
}

}  // namespace omnislice::test
