// SPDX-License-Identifier: MIT
// Kinematic feed field and drive-direction search of paper 003 (feed_rate.h).
//
// Per sample: exact inverse kinematics on a 13-point stencil in the sample's tangent coordinates
// (u, v) on its local quadric w = -(u v) S (u v)^T / 2 (normals from the quadric), a cubic fitted
// to each machine value by least squares with one pseudo-inverse shared by every sample (the
// pattern is the same everywhere, only scaled by the stencil radius), its nine derivatives stored.
// A candidate curve through the sample with unit tangent t = (a, b), geodesic curvature kg and
// normal curvature kappa along t has, in tangent coordinates, x' = t, x'' = kg e (e = n x t) and
// x''' = -(kg^2 + kappa^2) t + c3 e (Darboux frame; c3 depends on the curve's third order), so
//   Q'   = grad Q . t
//   Q''  = H[t, t] + kg grad Q . e
//   Q''' = T[t, t, t] + 3 kg H[t, e] + grad Q . x'''.
// The drive-plane section of the quadric has c3 = 3 g^2 kappa_f S_fk (g = (q.n) / (q.k)).
#include "isoplanar/feed_rate.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "common/math_constants.h"
#include "common/stopwatch.h"
#include "kinematics/kinematics.h"
#include "kinematics/robot_arm.h"

namespace omnislice {

namespace {

constexpr double kTwoPi = 2 * kPi;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kStencil = 13;
constexpr int kJets = 9;
constexpr double kLimitSlack = 1e-9;

// The stencil at unit radius: centre, 4 points at radius 1/2 on the axes, 8 at radius 1 every 45
// degrees (the outer ring fixes the cubic's restriction to the circle, a trigonometric polynomial
// of degree 3; centre and inner ring the remaining (u^2 + v^2 - 1)(linear) part: rank 10).
struct StencilPattern {
  double u[kStencil], v[kStencil];
  // Rows 1..9 of the pseudo-inverse of the monomials [1, u, v, u^2/2, uv, v^2/2, u^3/6, u^2 v/2,
  // u v^2/2, v^3/6] at the unit-radius points: the derivatives Qu .. Qvvv at the centre.
  double pinv[kJets][kStencil];
  int degree[kJets];
};

const StencilPattern& stencilPattern() {
  static const StencilPattern p = [] {
    StencilPattern s{};
    s.u[0] = s.v[0] = 0;
    for (int k = 0; k < 4; ++k) {
      s.u[1 + k] = 0.5 * std::cos(k * kPi / 2);
      s.v[1 + k] = 0.5 * std::sin(k * kPi / 2);
    }
    for (int k = 0; k < 8; ++k) {
      s.u[5 + k] = std::cos(k * kPi / 4);
      s.v[5 + k] = std::sin(k * kPi / 4);
    }
    Eigen::Matrix<double, kStencil, 10> a;
    for (int i = 0; i < kStencil; ++i) {
      const double u = s.u[i], v = s.v[i];
      a(i, 0) = 1;
      a(i, 1) = u;
      a(i, 2) = v;
      a(i, 3) = u * u / 2;
      a(i, 4) = u * v;
      a(i, 5) = v * v / 2;
      a(i, 6) = u * u * u / 6;
      a(i, 7) = u * u * v / 2;
      a(i, 8) = u * v * v / 2;
      a(i, 9) = v * v * v / 6;
    }
    const Eigen::Matrix<double, 10, 10> ata = a.transpose() * a;
    const Eigen::Matrix<double, 10, kStencil> pinv = ata.ldlt().solve(a.transpose());
    const int deg[kJets] = {1, 1, 2, 2, 2, 3, 3, 3, 3};
    for (int j = 0; j < kJets; ++j) {
      s.degree[j] = deg[j];
      for (int i = 0; i < kStencil; ++i) s.pinv[j][i] = pinv(j + 1, i);
    }
    return s;
  }();
  return p;
}

// Point and unit normal of the sample's local quadric at tangent coordinates (u, v).
inline void quadricPoint(const SurfaceSample& s, double u, double v, Eigen::Vector3d& p,
                         Eigen::Vector3d& n) {
  const double s00 = s.shape(0, 0), s01 = 0.5 * (s.shape(0, 1) + s.shape(1, 0)),
               s11 = s.shape(1, 1);
  const double w = -0.5 * (s00 * u * u + 2 * s01 * u * v + s11 * v * v);
  p = s.position + u * s.tangentU + v * s.tangentV + w * s.normal;
  n = (s.normal + (s00 * u + s01 * v) * s.tangentU + (s01 * u + s11 * v) * s.tangentV).normalized();
}

inline bool inside(double v, const std::pair<double, double>& l) {
  return v >= l.first - kLimitSlack && v <= l.second + kLimitSlack;
}

// The 2 pi alias of v nearest `target` inside the limits (the nearest one overall when it is
// inside, else its neighbours); false when none of those is inside.
inline bool aliasNear(double v, double target, const std::pair<double, double>& l, double& out) {
  const double c = v + kTwoPi * std::round((target - v) / kTwoPi);
  if (inside(c, l)) {
    out = c;
    return true;
  }
  const double lo = c - kTwoPi, hi = c + kTwoPi;
  const bool il = inside(lo, l), ih = inside(hi, l);
  if (il && (!ih || std::abs(lo - target) <= std::abs(hi - target))) {
    out = lo;
    return true;
  }
  if (ih) {
    out = hi;
    return true;
  }
  return false;
}

// Paper 003 Eq. 5 (singularityMeasure() of robot_arm.h) from G = J^T J: w = sqrt(|det J|) *
// (l_min / l_max)^(1/4) with l the eigenvalues of G. G is reduced to tridiagonal form by
// Householder reflections; det G is its characteristic polynomial at 0, and the extreme roots
// follow by Newton iterations from outside (all roots are real and >= 0, so Newton from above the
// largest root / below the smallest one converges monotonically). 3x faster than the 6 x 6
// eigen-solver, equal to the SVD's value to ~1e-12 (tested through the field's w_PS).
double singularityOf(const Eigen::Matrix<double, 6, 6>& j) {
  double a[6][6];
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c <= r; ++c) a[r][c] = a[c][r] = j.col(r).dot(j.col(c));
  double d[6], e[6] = {0, 0, 0, 0, 0, 0};
  for (int k = 0; k < 4; ++k) {
    const int m = 5 - k;  // size of the trailing block rows k+1..5
    double v[6], norm2 = 0;
    for (int i = 0; i < m; ++i) v[i] = a[k + 1 + i][k], norm2 += v[i] * v[i];
    const double norm = std::sqrt(norm2);
    if (!(norm > 0)) {
      e[k] = 0;
      continue;
    }
    const double alpha = v[0] > 0 ? -norm : norm;
    v[0] -= alpha;
    double vn2 = 0;
    for (int i = 0; i < m; ++i) vn2 += v[i] * v[i];
    e[k] = alpha;
    if (!(vn2 > 0)) continue;
    const double inv = 1 / std::sqrt(vn2);
    for (int i = 0; i < m; ++i) v[i] *= inv;
    double p[6], kk = 0;
    for (int i = 0; i < m; ++i) {
      double s = 0;
      for (int c = 0; c < m; ++c) s += a[k + 1 + i][k + 1 + c] * v[c];
      p[i] = s;
      kk += v[i] * s;
    }
    for (int i = 0; i < m; ++i) p[i] -= kk * v[i];
    for (int i = 0; i < m; ++i)
      for (int c = 0; c < m; ++c) a[k + 1 + i][k + 1 + c] -= 2 * (v[i] * p[c] + p[i] * v[c]);
  }
  e[4] = a[5][4];
  for (int i = 0; i < 6; ++i) d[i] = a[i][i];
  double e2[5];
  for (int i = 0; i < 5; ++i) e2[i] = e[i] * e[i];
  auto poly = [&](double x, double& dp) {
    double p0 = 1, p1 = d[0] - x, q0 = 0, q1 = -1;
    for (int i = 1; i < 6; ++i) {
      const double p2 = (d[i] - x) * p1 - e2[i - 1] * p0;
      const double q2 = (d[i] - x) * q1 - p1 - e2[i - 1] * q0;
      p0 = p1;
      p1 = p2;
      q0 = q1;
      q1 = q2;
    }
    dp = q1;
    return p1;
  };
  double dp = 0;
  const double det = poly(0, dp);
  if (!(det > 0)) return 0;
  double hi = 0;
  for (int i = 0; i < 6; ++i)
    hi = std::max(hi, d[i] + (i > 0 ? std::abs(e[i - 1]) : 0) + (i < 5 ? std::abs(e[i]) : 0));
  double x = hi;
  for (int it = 0; it < 200; ++it) {
    const double p = poly(x, dp);
    if (!(dp != 0)) break;
    const double nx = x - p / dp;
    if (!(nx < x)) break;
    x = nx;
  }
  const double lmax = x;
  x = 0;
  for (int it = 0; it < 200; ++it) {
    const double p = poly(x, dp);
    if (!(dp != 0)) break;
    const double nx = x - p / dp;
    if (!(nx > x)) break;
    x = nx;
  }
  const double lmin = x;
  if (!(lmax > 0) || !(lmin > 0)) return 0;
  return std::sqrt(std::sqrt(det) * std::sqrt(lmin / lmax));
}

struct Solver {
  const MachineProfile& m;
  int axes = 0;
  bool robot = false, cartesian = false;
  std::vector<std::pair<double, double>> limits;

