// SPDX-License-Identifier: MIT
// Tetrahedral meshes: the `.tet` reader, validation, boundary surface and quality statistics.
// The reader is line-oriented (each vertex and tet is one line, so arity errors are caught and
// messages name the line); faces and edges are matched by a counting sort on their smallest
// vertex followed by small per-bucket sorts, linear in practice.
#include "tet/tet_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "common/math_constants.h"
#include "mesh/parse_number.h"
#include "mesh/text_cursor.h"

namespace omnislice {
namespace {


// Relative threshold below which a tet counts as flat: |6 V| <= kFlatRelative * (longest edge)^3.
// Only roundoff-level volumes are rejected; slivers stay (tetQuality reports them).
constexpr double kFlatRelative = 1e-12;

// Local vertex triples of the four outward faces of a positively oriented tet (a, b, c, d):
// (b, c, d), (a, d, c), (a, b, d), (a, c, b).
constexpr int kFaceCorners[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
constexpr int kEdgeCorners[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

Eigen::Vector3d at(const std::vector<double>& p, uint32_t i) {
  return {p[3 * size_t(i)], p[3 * size_t(i) + 1], p[3 * size_t(i) + 2]};
}

// 6 x signed volume of (a, b, c, d): (b - a) . ((c - a) x (d - a)).
double sixVolume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                 const Eigen::Vector3d& d) {
  return (b - a).dot((c - a).cross(d - a));
}

// Checks one tet (indices into positions with nv vertices) and flips it to positive volume.
// Returns Ok, or the status with the reason in `why`.
Status checkTet(const std::vector<double>& positions, size_t nv, uint32_t* t, size_t& flipped,
                std::string& why) {
  for (int k = 0; k < 4; ++k) {
    if (t[k] >= nv) {
      why = "vertex index " + std::to_string(t[k]) + " out of range (" + std::to_string(nv) + " vertices)";
      return Status::DegenerateInput;
    }
  }
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      if (t[i] == t[j]) {
        why = "repeated vertex " + std::to_string(t[i]);
        return Status::DegenerateInput;
      }
    }
  }
  const Eigen::Vector3d a = at(positions, t[0]), b = at(positions, t[1]), c = at(positions, t[2]),
                        d = at(positions, t[3]);
  const double v6 = sixVolume(a, b, c, d);
  double longest = 0;
  const Eigen::Vector3d p[4] = {a, b, c, d};
  for (const auto& e : kEdgeCorners) longest = std::max(longest, (p[e[1]] - p[e[0]]).squaredNorm());
  longest = std::sqrt(longest);
  if (!(std::abs(v6) > kFlatRelative * longest * longest * longest)) {
    why = "zero-volume (flat) tet on vertices " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " +
          std::to_string(t[2]) + " " + std::to_string(t[3]);
    return Status::DegenerateInput;
  }
  if (v6 < 0) {
    std::swap(t[2], t[3]);
    ++flipped;
  }
  return Status::Ok;
}

void warnUnused(TetMeshResult& r) {
  std::vector<char> used(r.mesh.vertexCount(), 0);
  for (uint32_t v : r.mesh.tets) used[v] = 1;
  const size_t unused = static_cast<size_t>(std::count(used.begin(), used.end(), 0));
  if (unused > 0) r.warnings.push_back(std::to_string(unused) + " vertices are used by no tet");
  if (r.flipped > 0) {
    r.warnings.push_back(std::to_string(r.flipped) + " negatively oriented tets were flipped");
  }
}

// Line scanner: yields the next line holding a token (blank lines and '#' comments skipped),
// with its 1-based number, and the tokens of that line.
struct LineScanner {
  const char* p;
  const char* end;
  size_t line = 0;  // number of the last line returned
  const char* lb = nullptr;
  const char* le = nullptr;  // current line content [lb, le), comment stripped

  LineScanner(const uint8_t* data, size_t size)
      : p(reinterpret_cast<const char*>(data)), end(reinterpret_cast<const char*>(data) + size) {}

