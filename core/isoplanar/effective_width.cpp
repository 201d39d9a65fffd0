// SPDX-License-Identifier: MIT
// Cusp-area equilibrium of paper 003 Section 2.1 (see effective_width.h for the geometry).
//
// Frame: the first NL point p1 at the origin, k to the right, n up (nozzle side). The current
// surface is the circle of signed curvature kappa through p1 with horizontal tangent (centre
// C = (0, -1/kappa)); the previous surface the concentric circle through the bead bottom
// p1b = (0, -h). The neighbour ellipse E2 is E1 rotated about C by kappa * a, i.e. E1 mirrored in
// the bisector line L through C at half that angle. L meets the current surface at
//   T = ((a/2) sin(x)/x, -(a/2) (1 - cos x)/x),  x = kappa a / 2,
// with inward direction d = -(sin x, cos x) and meets the previous surface at T + h d (every
// formula is written in x so that kappa -> 0 is the flat case without cancellation).
// By symmetry every area is twice an area on E1's side of L; each is a closed loop of straight
// pieces, ellipse arcs and circle arcs, integrated by Gauss-Green: a piece from P to Q contributes
// (P x Q) / 2 plus, for an arc, the signed segment between chord and arc, (ab/2)(dt - sin dt) for
// an ellipse x = c + (a cos t, b sin t) and R^2/2 (dt - sin dt) for a circle (dt signed, CCW > 0).
#include "common/math_constants.h"
#include "isoplanar/effective_width.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace omnislice {
namespace {


// t - sin t without cancellation for small t.
double segmentTerm(double t) {
  if (std::fabs(t) < 2e-2) {
    const double t2 = t * t;
    return t * t2 * (1.0 / 6 - t2 * (1.0 / 120 - t2 / 5040));
  }
  return t - std::sin(t);
}
// (t - sin t) / t^3, -> 1/6 at 0.
double segmentRatio(double t) {
  if (std::fabs(t) < 2e-2) {
    const double t2 = t * t;
    return 1.0 / 6 - t2 * (1.0 / 120 - t2 / 5040);
  }
  return (t - std::sin(t)) / (t * t * t);
}
double sinc(double t) {
  if (std::fabs(t) < 1e-4) return 1 - t * t / 6;
  return std::sin(t) / t;
}
// (1 - cos t) / t, odd, -> t / 2 at 0.
double cosc(double t) {
  if (std::fabs(t) < 1e-4) return t / 2 - t * t * t / 24;
  return (1 - std::cos(t)) / t;
}

struct P2 {
  double k = 0, n = 0;
};
P2 operator+(P2 a, P2 b) { return {a.k + b.k, a.n + b.n}; }
P2 operator*(double s, P2 a) { return {s * a.k, s * a.n}; }
double cross(P2 a, P2 b) { return a.k * b.n - a.n * b.k; }

// Supported curvature range for bead (s, h): the bead ellipse must lie inside the annulus between
// the previous and the current surface (the gap areas are then real areas). Convex: the
// current circle must contain the ellipse, which the circle of curvature at the ellipse's top
// vertex (radius s^2 / (2h)) does exactly at the limit; concave: the previous circle (radius
// R + h) must contain it. Both are capped at 2 / s (circle radius half the bead width) and the
// convex one so that the previous circle keeps a radius of at least h.
struct KappaLimits {
  double convex = 0, concave = 0;  // both > 0
};
KappaLimits kappaLimits(double s, double h) {
  KappaLimits l;
  const double cap = 2 / s;
  l.convex = std::min({2 * h / (s * s), 1 / (2 * h), cap});
  const double r = s * s / (2 * h) - h;
  l.concave = r > 1 / cap ? 1 / r : cap;
  return l;
}

struct Geometry {
  CuspAreas areas;
  double difference = 0;  // A_g - A_o
};

Geometry evaluate(double s, double h, double kappa, double a) {
  Geometry g;
  const double A = s / 2, B = h / 2, ab = A * B;
  const double half = a / 2, x = kappa * half;
  const P2 T{half * sinc(x), -half * cosc(x)};
  const P2 d{-std::sin(x), -std::cos(x)};
  const P2 Bb = T + h * d;
  const P2 p1b{0, -h};
  // Current-circle arc T -> p1 (dt = x) and previous-circle arc p1b -> Bb (dt = -x).
  const double segCurrent = kappa * half * half * half * segmentRatio(x) / 2;
  const double oneMinus = 1 - kappa * h;
  const double segPrevious = -oneMinus * oneMinus * kappa * half * half * half * segmentRatio(x) / 2;

  // L: P(t) = T + t d against E1: ((P.k)/A)^2 + ((P.n + h/2)/B)^2 = 1.
  const double ck = T.k / A, cn = (T.n + B) / B, dk = d.k / A, dn = d.n / B;
  const double qa = dk * dk + dn * dn, qb = ck * dk + cn * dn, qc = ck * ck + cn * cn - 1;
  const double disc = qb * qb - qa * qc;
  P2 top, bottom;        // E1 points where the top / bottom loops leave and rejoin E1
  P2 topL, bottomL;      // their partners on L
  double rhoTop = 0, rhoBottom = 0;
  if (disc > 0) {
    const double q = -(qb + (qb >= 0 ? 1 : -1) * std::sqrt(disc));
    double t1 = q / qa, t2 = qc / q;
    if (t1 > t2) std::swap(t1, t2);
    top = topL = T + t1 * d;
    bottom = bottomL = T + t2 * d;
    rhoTop = std::atan2((top.n + B) / B, top.k / A);
    rhoBottom = std::atan2((bottom.n + B) / B, bottom.k / A);
    g.areas.rhoUpper = rhoTop;
    g.areas.rhoLower = rhoBottom;
    g.areas.overlap = ab * segmentTerm(rhoTop - rhoBottom);
  } else {
    // Disjoint beads: no lens; the one gap is split by the segment joining the beads' widest
    // points (E1 at rho = 0 and its mirror image), which crosses L at right angles.
    const P2 w{A, -B};
    const double along = (w.k - T.k) * d.k + (w.n - T.n) * d.n;
    top = bottom = w;
    topL = bottomL = T + along * d;
    g.areas.rhoUpper = g.areas.rhoLower = std::numeric_limits<double>::quiet_NaN();
    g.areas.overlap = 0;
  }
  // Top loop: p1 -> E1 (pi/2 -> rhoTop) -> top -> topL -> T -> current arc -> p1 (p1 = origin).
  const double halfTop = ab / 2 * segmentTerm(rhoTop - kPi / 2) + cross(top, topL) / 2 +
                         cross(topL, T) / 2 + segCurrent;
  // Bottom loop: p1b -> previous arc -> Bb -> bottomL -> bottom -> E1 (rhoBottom -> -pi/2) -> p1b.
  const double halfBottom = cross(p1b, Bb) / 2 + segPrevious + cross(Bb, bottomL) / 2 +
                            cross(bottomL, bottom) / 2 + cross(bottom, p1b) / 2 +
                            ab / 2 * segmentTerm(-kPi / 2 - rhoBottom);
  g.areas.gapTop = 2 * halfTop;
  g.areas.gapBottom = 2 * halfBottom;
  g.difference = g.areas.gapTop + g.areas.gapBottom - g.areas.overlap;
  return g;
}

bool validBead(double s, double h) {
  return std::isfinite(s) && std::isfinite(h) && s > 0 && h > 0;
}

double clampKappa(double s, double h, double kappa, bool* clamped) {
  const KappaLimits l = kappaLimits(s, h);
  double k = kappa;
  if (!std::isfinite(k)) k = 0;
  if (k > l.convex) k = l.convex;
  if (k < -l.concave) k = -l.concave;
  if (clamped) *clamped = (k != kappa);
  return k;
}

}  // namespace

