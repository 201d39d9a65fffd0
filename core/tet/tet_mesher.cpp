// SPDX-License-Identifier: MIT
// Isosurface stuffing (after Labelle and Shewchuk 2007) on a body-centred cubic lattice: black
// vertices at the corners of cubes of side h, red vertices at their centres. Lattice edges are
// "long" (black-black and red-red, length h) or "short" (red-black, length h sqrt(3)/2); every
// BCC tet has one long black edge, one long red edge (opposite) and four short edges, and each
// pair of face-adjacent cubes holds four of them (the red edge through the shared face plus one
// edge of that face's square).
// Steps: (1) classify every lattice vertex inside/outside by the parity of the surface crossings
// of its vertical column (all vertices of a column at once); (2) compute the exact crossing of
// the surface with every lattice edge joining an inside and an outside vertex (the cut point),
// searching only the triangles binned into the lattice cubes the edge lies in; (3) warp: a
// vertex closer to a cut point on one of its edges than alpha x (edge length) moves onto the
// nearest such cut point and becomes a surface vertex (alpha_long = 0.24999, alpha_short =
// 0.41189, the paper's values); (4) fill each BCC tet by the stencil of its sign pattern, and
// where warping pinched the boundary (an edge on more than two boundary faces) put the warped
// ends back and fill again; (5) move interior vertices of slivers (left by put-back vertices)
// where that raises the smallest dihedral angle around them, and boundary vertices lying off the
// surface by more than roundoff onto it (closest point), each move shortened or undone if it
// would flatten a tet. Output tets are oriented by their position in the undeformed lattice (cut
// points at edge midpoints), where every stencil is a true subdivision of its BCC tet, so an
// inverted tet would show as negative volume rather than being silently flipped.
#include "common/det_math.h"
#include "common/stopwatch.h"
#include "tet/tet_mesher.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "geometry/aabb_tree.h"

namespace omnislice {
namespace {

using Vec3 = Eigen::Vector3d;

constexpr double kAlphaLong = 0.24999;
constexpr double kAlphaShort = 0.41189;
// Cut points keep this fraction of the edge from its ends (1e-3 x cell, far below the
// boundary tolerance).
constexpr double kMinCutParameter = 1e-3;
// Interior vertices of tets with a smaller dihedral angle than this are moved to improve them.
constexpr double kSliverDegrees = 10;
// Tets with all four vertices on the surface are kept only above this smallest dihedral.
constexpr double kMinSurfaceTetDegrees = 15;
// About 10 bytes per lattice vertex (signs, output ids, triangle bins): 160 MB at the limit.
constexpr size_t kMaxLatticeVertices = 16u * 1024u * 1024u;
// Extra tets per unit of surface area (in cell-size units) over the 12 per interior cube; with
// 1.2 the counts for cellSize = 0 land within 3 % of targetTets on spheres, the bunny, kitten
// and fertility at 60k (tests check a 1.5x band from 3k to 100k on spheres, tori and boxes).
constexpr double kSurfaceTetsPerArea = 1.2;
// Snapping guard: a move is accepted when no incident tet's 6V / l_max^3 (0.707 for the regular
// tet) falls below min(its value before the move, kMinShape).
constexpr double kMinShape = 0.05;
// Lattice origin shift (in cells) below the bounding box: more than one cell so the outermost
// layer of cubes lies entirely outside the solid, and an odd fraction so axis-aligned models do
// not put lattice planes exactly on their faces.
constexpr double kMargin = 1.2371;

double sixVolume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return (b - a).dot((c - a).cross(d - a));
}

// Smallest dihedral angle of a tet, in degrees (0 for a flat or inverted one).
double minDihedralDegrees(const Vec3 p[4]) {
  constexpr int kEdges[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
  double best = 180;
  for (const auto& e : kEdges) {
    const Vec3 axis = (p[e[1]] - p[e[0]]).normalized();
    Vec3 u = p[e[2]] - p[e[0]], v = p[e[3]] - p[e[0]];
    u -= axis.dot(u) * axis;
    v -= axis.dot(v) * axis;
    const double c = u.dot(v) / (u.norm() * v.norm());
    if (!std::isfinite(c)) return 0;
    best = std::min(best, det::acos(std::clamp(c, -1.0, 1.0)) * 57.29577951308232);
  }
  return best;
}

// 6V / (longest edge)^3: 0.707 for the regular tet, 0 for a flat one, negative when inverted.
double shapeMeasure(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double l2 = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (d - a).squaredNorm(),
                              (c - b).squaredNorm(), (d - b).squaredNorm(), (d - c).squaredNorm()});
  if (!(l2 > 0)) return 0;
  return sixVolume(a, b, c, d) / (l2 * std::sqrt(l2));
}

// The BCC lattice: (nx+1)(ny+1)(nz+1) black vertices then nx ny nz red ones.
struct Lattice {
  int nx = 0, ny = 0, nz = 0;
  Vec3 origin{0, 0, 0};
  double h = 1;
  uint32_t nb = 0, nr = 0;