  bool nextLine() {
    while (p != end) {
      const char* nl = static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(end - p)));
      const char* stop = nl ? nl : end;
      ++line;
      lb = p;
      le = stop;
      p = nl ? nl + 1 : end;
      const char* hash = static_cast<const char*>(std::memchr(lb, '#', static_cast<size_t>(le - lb)));
      if (hash) le = hash;
      const char* q = lb;
      while (q != le && isTextSpace(*q)) ++q;
      if (q != le) {
        lb = q;
        return true;
      }
    }
    return false;
  }

  // Next token of the current line.
  bool token(const char*& b, const char*& e) {
    while (lb != le && isTextSpace(*lb)) ++lb;
    if (lb == le) return false;
    b = lb;
    while (lb != le && !isTextSpace(*lb)) ++lb;
    e = lb;
    return true;
  }

  // Tokens of the current line, up to max (returns the full count, storing at most max).
  int tokens(const char** bs, const char** es, int max) {
    int n = 0;
    const char* b;
    const char* e;
    while (token(b, e)) {
      if (n < max) {
        bs[n] = b;
        es[n] = e;
      }
      ++n;
    }
    return n;
  }
};

bool isVertexWord(const char* b, const char* e) {
  return tokenIs(b, e, "vertices") || tokenIs(b, e, "vertex") || tokenIs(b, e, "verts") || tokenIs(b, e, "nodes");
}

bool isTetWord(const char* b, const char* e) {
  return tokenIs(b, e, "tets") || tokenIs(b, e, "tet") || tokenIs(b, e, "tetrahedra") ||
         tokenIs(b, e, "tetrahedrons") || tokenIs(b, e, "tetras") || tokenIs(b, e, "elements");
}

// Faces of the tets grouped by vertex set. For each tet face f = 4 t + k (local face k of
// kFaceCorners), group[f] is the id of its vertex set and groupSize[id] the number of tet faces
// sharing it.
struct FaceGroups {
  std::vector<uint32_t> group;
  std::vector<uint32_t> groupSize;
};

// Groups items (each an ascending vertex tuple of N entries, N = 2 or 3) by equality. keys has
// N * count entries; returns per-item group id and per-group size. Counting sort on the first
// vertex, then sorting each (small) bucket on the remaining entries.
template <int N>
void groupTuples(const std::vector<uint32_t>& keys, size_t nv, std::vector<uint32_t>& group,
                 std::vector<uint32_t>& groupSize) {
  const size_t count = keys.size() / N;
  std::vector<uint32_t> start(nv + 1, 0);
  for (size_t i = 0; i < count; ++i) ++start[keys[N * i] + 1];
  for (size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  // Bucket by first vertex, each item carrying its remaining vertices packed into one key.
  std::vector<std::pair<uint64_t, uint32_t>> order(count);
  {
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (size_t i = 0; i < count; ++i) {
      const uint64_t rest = N == 3 ? (uint64_t(keys[N * i + 1]) << 32) | keys[N * i + N - 1] : keys[N * i + 1];
      order[fill[keys[N * i]]++] = {rest, static_cast<uint32_t>(i)};
    }
  }
  group.assign(count, 0);
  groupSize.clear();
  for (size_t v = 0; v < nv; ++v) {
    const auto b = order.begin() + start[v], e = order.begin() + start[v + 1];
    std::sort(b, e);
    for (auto it = b; it != e; ++it) {
      if (it == b || (it - 1)->first != it->first) groupSize.push_back(0);
      group[it->second] = static_cast<uint32_t>(groupSize.size() - 1);
      ++groupSize.back();
    }
  }
}

FaceGroups groupFaces(const TetMesh& mesh) {
  const size_t nt = mesh.tetCount();
  std::vector<uint32_t> keys(12 * nt);
  for (size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 4; ++k) {
      uint32_t f[3] = {mesh.tets[4 * t + kFaceCorners[k][0]], mesh.tets[4 * t + kFaceCorners[k][1]],
                       mesh.tets[4 * t + kFaceCorners[k][2]]};
      std::sort(f, f + 3);
      std::copy(f, f + 3, keys.begin() + 3 * (4 * t + k));
    }
  }
  FaceGroups g;
  groupTuples<3>(keys, mesh.vertexCount(), g.group, g.groupSize);
  return g;
}

