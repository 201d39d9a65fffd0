// SPDX-License-Identifier: MIT
#include "common/math_constants.h"
#include "isoplanar/effective_width.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

namespace omnislice {
namespace {


// Independent brute-force areas of the configuration of effective_width.h by counting grid cell
// centres: the two ellipses (the second one obtained by rotating the first about the curvature
// centre, tested by rotating the query point back), the annular sector between the rays through
// the two NL points, and the two gaps as the connected components of sector \ (E1 u E2) that
// touch the current and the previous surface on the bisector.
struct BruteAreas {
  double overlap = 0, gapTop = 0, gapBottom = 0;
};

BruteAreas bruteForce(double s, double h, double kappa, double a, double cell) {
  const bool flat = kappa == 0;
  const double R = flat ? 0 : 1 / std::fabs(kappa);
  const double phi = flat ? 0 : a / R;
  // Centre: below p1 for convex, above for concave.
  const double cn = flat ? 0 : (kappa > 0 ? -R : R);
  auto inE1 = [&](double k, double n) {
    const double u = k / (s / 2), v = (n + h / 2) / (h / 2);
    return u * u + v * v <= 1;
  };
  // E2 = E1 moved by the arc spacing: translation when flat, rotation about the centre by phi
  // (clockwise for convex so p1 moves to +k, counter-clockwise for concave).
  auto inE2 = [&](double k, double n) {
    if (flat) return inE1(k - a, n);
    const double ang = kappa > 0 ? phi : -phi;  // rotate the query point back
    const double dk = k, dn = n - cn;
    const double c = std::cos(ang), sn = std::sin(ang);
    const double rk = c * dk - sn * dn, rn = sn * dk + c * dn;
    return inE1(rk, rn + cn);
  };
  auto inCell = [&](double k, double n) {
    if (flat) return k >= 0 && k <= a && n >= -h && n <= 0;
    const double dk = k, dn = n - cn;
    const double r = std::hypot(dk, dn);
    double psi;
    if (kappa > 0) {
      if (r < R - h || r > R) return false;
      psi = std::atan2(dk, dn);
    } else {
      if (r < R || r > R + h) return false;
      psi = std::atan2(dk, -dn);
    }
    return psi >= 0 && psi <= phi;
  };
  const double sag = std::fabs(kappa) * (a + s) * (a + s) / 2;
  const double k0 = -0.6 * s, k1 = a + 0.6 * s, n0 = -h - sag - 0.05 * h, n1 = sag + 0.05 * h;
  const int nk = static_cast<int>((k1 - k0) / cell) + 1, nn = static_cast<int>((n1 - n0) / cell) + 1;
  std::vector<uint8_t> state(static_cast<size_t>(nk) * nn, 0);  // 1 free, 2 top, 3 bottom
  size_t overlapCount = 0;
  for (int j = 0; j < nn; ++j)
    for (int i = 0; i < nk; ++i) {
      const double k = k0 + (i + 0.5) * cell, n = n0 + (j + 0.5) * cell;
      const bool e1 = inE1(k, n), e2 = inE2(k, n);
      if (e1 && e2) ++overlapCount;
      if (!e1 && !e2 && inCell(k, n)) state[static_cast<size_t>(j) * nk + i] = 1;
    }
  auto fill = [&](double sk, double sn, double stepN, uint8_t label) {
    // Walk from the surface point along -n (or +n) to the first free cell, then flood fill.
    int si = static_cast<int>((sk - k0) / cell), sj = static_cast<int>((sn - n0) / cell);
    for (int t = 0; t < 50 && sj >= 0 && sj < nn && state[static_cast<size_t>(sj) * nk + si] != 1;
         ++t)
      sj += stepN > 0 ? 1 : -1;
    size_t count = 0;
    if (sj < 0 || sj >= nn || state[static_cast<size_t>(sj) * nk + si] != 1) return count;
    std::vector<int> stack{sj * nk + si};
    state[static_cast<size_t>(sj) * nk + si] = label;
    while (!stack.empty()) {
      const int id = stack.back();
      stack.pop_back();
      ++count;
      const int i = id % nk, j = id / nk;
      const int nb[4][2] = {{i + 1, j}, {i - 1, j}, {i, j + 1}, {i, j - 1}};
      for (auto& q : nb) {
        if (q[0] < 0 || q[0] >= nk || q[1] < 0 || q[1] >= nn) continue;
        uint8_t& st = state[static_cast<size_t>(q[1]) * nk + q[0]];
        if (st == 1) {
          st = label;
          stack.push_back(q[1] * nk + q[0]);
        }
      }
    }
    return count;
  };
  // Bisector points on the current and the previous surface.
  double tk, tn, bk, bn;
  if (flat) {
    tk = a / 2, tn = 0, bk = a / 2, bn = -h;
  } else if (kappa > 0) {
    tk = R * std::sin(phi / 2), tn = cn + R * std::cos(phi / 2);
    bk = (R - h) * std::sin(phi / 2), bn = cn + (R - h) * std::cos(phi / 2);
  } else {
    tk = R * std::sin(phi / 2), tn = cn - R * std::cos(phi / 2);
    bk = (R + h) * std::sin(phi / 2), bn = cn - (R + h) * std::cos(phi / 2);
  }
  BruteAreas out;
  const double ca = cell * cell;
  out.overlap = overlapCount * ca;
  out.gapTop = fill(tk, tn - 0.5 * cell, -1, 2) * ca;
  out.gapBottom = fill(bk, bn + 0.5 * cell, +1, 3) * ca;
  return out;
}

TEST(EffectiveWidth, FlatIsQuarterPiTimesBeadWidthForAnyHeight) {
  for (double s : {0.4, 0.6, 1.0}) {
    for (double h : {0.05, 0.1, 0.2, 0.3}) {
      const EffectiveWidth w = effectiveWidth(s, h, 0);
      EXPECT_NEAR(w.width, kPi * s / 4, 1e-10 * s) << s << " " << h;
      EXPECT_NEAR(w.arcSpacing, kPi * s / 4, 1e-10 * s);
      EXPECT_NEAR(std::cos(w.rho), kPi / 4, 1e-10);
      EXPECT_FALSE(w.clamped);
      // Bead area = spacing x height.
      EXPECT_NEAR(kPi * s * h / 4, w.arcSpacing * h, 1e-12);
    }
  }
}

TEST(EffectiveWidth, EquilibriumHoldsAndIsClosedFormInTheSupportedRange) {
  // A_g - A_o = A_cell - |E1 in cell| - |E2 in cell| = a h (1 - kappa h / 2) - pi s h / 4.
  for (double kappa : {-1.5, -0.5, -0.05, 0.0, 0.02, 0.3, 1.0, 2.0}) {
    const double s = 0.4, h = 0.2;
    const EffectiveWidth w = effectiveWidth(s, h, kappa);
    ASSERT_FALSE(w.clamped) << kappa;
    EXPECT_NEAR(w.arcSpacing, kPi * s / (4 * (1 - kappa * h / 2)), 1e-10) << kappa;
    const CuspAreas c = cuspAreas(s, h, kappa, w.arcSpacing);
    EXPECT_NEAR(c.gapTop + c.gapBottom, c.overlap, 1e-12);
    EXPECT_NEAR(c.overlap, w.overlap, 1e-14);
    EXPECT_GT(c.gapTop, 0);
    EXPECT_GT(c.gapBottom, 0);
    EXPECT_GT(c.rhoUpper, 0);
    EXPECT_LT(c.rhoLower, 0);
    for (double a : {0.3, 0.35, 0.45}) {
      const CuspAreas d = cuspAreas(s, h, kappa, a);
      EXPECT_NEAR(d.gapTop + d.gapBottom - d.overlap, a * h * (1 - kappa * h / 2) - kPi * s * h / 4,
                  1e-12);
    }
  }
}

TEST(EffectiveWidth, AreasMatchBruteForceCounting) {
  struct Case {
    double s, h, kappa;
  };
  const Case cases[] = {{0.4, 0.2, 0.0},  {0.4, 0.2, 1.5},  {0.4, 0.2, -2.0}, {0.6, 0.15, 0.4},
                        {0.4, 0.1, -0.8}, {0.5, 0.3, 1.0}, {0.4, 0.2, 0.05}};
  for (const Case& c : cases) {
    const EffectiveWidth w = effectiveWidth(c.s, c.h, c.kappa);
    ASSERT_FALSE(w.clamped);
    const double bead = kPi * c.s * c.h / 4;
    const double cell = c.h / 500;
    for (double a : {w.arcSpacing, 0.9 * w.arcSpacing, 1.1 * w.arcSpacing}) {
      const CuspAreas ca = cuspAreas(c.s, c.h, c.kappa, a);
      const BruteAreas b = bruteForce(c.s, c.h, c.kappa, a, cell);
      // Tolerance: 0.2 % of the bead's area (grid of h / 500; the counts agree to ~1e-4 of it).
      const double tol = 2e-3 * bead;
      EXPECT_NEAR(ca.overlap, b.overlap, tol) << c.s << " " << c.h << " " << c.kappa << " " << a;
      EXPECT_NEAR(ca.gapTop, b.gapTop, tol) << c.s << " " << c.h << " " << c.kappa << " " << a;
      EXPECT_NEAR(ca.gapBottom, b.gapBottom, tol) << c.s << " " << c.h << " " << c.kappa << " " << a;
      std::printf("s %.2f h %.2f k %+.2f a %.4f: A_o %.6f/%.6f top %.6f/%.6f bottom %.6f/%.6f\n", c.s,
                  c.h, c.kappa, a, ca.overlap, b.overlap, ca.gapTop, b.gapTop, ca.gapBottom,
                  b.gapBottom);
      if (a == w.arcSpacing) {
        EXPECT_NEAR(b.gapTop + b.gapBottom, b.overlap, 2 * tol);  // the equilibrium itself
      }
    }
  }
}

TEST(EffectiveWidth, TouchingFlatBeadsHaveNoOverlap) {
  const CuspAreas c = cuspAreas(0.4, 0.2, 0, 0.4);
  EXPECT_NEAR(c.overlap, 0, 1e-15);
  // Gaps: the cell (0.4 x 0.2) minus two half ellipses, split in equal halves.
  EXPECT_NEAR(c.gapTop + c.gapBottom, 0.4 * 0.2 - kPi * 0.4 * 0.2 / 4, 1e-12);
  EXPECT_NEAR(c.gapTop, c.gapBottom, 1e-12);
  const CuspAreas far = cuspAreas(0.4, 0.2, 0, 0.5);
  EXPECT_EQ(far.overlap, 0);
  EXPECT_TRUE(std::isnan(far.rhoUpper));
}

TEST(EffectiveWidth, ConvexWiderConcaveNarrowerMonotone) {
  for (double h : {0.1, 0.2, 0.3}) {
    const double s = 0.4;
    double prevA = 0, prevW = 0;
    bool first = true;
    for (double kappa = -3; kappa <= 3; kappa += 0.01) {
      const EffectiveWidth w = effectiveWidth(s, h, kappa);
      if (!first) {
        EXPECT_GE(w.arcSpacing, prevA - 1e-12) << h << " " << kappa;
        EXPECT_GE(w.width, prevW - 1e-12) << h << " " << kappa;
      }
      first = false;
      prevA = w.arcSpacing;
      prevW = w.width;
      const EffectiveWidth flat = effectiveWidth(s, h, 0);
      if (kappa > 0.005 && !w.clamped) {
        EXPECT_GT(w.arcSpacing, flat.arcSpacing);
        EXPECT_GT(w.width, flat.width);
      }
      if (kappa < -0.005 && !w.clamped) {
        EXPECT_LT(w.arcSpacing, flat.arcSpacing);
        EXPECT_LT(w.width, flat.width);
      }
    }
  }
}

TEST(EffectiveWidth, StrongCurvatureIsClamped) {
  const EffectiveWidth w = effectiveWidth(0.4, 0.2, 50);
  EXPECT_TRUE(w.clamped);
  EXPECT_GT(w.width, 0);
  EXPECT_TRUE(std::isfinite(w.width));
  const EffectiveWidth c = effectiveWidth(0.4, 0.2, -50);
  EXPECT_TRUE(c.clamped);
  EXPECT_GT(c.width, 0);
  // The clamp is where the ellipse stops fitting under the current surface (convex): the
  // circle of curvature at its top vertex, radius s^2 / (2h).
  EXPECT_FALSE(effectiveWidth(0.4, 0.2, 2.49).clamped);
  EXPECT_TRUE(effectiveWidth(0.4, 0.2, 2.51).clamped);
  EXPECT_EQ(effectiveWidth(0.4, 0.2, 50).width, effectiveWidth(0.4, 0.2, 1e9).width);
}

TEST(EffectiveWidth, BadInputGivesZero) {
  EXPECT_EQ(effectiveWidth(0, 0.2, 0).width, 0);
  EXPECT_EQ(effectiveWidth(0.4, -1, 0).width, 0);
  EXPECT_EQ(effectiveWidth(NAN, 0.2, 0).width, 0);
  EXPECT_EQ(effectiveWidth(0.4, INFINITY, 0).width, 0);
  const EffectiveWidth w = effectiveWidth(0.4, 0.2, NAN);  // treated as flat, flagged
  EXPECT_TRUE(w.clamped);
  EXPECT_NEAR(w.width, kPi * 0.4 / 4, 1e-10);
  EXPECT_EQ(cuspAreas(0.4, 0.2, 0, -1).overlap, 0);
  EXPECT_EQ(EffectiveWidthTable(0, 0.1, 0.2).width(0, 0.1), 0);
  EXPECT_EQ(EffectiveWidthTable().width(0, 0.1), 0);
  EXPECT_EQ(EffectiveWidthTable(0.4, 0.3, 0.1).width(0.5, 0.2), EffectiveWidthTable(0.4, 0.1, 0.3).width(0.5, 0.2));
}

TEST(EffectiveWidth, TableMatchesDirectSolveAndIsFast) {
  const double s = 0.4, hMin = 0.1, hMax = 0.3;
  auto t0 = std::chrono::steady_clock::now();
  const EffectiveWidthTable table(s, hMin, hMax);
  auto t1 = std::chrono::steady_clock::now();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> kd(-2 / s, 2 / s), hd(hMin, hMax);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    const double k = kd(rng), h = hd(rng);
    const double direct = effectiveWidth(s, h, k).width;
    worst = std::max(worst, std::fabs(table.width(k, h) - direct) / direct);
  }
  EXPECT_LT(worst, 1e-4);
  // Another bead and a wider height range.
  const EffectiveWidthTable wide(0.6, 0.05, 0.45);
  double worstWide = 0;
  std::uniform_real_distribution<double> kw(-4, 4), hw(0.05, 0.45);
  for (int i = 0; i < 20000; ++i) {
    const double k = kw(rng), h = hw(rng);
    const double direct = effectiveWidth(0.6, h, k).width;
    worstWide = std::max(worstWide, std::fabs(wide.width(k, h) - direct) / direct);
  }
  EXPECT_LT(worstWide, 1e-4);
  // Exact at nodes, clamped outside the ranges.
  EXPECT_NEAR(table.width(0, 0.2), kPi * s / 4, 1e-12);
  EXPECT_NEAR(table.width(100, 0.2), effectiveWidth(s, 0.2, 100).width, 1e-12);
  EXPECT_NEAR(table.width(0.5, 10), table.width(0.5, hMax), 1e-15);
  const WidthFn fn = table.function();
  EXPECT_EQ(fn(0.7, 0.15), table.width(0.7, 0.15));
  // Timing.
  const int calls = 2000000;
  double sum = 0;
  auto t2 = std::chrono::steady_clock::now();
  for (int i = 0; i < calls; ++i) sum += table.width(-4 + 8.0 * (i % 1000) / 1000, 0.1 + 0.0001 * (i % 2000));
  auto t3 = std::chrono::steady_clock::now();
  const int direct = 20000;
  for (int i = 0; i < direct; ++i) sum += effectiveWidth(s, 0.2, -2 + 4.0 * i / direct).width;
  auto t4 = std::chrono::steady_clock::now();
  auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
  std::printf("table build %.1f ms, table lookup %.1f ns, effectiveWidth %.2f us, worst rel %.2e / %.2e (%g)\n",
              ms(t0, t1), ms(t2, t3) * 1e6 / calls, ms(t3, t4) * 1e3 / direct, worst, worstWide, sum);
}

TEST(EffectiveWidth, RandomBeadsGiveFiniteWidthsAndEquilibrium) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> sd(0.1, 2.0), ratio(0.05, 2.5), kd(-30, 30);
  for (int i = 0; i < 20000; ++i) {
    const double s = sd(rng), h = s * ratio(rng), k = kd(rng) / s;
    const EffectiveWidth w = effectiveWidth(s, h, k);
    ASSERT_TRUE(std::isfinite(w.width)) << s << " " << h << " " << k;
    ASSERT_GT(w.width, 0.15 * s) << s << " " << h << " " << k;
    ASSERT_LT(w.width, s) << s << " " << h << " " << k;
    const CuspAreas c = cuspAreas(s, h, w.clamped ? 0 : k, w.arcSpacing);
    if (!w.clamped) {
      ASSERT_NEAR(c.gapTop + c.gapBottom, c.overlap, 1e-9 * s * h) << s << " " << h << " " << k;
      ASSERT_GE(c.gapTop, -1e-12 * s * h);
      ASSERT_GE(c.gapBottom, -1e-12 * s * h);
    }
  }
}

TEST(EffectiveWidth, SingleHeightTable) {
  const EffectiveWidthTable table(0.4, 0.2, 0.2);
  for (double k : {-3.0, -0.3, 0.0, 0.123, 2.0})
    EXPECT_NEAR(table.width(k, 0.2), effectiveWidth(0.4, 0.2, k).width, 1e-6);
}

}  // namespace
}  // namespace omnislice