  uint32_t count() const { return nb + nr; }
  uint32_t black(int i, int j, int k) const {
    return uint32_t(i + (nx + 1) * (j + size_t(ny + 1) * k));
  }
  uint32_t red(int i, int j, int k) const { return nb + uint32_t(i + nx * (j + size_t(ny) * k)); }
  bool isRed(uint32_t v) const { return v >= nb; }
  void decode(uint32_t v, int& i, int& j, int& k) const {
    if (v < nb) {
      i = int(v % uint32_t(nx + 1));
      v /= uint32_t(nx + 1);
      j = int(v % uint32_t(ny + 1));
      k = int(v / uint32_t(ny + 1));
    } else {
      v -= nb;
      i = int(v % uint32_t(nx));
      v /= uint32_t(nx);
      j = int(v % uint32_t(ny));
      k = int(v / uint32_t(ny));
    }
  }
  Vec3 position(uint32_t v) const {
    int i, j, k;
    decode(v, i, j, k);
    const double s = isRed(v) ? 0.5 : 0.0;
    return origin + h * Vec3(i + s, j + s, k + s);
  }
  // Neighbours of v along lattice edges (6 long, up to 8 short); `isLong` per neighbour.
  int neighbours(uint32_t v, uint32_t* out, bool* isLong) const {
    int i, j, k, n = 0;
    decode(v, i, j, k);
    const int d[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    if (!isRed(v)) {
      for (const auto& e : d) {
        const int a = i + e[0], b = j + e[1], c = k + e[2];
        if (a < 0 || b < 0 || c < 0 || a > nx || b > ny || c > nz) continue;
        isLong[n] = true;
        out[n++] = black(a, b, c);
      }
      for (int s = 0; s < 8; ++s) {
        const int a = i - 1 + (s & 1), b = j - 1 + ((s >> 1) & 1), c = k - 1 + (s >> 2);
        if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz) continue;
        isLong[n] = false;
        out[n++] = red(a, b, c);
      }
    } else {
      for (const auto& e : d) {
        const int a = i + e[0], b = j + e[1], c = k + e[2];
        if (a < 0 || b < 0 || c < 0 || a >= nx || b >= ny || c >= nz) continue;
        isLong[n] = true;
        out[n++] = red(a, b, c);
      }
      for (int s = 0; s < 8; ++s) {
        isLong[n] = false;
        out[n++] = black(i + (s & 1), j + ((s >> 1) & 1), k + (s >> 2));
      }
    }
    return n;
  }
  // Cube holding p (clamped to the lattice).
  size_t cubeOf(const Vec3& p) const {
    int c[3];
    const int n[3] = {nx, ny, nz};
    for (int a = 0; a < 3; ++a) {
      const double t = std::floor((p[a] - origin[a]) / h);
      c[a] = t < 0 ? 0 : (t >= n[a] ? n[a] - 1 : int(t));
    }
    return size_t(c[0]) + size_t(nx) * (size_t(c[1]) + size_t(ny) * size_t(c[2]));
  }
};

uint64_t edgeKey(uint32_t u, uint32_t v) {
  if (u > v) std::swap(u, v);
  return (uint64_t(u) << 32) | v;
}

// Segment p + t d, t in [0, 1], against triangle (a, b, c) (Moller-Trumbore, slightly inclusive
// so a crossing through a shared triangle edge is found on at least one side).
bool segmentTriangle(const Vec3& p, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c,
                     double& t) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 pv = d.cross(e2);
  const double det = e1.dot(pv);
  if (det == 0 || !std::isfinite(det)) return false;
  const double inv = 1.0 / det;
  const Vec3 s = p - a;
  const double u = s.dot(pv) * inv;
  constexpr double eps = 1e-9;
  if (u < -eps || u > 1 + eps) return false;
  const Vec3 qv = s.cross(e1);
  const double v = d.dot(qv) * inv;
  if (v < -eps || u + v > 1 + eps) return false;
  t = e2.dot(qv) * inv;
  return t >= -eps && t <= 1 + eps;
}

// Triangles binned into the lattice cubes their (slightly grown) bounding boxes overlap.
struct TriangleBins {
  std::vector<uint32_t> start;  // per cube, CSR
  std::vector<uint32_t> tris;
};

struct Solid {
  std::vector<Vec3> a, b, c;  // valid triangles' corners
};

TriangleBins binTriangles(const Solid& s, const Lattice& L) {
  TriangleBins bins;
  const size_t cubes = size_t(L.nx) * L.ny * L.nz;
  bins.start.assign(cubes + 1, 0);
  const int n[3] = {L.nx, L.ny, L.nz};
  auto range = [&](size_t t, int lo[3], int hi[3]) {
    const Vec3 mn = s.a[t].cwiseMin(s.b[t]).cwiseMin(s.c[t]);
    const Vec3 mx = s.a[t].cwiseMax(s.b[t]).cwiseMax(s.c[t]);
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::clamp(int(std::floor((mn[k] - L.origin[k]) / L.h - 1e-6)), 0, n[k] - 1);
      hi[k] = std::clamp(int(std::floor((mx[k] - L.origin[k]) / L.h + 1e-6)), 0, n[k] - 1);
    }
  };
  for (int pass = 0; pass < 2; ++pass) {
    for (size_t t = 0; t < s.a.size(); ++t) {
      int lo[3], hi[3];
      range(t, lo, hi);
      for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j)
          for (int i = lo[0]; i <= hi[0]; ++i) {
            const size_t c = size_t(i) + size_t(L.nx) * (size_t(j) + size_t(L.ny) * k);
            if (pass == 0) {
              ++bins.start[c + 1];
            } else {
              bins.tris[bins.start[c]++] = uint32_t(t);
            }
          }
    }
    if (pass == 0) {
      for (size_t c = 0; c < cubes; ++c) bins.start[c + 1] += bins.start[c];
      bins.tris.resize(bins.start[cubes]);
    } else {
      for (size_t c = cubes; c > 0; --c) bins.start[c] = bins.start[c - 1];
      bins.start[0] = 0;
    }
  }
  return bins;
}

// Reference of an output vertex: a lattice vertex id, or count() + cut index.
struct Stuffer {
  const Lattice& L;
  const std::vector<int8_t>& sign;
  const std::unordered_map<uint64_t, uint32_t>& cutOf;
  const std::vector<uint32_t>& cutU;  // inside end of each cut edge
  const std::vector<uint32_t>& cutV;  // outside end
  const std::vector<Vec3>& cutPos;    // position of each cut point
  const AabbTree& tree;
  std::vector<uint32_t> out;  // 4 references per emitted tet

  uint32_t cut(uint32_t a, uint32_t b) const { return L.count() + cutOf.at(edgeKey(a, b)); }

  Vec3 reference(uint32_t r) const {
    if (r < L.count()) return L.position(r);
    const uint32_t c = r - L.count();
    return 0.5 * (L.position(cutU[c]) + L.position(cutV[c]));
  }

  void emit(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    if (sixVolume(reference(a), reference(b), reference(c), reference(d)) < 0) std::swap(c, d);
    out.insert(out.end(), {a, b, c, d});
  }