  explicit Solver(const MachineProfile& machine) : m(machine) {
    axes = machineAxisCount(m.kind);
    robot = m.kind == MachineKind::Robot6;
    cartesian = m.kind == MachineKind::Cartesian3;
    limits = machineLimits(m);
  }

  // robot6: joint values for (tip, axis) at free angle gamma on one branch, unwrapped to the
  // alias nearest `ref` (or nearest 0) inside the limits.
  bool robotValues(const Eigen::Vector3d& tip, const Eigen::Vector3d& axis, double gamma,
                   int branch, const MachineValues* ref, MachineValues& out) const {
    const RobotFreeRotation fr = robotFreeRotation(m, tip, axis);
    const Eigen::Matrix4d f = robotFlangeForFreeAngle(fr, gamma);
    JointValues sol[8];
    int br[8];
    if (armInverseBranches(m.dh, f, (1 << branch) & m.ikBranches, sol, br) != 1) return false;
    for (int j = 0; j < 6; ++j) {
      if (!aliasNear(sol[0][j], ref ? (*ref)[j] : 0.0, limits[j], out[j])) return false;
    }
    return true;
  }

  // G-code kinds: the candidate nearest `ref` (angular values first), or the first candidate.
  // cartesian3 cannot tilt: the nozzle stays vertical and the values are the tip.
  bool gcodeValues(const Eigen::Vector3d& tip, const Eigen::Vector3d& axis,
                   const MachineValues* ref, MachineValues& out) const {
    if (cartesian) {
      if (!(inside(tip.x(), limits[0]) && inside(tip.y(), limits[1]) &&
            inside(tip.z(), limits[2]))) {
        return false;
      }
      out = {tip.x(), tip.y(), tip.z(), 0, 0, 0};
      return true;
    }
    IkOptions io;
    io.reference = ref;
    const IkResult r = inverseMap(m, tip, axis, io);
    if (!r.ok() || r.candidates.empty()) return false;
    size_t best = 0;
    if (ref) {
      double bestD = kInf;
      for (size_t c = 0; c < r.candidates.size(); ++c) {
        double d = 0;
        for (int j = 3; j < axes; ++j) d += std::abs(r.candidates[c].values[j] - (*ref)[j]);
        if (d < bestD) bestD = d, best = c;
      }
    }
    out = r.candidates[best].values;
    return true;
  }
};

// robot6 redundancy (Eq. 6): w_PS over the free angle.
struct Pose {
  double gamma = 0, w = -1;
  int branch = -1;
  MachineValues q{};
};

struct RobotGamma {
  const Solver& s;
  RobotFreeRotation fr;

