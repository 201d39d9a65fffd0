// SPDX-License-Identifier: MIT
// Wavefront OBJ reader: only geometry statements matter here. 'v' gives positions (an optional
// w and vertex colours are ignored), 'f' gives polygons in any index form (v, v/vt, v//vn,
// v/vt/vn, negative = relative to the vertices read so far), fan-triangulated. Every other
// statement (vn, vt, g, o, s, usemtl, mtllib, l, ...) is skipped.
#include <string>
#include <vector>

#include "mesh/parse_number.h"
#include "mesh/read_formats.h"

namespace omnislice {
namespace {

inline bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

inline bool isKeywordChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

// Joins lines ending in a backslash (a rarely used OBJ feature) into one, keeping the line count
// by moving the swallowed newlines after the joined line.
std::vector<char> joinContinuations(const char* p, const char* end) {
  std::vector<char> out;
  out.reserve(static_cast<size_t>(end - p));
  size_t pendingNewlines = 0;
  while (p != end) {
    // Copy up to the next backslash or newline in one go.
    const char* q = p;
    while (q != end && *q != '\\' && *q != '\n') ++q;
    out.insert(out.end(), p, q);
    p = q;
    if (p == end) break;
    if (*p == '\n') {
      out.push_back('\n');
      out.insert(out.end(), pendingNewlines, '\n');
      pendingNewlines = 0;
      ++p;
      continue;
    }
    const char* r = p + 1;
    while (r != end && (*r == '\r' || *r == ' ' || *r == '\t')) ++r;
    if (r != end && *r == '\n') {
      out.push_back(' ');
      ++pendingNewlines;
      p = r + 1;
    } else {
      out.push_back('\\');
      ++p;
    }
  }
  out.insert(out.end(), pendingNewlines, '\n');
  return out;
}

bool hasContinuation(const char* p, const char* end) {
  for (; p != end; ++p) {
    if (*p != '\\') continue;
    const char* q = p + 1;
    while (q != end && (*q == '\r' || *q == ' ' || *q == '\t')) ++q;
    if (q != end && *q == '\n') return true;
  }
  return false;
}

struct ForwardRef {
  size_t line;
  int64_t index;
};

ReadMeshResult parseObj(const char* p, const char* end) {
  ReadMeshResult r;
  r.format = "obj";
  Mesh& m = r.mesh;
  std::vector<uint32_t> polygon;
  std::vector<ForwardRef> forward;  // positive indices beyond the vertices read so far
  size_t line = 0;
  size_t skippedFaces = 0;
  auto fail = [&r, &line](Status s, const std::string& what) {
    r.status = s;
    r.message = "OBJ line " + std::to_string(line) + ": " + what;
    r.mesh = Mesh();
    return r;
  };
  while (p != end) {
    ++line;
    const char* lineEnd = p;
    while (lineEnd != end && *lineEnd != '\n') ++lineEnd;
    const char* next = lineEnd == end ? end : lineEnd + 1;
    // Comments run to the end of the line.
    const char* stop = p;
    while (stop != lineEnd && *stop != '#') ++stop;
    const char* q = p;
    while (q != stop && isBlank(*q)) ++q;
    const char* kb = q;
    while (q != stop && !isBlank(*q)) ++q;
    const char* ke = q;
    p = next;
    if (kb == ke) continue;
    const size_t klen = static_cast<size_t>(ke - kb);
    auto token = [&q, stop](const char*& b, const char*& e) {
      while (q != stop && isBlank(*q)) ++q;
      if (q == stop) return false;
      b = q;
      while (q != stop && !isBlank(*q)) ++q;
      e = q;
      return true;
    };
    const char* b;
    const char* e;
    if (klen == 1 && kb[0] == 'v') {
      double xyz[3];
      for (int k = 0; k < 3; ++k) {
        if (!token(b, e)) return fail(Status::ParseError, "vertex with fewer than 3 coordinates");
        if (!parseDouble(b, e, xyz[k])) return fail(Status::ParseError, "bad vertex coordinate " + std::string(b, e - b > 40 ? 40 : e - b));
      }
      // Anything after x y z (w, or r g b colours) is ignored.
      pushXyz(m.positions, xyz);
      continue;
    }
    if (klen == 1 && kb[0] == 'f') {
      polygon.clear();
      const int64_t vcount = static_cast<int64_t>(m.positions.size() / 3);
      while (token(b, e)) {
        const char* slash = b;
        while (slash != e && *slash != '/') ++slash;
        int64_t idx;
        if (!parseInt64(b, slash, idx)) return fail(Status::ParseError, "bad face index " + std::string(b, e - b > 40 ? 40 : e - b));
        // The vt / vn parts after the slashes are ignored, but must be index-like.
        for (const char* s = slash; s != e; ++s) {
          if (!(*s == '/' || *s == '-' || (*s >= '0' && *s <= '9'))) {
            return fail(Status::ParseError, "bad face index " + std::string(b, e - b > 40 ? 40 : e - b));
          }
        }
        int64_t resolved;
        if (idx > 0) {
          resolved = idx - 1;
          if (idx > vcount) forward.push_back({line, idx});
        } else if (idx < 0) {
          resolved = vcount + idx;
          if (resolved < 0) {
            return fail(Status::ParseError, "relative index " + std::to_string(idx) + " reaches before the first vertex (" +
                                                std::to_string(vcount) + " vertices so far)");
          }
        } else {
          return fail(Status::ParseError, "face index 0 (OBJ indices start at 1)");
        }
        if (resolved > 0xFFFFFFFEll) return fail(Status::ParseError, "face index " + std::to_string(idx) + " out of range");
        polygon.push_back(static_cast<uint32_t>(resolved));
      }
      if (polygon.size() < 3) {
        ++skippedFaces;
        continue;
      }
      for (size_t k = 1; k + 1 < polygon.size(); ++k) {
        m.triangles.push_back(polygon[0]);
        m.triangles.push_back(polygon[k]);
        m.triangles.push_back(polygon[k + 1]);
      }
      continue;
    }
    // Other statements are skipped; a keyword that is not a word means this is not OBJ text.
    for (const char* s = kb; s != ke; ++s) {
      if (!isKeywordChar(*s)) {
        return fail(Status::ParseError, "unknown statement starting with a non-keyword character (byte " +
                                            std::to_string(static_cast<unsigned>(static_cast<unsigned char>(*s))) + ")");
      }
    }
  }
  const int64_t vcount = static_cast<int64_t>(m.positions.size() / 3);
  for (const ForwardRef& f : forward) {
    if (f.index > vcount) {
      line = f.line;
      return fail(Status::ParseError, "face index " + std::to_string(f.index) + " out of range (" +
                                          std::to_string(vcount) + " vertices)");
    }
  }
  if (vcount > 0xFFFFFFFFll) return fail(Status::ParseError, "too many vertices for 32-bit indices");
  if (skippedFaces > 0) r.warnings.push_back("OBJ: skipped " + std::to_string(skippedFaces) + " faces with fewer than 3 vertices");
  return r;
}

}  // namespace

ReadMeshResult readObj(const uint8_t* data, size_t size) {
  const char* p = reinterpret_cast<const char*>(data);
  const char* end = p + size;
  if (hasContinuation(p, end)) {
    const std::vector<char> joined = joinContinuations(p, end);
    return parseObj(joined.data(), joined.data() + joined.size());
  }
  return parseObj(p, end);
}

}  // namespace omnislice