  // Fills one BCC tet by the stencil of its sign pattern. Quadrilaterals lying on a lattice face
  // (shared with the neighbouring BCC tet) are split by the diagonal from their lattice vertex of
  // lower id, which both neighbours choose alike; with that rule the prism of the (3-, 1+) case
  // never has cyclic diagonals (its lowest vertex takes two of them).
  void fill(const uint32_t v[4], const Vec3* latticeActual) {
    uint32_t neg[4], zer[4], pos[4];
    int nn = 0, nz = 0, np = 0;
    for (int k = 0; k < 4; ++k) {
      const int8_t s = sign[v[k]];
      if (s < 0) {
        neg[nn++] = v[k];
      } else if (s == 0) {
        zer[nz++] = v[k];
      } else {
        pos[np++] = v[k];
      }
    }
    if (np == 0) {
      if (nn == 0) {
        // All four on the surface: keep the tet when its centroid is inside and it is not a
        // sliver (four surface points on a nearly flat patch); dropping one changes the volume
        // by that sliver only.
        const Vec3 g = 0.25 * (latticeActual[0] + latticeActual[1] + latticeActual[2] +
                               latticeActual[3]);
        if (minDihedralDegrees(latticeActual) < kMinSurfaceTetDegrees || !tree.inside(g)) return;
      }
      emit(v[0], v[1], v[2], v[3]);
      return;
    }
    if (nn == 0) return;
    for (int x = 1; x < nn; ++x)  // ascending ids (at most 3)
      for (int y = x; y > 0 && neg[y - 1] > neg[y]; --y) std::swap(neg[y - 1], neg[y]);
    if (nn == 1 && nz == 0) {
      const uint32_t a = neg[0];
      emit(a, cut(a, pos[0]), cut(a, pos[1]), cut(a, pos[2]));
    } else if (nn == 1 && nz == 1) {
      const uint32_t a = neg[0];
      emit(a, zer[0], cut(a, pos[0]), cut(a, pos[1]));
    } else if (nn == 1 && nz == 2) {
      const uint32_t a = neg[0];
      emit(a, zer[0], zer[1], cut(a, pos[0]));
    } else if (nn == 2 && nz == 1) {
      // Pyramid apex z over the quadrilateral (a, b, c_bp, c_ap) on face (a, b, p).
      const uint32_t a = neg[0], b = neg[1], z = zer[0], p = pos[0];
      const uint32_t cap = cut(a, p), cbp = cut(b, p);
      emit(z, a, b, cbp);
      emit(z, a, cbp, cap);
    } else if (nn == 2 && nz == 0) {
      // Prism (m, c_mp, c_mq) - (o, c_op, c_oq), m the lower id: the side quadrilaterals take
      // the diagonals m-c_op and m-c_oq; the surface quadrilateral its shorter diagonal.
      const uint32_t m = neg[0], o = neg[1], p = pos[0], q = pos[1];
      const uint32_t cmp = cut(m, p), cmq = cut(m, q), cop = cut(o, p), coq = cut(o, q);
      emit(m, o, cop, coq);
      const uint32_t n = L.count();
      const double d1 = (cutPos[cmp - n] - cutPos[coq - n]).squaredNorm();
      const double d2 = (cutPos[cmq - n] - cutPos[cop - n]).squaredNorm();
      if (d1 <= d2) {
        emit(m, cmp, cmq, coq);
        emit(m, cmp, coq, cop);
      } else {
        emit(m, cmp, cmq, cop);
        emit(m, cmq, coq, cop);
      }
    } else {
      // nn == 3, np == 1: prism (m, s, t) - (c_mp, c_sp, c_tp), m < s < t.
      const uint32_t m = neg[0], s = neg[1], t = neg[2], p = pos[0];
      const uint32_t cmp = cut(m, p), csp = cut(s, p), ctp = cut(t, p);
      emit(m, cmp, csp, ctp);
      emit(m, s, t, ctp);
      emit(m, s, ctp, csp);
    }
  }
};

void fail(TetMesherResult& r, Status s, std::string message) {
  r = TetMesherResult{};
  r.status = s;
  r.message = std::move(message);
}