  RobotGamma(const Solver& solver, const Eigen::Vector3d& tip, const Eigen::Vector3d& axis)
      : s(solver), fr(robotFreeRotation(solver.m, tip, axis)) {}

  // w_PS of one branch at gamma (-1 when unreachable or out of the limits).
  double measure(double gamma, int branch, MachineValues* q = nullptr) const {
    const Eigen::Matrix4d f = robotFlangeForFreeAngle(fr, gamma);
    JointValues sol[8];
    int br[8];
    if (armInverseBranches(s.m.dh, f, (1 << branch) & s.m.ikBranches, sol, br) != 1) return -1;
    MachineValues v{};
    for (int j = 0; j < 6; ++j) {
      if (!aliasNear(sol[0][j], 0.0, s.limits[j], v[j])) return -1;
    }
    if (q) *q = v;
    return singularityOf(armJacobian(s.m.dh, sol[0]));
  }

  // Eq. 6 in full: every branch at `samples` angles over [-pi, pi), then golden-section search
  // on the best branch around the best sample.
  Pose full(int samples) const {
    Pose best;
    JointValues sol[8];
    int br[8];
    for (int k = 0; k < samples; ++k) {
      const double g = robotFreeAngle(k, samples);
      const Eigen::Matrix4d f = robotFlangeForFreeAngle(fr, g);
      const int n = armInverseBranches(s.m.dh, f, s.m.ikBranches, sol, br);
      for (int c = 0; c < n; ++c) {
        MachineValues v{};
        bool ok = true;
        for (int j = 0; j < 6 && ok; ++j) ok = aliasNear(sol[c][j], 0.0, s.limits[j], v[j]);
        if (!ok) continue;
        const double w = singularityOf(armJacobian(s.m.dh, sol[c]));
        // Wrist-flipped solutions have the same w_PS: ties (to rounding) go to the lower branch
        // so neighbouring samples do not flip between them.
        if (w > best.w * (1 + 1e-9) || (w >= best.w * (1 - 1e-9) && br[c] < best.branch)) {
          best = {g, w, br[c], v};
        }
      }
    }
    if (best.branch < 0) return best;
    return golden(best, kTwoPi / samples);
  }

  // Golden-section search for the largest w_PS on best.branch over [gamma - h, gamma + h]; keeps
  // the best value seen (never worse than the start).
  Pose golden(const Pose& start, double h) const {
    constexpr double kR = 0.6180339887498949;
    Pose best = start;
    double lo = start.gamma - h, hi = start.gamma + h;
    double x1 = hi - kR * (hi - lo), x2 = lo + kR * (hi - lo);
    MachineValues q1{}, q2{};
    double f1 = measure(x1, start.branch, &q1), f2 = measure(x2, start.branch, &q2);
    auto keep = [&](double x, double f, const MachineValues& q) {
      if (f > best.w) best = {x, f, start.branch, q};
    };
    keep(x1, f1, q1);
    keep(x2, f2, q2);
    while (hi - lo > 1e-3) {
      if (f1 >= f2) {
        hi = x2;
        x2 = x1;
        f2 = f1;
        x1 = hi - kR * (hi - lo);
        f1 = measure(x1, start.branch, &q1);
        keep(x1, f1, q1);
      } else {
        lo = x1;
        x1 = x2;
        f1 = f2;
        x2 = lo + kR * (hi - lo);
        f2 = measure(x2, start.branch, &q2);
        keep(x2, f2, q2);
      }
    }
    return best;
  }

