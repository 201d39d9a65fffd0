// SPDX-License-Identifier: MIT
// Local refinement of the found planes (plane_refinement.h): coordinate descent (refinePlanes)
// and the iterated local search around it (perturbPlanes).
#include "multidir/plane_refinement.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "common/det_math.h"
#include "common/math_constants.h"
#include "multidir/candidate_normals.h"

namespace omnislice::decomposition_detail {
namespace {

// Criteria II-IV for planes [from, end) starting from the cells kept before `from`.
bool planesValid(const Model& m, const MultidirOptions& o, Bits s, size_t count,
                 const std::vector<Vec3>& ns, const std::vector<double>& ds, size_t from, FloodScratch& fs) {
  const size_t minPart = static_cast<size_t>(std::ceil(static_cast<double>(m.cells) / o.w - 1e-9));
  for (size_t k = from; k < ns.size(); ++k) {
    if (m.platformLimit(ns[k]) > ds[k] + 1e-9) return false;
    size_t nBelow = 0;
    Bits below = cellsBelow(m, s, ns[k], ds[k], nBelow);
    const size_t nAbove = count - nBelow;
    if (nAbove == 0 || nAbove < minPart) return false;
    const size_t reached = reachableBelow(m, s, ns[k], ds[k], fs);
    if (static_cast<double>(nBelow - reached) > o.floatingToleranceCells) return false;
    s.swap(below);
    count = nBelow;
  }
  return true;
}

struct Piece {
  uint32_t face;
  bool whole;  // the whole triangle (closed form), else `poly`
  Poly poly;
  double area;
  double w;    // 1 when risky in the part it falls in without plane k
};

// Pieces of the faces kept by planes [0, k), split by the later planes (plane k ignored), and
// t0 = sum of w * area over them: the risky area of parts k.. when plane k cuts nothing.
struct Pieces {
  std::vector<Piece> list;
  double t0 = 0;
};

Pieces piecesWithoutPlane(const Model& m, const std::vector<Vec3>& ns, const std::vector<double>& ds, size_t k) {
  const size_t np = ns.size();
  Pieces out;
  std::vector<Piece>& pieces = out.list;
  double& t0 = out.t0;
  for (uint32_t f = 0; f < m.tri.size(); ++f) {
    if (!(m.area[f] > 0)) continue;
    Poly poly = {m.corner[f][0], m.corner[f][1], m.corner[f][2]};
    bool whole = true;
    for (size_t i = 0; i < k && !poly.empty(); ++i) {
      double tmin = std::numeric_limits<double>::infinity(), tmax = -tmin;
      for (const Vec3& q : poly) {
        tmin = std::min(tmin, ns[i].dot(q));
        tmax = std::max(tmax, ns[i].dot(q));
      }
      if (tmin >= ds[i]) poly.clear();
      else if (tmax > ds[i]) {
        poly = clipPoly(poly, ns[i], ds[i], false);
        whole = false;
      }
    }
    if (poly.empty()) continue;
    auto add = [&](Poly&& p, bool isWhole, double w) {
      Piece pc{f, isWhole, std::move(p), 0, w};
      pc.area = isWhole ? m.area[f] : polyArea(pc.poly, m.normal[f]);
      t0 += w * pc.area;
      pieces.push_back(std::move(pc));
    };
    for (size_t j = k + 1; j < np && !poly.empty(); ++j) {
      double tmin = std::numeric_limits<double>::infinity(), tmax = -tmin;
      for (const Vec3& q : poly) {
        tmin = std::min(tmin, ns[j].dot(q));
        tmax = std::max(tmax, ns[j].dot(q));
      }
      const double w = m.riskyAlong(f, ns[j]) ? 1.0 : 0.0;
      if (tmin >= ds[j]) {
        add(std::move(poly), whole, w);
        poly.clear();
      } else if (tmax > ds[j]) {
        add(clipPoly(poly, ns[j], ds[j], true), false, w);
        poly = clipPoly(poly, ns[j], ds[j], false);
        whole = false;
      }
    }
    if (!poly.empty()) add(std::move(poly), whole, m.platRisk[f] > 0 ? 1.0 : 0.0);
  }
  return out;
}

// The offsets tried for plane k: span offsets d0 + i * delta, i in [0, span).
struct OffsetWindow {
  double d0 = 0, delta = 0;
  int span = 0;
};

// The pieces that matter for some normal tried (within `reach` of n_k) and offset of the
// window, and for each whether it lies wholly above the window along every normal tried.
// Pieces whose weight (w - risky along n') is 0 for every normal tried are skipped: a face's
// n_f . n' differs from n_f . n_k by at most |n' - n_k|, so away from the risky boundary its
// state is the same for all of them (the sums are unchanged). Likewise
// |n' . q - n_k . q| <= |n' - n_k| |q|: a piece wholly below the offset window along n_k by more
// than that is below it along every normal tried (skipped), one wholly above it is above it along
// all (its weight goes to the top offset without projecting).
void activePieces(const Model& m, const std::vector<Piece>& pieces, const Vec3& nk, double reach,
                  const OffsetWindow& win, std::vector<uint32_t>& active, std::vector<uint8_t>& aboveAll) {
  const double d0 = win.d0;
  const double top = d0 + (win.span - 1) * win.delta;
  for (uint32_t i = 0; i < pieces.size(); ++i) {
    const Piece& pc = pieces[i];
    const double margin = m.normal[pc.face].dot(nk) + m.sinAlpha;
    if (pc.w == 0 ? margin > reach : margin < -reach) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo, rho = 0;
    auto extend = [&](const Vec3& q) {
      lo = std::min(lo, nk.dot(q));
      hi = std::max(hi, nk.dot(q));
      rho = std::max(rho, q.norm());
    };
    if (pc.whole) {
      for (const Vec3& q : m.corner[pc.face]) extend(q);
    } else {
      for (const Vec3& q : pc.poly) extend(q);
    }
    const double slack = reach * rho + 1e-6;
    if (hi + slack <= d0) continue;
    active.push_back(i);
    aboveAll.push_back(lo - slack >= top ? 1 : 0);
  }
}

// A place plane k may move to, with the exact risky area of parts k.. there.
struct Option {
  double tail;
  size_t order;  // creation order: a total order, so every platform sorts alike
  Vec3 n;
  double d;
};

// tail(n, d_i) = t0 - sum over pieces of (w - risky along n) * (area above d_i) for every
// offset of the window along normal n; the offsets lowering the tail by more than 1e-6 are
// appended to `options`. Returns the number of offsets evaluated.
size_t addOffsetOptions(const Model& m, const Pieces& pieces, const std::vector<uint32_t>& active,
                        const std::vector<uint8_t>& aboveAll, const Vec3& n, const OffsetWindow& win,
                        double tail, std::vector<double>& diff, std::vector<Option>& options) {
  const double d0 = win.d0, delta = win.delta;
  const int span = win.span;
  size_t evaluated = 0;
  std::fill(diff.begin(), diff.end(), 0.0);
  for (size_t j = 0; j < active.size(); ++j) {
    const Piece& pc = pieces.list[active[j]];
    const double c = pc.w - (m.riskyAlong(pc.face, n) ? 1.0 : 0.0);
    if (c == 0) continue;
    if (aboveAll[j]) {
      diff[span - 1] += c * pc.area;
      continue;
    }
    double a, b = 0, e;
    if (pc.whole) {
      a = n.dot(m.corner[pc.face][0]);
      b = n.dot(m.corner[pc.face][1]);
      e = n.dot(m.corner[pc.face][2]);
      sort3(a, b, e);
    } else {
      a = std::numeric_limits<double>::infinity();
      e = -a;
      for (const Vec3& q : pc.poly) {
        a = std::min(a, n.dot(q));
        e = std::max(e, n.dot(q));
      }
    }
    // wholly above offsets i <= iFull, partly above iFull < i < iTop
    const int iFull = static_cast<int>(std::floor((a - d0) / delta));
    const int iTop = static_cast<int>(std::ceil((e - d0) / delta));
    if (iTop <= 0) continue;
    if (iFull >= 0) diff[std::min(iFull, span - 1)] += c * pc.area;
    for (int i = std::max(iFull + 1, 0); i < std::min(iTop, span); ++i) {
      const double d = d0 + i * delta;
      const double above = pc.whole ? pc.area * triFractionAbove(a, b, e, d)
                                    : polyArea(clipPoly(pc.poly, n, d, true), m.normal[pc.face]);
      diff[i] += c * above;
      if (i > 0) diff[i - 1] -= c * above;
    }
  }
  double above = 0;
  for (int i = span - 1; i >= 0; --i) {
    above += diff[i];
    ++evaluated;
    const double t = pieces.t0 - above;
    if (t < tail - 1e-6) options.push_back({t, options.size(), n, d0 + i * delta});
  }
  return evaluated;
}

// Moves plane k to the first of the (sorted) options, among the first 24, with which planes
// k.. still meet Criteria II-IV. True when it moved.
bool moveToFirstValid(const Model& m, const MultidirOptions& o, const std::vector<Option>& options, size_t k,
                      std::vector<Vec3>& ns, std::vector<double>& ds, FloodScratch& fs) {
  size_t count = 0;
  const Bits kept = cellsKept(m, ns, ds, k, count);
  int tries = 0;
  for (const Option& op : options) {
    if (++tries > 24) break;
    std::vector<Vec3> ns2 = ns;
    std::vector<double> ds2 = ds;
    ns2[k] = op.n;
    ds2[k] = op.d;
    if (!planesValid(m, o, kept, count, ns2, ds2, k, fs)) continue;
    ns.swap(ns2);
    ds.swap(ds2);
    return true;
  }
  return false;
}

}  // namespace

size_t refinePlanes(const Model& m, const MultidirOptions& o, bool fourDof, const Vec3& axis,
                    std::vector<Vec3>& ns, std::vector<double>& ds, const ProgressFn& progress,
                    double fraction, bool& cancelled) {
  const size_t np = ns.size();
  const double delta = 0.5 * o.offsetStepMm;
  const int half = static_cast<int>(std::lround(4.0 / delta));
  const int span = 2 * half + 1;
  size_t evaluated = 0;
  FloodScratch fs;
  for (int pass = 0; pass < 2; ++pass) {
    bool improved = false;
    for (size_t k = 0; k < np; ++k) {
      if (!reportProgress(progress, "decompose", fraction)) {
        cancelled = true;
        return evaluated;
      }
      const std::vector<double> risk = exactRisk(m, ns, ds);
      double tail = 0;
      for (size_t i = k; i < risk.size(); ++i) tail += risk[i];
      if (tail <= kMinGainMm2) break;
      const Pieces pieces = piecesWithoutPlane(m, ns, ds, k);
      std::vector<Vec3> normals = nearbyNormals(o, fourDof, axis, ns[k]);
      normals.insert(normals.begin(), ns[k]);
      double reach = 0;
      for (const Vec3& n : normals) reach = std::max(reach, (n - ns[k]).norm());
      reach += 1e-9;
      const OffsetWindow win{ds[k] - half * delta, delta, span};
      std::vector<uint32_t> active;
      std::vector<uint8_t> aboveAll;
      activePieces(m, pieces.list, ns[k], reach, win, active, aboveAll);
      std::vector<Option> options;
      std::vector<double> diff(span + 1);
      for (const Vec3& n : normals) {
        evaluated += addOffsetOptions(m, pieces, active, aboveAll, n, win, tail, diff, options);
      }
      std::sort(options.begin(), options.end(), [](const Option& x, const Option& y) {
        return x.tail != y.tail ? x.tail < y.tail : x.order < y.order;
      });
      if (moveToFirstValid(m, o, options, k, ns, ds, fs)) improved = true;
    }
    if (!improved) break;
  }
  return evaluated;
}

// Iterated local search on the refined planes (the refinement alone stops in the first local
// minimum): `o.perturbations` times, one plane, picked by a fixed pseudo-random sequence (the same
// on every platform), jumps 6-20 deg away (4dof: a rotation of 6-20 deg about the axis, on the
// stepper's angles, within range) and up to 8 offset steps; when Criteria II-IV still hold, the
// whole sequence is refined again and kept if its exact J_G drops. Stops once J_G <= delta0.
// Returns the number of moves kept. (Refining only the moved plane's neighbours costs ~30% less
// and measured a little worse over 6 random sequences x 4 models, e.g. branches_16 0.494 against
// 0.489 on average.)
size_t perturbPlanes(const Model& m, const MultidirOptions& o, bool fourDof, const Vec3& axis,
                     std::vector<Vec3>& ns, std::vector<double>& ds, double& jg, const ProgressFn& progress,
                     double fractionFrom, double fractionTo, bool& cancelled, MultidirStats& stats) {
  if (ns.empty() || o.perturbations <= 0 || !o.candidateNormals.empty()) return 0;
  uint64_t state = 0x9E3779B97F4A7C15ULL;
  auto uniform = [&state]() {  // [0, 1), exact on every platform
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0);
  };
  const double halfStep = 0.5 * o.offsetStepMm;
  const double minZ = det::cos(o.maxTiltDeg * kPi / 180) - 1e-12;
  FloodScratch fs;
  std::vector<Bits> keptBefore;
  std::vector<size_t> keptCount;
  size_t kept = 0;
  for (int it = 0; it < o.perturbations && jg > o.delta0; ++it) {
    const double fraction = fractionFrom + (fractionTo - fractionFrom) * it / o.perturbations;
    if (!reportProgress(progress, "decompose", fraction)) {
      cancelled = true;
      return kept;
    }
    ++stats.perturbations;
    std::vector<Vec3> ns2 = ns;
    std::vector<double> ds2 = ds;
    const size_t k = std::min(ns.size() - 1, static_cast<size_t>(uniform() * static_cast<double>(ns.size())));
    const double angle = (6 + 14 * uniform()) * kPi / 180;
    const double azimuth = 2 * kPi * uniform();
    const double shift = (2 * uniform() - 1) * 8 * o.offsetStepMm;
    if (!fourDof) {
      const Vec3 u = ns[k].unitOrthogonal(), v = ns[k].cross(u);
      ns2[k] = (det::cos(angle) * ns[k] + det::sin(angle) * (det::cos(azimuth) * u + det::sin(azimuth) * v)).normalized();
      if (ns2[k].z() < minZ) continue;
    } else {
      const Vec3 side = axis.cross(Vec3(0, 0, 1)).normalized();
      double t = det::atan2(ns[k].dot(side), ns[k].z()) + (azimuth < kPi ? angle : -angle);
      if (o.stepAngleDeg > 0) {
        const double step = o.stepAngleDeg * kPi / 180;
        t = std::round(t / step) * step;
      }
      if (std::abs(t) > o.rangeDeg * kPi / 180 + 1e-9) continue;
      ns2[k] = det::cos(t) * Vec3(0, 0, 1) + det::sin(t) * side;
    }
    ds2[k] = std::round((ds[k] + shift) / halfStep) * halfStep;
    // The cells kept by the planes before k (unchanged by the move), once per plane until a
    // move is kept.
    if (keptBefore.size() != ns.size()) {
      keptBefore.assign(ns.size(), Bits());
      keptCount.assign(ns.size(), 0);
    }
    if (keptBefore[k].empty()) keptBefore[k] = cellsKept(m, ns, ds, k, keptCount[k]);
    if (!planesValid(m, o, keptBefore[k], keptCount[k], ns2, ds2, k, fs)) continue;
    stats.refineEvaluated += refinePlanes(m, o, fourDof, axis, ns2, ds2, progress, fraction, cancelled);
    if (cancelled) return kept;
    double jg2 = 0;
    for (double r : exactRisk(m, ns2, ds2)) jg2 += r;
    if (jg2 < jg - kMinGainMm2) {
      ns.swap(ns2);
      ds.swap(ds2);
      jg = jg2;
      ++kept;
      keptBefore.clear();
    }
  }
  return kept;
}

}  // namespace omnislice::decomposition_detail
