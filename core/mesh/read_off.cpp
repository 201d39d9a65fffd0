// SPDX-License-Identifier: MIT
// OFF reader (Geomview Object File Format, ASCII). Header keyword OFF with optional ST/C/N
// prefixes, then "nv nf [ne]", nv vertex lines (x y z, anything after is colour/normal/texture
// data and ignored), nf face lines (n i1 .. in, colour after the indices ignored).
#include <algorithm>
#include <string>
#include <vector>

#include "mesh/parse_number.h"
#include "mesh/read_formats.h"
#include "mesh/text_cursor.h"

namespace omnislice {
namespace {

// Header keywords: [ST][C][N][4][n]OFF. Returns 1 for a plain 3D header, 2 for a supported
// header variant we cannot read (4D, nOFF), 0 for no header keyword.
int headerKind(const char* b, const char* e) {
  const size_t n = static_cast<size_t>(e - b);
  if (n < 3 || !tokenIs(e - 3, e, "off")) return 0;
  for (const char* p = b; p != e - 3; ++p) {
    const char c = *p;
    if (c == 'S' || c == 'T' || c == 'C' || c == 'N') continue;
    if (c == '4' || c == 'n') return 2;
    return 0;
  }
  return 1;
}

}  // namespace

ReadMeshResult readOff(const uint8_t* data, size_t size) {
  ReadMeshResult r;
  r.format = "off";
  TextCursor c(data, size);
  c.commentChar = '#';
  const char* b;
  const char* e;
  auto fail = [&r, &c](Status s, const std::string& what) {
    r.status = s;
    r.message = "OFF line " + std::to_string(c.lineNumber()) + ": " + what;
    r.mesh = Mesh();
    return r;
  };
  if (!c.next(b, e)) return fail(Status::EmptyInput, "no content");
  const int kind = headerKind(b, e);
  if (kind == 2) return fail(Status::UnsupportedFormat, "OFF variant " + tokenForMessage(b, e) + " (4D or n-dimensional) is not supported");
  if (kind == 1) {
    if (!c.next(b, e)) return fail(Status::TruncatedFile, "missing vertex and face counts");
    if (tokenIs(b, e, "binary")) return fail(Status::UnsupportedFormat, "binary OFF is not supported");
  }
  int64_t nv, nf;
  if (!parseInt64(b, e, nv) || nv < 0) return fail(Status::ParseError, "bad vertex count " + tokenForMessage(b, e));
  if (!c.next(b, e)) return fail(Status::TruncatedFile, "missing face count");
  if (!parseInt64(b, e, nf) || nf < 0) return fail(Status::ParseError, "bad face count " + tokenForMessage(b, e));
  if (nv > 0xFFFFFFFFll) return fail(Status::ParseError, "vertex count " + std::to_string(nv) + " too large");
  c.skipLine();  // the edge count, unused
  Mesh& m = r.mesh;
  // Reserve from the declared counts only as far as the data could possibly hold them.
  const size_t maxItems = size / 4 + 1;
  m.positions.reserve(3 * std::min<size_t>(static_cast<size_t>(nv), maxItems));
  m.triangles.reserve(3 * std::min<size_t>(static_cast<size_t>(nf), maxItems));
  for (int64_t i = 0; i < nv; ++i) {
    double xyz[3];
    for (int k = 0; k < 3; ++k) {
      if (!c.next(b, e)) {
        return fail(Status::TruncatedFile, "file ends at vertex " + std::to_string(i) + " of " + std::to_string(nv) + " declared");
      }
      if (!parseDouble(b, e, xyz[k])) return fail(Status::ParseError, "bad vertex coordinate " + tokenForMessage(b, e));
    }
    pushXyz(m.positions, xyz);
    c.skipLine();
  }
  std::vector<uint32_t> polygon;
  size_t skipped = 0;
  for (int64_t i = 0; i < nf; ++i) {
    if (!c.next(b, e)) {
      return fail(Status::TruncatedFile, "file ends at face " + std::to_string(i) + " of " + std::to_string(nf) + " declared");
    }
    int64_t n;
    if (!parseInt64(b, e, n) || n < 0) return fail(Status::ParseError, "bad face vertex count " + tokenForMessage(b, e));
    polygon.clear();
    for (int64_t k = 0; k < n; ++k) {
      if (!c.next(b, e)) {
        return fail(Status::TruncatedFile, "file ends inside face " + std::to_string(i) + " of " + std::to_string(nf) + " declared");
      }
      int64_t idx;
      if (!parseInt64(b, e, idx)) return fail(Status::ParseError, "bad face index " + tokenForMessage(b, e));
      if (idx < 0 || idx >= nv) {
        return fail(Status::ParseError, "face index " + std::to_string(idx) + " out of range (" + std::to_string(nv) + " vertices)");
      }
      polygon.push_back(static_cast<uint32_t>(idx));
    }
    c.skipLine();  // an optional colour follows the indices
    if (polygon.size() < 3) {
      ++skipped;
      continue;
    }
    for (size_t k = 1; k + 1 < polygon.size(); ++k) {
      m.triangles.push_back(polygon[0]);
      m.triangles.push_back(polygon[k]);
      m.triangles.push_back(polygon[k + 1]);
    }
  }
  if (skipped > 0) r.warnings.push_back("OFF: skipped " + std::to_string(skipped) + " faces with fewer than 3 vertices");
  return r;
}

}  // namespace omnislice