  // Local refinement from a nearby sample's (gamma, branch): w_PS at gamma and gamma +- h, the
  // vertex of the parabola through them (clamped to the bracket); the best of the four.
  Pose local(double gamma, int branch, double h) const {
    Pose best;
    MachineValues q{};
    double w0 = measure(gamma, branch, &q);
    if (w0 < 0) return best;
    best = {gamma, w0, branch, q};
    const double wm = measure(gamma - h, branch, &q);
    if (wm > best.w) best = {gamma - h, wm, branch, q};
    const double wp = measure(gamma + h, branch, &q);
    if (wp > best.w) best = {gamma + h, wp, branch, q};
    if (wm < 0 || wp < 0) return best;
    const double den = wm - 2 * w0 + wp;
    if (den < 0) {
      const double x = gamma + 0.5 * h * (wm - wp) / den;
      const double xc = std::min(gamma + h, std::max(gamma - h, x));
      const double wx = measure(xc, branch, &q);
      if (wx > best.w) best = {xc, wx, branch, q};
    }
    return best;
  }
};

// Seeds of the free-angle search: one sample per cell of a grid of `spacing` (the one nearest the
// cell centre); seedOf[i] = the seed of sample i's cell.
std::vector<size_t> seedsOf(const std::vector<SurfaceSample>& samples, double spacing,
                            std::vector<uint8_t>& isSeed) {
  const size_t n = samples.size();
  std::vector<size_t> seedOf(n);
  isSeed.assign(n, 0);
  if (!(spacing > 0)) {
    for (size_t i = 0; i < n; ++i) seedOf[i] = i, isSeed[i] = 1;
    return seedOf;
  }
  struct Hash {
    size_t operator()(const std::array<int64_t, 3>& k) const {
      // Unsigned arithmetic: wraps instead of overflowing.
      return static_cast<size_t>(static_cast<uint64_t>(k[0]) * 73856093u ^
                                 static_cast<uint64_t>(k[1]) * 19349663u ^
                                 static_cast<uint64_t>(k[2]) * 83492791u);
    }
  };
  std::unordered_map<std::array<int64_t, 3>, std::pair<size_t, double>, Hash> cells;
  std::vector<std::array<int64_t, 3>> key(n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d c = samples[i].position / spacing;
    std::array<int64_t, 3> k{};
    double d = 0;
    for (int a = 0; a < 3; ++a) {
      const double f = std::floor(c[a]);
      k[a] = std::isfinite(f) ? static_cast<int64_t>(std::max(-1e15, std::min(1e15, f))) : 0;
      d += (c[a] - f - 0.5) * (c[a] - f - 0.5);
    }
    key[i] = k;
    auto it = cells.find(k);
    if (it == cells.end()) {
      cells.emplace(k, std::make_pair(i, d));
    } else if (d < it->second.second) {
      it->second = {i, d};
    }
  }
  for (size_t i = 0; i < n; ++i) seedOf[i] = cells[key[i]].first;
  for (size_t i = 0; i < n; ++i) isSeed[seedOf[i]] = 1;
  return seedOf;
}

// Derivatives of every value along a curve with tangent (a, b), geodesic curvature kg, normal
// curvature kappa and across component c3 of x''' (see the file comment); the Eq. 8-9 limits.
inline FeedLimit limitFromJets(const std::array<std::array<double, 9>, 6>& jets, int axes,
                               const double invV[6], const double invA[6], const double invJ[6],
                               double a, double b, double kg, double kappa, double c3,
                               double maxFeed) {
  double rv = 0, ra = 0, rj = 0;
  int iv = -1, ia = -1, ij = -1;
  const double a2 = a * a, b2 = b * b, ab = a * b;
  const double t3 = -(kg * kg + kappa * kappa);
  for (int j = 0; j < axes; ++j) {
    const double* q = jets[j].data();
    const double d1 = q[0] * a + q[1] * b;
    const double je = q[1] * a - q[0] * b;
    const double hdd = q[2] * a2 + 2 * q[3] * ab + q[4] * b2;
    const double hde = ab * (q[4] - q[2]) + q[3] * (a2 - b2);
    const double tddd = a * (q[5] * a2 + 3 * q[6] * ab) + b * (3 * q[7] * ab + q[8] * b2);
    const double d2 = hdd + kg * je;
    const double d3 = tddd + 3 * kg * hde + t3 * d1 + c3 * je;
    const double v = std::abs(d1) * invV[j], ac = std::abs(d2) * invA[j],
                 jk = std::abs(d3) * invJ[j];
    if (v > rv) rv = v, iv = j;
    if (ac > ra) ra = ac, ia = j;
    if (jk > rj) rj = jk, ij = j;
  }
  FeedLimit out;
  out.velocity = rv > 0 ? 1 / rv : kInf;
  out.acceleration = ra > 0 ? 1 / std::sqrt(ra) : kInf;
  out.jerk = rj > 0 ? 1 / std::cbrt(rj) : kInf;
  out.feed = out.velocity;
  out.limitingValue = iv;
  if (out.acceleration < out.feed) out.feed = out.acceleration, out.limitingValue = ia;
  if (out.jerk < out.feed) out.feed = out.jerk, out.limitingValue = ij;
  if (maxFeed > 0 && maxFeed <= out.feed) out.feed = maxFeed, out.limitingValue = -1;
  return out;
}

void inverseLimits(const FeedField& field, double invV[6], double invA[6], double invJ[6]) {
  for (int j = 0; j < 6; ++j) {
    const AxisDynamics& d = field.dynamics[j];
    invV[j] = d.velocity > 0 ? 1 / d.velocity : 0;
    invA[j] = d.acceleration > 0 ? 1 / d.acceleration : 0;
    invJ[j] = d.jerk > 0 ? 1 / d.jerk : 0;
  }
}

// Tangent coordinates (a, b) of a part-frame direction projected onto the sample's tangent plane;
// false when it is along the normal.
inline bool tangentCoordinates(const SurfaceSample& s, const Eigen::Vector3d& d, double& a,
                               double& b) {
  a = d.dot(s.tangentU);
  b = d.dot(s.tangentV);
  const double len = std::sqrt(a * a + b * b);
  if (!(len > 1e-12)) return false;
  a /= len;
  b /= len;
  return true;
}

inline double shapeAlong(const SurfaceSample& s, double a, double b, double c, double d) {
  const double s01 = 0.5 * (s.shape(0, 1) + s.shape(1, 0));
  return s.shape(0, 0) * a * c + s01 * (a * d + b * c) + s.shape(1, 1) * b * d;
}

// Tangent (a, b), geodesic curvature, normal curvature along f and c3 of the drive-plane section
// at a sample (the fallback when the plane is tangent: the plane's horizontal direction, kg = 0).
struct DriveGeometry {
  double a = 1, b = 0, kg = 0, kappa = 0, c3 = 0, across = 0;
};

inline DriveGeometry driveGeometry(const SurfaceSample& s, double ct, double st) {
  DriveGeometry g;
  const Eigen::Vector3d q(-st, ct, 0);
  const Eigen::Vector3d& n = s.normal;
  Eigen::Vector3d f = n.cross(q);
  const double len = f.norm();
  if (len > 1e-9) {
    f /= len;
    tangentCoordinates(s, f, g.a, g.b);
    const Eigen::Vector3d k = n.cross(f);
    const double qk = q.dot(k), qn = q.dot(n);
    g.kappa = shapeAlong(s, g.a, g.b, g.a, g.b);
    const double sfk = shapeAlong(s, g.a, g.b, -g.b, g.a);
    g.across = shapeAlong(s, -g.b, g.a, -g.b, g.a);
    const double ratio = qn / qk;
    g.kg = ratio * g.kappa;
    g.c3 = 3 * ratio * ratio * g.kappa * sfk;
  } else if (!tangentCoordinates(s, Eigen::Vector3d(ct, st, 0), g.a, g.b)) {
    g.a = 1, g.b = 0;
  }
  if (len <= 1e-9) {
    g.kappa = shapeAlong(s, g.a, g.b, g.a, g.b);
    g.across = shapeAlong(s, -g.b, g.a, -g.b, g.a);
  }
  return g;
}

}  // namespace

