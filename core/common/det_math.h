// SPDX-License-Identifier: MIT
// Trigonometry that gives the same bits natively and in wasm. The C library's sin, cos, atan2 and
// acos are not correctly rounded and differ between glibc (native) and musl (Emscripten) in the
// last bit; a search that compares sums built from them (the multidir plane search) can then break
// a near-tie differently and return other planes. These use only +, -, *, / and sqrt (correctly
// rounded in IEEE 754 on both targets; no FMA contraction on either), so they agree everywhere.
// Accuracy: about 1e-15 absolute for |x| <= 1e5 (sin, cos), 2e-16 for atan2 and acos.
#pragma once
#include <cmath>

#include "common/math_constants.h"

namespace omnislice::det {

namespace detail {
// sin and cos of r, |r| <= pi/4 (+ rounding), by their Taylor series to r^19 / r^18.
inline double sinPoly(double r) {
  const double r2 = r * r;
  // sin r = r + r r2 s, s = -1/3! + r2/5! - ... - r2^8/19! (Horner from the highest power)
  const double inv[] = {1.0 / 355687428096000.0, -1.0 / 1307674368000.0, 1.0 / 6227020800.0,
                        -1.0 / 39916800.0,       1.0 / 362880.0,         -1.0 / 5040.0,
                        1.0 / 120.0,             -1.0 / 6.0};
  double s = -1.0 / 121645100408832000.0;  // -1/19!
  for (double c : inv) s = s * r2 + c;
  return r + r * r2 * s;
}
inline double cosPoly(double r) {
  const double r2 = r * r;
  const double inv[] = {1.0 / 6402373705728000.0, -1.0 / 20922789888000.0, 1.0 / 87178291200.0,
                        -1.0 / 479001600.0,       1.0 / 3628800.0,         -1.0 / 40320.0,
                        1.0 / 720.0,              -1.0 / 24.0,             1.0 / 2.0};
  double c = 0;
  for (double k : inv) c = c * r2 + k;
  // c = 1/2 - r^2/24 + ...: cos r = 1 - r^2 c
  return 1.0 - r2 * c;
}
// x = k pi/2 + r with |r| <= ~pi/4 (Cody-Waite, pi/2 in two parts).
inline double reduce(double x, long& k) {
  constexpr double pio2Hi = 1.57079632673412561417e+00;  // first 33 bits of pi/2
  constexpr double pio2Lo = 6.07710050650619224932e-11;  // pi/2 - pio2Hi
  const double kd = std::nearbyint(x * (2.0 / kPi));
  k = static_cast<long>(kd);
  return (x - kd * pio2Hi) - kd * pio2Lo;
}
// atan(t) for 0 <= t <= 1.
inline double atanUnit(double t) {
  double base = 0;
  if (t > 0.41421356237309503) {  // tan(pi/8): atan t = pi/4 + atan((t - 1) / (t + 1))
    base = kPi / 4;
    t = (t - 1) / (t + 1);
  }
  const double t2 = t * t;
  double sum = 0;
  for (int n = 30; n >= 0; --n) sum = sum * t2 + ((n % 2) ? -1.0 : 1.0) / (2 * n + 1);
  return base + t * sum;
}
}  // namespace detail

inline double sin(double x) {
  long k = 0;
  const double r = detail::reduce(x, k);
  switch (k & 3) {
    case 0: return detail::sinPoly(r);
    case 1: return detail::cosPoly(r);
    case 2: return -detail::sinPoly(r);
    default: return -detail::cosPoly(r);
  }
}

inline double cos(double x) {
  long k = 0;
  const double r = detail::reduce(x, k);
  switch (k & 3) {
    case 0: return detail::cosPoly(r);
    case 1: return -detail::sinPoly(r);
    case 2: return -detail::cosPoly(r);
    default: return detail::sinPoly(r);
  }
}

inline double atan2(double y, double x) {
  if (std::isnan(x) || std::isnan(y)) return std::nan("");
  const double ax = std::abs(x), ay = std::abs(y);
  if (ax == 0 && ay == 0) return std::signbit(x) ? (std::signbit(y) ? -kPi : kPi) : (std::signbit(y) ? -0.0 : 0.0);
  double a = ay <= ax ? detail::atanUnit(ay / ax) : kPi / 2 - detail::atanUnit(ax / ay);
  if (x < 0 || (x == 0 && std::signbit(x))) a = kPi - a;
  return std::signbit(y) ? -a : a;
}

// acos of x clamped to [-1, 1].
inline double acos(double x) {
  x = x < -1 ? -1 : (x > 1 ? 1 : x);
  return atan2(std::sqrt((1 - x) * (1 + x)), x);
}

}  // namespace omnislice::det
