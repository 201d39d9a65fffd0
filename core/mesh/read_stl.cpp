// SPDX-License-Identifier: MIT
// STL reader. Binary or ASCII is decided by the size rule (84 + 50 * count == size) and by
// whether the content is text with STL keywords, never by the first word alone: many binary
// exporters write "solid" at the start of the 80-byte header.
#include <cstring>
#include <string>

#include "mesh/parse_number.h"
#include "mesh/read_formats.h"
#include "mesh/text_cursor.h"

namespace omnislice {
namespace {

inline bool isTextByte(uint8_t c) { return c >= 32 || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

bool allText(const uint8_t* data, size_t size) {
  for (size_t i = 0; i < size; ++i) {
    if (!isTextByte(data[i])) return false;
  }
  return true;
}

// Offset just past "solid" (after leading whitespace), or 0 when the data does not start so.
size_t solidKeywordEnd(const uint8_t* data, size_t size) {
  size_t i = 0;
  while (i < size && TextCursor::isSpace(static_cast<char>(data[i]))) ++i;
  const char* b = reinterpret_cast<const char*>(data + i);
  if (size - i < 5 || !tokenIs(b, b + 5, "solid")) return 0;
  i += 5;
  if (i < size && !TextCursor::isSpace(static_cast<char>(data[i]))) return 0;
  return i;
}

inline float readFloatLE(const uint8_t* p) {
  const uint32_t bits = uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

ReadMeshResult fail(Status status, std::string message) { return failed<ReadMeshResult>(status, std::move(message)); }

ReadMeshResult readBinaryStl(const uint8_t* data, size_t size) {
  ReadMeshResult r;
  r.format = "stl-binary";
  if (size < 84) {
    r.status = Status::TruncatedFile;
    r.message = "binary STL: " + std::to_string(size) + " bytes, shorter than its 84-byte header";
    return r;
  }
  const uint64_t declared = uint64_t{data[80]} | uint64_t{data[81]} << 8 | uint64_t{data[82]} << 16 |
                            uint64_t{data[83]} << 24;
  const uint64_t available = (size - 84) / 50;
  uint64_t count = declared;
  if (84 + 50 * declared > size) {
    r.status = Status::TruncatedFile;
    r.message = "binary STL: header declares " + std::to_string(declared) + " triangles (" +
                std::to_string(84 + 50 * declared) + " bytes) but the file has " + std::to_string(size) +
                " bytes (" + std::to_string(available) + " whole triangles)";
    return r;
  }
  if (84 + 50 * declared < size) {
    r.warnings.push_back("STL header count " + std::to_string(declared) + " < " + std::to_string(available) +
                         " triangles present; read the declared " + std::to_string(declared) +
                         " and ignored " + std::to_string(size - 84 - 50 * declared) + " trailing bytes");
  }
  if (3 * count > 0xFFFFFFFFull) return fail(Status::ParseError, "binary STL: too many triangles for 32-bit indices");
  Mesh& m = r.mesh;
  m.positions.resize(9 * count);
  m.triangles.resize(3 * count);
  double* out = m.positions.data();
  const uint8_t* f = data + 84;
  for (uint64_t i = 0; i < count; ++i, f += 50) {
    // Bytes 0..11 hold the facet normal (ignored: recomputed from the vertices downstream).
    for (int k = 0; k < 9; ++k) *out++ = readFloatLE(f + 12 + 4 * k);
  }
  for (uint32_t i = 0; i < 3 * count; ++i) m.triangles[i] = i;
  return r;
}

// A cheap check that a skipped normal component is a number-like token, not a keyword.
inline bool numberLike(const char* b) {
  const char c = *b;
  return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' || c == 'n' || c == 'N' || c == 'i' || c == 'I';
}

ReadMeshResult readAsciiStl(const uint8_t* data, size_t size) {
  ReadMeshResult r;
  r.format = "stl-ascii";
  Mesh& m = r.mesh;
  m.positions.reserve(size / 20);
  m.triangles.reserve(size / 60);
  TextCursor c(data, size);
  const char* b;
  const char* e;
  auto where = [&c]() { return "ASCII STL line " + std::to_string(c.lineNumber()) + ": "; };
  size_t polygons = 0;          // facets with more than 3 vertices
  size_t firstPolygonLine = 0;
  auto truncated = [&](const char* what) {
    return fail(Status::TruncatedFile, "ASCII STL: file ends inside a facet (expected " + std::string(what) + ")");
  };
  bool inSolid = false;
  bool sawSolid = false;
  double loopCoords[3];
  std::vector<double> polygon;
  while (c.next(b, e)) {
    if (tokenIs(b, e, "solid")) {
      if (inSolid && r.warnings.size() < 20) r.warnings.push_back(where() + "'solid' before 'endsolid' of the previous solid");
      inSolid = sawSolid = true;
      c.skipLine();  // the rest of the line is the solid's name
      continue;
    }
    if (tokenIs(b, e, "endsolid")) {
      if (!inSolid) return fail(Status::ParseError, where() + "'endsolid' without 'solid'");
      inSolid = false;
      c.skipLine();
      continue;
    }
    if (!tokenIs(b, e, "facet")) {
      return fail(Status::ParseError, where() + "expected 'facet' or 'endsolid', found " + tokenForMessage(b, e));
    }
    if (!sawSolid) return fail(Status::ParseError, where() + "'facet' before 'solid'");
    if (!c.next(b, e)) return truncated("'normal' or 'outer'");
    if (tokenIs(b, e, "normal")) {
      for (int k = 0; k < 3; ++k) {
        if (!c.next(b, e)) return truncated("a normal component");
        if (!numberLike(b)) return fail(Status::ParseError, where() + "bad facet normal component " + tokenForMessage(b, e));
      }
      if (!c.next(b, e)) return truncated("'outer'");
    }
    if (!tokenIs(b, e, "outer")) return fail(Status::ParseError, where() + "expected 'outer loop', found " + tokenForMessage(b, e));
    if (!c.next(b, e)) return truncated("'loop'");
    if (!tokenIs(b, e, "loop")) return fail(Status::ParseError, where() + "expected 'loop', found " + tokenForMessage(b, e));
    const size_t first = m.positions.size();
    for (;;) {
      if (!c.next(b, e)) return truncated("'vertex' or 'endloop'");
      if (tokenIs(b, e, "endloop")) break;
      if (!tokenIs(b, e, "vertex")) {
        return fail(Status::ParseError, where() + "expected 'vertex' or 'endloop', found " + tokenForMessage(b, e));
      }
      for (int k = 0; k < 3; ++k) {
        if (!c.next(b, e)) return truncated("a vertex coordinate");
        if (!parseDouble(b, e, loopCoords[k])) {
          return fail(Status::ParseError, where() + "bad vertex coordinate " + tokenForMessage(b, e));
        }
      }
      pushXyz(m.positions, loopCoords);
    }
    const size_t n = (m.positions.size() - first) / 3;
    if (n < 3) return fail(Status::ParseError, where() + "facet loop with " + std::to_string(n) + " vertices");
    if (m.positions.size() / 3 > 0xFFFFFFFFull) return fail(Status::ParseError, "ASCII STL: too many vertices");
    const uint32_t v0 = static_cast<uint32_t>(first / 3);
    if (n > 3 && polygons++ == 0) firstPolygonLine = c.lineNumber();
    for (uint32_t k = 1; k + 1 < n; ++k) {
      m.triangles.push_back(v0);
      m.triangles.push_back(v0 + k);
      m.triangles.push_back(v0 + k + 1);
    }
    if (!c.next(b, e)) return truncated("'endfacet'");
    if (!tokenIs(b, e, "endfacet")) return fail(Status::ParseError, where() + "expected 'endfacet', found " + tokenForMessage(b, e));
  }
  if (!sawSolid) return fail(Status::ParseError, "ASCII STL: no 'solid' keyword");
  if (inSolid) r.warnings.push_back("ASCII STL: missing 'endsolid' at the end of the file");
  if (polygons > 0) {
    r.warnings.push_back("ASCII STL: " + std::to_string(polygons) + " facets with more than 3 vertices fan-triangulated (first at line " +
                         std::to_string(firstPolygonLine) + ")");
  }
  return r;
}

}  // namespace

bool binaryStlSizeMatches(const uint8_t* data, size_t size) {
  if (size < 84) return false;
  const uint64_t n = uint64_t{data[80]} | uint64_t{data[81]} << 8 | uint64_t{data[82]} << 16 | uint64_t{data[83]} << 24;
  return 84 + 50 * n == size;
}

bool looksLikeAsciiStl(const uint8_t* data, size_t size) {
  size_t i = solidKeywordEnd(data, size);
  if (i == 0) return false;
  const size_t probe = size < 1024 ? size : 1024;
  if (!allText(data, probe)) return false;
  // The token after the solid's name line must be an STL keyword.
  while (i < size && data[i] != '\n') ++i;
  TextCursor c(data + i, size - i);
  const char* b;
  const char* e;
  if (!c.next(b, e)) return false;
  return tokenIs(b, e, "facet") || tokenIs(b, e, "endsolid");
}

ReadMeshResult readStl(const uint8_t* data, size_t size) {
  const bool sizeRule = binaryStlSizeMatches(data, size);
  if (sizeRule) {
    // An ASCII file that happens to satisfy the size rule is all text; binary floats are not.
    if (looksLikeAsciiStl(data, size) && allText(data, size)) return readAsciiStl(data, size);
    return readBinaryStl(data, size);
  }
  if (looksLikeAsciiStl(data, size)) return readAsciiStl(data, size);
  // "solid" followed by text that is not a valid ASCII STL: report the ASCII parse error.
  if (solidKeywordEnd(data, size) != 0 && allText(data, size < 1024 ? size : 1024)) return readAsciiStl(data, size);
  return readBinaryStl(data, size);
}

}  // namespace omnislice