FeedField buildFeedField(const std::vector<SurfaceSample>& samples, const MachineProfile& machine,
                         const FeedFieldOptions& options, const ProgressFn& progress) {
  const auto t0 = Clock::now();
  FeedField out;
  auto fail = [&](Status st, const std::string& msg) {
    FeedField bad;
    bad.status = st;
    bad.message = msg;
    return bad;
  };
  if (!(options.stencilRadius > 0) || !std::isfinite(options.stencilRadius)) {
    return fail(Status::InvalidOption, "buildFeedField: stencilRadius must be a positive length");
  }
  if (options.gammaSamples < 4 || options.gammaSamples > 3600) {
    return fail(Status::InvalidOption, "buildFeedField: gammaSamples must be in [4, 3600]");
  }
  if (!(options.gammaSeedSpacing >= 0) || !std::isfinite(options.gammaSeedSpacing)) {
    return fail(Status::InvalidOption, "buildFeedField: gammaSeedSpacing must be >= 0");
  }
  const Solver solver(machine);
  if (solver.robot && !hasAnalyticInverse(machine.dh)) {
    return fail(Status::InvalidOption, "buildFeedField: robot6 needs a DH table with an analytic inverse (UR family or spherical wrist)");
  }
  out.axes = solver.axes;
  if (options.useDynamics) {
    if (solver.robot) {
      out.dynamics = machine.jointDynamics;
    } else {
      const std::vector<std::string> names = machineAxisNames(machine.kind);
      for (int j = 0; j < solver.axes; ++j) {
        auto it = machine.axisDynamics.find(names[j]);
        if (it != machine.axisDynamics.end()) out.dynamics[j] = it->second;
      }
    }
  }
  const size_t n = samples.size();
  out.values.assign(n, MachineValues{});
  out.reachable.assign(n, 0);
  out.freeAngle.assign(n, 0);
  out.singularity.assign(n, 0);
  out.jets.assign(n, {});

  const StencilPattern& pat = stencilPattern();
  const double r = options.stencilRadius;
  const bool table = machine.kind == MachineKind::Table5 || machine.kind == MachineKind::Head5;  // a C singularity
  auto finite = [](const SurfaceSample& s) {
    return s.position.allFinite() && s.normal.allFinite() && s.tangentU.allFinite() &&
           s.tangentV.allFinite() && s.shape.allFinite() && std::abs(s.normal.norm() - 1) < 1e-6;
  };

  // robot6: gamma* and branch per sample, seeds first.
  std::vector<Pose> poses;
  if (solver.robot) {
    poses.assign(n, Pose{});
    std::vector<uint8_t> isSeed;
    const std::vector<size_t> seedOf = seedsOf(samples, options.gammaSeedSpacing, isSeed);
    const double h = kPi / options.gammaSamples;
    size_t done = 0;
    if (options.singleFreeAngle) {
      // min over the seeds of w_PS per (grid gamma, branch); -1 where some seed is unreachable.
      const int gs = options.gammaSamples;
      std::vector<double> worst(static_cast<size_t>(gs) * 8, kInf);
      size_t seeds = 0;
      for (size_t i = 0; i < n; ++i) {
        if (!isSeed[i] || !finite(samples[i])) continue;
        if ((++seeds & 15) == 0 && !reportProgress(progress, "feed", 0.25 * seeds / n)) {
          return fail(Status::Cancelled, "buildFeedField: cancelled");
        }
        const RobotGamma rg(solver, samples[i].position, samples[i].normal);
        for (int k = 0; k < gs; ++k) {
          for (int b = 0; b < 8; ++b) {
            double& wk = worst[static_cast<size_t>(k) * 8 + b];
            if (wk > 0) wk = std::min(wk, rg.measure(robotFreeAngle(k, gs), b));
          }
        }
      }
      double bestW = 0;
      int bestK = -1, bestB = -1;
      for (int k = 0; k < gs; ++k) {
        for (int b = 0; b < 8; ++b) {
          const double wk = worst[static_cast<size_t>(k) * 8 + b];
          if (std::isfinite(wk) && wk > bestW * (1 + 1e-9)) bestW = wk, bestK = k, bestB = b;
        }
      }
      for (size_t i = 0; i < n && bestK >= 0; ++i) {
        if (!finite(samples[i])) continue;
        const RobotGamma rg(solver, samples[i].position, samples[i].normal);
        Pose& p = poses[i];
        p.gamma = robotFreeAngle(bestK, gs);
        p.w = rg.measure(p.gamma, bestB, &p.q);
        p.branch = p.w >= 0 ? bestB : -1;
      }
    }
    for (int pass = 0; pass < 2 && !options.singleFreeAngle; ++pass) {
      for (size_t i = 0; i < n; ++i) {
        if ((pass == 0) != (isSeed[i] != 0)) continue;
        if (((++done & 127) == 0 || pass == 0) &&
            !reportProgress(progress, "feed", 0.5 * done / n)) {
          return fail(Status::Cancelled, "buildFeedField: cancelled");
        }
        const SurfaceSample& s = samples[i];
        if (!finite(s)) continue;
        const RobotGamma rg(solver, s.position, s.normal);
        if (pass == 0) {
          poses[i] = rg.full(options.gammaSamples);
        } else {
          const Pose& seed = poses[seedOf[i]];
          if (seed.branch >= 0) poses[i] = rg.local(seed.gamma, seed.branch, h);
          if (poses[i].branch < 0) poses[i] = rg.full(options.gammaSamples);
        }
      }
    }
  }

  for (size_t i = 0; i < n; ++i) {
    if ((i & 255) == 0 &&
        !reportProgress(progress, "feed", solver.robot ? 0.5 + 0.5 * i / n : double(i) / n)) {
      return fail(Status::Cancelled, "buildFeedField: cancelled");
    }
    const SurfaceSample& s = samples[i];
    if (!finite(s)) continue;
    MachineValues centre{};
    if (solver.robot) {
      const Pose& p = poses[i];
      if (p.branch < 0) continue;
      centre = p.q;
      out.freeAngle[i] = p.gamma;
      out.singularity[i] = p.w;
    } else if (!solver.gcodeValues(s.position, s.normal, nullptr, centre)) {
      continue;
    }
    // table5: C is the azimuth of the nozzle axis, which turns on a scale of sin(B) / kappa near
    // a vertical axis; the cubic fit's O(r^2) error needs r well below it (1/20), down to
    // l_c / 16 (closer to vertical the table must spin anyway and f* is small).
    double ri = r;
    if (table && options.adaptStencil) {
      const double rho = std::sqrt(s.normal.x() * s.normal.x() + s.normal.y() * s.normal.y());
      const double m = 0.5 * (s.shape(0, 0) + s.shape(1, 1));
      const double dd = 0.5 * (s.shape(0, 0) - s.shape(1, 1));
      const double off = 0.5 * (s.shape(0, 1) + s.shape(1, 0));
      const double kmax = std::abs(m) + std::sqrt(dd * dd + off * off);
      if (kmax > 0) ri = std::min(r, std::max(r / 16, 0.05 * rho / kmax));
    }
    double vals[kStencil][6];
    bool ok = true;
    for (int k = 0; k < kStencil && ok; ++k) {
      MachineValues v{};
      if (k == 0) {
        v = centre;
      } else {
        Eigen::Vector3d p, nn;
        quadricPoint(s, ri * pat.u[k], ri * pat.v[k], p, nn);
        ok = solver.robot ? solver.robotValues(p, nn, poses[i].gamma, poses[i].branch, &centre, v)
                          : solver.gcodeValues(p, nn, &centre, v);
      }
      for (int j = 0; j < 6; ++j) vals[k][j] = v[j];
    }
    if (!ok) continue;
    out.values[i] = centre;
    out.reachable[i] = 1;
    auto& jet = out.jets[i];
    const double scale[4] = {1, 1 / ri, 1 / (ri * ri), 1 / (ri * ri * ri)};
    for (int j = 0; j < solver.axes; ++j) {
      for (int d = 0; d < kJets; ++d) {
        double acc = 0;
        for (int k = 1; k < kStencil; ++k) acc += pat.pinv[d][k] * (vals[k][j] - vals[0][j]);
        jet[j][d] = acc * scale[pat.degree[d]];
      }
    }
  }
  for (uint8_t rch : out.reachable) out.unreachable += rch ? 0 : 1;
  if (!reportProgress(progress, "feed", 1)) {
    return fail(Status::Cancelled, "buildFeedField: cancelled");
  }
  out.ms = msSince(t0);
  return out;
}