CuspAreas cuspAreas(double s, double h, double kappa, double arcSpacing) {
  if (!validBead(s, h) || !std::isfinite(kappa) || !std::isfinite(arcSpacing) ||
      arcSpacing <= 0) {
    CuspAreas none;
    none.rhoUpper = none.rhoLower = std::numeric_limits<double>::quiet_NaN();
    return none;
  }
  return evaluate(s, h, kappa, arcSpacing).areas;
}

EffectiveWidth effectiveWidth(double s, double h, double kappa) {
  EffectiveWidth out;
  if (!validBead(s, h)) return out;
  const double k = clampKappa(s, h, kappa, &out.clamped);
  // A_g - A_o grows with a (it is A_cell(a) - pi s h / 4 while the beads intersect, A_cell
  // linear in a); bracket it and refine by regula falsi with the Illinois modification.
  double lo = s / 8, hi = 2 * s;
  double flo = evaluate(s, h, k, lo).difference, fhi = evaluate(s, h, k, hi).difference;
  for (int i = 0; i < 60 && flo > 0; ++i) {
    lo /= 2;
    flo = evaluate(s, h, k, lo).difference;
  }
  for (int i = 0; i < 60 && fhi < 0; ++i) {
    hi *= 2;
    fhi = evaluate(s, h, k, hi).difference;
  }
  if (!(flo <= 0 && fhi >= 0)) return out;  // cannot happen for a supported kappa
  double a = lo;
  int side = 0;
  for (int it = 0; it < 100; ++it) {
    a = (lo * fhi - hi * flo) / (fhi - flo);
    if (!(a > lo && a < hi)) a = (lo + hi) / 2;
    const double fa = evaluate(s, h, k, a).difference;
    if (fa == 0 || hi - lo < 1e-13 * s) break;
    if (fa < 0) {
      lo = a;
      flo = fa;
      if (side == -1) fhi /= 2;
      side = -1;
    } else {
      hi = a;
      fhi = fa;
      if (side == 1) flo /= 2;
      side = 1;
    }
    if (std::fabs(fa) < 1e-15 * s * h) break;
  }
  const CuspAreas areas = evaluate(s, h, k, a).areas;
  out.arcSpacing = a;
  out.rho = areas.rhoUpper;
  out.overlap = areas.overlap;
  out.width = std::isfinite(areas.rhoUpper) ? s * std::cos(areas.rhoUpper) : 0;
  return out;
}