bool indicesInRange(const TetMesh& mesh) {
  const size_t nv = mesh.vertexCount();
  for (uint32_t v : mesh.tets) {
    if (v >= nv) return false;
  }
  return mesh.positions.size() % 3 == 0 && mesh.tets.size() % 4 == 0;
}

}  // namespace

TetMeshResult readTetMesh(const uint8_t* data, size_t size) {
  TetMeshResult r;
  if (size == 0 || data == nullptr) {
    r.status = Status::EmptyInput;
    r.message = ".tet: empty input";
    return r;
  }
  // A UTF-8 byte order mark (some Windows editors write one) is skipped.
  const size_t bom = size >= 3 && data[0] == 0xEF && data[1] == 0xBB && data[2] == 0xBF ? 3 : 0;
  LineScanner s(data + bom, size - bom);
  auto fail = [&r, &s](Status st, const std::string& what) {
    r.status = st;
    r.message = ".tet line " + std::to_string(s.line) + ": " + what;
    r.mesh = TetMesh();
    r.flipped = 0;
    r.warnings.clear();
    return r;
  };
  if (!s.nextLine()) {
    r.status = Status::EmptyInput;
    r.message = ".tet: no content (only blank lines or comments)";
    return r;
  }
  // Header: vertex count [word], tet count [word], on one or two lines.
  const char* b = nullptr;
  const char* e = nullptr;
  int64_t counts[2] = {-1, -1};
  for (int which = 0; which < 2; ++which) {
    if (!s.token(b, e)) {
      if (!s.nextLine()) return fail(Status::TruncatedFile, "file ends before the tet count");
      s.token(b, e);
    }
    if (!parseInt64(b, e, counts[which])) {
      return fail(Status::ParseError, std::string("expected the ") + (which == 0 ? "vertex" : "tet") +
                                          " count, found " + tokenForMessage(b, e));
    }
    if (counts[which] < 0 || counts[which] > 0xFFFFFFFFll) {
      return fail(Status::ParseError, std::string("bad ") + (which == 0 ? "vertex" : "tet") + " count " +
                                          std::to_string(counts[which]));
    }
    const char* save = s.lb;
    if (s.token(b, e)) {
      if (which == 0 ? isVertexWord(b, e) : isTetWord(b, e)) {
        // the optional word, consumed
      } else if (which == 0) {
        s.lb = save;  // "N M" on one line: the tet count follows
      } else {
        return fail(Status::ParseError, "unexpected " + tokenForMessage(b, e) + " after the tet count");
      }
    }
  }
  if (s.token(b, e)) return fail(Status::ParseError, "unexpected " + tokenForMessage(b, e) + " after the counts");
  const size_t nv = static_cast<size_t>(counts[0]), nt = static_cast<size_t>(counts[1]);
  if (nt == 0) return fail(Status::DegenerateInput, "the file declares no tets");
  TetMesh& m = r.mesh;
  // Reserve only as far as the bytes could hold (a vertex line takes at least 6 bytes, a tet 10).
  m.positions.reserve(3 * std::min(nv, size / 6 + 1));
  m.tets.reserve(4 * std::min(nt, size / 10 + 1));
  const char* tb[6];
  const char* te[6];
  for (size_t i = 0; i < nv; ++i) {
    if (!s.nextLine()) {
      return fail(Status::TruncatedFile, "file ends after " + std::to_string(i) + " of " + std::to_string(nv) +
                                             " declared vertices");
    }
    const int n = s.tokens(tb, te, 3);
    if (n != 3) {
      return fail(Status::ParseError, "vertex " + std::to_string(i) + " has " + std::to_string(n) +
                                          " values, expected 3 (x y z)");
    }
    for (int k = 0; k < 3; ++k) {
      double x;
      if (!parseDouble(tb[k], te[k], x)) return fail(Status::ParseError, "bad coordinate " + tokenForMessage(tb[k], te[k]));
      if (!std::isfinite(x)) {
        return fail(Status::NonFiniteVertex, "non-finite coordinate " + tokenForMessage(tb[k], te[k]) + " of vertex " +
                                                 std::to_string(i));
      }
      m.positions.push_back(x);
    }
  }
  std::string why;
  for (size_t i = 0; i < nt; ++i) {
    if (!s.nextLine()) {
      return fail(Status::TruncatedFile, "file ends after " + std::to_string(i) + " of " + std::to_string(nt) +
                                             " declared tets");
    }
    const int n = s.tokens(tb, te, 6);
    int64_t arity = -1;
    if (n >= 1 && !parseInt64(tb[0], te[0], arity)) {
      return fail(Status::ParseError, "bad tet vertex count " + tokenForMessage(tb[0], te[0]));
    }
    if (arity != 4) {
      return fail(Status::ParseError, "tet " + std::to_string(i) + " starts with " + std::to_string(arity) +
                                          ", expected 4 (only tetrahedra)");
    }
    if (n != 5) {
      return fail(Status::ParseError, "tet " + std::to_string(i) + " has " + std::to_string(n - 1) +
                                          " indices, expected 4");
    }
    uint32_t t[4];
    for (int k = 0; k < 4; ++k) {
      int64_t idx;
      if (!parseInt64(tb[k + 1], te[k + 1], idx)) {
        return fail(Status::ParseError, "bad vertex index " + tokenForMessage(tb[k + 1], te[k + 1]));
      }
      if (idx < 0 || static_cast<uint64_t>(idx) >= nv) {
        return fail(Status::DegenerateInput, "tet " + std::to_string(i) + ": vertex index " + std::to_string(idx) +
                                                 " out of range (" + std::to_string(nv) + " vertices, 0-based)");
      }
      t[k] = static_cast<uint32_t>(idx);
    }
    const Status st = checkTet(m.positions, nv, t, r.flipped, why);
    if (st != Status::Ok) return fail(st, "tet " + std::to_string(i) + ": " + why);
    m.tets.insert(m.tets.end(), t, t + 4);
  }
  size_t trailing = 0;
  while (s.nextLine()) ++trailing;
  if (trailing > 0) r.warnings.push_back(".tet: ignored " + std::to_string(trailing) + " lines after the declared tets");
  warnUnused(r);
  return r;
}