bool driveFrame(const SurfaceSample& sample, double theta, Eigen::Vector3d& feed,
                Eigen::Vector3d& cross) {
  const Eigen::Vector3d q(-std::sin(theta), std::cos(theta), 0);
  Eigen::Vector3d f = sample.normal.cross(q);
  const double len = f.norm();
  if (!(len > 1e-9)) return false;
  feed = f / len;
  cross = sample.normal.cross(feed);
  return true;
}

FeedLimit feedLimit(const FeedField& field, const SurfaceSample& sample, size_t i,
                    const Eigen::Vector3d& direction, double geodesicCurvature, double maxFeed) {
  FeedLimit none;
  if (i >= field.reachable.size() || i >= field.jets.size() || !field.reachable[i]) return none;
  double a = 1, b = 0;
  if (!tangentCoordinates(sample, direction, a, b)) return none;
  double invV[6], invA[6], invJ[6];
  inverseLimits(field, invV, invA, invJ);
  const double kappa = shapeAlong(sample, a, b, a, b);
  // A general curve: its tangent-plane projection's curvature taken as constant to third order
  // (c3 = 0).
  return limitFromJets(field.jets[i], field.axes, invV, invA, invJ, a, b, geodesicCurvature, kappa,
                       0.0, maxFeed);
}

FeedLimit driveFeedLimit(const FeedField& field, const SurfaceSample& sample, size_t i,
                         double theta, double maxFeed) {
  FeedLimit none;
  if (i >= field.reachable.size() || i >= field.jets.size() || !field.reachable[i]) return none;
  double invV[6], invA[6], invJ[6];
  inverseLimits(field, invV, invA, invJ);
  const DriveGeometry g = driveGeometry(sample, std::cos(theta), std::sin(theta));
  return limitFromJets(field.jets[i], field.axes, invV, invA, invJ, g.a, g.b, g.kg, g.kappa, g.c3,
                       maxFeed);
}

}  // namespace omnislice