// Table (linear in kappa, cubic in h): the nodes hold the model's width WITHOUT the clamp (the closed-form geometry continues
// smoothly a little beyond the supported range), and width() clamps kappa to the supported range
// of the queried height before interpolating. The clamp, which depends on h, thus never falls
// inside a cell of the interpolated function (a kink there would cost ~1e-2 relative).
namespace {

double unclampedWidth(double s, double h, double kappa) {
  if (!(kappa * h < 1.9)) return std::numeric_limits<double>::quiet_NaN();
  double lo = s / 8, hi = 2 * s;
  double flo = evaluate(s, h, kappa, lo).difference, fhi = evaluate(s, h, kappa, hi).difference;
  if (!(flo <= 0 && fhi >= 0)) return std::numeric_limits<double>::quiet_NaN();
  double a = lo;
  for (int it = 0; it < 100 && hi - lo > 1e-13 * s; ++it) {
    a = (lo * fhi - hi * flo) / (fhi - flo);
    if (!(a > lo && a < hi)) a = (lo + hi) / 2;
    const double fa = evaluate(s, h, kappa, a).difference;
    if (std::fabs(fa) < 1e-15 * s * h) break;
    if (fa < 0) lo = a, flo = fa;
    else hi = a, fhi = fa;
  }
  const double rho = evaluate(s, h, kappa, a).areas.rhoUpper;
  return std::isfinite(rho) ? s * std::cos(rho) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

EffectiveWidthTable::EffectiveWidthTable(double s, double hMin, double hMax, double kappaMax,
                                         int kappaNodes, int heightNodes) {
  if (hMax < hMin) std::swap(hMin, hMax);
  kappaMax = std::fabs(kappaMax);
  if (!validBead(s, hMin) || !std::isfinite(hMax) || !std::isfinite(kappaMax) || kappaNodes < 2 ||
      heightNodes < 1)
    return;  // width() then answers 0
  s_ = s;
  hMin_ = hMin;
  hMax_ = hMax;
  kappaMax_ = kappaMax > 0 ? kappaMax : 2 / s;
  kn_ = kappaNodes;
  hn_ = hMax > hMin ? std::max(heightNodes, 2) : 1;
  values_.assign(static_cast<size_t>(kn_) * hn_, 0);
  for (int j = 0; j < hn_; ++j) {
    const double h = hn_ == 1 ? hMin : hMin + (hMax - hMin) * j / (hn_ - 1);
    double* row = &values_[static_cast<size_t>(j) * kn_];
    for (int i = 0; i < kn_; ++i) row[i] = unclampedWidth(s, h, -kappaMax_ + 2 * kappaMax_ * i / (kn_ - 1));
    // Far beyond the supported range the geometry may not exist: continue the last value
    // (such nodes are never reached by a clamped query nor by its interpolation cell... but keep
    // them finite).
    int first = 0;
    while (first < kn_ && !std::isfinite(row[first])) ++first;
    if (first == kn_) {
      for (int i = 0; i < kn_; ++i) row[i] = effectiveWidth(s, h, 0).width;
      continue;
    }
    for (int i = 0; i < first; ++i) row[i] = row[first];
    for (int i = first + 1; i < kn_; ++i)
      if (!std::isfinite(row[i])) row[i] = row[i - 1];
  }
}

double EffectiveWidthTable::width(double kappa, double height) const {
  if (values_.empty()) return 0;
  double h = height;
  if (!(h >= hMin_)) h = hMin_;  // also NaN
  if (h > hMax_) h = hMax_;
  const KappaLimits l = kappaLimits(s_, h);
  double k = kappa;
  if (!(k == k)) k = 0;
  k = std::min(k, std::min(kappaMax_, l.convex));
  k = std::max(k, -std::min(kappaMax_, l.concave));
  double fi = (k + kappaMax_) / (2 * kappaMax_) * (kn_ - 1);
  int i = static_cast<int>(fi);
  if (i >= kn_ - 1) i = kn_ - 2;
  if (i < 0) i = 0;
  const double ti = fi - i;
  if (hn_ == 1) return values_[i] + ti * (values_[i + 1] - values_[i]);
  const double fj = (h - hMin_) / (hMax_ - hMin_) * (hn_ - 1);
  auto row = [&](int j) {
    const double* r = &values_[static_cast<size_t>(j) * kn_ + i];
    return r[0] + ti * (r[1] - r[0]);
  };
  if (hn_ < 4) {
    int j = std::min(static_cast<int>(fj), hn_ - 2);
    const double tj = fj - j, w0 = row(j);
    return w0 + tj * (row(j + 1) - w0);
  }
  // Cubic Lagrange through the 4 height rows around h (the width curves in h at strong
  // curvature: linear interpolation over 9 rows would leave ~5e-4 relative).
  const int j0 = std::min(std::max(static_cast<int>(fj) - 1, 0), hn_ - 4);
  const double x = fj - j0;  // in [0, 3]
  const double x1 = x - 1, x2 = x - 2, x3 = x - 3;
  return -row(j0) * x1 * x2 * x3 / 6 + row(j0 + 1) * x * x2 * x3 / 2 -
         row(j0 + 2) * x * x1 * x3 / 2 + row(j0 + 3) * x * x1 * x2 / 6;
}

WidthFn EffectiveWidthTable::function() const {
  auto table = std::make_shared<const EffectiveWidthTable>(*this);
  return [table](double kappa, double height) { return table->width(kappa, height); };
}

}  // namespace omnislice