TetMeshResult validateTetMesh(TetMesh mesh) {
  TetMeshResult r;
  auto fail = [&r](Status st, const std::string& what) {
    r.status = st;
    r.message = "tet mesh: " + what;
    r.mesh = TetMesh();
    r.flipped = 0;
    r.warnings.clear();
    return r;
  };
  if (mesh.positions.size() % 3 != 0) return fail(Status::ParseError, "positions size is not a multiple of 3");
  if (mesh.tets.size() % 4 != 0) return fail(Status::ParseError, "tets size is not a multiple of 4");
  if (mesh.tets.empty()) return fail(mesh.positions.empty() ? Status::EmptyInput : Status::DegenerateInput, "no tets");
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    if (!std::isfinite(mesh.positions[i])) {
      return fail(Status::NonFiniteVertex, "non-finite coordinate of vertex " + std::to_string(i / 3));
    }
  }
  const size_t nv = mesh.vertexCount();
  std::string why;
  for (size_t t = 0; t < mesh.tetCount(); ++t) {
    const Status st = checkTet(mesh.positions, nv, &mesh.tets[4 * t], r.flipped, why);
    if (st != Status::Ok) return fail(st, "tet " + std::to_string(t) + ": " + why);
  }
  r.mesh = std::move(mesh);
  warnUnused(r);
  return r;
}

std::vector<TetBoundaryFace> tetBoundaryFaces(const TetMesh& mesh) {
  std::vector<TetBoundaryFace> out;
  if (!indicesInRange(mesh)) return out;
  const FaceGroups g = groupFaces(mesh);
  for (size_t f = 0; f < g.group.size(); ++f) {
    if (g.groupSize[g.group[f]] != 1) continue;
    const size_t t = f / 4, k = f % 4;
    TetBoundaryFace face;
    face.tet = uint32_t(t);
    for (int j = 0; j < 3; ++j) face.v[j] = mesh.tets[4 * t + kFaceCorners[k][j]];
    out.push_back(face);
  }
  return out;
}

