// SPDX-License-Identifier: MIT
// Internal to the multidir decomposition (decomposition*.cpp, plane_search.cpp,
// plane_refinement.cpp, candidate_normals.cpp): the model the plane search works on (paper 000
// Sections III-IV). Its faces (area, unit normal, risk on the platform part), the occupancy grid
// of cell centres inside the solid (volumes and Criterion II), coarse volume samples (the
// Criterion IV prefilter) and the platform P (Criterion III); cell sets as bit sets with the
// Criterion II flood fill; the exact J_G of a plane sequence; and the convex-polygon clipping the
// exact sums share. Conventions as in decomposition.h.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "common/status.h"
#include "mesh/mesh.h"
#include "multidir/decomposition.h"
#include "multidir/risky_faces.h"

namespace omnislice::decomposition_detail {

constexpr double kMinGainMm2 = 1e-6;  // a plane must remove at least this much risky area
constexpr uint32_t kNoCell = 0xffffffffu;

using Vec3 = Eigen::Vector3d;
using Poly = std::vector<Vec3>;

inline bool isFinite(const Vec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

// ---- options and mesh -----------------------------------------------------------------------

// The options every entry point uses (alphaMaxDeg, w, platform*, gridResolution,
// floatingToleranceCells): InvalidOption when one is out of range.
Outcome checkCommonOptions(const MultidirOptions& o);

// EmptyInput, ParseError (index out of range, arrays not triples), NonFiniteVertex, or
// InvalidOption when the mesh lies below z = 0.
Outcome checkMesh(const Mesh& mesh);

// ---- geometry helpers -----------------------------------------------------------------------

// Keeps the part of a convex planar polygon with n . x >= d (above) or <= d (below).
inline Poly clipPoly(const Poly& p, const Vec3& n, double d, bool keepAbove) {
  Poly out;
  const size_t m = p.size();
  if (m == 0) return out;
  out.reserve(m + 1);
  for (size_t i = 0; i < m; ++i) {
    const Vec3& a = p[i];
    const Vec3& b = p[(i + 1) % m];
    double sa = n.dot(a) - d, sb = n.dot(b) - d;
    if (!keepAbove) {
      sa = -sa;
      sb = -sb;
    }
    if (sa >= 0) out.push_back(a);
    if ((sa >= 0) != (sb >= 0) && sa != sb) {
      const double t = sa / (sa - sb);
      out.push_back(a + t * (b - a));
    }
  }
  if (out.size() < 3) out.clear();
  return out;
}

inline double polyArea(const Poly& p, const Vec3& faceNormal) {
  if (p.size() < 3) return 0;
  Vec3 s = Vec3::Zero();
  for (size_t i = 0; i < p.size(); ++i) s += p[i].cross(p[(i + 1) % p.size()]);
  return std::max(0.0, 0.5 * faceNormal.dot(s));
}

// Fraction of a triangle's area above a plane, from its corners' heights a <= b <= c along the
// normal, for a < d < c: one corner above -> (c-d)^2 / ((c-a)(c-b)); two -> 1 - (d-a)^2 / ((b-a)(c-a)).
inline double triFractionAbove(double a, double b, double c, double d) {
  if (d >= b) return (c - d) * (c - d) / ((c - a) * (c - b));
  return 1.0 - (d - a) * (d - a) / ((b - a) * (c - a));
}

inline void sort3(double& a, double& b, double& c) {
  if (a > b) std::swap(a, b);
  if (b > c) std::swap(b, c);
  if (a > b) std::swap(a, b);
}

// ---- the model: faces, occupancy grid, platform ------------------------------------------------

struct Model {
  std::vector<Vec3> vert;
  std::vector<std::array<uint32_t, 3>> tri;
  std::vector<std::array<Vec3, 3>> corner;  // face corners, copied for locality in the sweeps
  std::vector<double> area;
  std::vector<Vec3> normal;      // unit (zero for degenerate faces: never risky)
  std::vector<double> platRisk;  // area when risky along +Z on the platform part, else 0
  double sinAlpha = 0;
  double jgBefore = 0;
  double volume = 0;
  double surfaceArea = 0;  // sum of the face areas in face order (sets the search's fixed point)
  Vec3 lo, hi;
  // Occupancy grid: cells whose centre is inside the solid (non-zero winding of vertical rays),
  // connected to the platform layer. Grid index = i + nx * (j + ny * k); one empty cell pads
  // every side; layer k = 1 holds the centres at z = h / 2.
  double h = 0;
  Vec3 origin;
  int nx = 0, ny = 0, nz = 0;
  std::vector<int32_t> cellOf;    // grid index -> cell id, -1 = not solid
  std::vector<uint32_t> gridOf;   // cell id -> grid index
  std::vector<Vec3> centre;       // cell id -> centre
  std::vector<uint32_t> baseCells;  // cells of the platform layer
  std::vector<uint8_t> isBase;      // cell id -> in the platform layer
  std::vector<uint32_t> nbr;        // 6 face neighbours per cell (kNoCell when not solid)
  size_t cells = 0;
  // Coarse volume samples (Criterion IV prefilter): blocks of blockFactor^3 cells, each at the
  // mean centre of its cells, weighted by their count.
  std::vector<Vec3> samplePos;
  std::vector<double> sampleWeight;
  size_t orphans = 0;
  // Platform P (Criterion III).
  std::vector<Eigen::Vector2d> footprint;
  double margin = 0, radius = 0;

  double platformLimit(const Vec3& n) const {  // max over P of n . p
    const double nxy = std::sqrt(n.x() * n.x() + n.y() * n.y());  // not hypot: libm differs in wasm
    if (radius > 0) return radius * nxy;
    double best = -std::numeric_limits<double>::infinity();
    for (const auto& p : footprint) best = std::max(best, n.x() * p.x() + n.y() * p.y());
    return best + margin * nxy;
  }
  bool riskyAlong(size_t f, const Vec3& d) const { return omnislice::riskyAlong(normal[f], d, sinAlpha); }
};

// The model of a placed, closed solid: faces, occupancy grid, volume samples and platform.
// Statuses as checkMesh, plus DegenerateInput (zero extent, or no cell centre inside the solid).
Outcome buildModel(const Mesh& mesh, const MultidirOptions& o, Model& m);

// ---- cell sets and Criterion II --------------------------------------------------------------

using Bits = std::vector<uint64_t>;
inline bool testBit(const Bits& b, size_t i) { return (b[i >> 6] >> (i & 63)) & 1u; }
inline void setBit(Bits& b, size_t i) { b[i >> 6] |= uint64_t(1) << (i & 63); }

template <class F>
void forEachBit(const Bits& b, F&& f) {
  for (size_t w = 0; w < b.size(); ++w) {
    uint64_t x = b[w];
    while (x) {
      const int t = __builtin_ctzll(x);
      f(w * 64 + static_cast<size_t>(t));
      x &= x - 1;
    }
  }
}

struct FloodScratch {
  std::vector<uint32_t> stamp;
  std::vector<uint32_t> queue;
  uint32_t gen = 0;
};

// Counts the cells of S n {n . x <= d} reachable from the platform layer through face neighbours.
size_t reachableBelow(const Model& m, const Bits& s, const Vec3& n, double d, FloodScratch& fs);

// The occupancy cells kept by planes [0, k).
Bits cellsKept(const Model& m, const std::vector<Vec3>& ns, const std::vector<double>& ds, size_t k,
               size_t& count);

// The cells of s whose centres lie on or below the plane {x : n.x = d}, and how many.
Bits cellsBelow(const Model& m, const Bits& s, const Vec3& n, double d, size_t& count);

// ---- exact J_G of a plane sequence ------------------------------------------------------------

// partRisk[k] for the part above plane k, partRisk.back() for the platform part.
std::vector<double> exactRisk(const Model& m, const std::vector<Vec3>& ns, const std::vector<double>& ds);

}  // namespace omnislice::decomposition_detail