namespace omnislice {

PathDerivatives drivePathDerivatives(const FeedField& field, const SurfaceSample& sample, size_t i,
                                     double theta) {
  PathDerivatives out;
  if (i >= field.reachable.size() || i >= field.jets.size() || !field.reachable[i]) return out;
  const DriveGeometry g = driveGeometry(sample, std::cos(theta), std::sin(theta));
  const double a = g.a, b = g.b, a2 = a * a, b2 = b * b, ab = a * b;
  for (int j = 0; j < field.axes; ++j) {
    const double* q = field.jets[i][j].data();
    const double d1 = q[0] * a + q[1] * b;
    const double je = q[1] * a - q[0] * b;
    const double hdd = q[2] * a2 + 2 * q[3] * ab + q[4] * b2;
    const double hde = ab * (q[4] - q[2]) + q[3] * (a2 - b2);
    const double tddd = a * (q[5] * a2 + 3 * q[6] * ab) + b * (3 * q[7] * ab + q[8] * b2);
    out.d1[j] = d1;
    out.d2[j] = hdd + g.kg * je;
    out.d3[j] = tddd + 3 * g.kg * hde - (g.kg * g.kg + g.kappa * g.kappa) * d1 + g.c3 * je;
  }
  out.reachable = true;
  return out;
}

}  // namespace omnislice

