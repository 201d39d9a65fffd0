// SPDX-License-Identifier: MIT
// Exact orientation predicates in plain doubles (no CGAL, the same bits natively and in wasm):
// the sign of a 2D or 3D orientation determinant, decided by Shewchuk's static error bounds where
// they can and by an exact sum of the determinant's products (an expansion of doubles) where they
// cannot. P is any point type with p[0], p[1], p[2] (CGAL's Point_3, Eigen's Vector3d, double[3]).
// Exact barring underflow and overflow: every nonzero coordinate of magnitude within
// [1e-30, 1e30] (coordinatesInExactRange) keeps products and their errors clear of both.
#pragma once
#include <cmath>

namespace omnislice::exact {

// a + b = x + y exactly, x the rounded sum (Knuth's two-sum).
inline void twoSum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a, av = x - bv;
  y = (a - av) + (b - bv);
}

// a * b = x + y exactly: fma where the hardware has it, else Dekker's product with Veltkamp's
// split (wasm has no fma instruction; its libm fma is slow software). No FMA contraction: the
// split's exactness needs each product rounded on its own (the project builds without it).
inline void twoProduct(double a, double b, double& x, double& y) {
  x = a * b;
#ifdef FP_FAST_FMA
  y = std::fma(a, b, -x);
#else
  auto split = [](double v, double& hi, double& lo) {
    const double c = 134217729.0 * v;  // 2^27 + 1
    hi = c - (c - v);
    lo = v - hi;
  };
  double ah, al, bh, bl;
  split(a, ah, al);
  split(b, bh, bl);
  y = al * bl - (((x - ah * bh) - al * bh) - ah * bl);
#endif
}

// An exact sum of doubles as a nonoverlapping expansion (Shewchuk's grow-expansion, zeros
// dropped): the sign of its largest component is the sign of the sum. Products enter exactly as
// their rounded value and its error. At most 100 terms (each term adds at most one component);
// the largest sum here has 96.
class ExactSum {
 public:
  void add(double t) {
    int m = 0;
    double q = t;
    for (int k = 0; k < n_; ++k) {
      double x, y;
      twoSum(q, e_[k], x, y);
      if (y != 0) e_[m++] = y;
      q = x;
    }
    if (q != 0) e_[m++] = q;
    n_ = m;
  }
  // + a b exactly.
  void addProduct(double a, double b) {
    double p, e;
    twoProduct(a, b, p, e);
    add(p);
    add(e);
  }
  // +/- a b c exactly (a b = p + e, then p c and e c each as a product).
  void addProduct(double a, double b, double c, bool negate) {
    double p, e;
    twoProduct(a, b, p, e);
    addProduct(negate ? -p : p, c);
    addProduct(negate ? -e : e, c);
  }
  int sign() const { return n_ == 0 ? 0 : (e_[n_ - 1] > 0 ? 1 : -1); }

 private:
  double e_[100];
  int n_ = 0;
};

// Whether every coordinate is 0 or of magnitude in [1e-30, 1e30] (the predicates are exact then).
template <class Range>
bool coordinatesInExactRange(const Range& coordinates) {
  for (double c : coordinates)
    if (!(c == 0 || (std::abs(c) >= 1e-30 && std::abs(c) <= 1e30))) return false;
  return true;
}

// Exact sign of the 2D orientation det = (q_i - p_i)(r_j - p_j) - (q_j - p_j)(r_i - p_i) in the
// coordinates (i, j), as the sum of its six coordinate products.
template <class P>
int orient2Exact(const P& p, const P& q, const P& r, int i, int j) {
  ExactSum sum;
  sum.addProduct(q[i], r[j]);
  sum.addProduct(-q[i], p[j]);
  sum.addProduct(-p[i], r[j]);
  sum.addProduct(-q[j], r[i]);
  sum.addProduct(q[j], p[i]);
  sum.addProduct(p[j], r[i]);
  return sum.sign();
}

// The same sign: +1 (counter-clockwise in (i, j)), -1 or 0. The static error bound (Shewchuk's
// ccwerrboundA) decides most cases, the exact sum the rest.
template <class P>
int orient2(const P& p, const P& q, const P& r, int i, int j) {
  const double l = (q[i] - p[i]) * (r[j] - p[j]), rr = (q[j] - p[j]) * (r[i] - p[i]);
  const double det = l - rr;
  const double bound = 3.3306690738754716e-16 * (std::abs(l) + std::abs(rr));
  if (det > bound) return 1;
  if (det < -bound) return -1;
  return orient2Exact(p, q, r, i, j);
}

// Exact sign of the 3D orientation det[q - p; r - p; s - p] (positive when s lies on the side of
// the plane (p, q, r) its normal (q - p) x (r - p) points to, as CGAL::orientation), as the
// expansion of det3(q,r,s) - det3(p,r,s) + det3(p,q,s) - det3(p,q,r), det3(x,y,z) = x . (y x z),
// in the coordinates themselves: 24 triple products, 96 exact terms.
template <class P>
int orient3Expanded(const P& p, const P& q, const P& r, const P& s) {
  ExactSum sum;
  auto addDet3 = [&sum](const P& x, const P& y, const P& z, bool negate) {
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      sum.addProduct(x[a], y[b], z[c], negate);
      sum.addProduct(x[a], y[c], z[b], !negate);
    }
  };
  addDet3(q, r, s, false);
  addDet3(p, r, s, true);
  addDet3(p, q, s, false);
  addDet3(p, q, r, true);
  return sum.sign();
}

// The same sign, exact: when the nine differences are exact (two-sum tails zero: neighbouring
// mesh points, by Sterbenz's lemma), the determinant of the differences (24 terms); else
// orient3Expanded.
template <class P>
int orient3Exact(const P& p, const P& q, const P& r, const P& s) {
  double d[3][3];
  bool exactDifferences = true;
  const P* rows[3] = {&q, &r, &s};
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) {
      double tail;
      twoSum((*rows[k])[a], -p[a], d[k][a], tail);
      exactDifferences = exactDifferences && tail == 0;
    }
  if (!exactDifferences) return orient3Expanded(p, q, r, s);
  ExactSum sum;
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    sum.addProduct(d[0][a], d[1][b], d[2][c], false);
    sum.addProduct(d[0][a], d[1][c], d[2][b], true);
  }
  return sum.sign();
}

// The same sign: Shewchuk's static filter (o3derrboundA) on the rounded determinant decides most
// cases, orient3Exact the rest.
template <class P>
int orient3(const P& p, const P& q, const P& r, const P& s) {
  const double ax = q[0] - p[0], ay = q[1] - p[1], az = q[2] - p[2];
  const double bx = r[0] - p[0], by = r[1] - p[1], bz = r[2] - p[2];
  const double cx = s[0] - p[0], cy = s[1] - p[1], cz = s[2] - p[2];
  const double m1 = by * cz, m2 = bz * cy, m3 = bz * cx, m4 = bx * cz, m5 = bx * cy, m6 = by * cx;
  const double det = ax * (m1 - m2) + ay * (m3 - m4) + az * (m5 - m6);
  const double permanent = (std::abs(m1) + std::abs(m2)) * std::abs(ax) +
                           (std::abs(m3) + std::abs(m4)) * std::abs(ay) +
                           (std::abs(m5) + std::abs(m6)) * std::abs(az);
  const double bound = 7.7715611723761027e-16 * permanent;
  if (det > bound) return 1;
  if (det < -bound) return -1;
  return orient3Exact(p, q, r, s);
}

}  // namespace omnislice::exact
