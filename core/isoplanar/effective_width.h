// SPDX-License-Identifier: MIT
// Effective printing width of paper 003 Section 2.1 (Eq. 1-2): the cusp-area equilibrium of the
// ellipse bead model on a curved layer.
//
// Cross-section in the n_p-k_p plane at an NL point p (p at the origin, n up, k across the path):
//   - the bead is the ellipse of Eq. 1, k = (s/2) cos(rho), n = (h/2)(sin(rho) - 1): width s
//     (nozzle diameter), height h (local layer thickness), its top at p;
//   - the current layer surface is the circle through p with signed normal curvature kappa in the
//     k direction, the previous layer surface the concentric circle through the bead's bottom
//     (offset by h); kappa > 0 is CONVEX (the surface bends away from the nozzle side, like a dome
//     seen from above: height along n over the tangent plane w(k) ~ -kappa k^2 / 2), kappa < 0
//     concave, kappa = 0 flat (straight lines);
//   - the neighbouring bead is the same ellipse moved along the current surface by the arc
//     spacing a (rotated about the circles' centre; translated when flat).
// A_o = area of the lens where the two ellipses overlap; A_g = the two gap areas enclosed between
// the ellipses and the current surface (above their upper intersection) and between the ellipses
// and the previous surface (below the lower one). The equilibrium A_g = A_o fixes a; the upper
// intersection point of the ellipses is at parameter rho* on the ellipse and w_eff = s cos(rho*)
// (Eq. 2). Areas by Gauss-Green on the ellipse segments and circular segments (closed forms),
// a by bracketed root finding (A_g - A_o grows with a).
// Flat surface: A_g = A_o is exactly "bead area = spacing x height", a = w_eff = pi s / 4.
#pragma once
#include <functional>
#include <vector>

namespace omnislice {

struct CuspAreas {
  double overlap = 0;    // A_o, mm^2
  double gapTop = 0;     // gap between the ellipses and the current layer surface, mm^2
  double gapBottom = 0;  // gap between the ellipses and the previous layer surface, mm^2
  double rhoUpper = 0;   // rho of the upper intersection on the first ellipse, rad (NaN if none)
  double rhoLower = 0;   // rho of the lower intersection, rad (NaN if none)
};

// Areas of the configuration above for bead width s, height h (mm), curvature kappa (1/mm) and arc
// spacing a (mm, along the current surface). For the tests and the page's explanation.
CuspAreas cuspAreas(double s, double h, double kappa, double arcSpacing);

struct EffectiveWidth {
  double width = 0;        // w_eff = s cos(rho*), mm
  double arcSpacing = 0;   // a at equilibrium: distance of adjacent NL points along the surface, mm
  double rho = 0;          // rho*, rad
  double overlap = 0;      // A_o = A_g at equilibrium, mm^2
  bool clamped = false;    // |kappa| beyond what the model supports (circle radius below about
                           // the bead size): kappa was clamped to the supported range, where
                           // the bead ellipse still fits between the two surfaces: convex
                           // 1/kappa >= max(s^2 / (2h), 2h, s / 2), concave
                           // 1/|kappa| + h >= s^2 / (2h) and 1/|kappa| >= s / 2 (NaN: flat)
};

// w_eff for bead width s > 0, height h > 0 (mm) and curvature kappa (1/mm; sign as above).
// Non-finite or non-positive s, h: width 0.
EffectiveWidth effectiveWidth(double s, double h, double kappa);

// w_eff as a function of (kappa, h) for one bead width: the inner loops of the drive-direction
// search and the path planner call this millions of times.
using WidthFn = std::function<double(double kappa, double height)>;

// Tabulated effectiveWidth(s, h, kappa).width over kappa in [-kappaMax, kappaMax] and h in
// [hMin, hMax] (linear in kappa, cubic through 4 rows in h; exact at the nodes; values outside
// the ranges are clamped to them, and kappa to the model's supported range for h). hMin and
// hMax may come in either order; a non-positive or non-finite s or h gives a table answering 0.
// Relative error against effectiveWidth() below 1e-4 on the default resolution (tested).
class EffectiveWidthTable {
 public:
  EffectiveWidthTable() = default;
  EffectiveWidthTable(double s, double hMin, double hMax, double kappaMax = 0,
                      int kappaNodes = 1025, int heightNodes = 9);  // kappaMax 0 = 2 / s
  double width(double kappa, double height) const;
  double beadWidth() const { return s_; }
  WidthFn function() const;  // a WidthFn that calls width() on a copy of the table

 private:
  double s_ = 0, hMin_ = 0, hMax_ = 0, kappaMax_ = 0;
  int kn_ = 0, hn_ = 0;
  std::vector<double> values_;  // hn_ x kn_
};

}  // namespace omnislice