namespace omnislice {

DriveDirectionResult searchDriveDirection(const std::vector<SurfaceSample>& samples,
                                          const FeedField& field,
                                          const DriveDirectionOptions& options,
                                          const ProgressFn& progress) {
  const auto t0 = Clock::now();
  DriveDirectionResult out;
  auto fail = [&](Status st, const std::string& msg) {
    DriveDirectionResult bad;
    bad.status = st;
    bad.message = msg;
    return bad;
  };
  if (options.directions < 1 || options.directions > 100000) {
    return fail(Status::InvalidOption, "searchDriveDirection: directions must be in [1, 100000]");
  }
  if (!(options.beadWidth > 0) || !std::isfinite(options.beadWidth)) {
    return fail(Status::InvalidOption, "searchDriveDirection: beadWidth must be positive");
  }
  if (!(options.maxFeed >= 0) || !std::isfinite(options.maxFeed)) {
    return fail(Status::InvalidOption, "searchDriveDirection: maxFeed must be >= 0 (0 = none)");
  }
  if (!std::isfinite(options.forcedThetaDegrees)) {
    return fail(Status::InvalidOption, "searchDriveDirection: forcedThetaDegrees must be finite");
  }
  if (!field.ok()) {
    return fail(Status::InvalidOption,
                "searchDriveDirection: the feed field failed: " + field.message);
  }
  const size_t n = samples.size();
  if (field.values.size() != n || field.reachable.size() != n || field.jets.size() != n) {
    return fail(Status::InvalidOption, "searchDriveDirection: " + std::to_string(n) +
                                           " samples but a feed field of " +
                                           std::to_string(field.values.size()));
  }
  if (n == 0) return fail(Status::EmptyInput, "searchDriveDirection: no samples");

  // w_eff table over the samples' heights (Eq. 2).
  double hMin = kInf, hMax = 0;
  for (const SurfaceSample& s : samples) {
    if (s.height > 0 && std::isfinite(s.height)) {
      hMin = std::min(hMin, s.height);
      hMax = std::max(hMax, s.height);
    }
  }
  if (!(hMax > 0)) hMin = hMax = 0.2;
  const EffectiveWidthTable table(options.beadWidth, hMin, hMax);

  const int nd = options.directions;
  const bool forced = options.forcedThetaDegrees >= 0;
  const double forcedDeg = forced ? std::fmod(options.forcedThetaDegrees, 180.0) : 0.0;
  const int cols = nd + (forced ? 1 : 0);
  std::vector<double> ct(cols), st(cols);
  out.thetaDegrees.resize(nd);
  for (int d = 0; d < cols; ++d) {
    const double deg = d < nd ? 180.0 * d / nd : forcedDeg;
    if (d < nd) out.thetaDegrees[d] = deg;
    ct[d] = std::cos(deg * kPi / 180);
    st[d] = std::sin(deg * kPi / 180);
  }
  std::vector<double> sumV(cols, 0), sumW(cols, 0), sumF(cols, 0);
  double invV[6], invA[6], invJ[6];
  inverseLimits(field, invV, invA, invJ);
  const int axes = field.axes;
  const double maxFeed = options.maxFeed;
  // Per-direction scratch (structure of arrays: the axis loops below vectorise over directions).
  std::vector<double> buf(static_cast<size_t>(cols) * 12);
  double* ga = buf.data();
  double* gb = ga + cols;
  double* gaa = gb + cols;
  double* gbb = gaa + cols;
  double* gab = gbb + cols;
  double* gkg = gab + cols;
  double* gt3 = gkg + cols;
  double* gc3 = gt3 + cols;
  double* gw = gc3 + cols;
  double* rv = gw + cols;
  double* ra = rv + cols;
  double* rj = ra + cols;
  for (size_t i = 0; i < n; ++i) {
    if ((i & 63) == 0 && !reportProgress(progress, "direction", double(i) / n)) {
      return fail(Status::Cancelled, "searchDriveDirection: cancelled");
    }
    const SurfaceSample& s = samples[i];
    const double h = s.height > 0 && std::isfinite(s.height) ? s.height : 0.0;
    const bool reach = field.reachable[i] && h > 0;
    if (!field.reachable[i]) ++out.unreachable;
    // Drive-plane geometry (driveGeometry() unrolled): f = n x q = c (-nz, 0, nx) + s (0, -nz, ny)
    // has tangent coordinates (c A1 + s A2, c B1 + s B2); q.k = -|f|, q.n = c ny - s nx.
    const Eigen::Vector3d& nn = s.normal;
    const double a1 = -nn.z() * s.tangentU.x() + nn.x() * s.tangentU.z();
    const double a2 = -nn.z() * s.tangentU.y() + nn.y() * s.tangentU.z();
    const double b1 = -nn.z() * s.tangentV.x() + nn.x() * s.tangentV.z();
    const double b2 = -nn.z() * s.tangentV.y() + nn.y() * s.tangentV.z();
    const double s00 = s.shape(0, 0), s01 = 0.5 * (s.shape(0, 1) + s.shape(1, 0)),
                 s11 = s.shape(1, 1);
    for (int d = 0; d < cols; ++d) {
      double a = ct[d] * a1 + st[d] * a2, b = ct[d] * b1 + st[d] * b2;
      const double len = std::sqrt(a * a + b * b);
      if (!(len > 1e-9)) {
        const DriveGeometry g = driveGeometry(s, ct[d], st[d]);
        ga[d] = g.a, gb[d] = g.b, gkg[d] = g.kg, gc3[d] = g.c3;
        gt3[d] = -(g.kg * g.kg + g.kappa * g.kappa);
        gw[d] = g.across;
      } else {
        a /= len;
        b /= len;
        const double ratio = -(ct[d] * nn.y() - st[d] * nn.x()) / len;
        const double aa = a * a, bb = b * b, ab = a * b;
        const double kappa = s00 * aa + 2 * s01 * ab + s11 * bb;
        const double sfk = ab * (s11 - s00) + s01 * (aa - bb);
        const double kg = ratio * kappa;
        ga[d] = a, gb[d] = b, gkg[d] = kg;
        gt3[d] = -(kg * kg + kappa * kappa);
        gc3[d] = 3 * ratio * ratio * kappa * sfk;
        gw[d] = s00 * bb - 2 * s01 * ab + s11 * aa;  // normal curvature across (along k)
      }
      gaa[d] = ga[d] * ga[d], gbb[d] = gb[d] * gb[d], gab[d] = ga[d] * gb[d];
    }
    for (int d = 0; d < cols; ++d) {
      gw[d] = table.width(gw[d], h > 0 ? h : hMin);
      sumW[d] += gw[d];
    }
    if (!reach) continue;
    for (int d = 0; d < cols; ++d) rv[d] = ra[d] = rj[d] = 0;
    const auto& jets = field.jets[i];
    for (int j = 0; j < axes; ++j) {
      // The jets scaled by the limits: ratios |d^k Q / ds^k| / limit directly.
      const double v0 = jets[j][0] * invV[j], v1 = jets[j][1] * invV[j];
      const double A0 = jets[j][0] * invA[j], A1 = jets[j][1] * invA[j], A2 = jets[j][2] * invA[j],
                   A3 = 2 * jets[j][3] * invA[j], A4 = jets[j][4] * invA[j];
      double T[9];
      for (int k = 0; k < 9; ++k) T[k] = jets[j][k] * invJ[j];
      const double T6 = 3 * T[6], T7 = 3 * T[7], T42 = T[4] - T[2];
      for (int d = 0; d < cols; ++d) {
        const double a = ga[d], b = gb[d], aa = gaa[d], bb = gbb[d], ab = gab[d];
        const double kg = gkg[d];
        const double d1 = v0 * a + v1 * b;
        const double d2 = A2 * aa + A3 * ab + A4 * bb + kg * (A1 * a - A0 * b);
        const double d3 = a * (T[5] * aa + T6 * ab) + b * (T7 * ab + T[8] * bb) +
                          3 * kg * (ab * T42 + T[3] * (aa - bb)) + gt3[d] * (T[0] * a + T[1] * b) +
                          gc3[d] * (T[1] * a - T[0] * b);
        rv[d] = std::max(rv[d], std::abs(d1));
        ra[d] = std::max(ra[d], std::abs(d2));
        rj[d] = std::max(rj[d], std::abs(d3));
      }
    }
    for (int d = 0; d < cols; ++d) {
      // f* = min(1 / rv, 1 / sqrt(ra), 1 / cbrt(rj), maxFeed) with one root at most.
      double f = rv[d] > 0 ? 1 / rv[d] : kInf;
      if (ra[d] * f * f > 1) f = 1 / std::sqrt(ra[d]);
      if (rj[d] * f * f * f > 1) f = 1 / std::cbrt(rj[d]);
      if (maxFeed > 0 && f > maxFeed) f = maxFeed;
      if (!std::isfinite(f)) continue;  // nothing moves and no cap: contributes no rate
      sumF[d] += f;
      sumV[d] += kPi * h * gw[d] * f;
    }
  }
  out.depositionRate.resize(nd);
  out.meanWidth.resize(nd);
  out.meanFeed.resize(nd);
  for (int d = 0; d < nd; ++d) {
    out.depositionRate[d] = sumV[d] / n;
    out.meanWidth[d] = sumW[d] / n;
    out.meanFeed[d] = sumF[d] / n;
    if (out.depositionRate[d] > out.depositionRate[out.best]) out.best = d;
  }
  out.thetaStarDegrees = forced ? forcedDeg : out.thetaDegrees[out.best];
  out.depositionRateAtTheta = forced ? sumV[nd] / n : out.depositionRate[out.best];
  out.samples = n;
  if (!reportProgress(progress, "direction", 1)) {
    return fail(Status::Cancelled, "searchDriveDirection: cancelled");
  }
  out.ms = msSince(t0);
  return out;
}

}  // namespace omnislice