Mesh tetBoundary(const TetMesh& mesh) {
  Mesh out;
  out.positions = mesh.positions;
  for (const TetBoundaryFace& f : tetBoundaryFaces(mesh))
    out.triangles.insert(out.triangles.end(), f.v.begin(), f.v.end());
  return out;
}

TetQuality tetQuality(const TetMesh& mesh) {
  TetQuality q;
  if (!indicesInRange(mesh) || mesh.tets.empty()) return q;
  const size_t nt = mesh.tetCount();
  q.minDihedralDegrees = 180;
  q.maxDihedralDegrees = 0;
  q.minRadiusRatio = 1e300;
  std::vector<uint32_t> edgeKeys(12 * nt);
  for (size_t t = 0; t < nt; ++t) {
    const uint32_t* ti = &mesh.tets[4 * t];
    Eigen::Vector3d p[4];
    for (int k = 0; k < 4; ++k) p[k] = at(mesh.positions, ti[k]);
    const double v6 = sixVolume(p[0], p[1], p[2], p[3]);
    q.volume += v6 / 6.0;
    // Outward face normals (area vectors x 2); the dihedral angle at the edge shared by faces i
    // and j is pi minus the angle between their outward normals.
    Eigen::Vector3d n[4];
    double area2 = 0;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d& a = p[kFaceCorners[k][0]];
      n[k] = (p[kFaceCorners[k][1]] - a).cross(p[kFaceCorners[k][2]] - a);
      if (v6 < 0) n[k] = -n[k];
      area2 += n[k].norm();
    }
    for (int i = 0; i < 4; ++i) {
      for (int j = i + 1; j < 4; ++j) {
        const double den = n[i].norm() * n[j].norm();
        double angle = 0;
        if (den > 0) angle = 180.0 - std::acos(std::clamp(n[i].dot(n[j]) / den, -1.0, 1.0)) * 180.0 / kPi;
        q.minDihedralDegrees = std::min(q.minDihedralDegrees, angle);
        q.maxDihedralDegrees = std::max(q.maxDihedralDegrees, angle);
      }
    }
    // r_in = 3 V / A = |6 V| / (sum of |2 area|); circumcentre offset from p0:
    // (|a|^2 (b x c) + |b|^2 (c x a) + |c|^2 (a x b)) / (2 a . (b x c)) with a, b, c the edges from p0.
    const Eigen::Vector3d a = p[1] - p[0], b = p[2] - p[0], c = p[3] - p[0];
    double ratio = 0;
    if (v6 != 0 && area2 > 0) {
      const Eigen::Vector3d o =
          (a.squaredNorm() * b.cross(c) + b.squaredNorm() * c.cross(a) + c.squaredNorm() * a.cross(b)) / (2.0 * v6);
      const double rin = std::abs(v6) / area2, rout = o.norm();
      if (rout > 0) ratio = 3.0 * rin / rout;
    }
    q.minRadiusRatio = std::min(q.minRadiusRatio, ratio);
    for (int k = 0; k < 6; ++k) {
      uint32_t u = ti[kEdgeCorners[k][0]], v = ti[kEdgeCorners[k][1]];
      if (u > v) std::swap(u, v);
      edgeKeys[2 * (6 * t + k)] = u;
      edgeKeys[2 * (6 * t + k) + 1] = v;
    }
  }
  // Mean length over the distinct edges.
  std::vector<uint32_t> group, groupSize;
  groupTuples<2>(edgeKeys, mesh.vertexCount(), group, groupSize);
  std::vector<char> seen(groupSize.size(), 0);
  double sum = 0;
  for (size_t i = 0; i < group.size(); ++i) {
    if (seen[group[i]]) continue;
    seen[group[i]] = 1;
    sum += (at(mesh.positions, edgeKeys[2 * i + 1]) - at(mesh.positions, edgeKeys[2 * i])).norm();
  }
  q.meanEdge = groupSize.empty() ? 0 : sum / static_cast<double>(groupSize.size());
  const FaceGroups g = groupFaces(mesh);
  for (uint32_t c : g.groupSize) q.nonManifoldFaces += c > 2;
  return q;
}

}  // namespace omnislice