std::string fmt(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

const char* const kStage = "tetmesh";

Outcome cancelled() { return failed<Outcome>(Status::Cancelled, "tetrahedralize: cancelled"); }

// ---- Input and options.
Outcome checkMesherOptions(const Mesh& solid, const TetMesherOptions& options) {
  auto fail = [](Status s, std::string message) { return failed<Outcome>(s, std::move(message)); };
  if (solid.triangles.empty() || solid.positions.empty()) {
    return fail(Status::EmptyInput, "tetrahedralize: the solid has no triangles");
  }
  if (!std::isfinite(options.cellSize) || options.cellSize < 0) {
    return fail(Status::InvalidOption,
                "tetrahedralize: cellSize must be finite and >= 0 (got " + fmt(options.cellSize) + ")");
  }
  if (!std::isfinite(options.boundaryTolerance) || options.boundaryTolerance < 0) {
    return fail(Status::InvalidOption, "tetrahedralize: boundaryTolerance must be finite and >= 0");
  }
  if (options.maxTets == 0 || (options.cellSize == 0 && options.targetTets == 0)) {
    return fail(Status::InvalidOption, "tetrahedralize: targetTets and maxTets must be positive");
  }
  return {};
}

// The solid's triangles, bounding box, volume and area.
struct SolidInfo {
  Solid s;
  Vec3 lo, hi;
  double volume = 0, area = 0, diag = 0;

  // Expected tets for cell size h: 12 per interior cube plus the boundary excess.
  double expectedTets(double h) const {
    return 12.0 * volume / (h * h * h) + kSurfaceTetsPerArea * area / (h * h);
  }
  double sizeFor(double tets) const {  // expectedTets(h) = tets, by bisection on log h
    double a = 1e-9 * diag, b = 10 * diag;
    for (int it = 0; it < 200; ++it) {
      const double m = std::sqrt(a * b);
      (expectedTets(m) > tets ? a : b) = m;
    }
    return b;
  }
};

// DegenerateInput (an index out of range, no volume) or NonFiniteVertex.
Outcome readSolid(const Mesh& solid, SolidInfo& info) {
  const size_t nv = solid.vertexCount();
  Solid& s = info.s;
  s.a.reserve(solid.faceCount());
  s.b.reserve(solid.faceCount());
  s.c.reserve(solid.faceCount());
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  double volume6 = 0, area2 = 0;
  // Volume against a point of the model (not the origin), so far-off models keep precision.
  const Vec3 ref = solid.triangles[0] < nv ? solid.vertex(solid.triangles[0]) : Vec3(0, 0, 0);
  for (size_t f = 0; f < solid.faceCount(); ++f) {
    const uint32_t i = solid.triangles[3 * f], j = solid.triangles[3 * f + 1],
                   k = solid.triangles[3 * f + 2];
    if (i >= nv || j >= nv || k >= nv) {
      return failed<Outcome>(Status::DegenerateInput, "tetrahedralize: triangle " + std::to_string(f) +
                                                          " has a vertex index out of range");
    }
    const Vec3 a = solid.vertex(i), b = solid.vertex(j), c = solid.vertex(k);
    if (!a.allFinite() || !b.allFinite() || !c.allFinite()) {
      return failed<Outcome>(Status::NonFiniteVertex,
                             "tetrahedralize: triangle " + std::to_string(f) + " has a non-finite vertex");
    }
    lo = lo.cwiseMin(a).cwiseMin(b).cwiseMin(c);
    hi = hi.cwiseMax(a).cwiseMax(b).cwiseMax(c);
    volume6 += (a - ref).dot((b - ref).cross(c - ref));
    area2 += (b - a).cross(c - a).norm();
    s.a.push_back(a);
    s.b.push_back(b);
    s.c.push_back(c);
  }
  info.lo = lo;
  info.hi = hi;
  info.volume = std::abs(volume6) / 6.0;
  info.area = area2 / 2.0;
  info.diag = (hi - lo).norm();
  if (!(info.volume > 1e-12 * info.diag * info.diag * info.diag)) {
    return failed<Outcome>(Status::DegenerateInput, "tetrahedralize: the solid encloses no volume");
  }
  return {};
}

// The lattice of cell size h around the box [lo, hi]. InvalidOption when it would have more
// than kMaxLatticeVertices vertices.
Outcome makeLattice(const Vec3& lo, const Vec3& hi, double h, Lattice& L) {
  L.h = h;
  L.origin = lo - Vec3::Constant(kMargin * h);
  {
    const Vec3 n = ((hi - L.origin) / h).array() + kMargin + 1.0;
    const double total = (n.x() + 1) * (n.y() + 1) * (n.z() + 1) + n.x() * n.y() * n.z();
    if (!(total <= double(kMaxLatticeVertices))) {
      return failed<Outcome>(Status::InvalidOption,
                             "tetrahedralize: cellSize " + fmt(h) + " mm needs a lattice of " + fmt(total) +
                                 " vertices (limit " + std::to_string(kMaxLatticeVertices) +
                                 "): the solid is too thin or sparse for its bounding box at this size");
    }
    L.nx = std::max(2, int(std::ceil(n.x())));
    L.ny = std::max(2, int(std::ceil(n.y())));
    L.nz = std::max(2, int(std::ceil(n.z())));
  }
  L.nb = uint32_t((L.nx + 1) * size_t(L.ny + 1) * (L.nz + 1));
  L.nr = uint32_t(size_t(L.nx) * L.ny * L.nz);
  return {};
}

// ---- (1) Classification by column parity: sign[v] = -1 inside, +1 outside. OpenMesh when a
// column enters the surface more often than it leaves it; Cancelled.
Outcome classifyColumns(const AabbTree& tree, const Lattice& L, const ProgressFn& progress,
                        std::vector<int8_t>& sign) {
  const double h = L.h;
  sign.assign(L.count(), 1);
  size_t unbalanced = 0;
  std::vector<ColumnCrossing> cr;
  const size_t columns = size_t(L.nx + 1) * (L.ny + 1) + size_t(L.nx) * L.ny;
  size_t done = 0;
  for (int red = 0; red < 2; ++red) {
    const int ni = red ? L.nx : L.nx + 1, nj = red ? L.ny : L.ny + 1, nk = red ? L.nz : L.nz + 1;
    const double off = red ? 0.5 : 0.0;
    for (int j = 0; j < nj; ++j) {
      if (!reportProgress(progress, kStage, 0.3 * double(done) / double(columns))) return cancelled();
      for (int i = 0; i < ni; ++i, ++done) {
        tree.columnCrossings(L.origin.x() + (i + off) * h, L.origin.y() + (j + off) * h, cr);
        if (cr.empty()) continue;
        std::sort(cr.begin(), cr.end(),
                  [](const ColumnCrossing& p, const ColumnCrossing& q) { return p.z < q.z; });
        size_t next = 0;
        int w = 0, total = 0;
        for (const ColumnCrossing& c : cr) total += c.sign;
        if (total != 0) ++unbalanced;
        for (int k = 0; k < nk; ++k) {
          const double z = L.origin.z() + (k + off) * h;
          while (next < cr.size() && cr[next].z <= z) w += cr[next++].sign;
          if (w != 0) sign[red ? L.red(i, j, k) : L.black(i, j, k)] = -1;
        }
      }
    }
  }
  if (unbalanced > 0) {
    return failed<Outcome>(Status::OpenMesh, "tetrahedralize: the surface is not closed (" +
                                                 std::to_string(unbalanced) +
                                                 " lattice columns enter it more often than they leave it)");
  }
  return {};
}

// The cut points of the lattice edges joining an inside and an outside vertex.
struct Cuts {
  std::unordered_map<uint64_t, uint32_t> cutOf;  // edge key -> cut index
  std::vector<uint32_t> cutU, cutV;              // inside and outside end of each cut edge
  std::vector<Vec3> cutPos;                      // position of each cut point
  size_t insideVertices = 0;
};

// ---- (2) Cut points on edges joining inside and outside vertices. Cancelled.
Outcome cutPoints(const Solid& s, const AabbTree& tree, const Lattice& L, const std::vector<int8_t>& sign,
                  const ProgressFn& progress, Cuts& cuts) {
  const TriangleBins bins = binTriangles(s, L);
  for (uint32_t u = 0; u < L.count(); ++u) {
    if ((u & 0xffff) == 0 && !reportProgress(progress, kStage, 0.3 + 0.1 * double(u) / L.count())) {
      return cancelled();
    }
    if (sign[u] >= 0) continue;
    ++cuts.insideVertices;
    uint32_t nb[14];
    bool isLong[14];
    const int n = L.neighbours(u, nb, isLong);
    const Vec3 pu = L.position(u);
    for (int e = 0; e < n; ++e) {
      if (sign[nb[e]] <= 0) continue;
      const Vec3 pv = L.position(nb[e]), d = pv - pu;
      double best = 2;
      size_t cubes[3] = {L.cubeOf(pu), L.cubeOf(pv), L.cubeOf(0.5 * (pu + pv))};
      for (int q = 0; q < 3; ++q) {
        if ((q > 0 && cubes[q] == cubes[0]) || (q > 1 && cubes[q] == cubes[1])) continue;
        for (uint32_t x = bins.start[cubes[q]]; x < bins.start[cubes[q] + 1]; ++x) {
          const uint32_t t = bins.tris[x];
          double tt;
          if (segmentTriangle(pu, d, s.a[t], s.b[t], s.c[t], tt) && tt < best) best = tt;
        }
      }
      if (best > 1) {
        // No crossing found in floating point (the parity saw one): take the surface point
        // nearest the edge's midpoint, projected onto the edge.
        const ClosestPoint cp = tree.closest(0.5 * (pu + pv));
        best = cp.triangle >= 0 ? (cp.point - pu).dot(d) / d.squaredNorm() : 0.5;
      }
      // Strictly inside the edge, so an un-warped end never coincides with its cut point.
      best = std::clamp(best, kMinCutParameter, 1 - kMinCutParameter);
      cuts.cutOf.emplace(edgeKey(u, nb[e]), uint32_t(cuts.cutPos.size()));
      cuts.cutU.push_back(u);
      cuts.cutV.push_back(nb[e]);
      cuts.cutPos.push_back(pu + best * d);
    }
  }
  return {};
}

// ---- (3) Warp lattice vertices that violate a cut point on one of their edges.
class Warping {
 public:
  Warping(const Lattice& L, const Cuts& cuts, std::vector<int8_t>& sign)
      : L_(L), cuts_(cuts), sign_(sign), originalSign_(sign), frozen_(L.count(), 0) {
    for (uint32_t c = 0; c < cuts.cutPos.size(); ++c) {
      const uint32_t ends[2] = {cuts.cutU[c], cuts.cutV[c]};
      const Vec3 pu = L.position(ends[0]), pv = L.position(ends[1]);
      const bool isLong = L.isRed(ends[0]) == L.isRed(ends[1]);
      const double limit = (isLong ? kAlphaLong : kAlphaShort) * (pv - pu).norm();
      const double du = (cuts.cutPos[c] - pu).norm(), dv = (cuts.cutPos[c] - pv).norm();
      if (du < limit) violations_.push_back({ends[0], ends[1], c, du});
      if (dv < limit) violations_.push_back({ends[1], ends[0], c, dv});
    }
    std::sort(violations_.begin(), violations_.end(), [](const Violation& p, const Violation& q) {
      // A total order (ties by cut): std::sort differs between libstdc++ and libc++ on equal keys.
      if (p.vertex != q.vertex) return p.vertex < q.vertex;
      return p.distance != q.distance ? p.distance < q.distance : p.cut < q.cut;
    });
  }

  // Each vertex takes its nearest violating cut whose edge is still cut (other end not warped).
  // Re-run after vertices are put back: their neighbours' cuts on edges to them count again.
  void warp() {
    for (const Violation& v : violations_) {
      if (frozen_[v.vertex] || sign_[v.vertex] == 0 || sign_[v.other] == 0) continue;
      sign_[v.vertex] = 0;
      warped_.emplace(v.vertex, cuts_.cutPos[v.cut]);
    }
  }

  // The position of lattice vertex v, warped or not.
  Vec3 actual(uint32_t v) const {
    const auto it = warped_.find(v);
    return it != warped_.end() ? it->second : L_.position(v);
  }

  // Where warping pinched the boundary (a boundary edge of the tets `out` on more than two
  // boundary faces), the warped ends go back (un-warped, frozen). Returns the number of pinched
  // edges; `restored` counts the vertices put back.
  size_t restorePinched(const std::vector<uint32_t>& out, size_t& restored) {
    // Boundary faces: faces met once, among faces without an inside lattice vertex (a face
    // with one is always shared by two filled tets).
    std::vector<std::array<uint32_t, 3>> faces;
    const size_t nt = out.size() / 4;
    for (size_t t = 0; t < nt; ++t) {
      const uint32_t* q = &out[4 * t];
      for (int f = 0; f < 4; ++f) {
        std::array<uint32_t, 3> tri{q[(f + 1) & 3], q[(f + 2) & 3], q[(f + 3) & 3]};
        bool candidate = true;
        for (uint32_t x : tri) candidate = candidate && !(x < L_.count() && sign_[x] < 0);
        if (!candidate) continue;
        std::sort(tri.begin(), tri.end());
        faces.push_back(tri);
      }
    }
    std::sort(faces.begin(), faces.end());
    std::vector<uint64_t> edges;
    for (size_t x = 0; x < faces.size();) {
      size_t y = x;
      while (y < faces.size() && faces[y] == faces[x]) ++y;
      if (y - x == 1) {
        const auto& f = faces[x];
        edges.push_back(edgeKey(f[0], f[1]));
        edges.push_back(edgeKey(f[1], f[2]));
        edges.push_back(edgeKey(f[0], f[2]));
      }
      x = y;
    }
    std::sort(edges.begin(), edges.end());
    size_t pinched = 0;
    restored = 0;
    for (size_t x = 0; x < edges.size();) {
      size_t y = x;
      while (y < edges.size() && edges[y] == edges[x]) ++y;
      if (y - x > 2) {
        ++pinched;
        // Put back the ends that were outside first: an outside vertex is not in the mesh, so
        // its return leaves no sliver, while an inside vertex returns next to its cut points.
        const uint32_t ends[2] = {uint32_t(edges[x] >> 32), uint32_t(edges[x])};
        bool anyOutside = false;
        for (const uint32_t end : ends)
          anyOutside = anyOutside || (end < L_.count() && sign_[end] == 0 && originalSign_[end] > 0);
        for (const uint32_t end : ends) {
          if (end < L_.count() && sign_[end] == 0 && (!anyOutside || originalSign_[end] > 0)) {
            sign_[end] = originalSign_[end];
            warped_.erase(end);
            frozen_[end] = 1;
            ++restored;
          }
        }
      }
      x = y;
    }
    return pinched;
  }

 private:
  struct Violation {
    uint32_t vertex, other, cut;
    double distance;
  };
  const Lattice& L_;
  const Cuts& cuts_;
  std::vector<int8_t>& sign_;
  const std::vector<int8_t> originalSign_;
  std::vector<char> frozen_;  // put back once: never warped again
  std::unordered_map<uint32_t, Vec3> warped_;
  std::vector<Violation> violations_;
};

// ---- (4) Stencils: every BCC tet of the lattice filled by the stencil of its sign pattern
// into st.out (positions of lattice vertices by warping.actual). False when cancelled.
bool fillLattice(const Lattice& L, const std::vector<int8_t>& sign, const Warping& warping, int round,
                 const ProgressFn& progress, Stuffer& st) {
  st.out.clear();
  for (int k = 0; k < L.nz; ++k) {
    if (!reportProgress(progress, kStage, 0.4 + 0.4 * (1 - std::pow(0.5, round + double(k) / L.nz)))) {
      return false;
    }
    for (int j = 0; j < L.ny; ++j)
      for (int i = 0; i < L.nx; ++i) {
        const uint32_t r1 = L.red(i, j, k);
        for (int axis = 0; axis < 3; ++axis) {
          const int i2 = i + (axis == 0), j2 = j + (axis == 1), k2 = k + (axis == 2);
          if (i2 >= L.nx || j2 >= L.ny || k2 >= L.nz) continue;
          const uint32_t r2 = L.red(i2, j2, k2);
          // Corners of the shared face, in cyclic order.
          uint32_t b[4];
          if (axis == 0) {
            b[0] = L.black(i2, j, k), b[1] = L.black(i2, j + 1, k);
            b[2] = L.black(i2, j + 1, k + 1), b[3] = L.black(i2, j, k + 1);
          } else if (axis == 1) {
            b[0] = L.black(i, j2, k), b[1] = L.black(i + 1, j2, k);
            b[2] = L.black(i + 1, j2, k + 1), b[3] = L.black(i, j2, k + 1);
          } else {
            b[0] = L.black(i, j, k2), b[1] = L.black(i + 1, j, k2);
            b[2] = L.black(i + 1, j + 1, k2), b[3] = L.black(i, j + 1, k2);
          }
          if (sign[r1] > 0 && sign[r2] > 0 && sign[b[0]] > 0 && sign[b[1]] > 0 &&
              sign[b[2]] > 0 && sign[b[3]] > 0)
            continue;
          for (int e = 0; e < 4; ++e) {
            const uint32_t v[4] = {r1, r2, b[e], b[(e + 1) & 3]};
            Vec3 pa[4];
            for (int q = 0; q < 4; ++q) {
              if (sign[v[q]] <= 0) pa[q] = warping.actual(v[q]);
            }
            st.fill(v, pa);
          }
        }
      }
  }
  return true;
}

// Compact the references into the output mesh.
TetMesh compactMesh(const std::vector<uint32_t>& out, const Lattice& L, const Cuts& cuts, const Warping& warping) {
  TetMesh mesh;
  std::vector<int32_t> outId(size_t(L.count()) + cuts.cutPos.size(), -1);
  mesh.tets.resize(out.size());
  for (size_t x = 0; x < out.size(); ++x) {
    const uint32_t ref = out[x];
    if (outId[ref] < 0) {
      outId[ref] = int32_t(mesh.positions.size() / 3);
      const Vec3 p = ref < L.count() ? warping.actual(ref) : cuts.cutPos[ref - L.count()];
      mesh.positions.insert(mesh.positions.end(), {p.x(), p.y(), p.z()});
    }
    mesh.tets[x] = uint32_t(outId[ref]);
  }
  return mesh;
}

// The tets around each vertex (CSR) and the vertices on the boundary, for step (5).
struct VertexTets {
  std::vector<uint32_t> first, inc;
  std::vector<char> onBoundary;

  explicit VertexTets(const TetMesh& mesh) {
    const Mesh boundary = tetBoundary(mesh);
    const size_t n = mesh.vertexCount();
    onBoundary.assign(n, 0);
    for (uint32_t v : boundary.triangles) onBoundary[v] = 1;
    // Vertex -> incident tets (CSR), for the guard.
    first.assign(n + 1, 0);
    inc.resize(mesh.tets.size());
    for (uint32_t v : mesh.tets) ++first[v + 1];
    for (size_t v = 0; v < n; ++v) first[v + 1] += first[v];
    std::vector<uint32_t> fill(first.begin(), first.end() - 1);
    for (size_t x = 0; x < mesh.tets.size(); ++x) inc[fill[mesh.tets[x]]++] = uint32_t(x / 4);
  }
};

double tetShape(const TetMesh& mesh, uint32_t t) {
  const uint32_t* q = &mesh.tets[4 * size_t(t)];
  return shapeMeasure(mesh.vertex(q[0]), mesh.vertex(q[1]), mesh.vertex(q[2]), mesh.vertex(q[3]));
}

// Slivers (left where a vertex was put back next to its cut points): their interior
// vertices try a few positions (toward the centroid of their neighbours, or away from the
// surface) and keep the one that most raises the smallest dihedral angle around them.
// 6V / l_max^3 <= sin(smallest dihedral), so tets above sin(kSliverDegrees) are skipped
// cheaply. Smooth models have no such tet. Returns the number of moves.
size_t smoothSlivers(const AabbTree& tree, const VertexTets& vt, double h, TetMesh& mesh) {
  const std::vector<uint32_t>& first = vt.first;
  const std::vector<uint32_t>& inc = vt.inc;
  size_t smoothed = 0;
  auto angleOf = [&](uint32_t t) {
    const uint32_t* q = &mesh.tets[4 * size_t(t)];
    const Vec3 p[4] = {mesh.vertex(q[0]), mesh.vertex(q[1]), mesh.vertex(q[2]),
                       mesh.vertex(q[3])};
    return sixVolume(p[0], p[1], p[2], p[3]) > 0 ? minDihedralDegrees(p) : -1.0;
  };
  auto worstAround = [&](uint32_t v) {
    double w = 180;
    for (uint32_t x = first[v]; x < first[v + 1]; ++x) w = std::min(w, angleOf(inc[x]));
    return w;
  };
  const double shapeLimit = det::sin(kSliverDegrees * 0.017453292519943295);
  std::vector<uint32_t> movable;
  for (uint32_t t = 0; t < mesh.tetCount(); ++t) {
    if (tetShape(mesh, t) >= shapeLimit || angleOf(t) >= kSliverDegrees) continue;
    for (int k = 0; k < 4; ++k) {
      const uint32_t v = mesh.tets[4 * size_t(t) + k];
      if (!vt.onBoundary[v]) movable.push_back(v);
    }
  }
  std::sort(movable.begin(), movable.end());
  movable.erase(std::unique(movable.begin(), movable.end()), movable.end());
  for (int pass = 0; pass < 3; ++pass) {
    for (uint32_t v : movable) {
      Vec3 centroid(0, 0, 0);
      double count = 0;
      for (uint32_t x = first[v]; x < first[v + 1]; ++x)
        for (int k = 0; k < 4; ++k) {
          const uint32_t w = mesh.tets[4 * size_t(inc[x]) + k];
          if (w != v) centroid += mesh.vertex(w), count += 1;
        }
      centroid /= count;
      const Vec3 p = mesh.vertex(v);
      const ClosestPoint cp = tree.closest(p);
      const Vec3 inward = cp.triangle >= 0 && cp.distance > 0 ? Vec3((p - cp.point) / cp.distance)
                                                             : Vec3(0, 0, 0);
      const Vec3 candidates[6] = {centroid, 0.5 * (p + centroid), p + 0.1 * h * inward,
                                  p + 0.2 * h * inward, p + 0.3 * h * inward,
                                  p + 0.4 * h * inward};
      double best = worstAround(v);
      Vec3 bestPos = p;
      for (const Vec3& q : candidates) {
        for (int k = 0; k < 3; ++k) mesh.positions[3 * v + k] = q[k];
        const double w = worstAround(v);
        if (w > best) best = w, bestPos = q;
      }
      for (int k = 0; k < 3; ++k) mesh.positions[3 * v + k] = bestPos[k];
      if (bestPos != p) ++smoothed;
    }
  }
  return smoothed;
}

// Boundary vertices onto the surface (options.snap), each move shortened or undone when it
// would flatten a tet; the boundary figures (count, largest distance, unsnapped) into r.
void snapBoundary(const AabbTree& tree, const VertexTets& vt, const TetMesherOptions& options, double h,
                  double tolerance, TetMesh& mesh, TetMesherResult& r) {
  const std::vector<uint32_t>& first = vt.first;
  const std::vector<uint32_t>& inc = vt.inc;
  const size_t n = mesh.vertexCount();
  std::vector<double> before;
  for (uint32_t v = 0; v < n; ++v) {
    if (!vt.onBoundary[v]) continue;
    ++r.boundaryVertices;
    const Vec3 p = mesh.vertex(v);
    const ClosestPoint cp = tree.closest(p);
    double dist = cp.distance;
    // Every vertex off the surface by more than roundoff is moved (cut points kept 1e-3 of an
    // edge from a lattice vertex, flat faces' vertices back onto their plane); the tolerance
    // only decides what counts as unsnapped.
    if (options.snap && dist > 1e-9 * h) {
      before.clear();
      for (uint32_t x = first[v]; x < first[v + 1]; ++x) before.push_back(tetShape(mesh, inc[x]));
      double step = 1;
      for (int attempt = 0; attempt < 6; ++attempt, step *= 0.5) {
        const Vec3 q = p + step * (cp.point - p);
        for (int k = 0; k < 3; ++k) mesh.positions[3 * v + k] = q[k];
        bool good = true;
        for (uint32_t x = first[v]; x < first[v + 1] && good; ++x) {
          good = tetShape(mesh, inc[x]) >= std::min(before[x - first[v]], kMinShape);
        }
        if (good) {
          dist = (q - cp.point).norm();
          break;
        }
        for (int k = 0; k < 3; ++k) mesh.positions[3 * v + k] = p[k];
      }
    }
    r.maxBoundaryDistance = std::max(r.maxBoundaryDistance, dist);
    if (dist > tolerance) ++r.unsnapped;
  }
}

// One meshing at options.cellSize (or the size estimated from targetTets when 0).
TetMesherResult meshOnce(const Mesh& solid, const TetMesherOptions& options,
                         const ProgressFn& progress) {
  TetMesherResult r;
  auto failWith = [&](const Outcome& o) {
    fail(r, o.status, o.message);
    return r;
  };
  Outcome ok = checkMesherOptions(solid, options);
  if (!ok.ok()) return failWith(ok);
  SolidInfo info;
  ok = readSolid(solid, info);
  if (!ok.ok()) return failWith(ok);
  const double h = options.cellSize > 0 ? options.cellSize : info.sizeFor(double(options.targetTets));
  const double expected = info.expectedTets(h);
  if (expected > double(options.maxTets)) {
    fail(r, Status::InvalidOption,
         "tetrahedralize: cellSize " + fmt(h) + " mm would make about " + fmt(expected) +
             " tets, more than maxTets " + std::to_string(options.maxTets) +
             "; a cellSize of at least " + fmt(info.sizeFor(double(options.maxTets))) + " mm fits");
    return r;
  }
  Lattice L;
  ok = makeLattice(info.lo, info.hi, h, L);
  if (!ok.ok()) return failWith(ok);
  r.cellSize = h;
  const double tolerance = options.boundaryTolerance > 0 ? options.boundaryTolerance : 0.05 * h;
  if (!reportProgress(progress, kStage, 0)) return failWith(cancelled());

  // (1) and (2): signs and cut points.
  double t0 = nowMs();
  const AabbTree tree(solid);
  std::vector<int8_t> sign;
  ok = classifyColumns(tree, L, progress, sign);
  if (!ok.ok()) return failWith(ok);
  Cuts cuts;
  ok = cutPoints(info.s, tree, L, sign, progress, cuts);
  if (!ok.ok()) return failWith(ok);
  r.classifyMs = nowMs() - t0;
  if (cuts.insideVertices == 0) {
    fail(r, Status::DegenerateInput,
         "tetrahedralize: no lattice vertex lies inside the solid at cellSize " + fmt(h) +
             " mm: the solid is thinner than the lattice (use a smaller cellSize)");
    return r;
  }
  if (!reportProgress(progress, kStage, 0.4)) return failWith(cancelled());

  // (3) and (4): warp, fill. Warping can pinch the boundary where the surface comes back within
  // a cell (two sheets of a crevice warped onto the same lattice edge): then a boundary edge
  // joins more than two boundary faces. Without warping, filling by sign patterns is marching
  // tetrahedra, whose boundary is always a closed 2-manifold, so the warped ends of such edges
  // are put back (un-warped) and the lattice re-filled, until no such edge remains.
  t0 = nowMs();
  Warping warping(L, cuts, sign);
  warping.warp();
  Stuffer st{L, sign, cuts.cutOf, cuts.cutU, cuts.cutV, cuts.cutPos, tree, {}};
  for (int round = 0;; ++round) {
    if (!fillLattice(L, sign, warping, round, progress, st)) return failWith(cancelled());
    size_t restored = 0;
    const size_t pinched = warping.restorePinched(st.out, restored);
    r.unwarped += restored;
    if (pinched == 0 || restored == 0 || round >= 8) {
      r.pinchedEdges = pinched;
      break;
    }
    warping.warp();
  }
  r.mesh = compactMesh(st.out, L, cuts, warping);
  TetMesh& mesh = r.mesh;
  r.stuffMs = nowMs() - t0;
  if (mesh.tetCount() == 0) {
    fail(r, Status::DegenerateInput,
         "tetrahedralize: no tet inside the solid at cellSize " + fmt(h) +
             " mm: the solid is thinner than the lattice (use a smaller cellSize)");
    return r;
  }
  if (mesh.tetCount() > options.maxTets) {
    const double tets = double(mesh.tetCount());
    fail(r, Status::InvalidOption,
         "tetrahedralize: cellSize " + fmt(h) + " mm makes " + fmt(tets) +
             " tets, more than maxTets " + std::to_string(options.maxTets) +
             "; a cellSize of at least " +
             fmt(h * std::cbrt(tets / double(options.maxTets))) + " mm fits");
    return r;
  }
  if (!reportProgress(progress, kStage, 0.8)) return failWith(cancelled());

  // (5) Slivers, then boundary vertices onto the surface, guarded.
  t0 = nowMs();
  {
    const VertexTets vt(mesh);
    r.smoothed += smoothSlivers(tree, vt, h, mesh);
    snapBoundary(tree, vt, options, h, tolerance, mesh, r);
  }
  r.snapMs = nowMs() - t0;
  r.quality = tetQuality(mesh);
  r.volumeRatio = r.quality.volume / info.volume;
  reportProgress(progress, kStage, 1);
  return r;
}

}  // namespace

TetMesherResult tetrahedralize(const Mesh& solid, const TetMesherOptions& options,
                               const ProgressFn& progress) {
  TetMesherResult r = meshOnce(solid, options, progress);
  if (options.cellSize != 0 || !r.ok()) return r;
  // The size estimate assumes the solid is resolved; thin parts lost at that size (or surface
  // detail) can leave the count far from targetTets: re-mesh at a corrected size, at most three
  // times, first assuming count ~ h^-3, then by the secant on log(count) over log(h) (thin
  // parts appear as h shrinks, so the exponent is steeper), keeping the closest result; a retry
  // that fails (e.g. over maxTets) ends the search.
  const double target = double(options.targetTets);
  double prevH = 0, prevCount = 0;
  TetMesherResult best = std::move(r);
  double h = best.cellSize, count = double(best.mesh.tetCount());
  for (int attempt = 0; attempt < 3; ++attempt) {
    const double ratio = count / target;
    if (ratio > 0.8 && ratio < 1.25) break;
    double exponent = 3;
    if (prevH > 0 && prevH != h && prevCount > 0 && prevCount != count) {
      exponent = std::clamp(-std::log(count / prevCount) / std::log(h / prevH), 1.0, 6.0);
    }
    TetMesherOptions again = options;
    again.cellSize = h * std::pow(ratio, 1.0 / exponent);
    TetMesherResult next = meshOnce(solid, again, progress);
    if (next.status == Status::Cancelled) return next;
    if (!next.ok()) break;
    prevH = h;
    prevCount = count;
    h = next.cellSize;
    count = double(next.mesh.tetCount());
    if (std::abs(std::log(count / target)) <
        std::abs(std::log(double(best.mesh.tetCount()) / target))) {
      best = std::move(next);
    }
  }
  r = std::move(best);
  return r;
}

}  // namespace omnislice
