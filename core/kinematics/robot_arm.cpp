// SPDX-License-Identifier: MIT
#include "common/math_constants.h"
#include "kinematics/robot_arm.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace omnislice {

namespace {
constexpr double kTwoPi = 2 * kPi;

// cos and sin of a DH twist. The UR family's twists are 0 and +-pi/2: their values are taken
// from std::cos / std::sin once (the same bits as every call would give), which halves the
// trigonometry of each forward map (half its cost in wasm, where sin and cos are software).
void twistTrig(double alpha, double& ca, double& sa) {
  // Through a volatile: the compiler would fold a constant argument with its own (correctly
  // rounded) arithmetic, which need not be the library's bits.
  static volatile double half = kPi / 2;
  static const double cPos = std::cos(half), sPos = std::sin(half);
  static const double cNeg = std::cos(-half), sNeg = std::sin(-half);
  if (alpha == 0) {
    ca = 1;      // std::cos(+-0) is exactly 1
    sa = alpha;  // std::sin(+-0) is +-0
  } else if (alpha == kPi / 2) {
    ca = cPos;
    sa = sPos;
  } else if (alpha == -kPi / 2) {
    ca = cNeg;
    sa = sNeg;
  } else {
    ca = std::cos(alpha);
    sa = std::sin(alpha);
  }
}

// frame times the standard DH link transform of row at joint value q.
void appendLink(const Eigen::Matrix4d& frame, const DhRow& row, double q, Eigen::Matrix4d& next) {
  const double th = q + row.thetaOffset;
  double ca, sa;
  twistTrig(row.alpha, ca, sa);
  appendDhLink(frame, row, std::cos(th), std::sin(th), ca, sa, next);
}
}  // namespace

void appendDhLink(const Eigen::Matrix4d& frame, const DhRow& row, double ct, double st, double ca, double sa,
                  Eigen::Matrix4d& next) {
  // Link [ct -st ca st sa a ct; st ct ca -ct sa a st; 0 sa ca d; 0 0 0 1]: its first column mixes
  // the frame's x and y, the next two its z and w = ct y - st x, the translation moves along both.
  const Eigen::Vector3d x = frame.block<3, 1>(0, 0), y = frame.block<3, 1>(0, 1), z = frame.block<3, 1>(0, 2);
  const Eigen::Vector3d c0 = ct * x + st * y, w = ct * y - st * x;
  next.block<3, 1>(0, 0) = c0;
  next.block<3, 1>(0, 1) = ca * w + sa * z;
  next.block<3, 1>(0, 2) = ca * z - sa * w;
  next.block<3, 1>(0, 3) = frame.block<3, 1>(0, 3) + row.a * c0 + row.d * z;
  next.row(3) << 0, 0, 0, 1;
}

Eigen::Matrix4d armForward(const DhTable& dh, const JointValues& q) {
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity(), next;
  for (int i = 0; i < 6; ++i) {
    appendLink(t, dh[i], q[i], next);
    t = next;
  }
  return t;
}

std::array<Eigen::Matrix4d, 7> armFrames(const DhTable& dh, const JointValues& q) {
  std::array<Eigen::Matrix4d, 7> frames;
  frames[0] = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 6; ++i) appendLink(frames[i], dh[i], q[i], frames[i + 1]);
  return frames;
}

namespace {
// Wrap an angle to (-pi, pi]. The inverse's angles are sums of a few atan2/acos values, so a
// couple of subtractions suffice (cheaper than std::remainder in the inner loop).
inline double wrapPi(double a) {
  if (!(std::abs(a) < 64 * kPi)) return std::isfinite(a) ? std::remainder(a, kTwoPi) : a;
  while (a > kPi) a -= kTwoPi;
  while (a <= -kPi) a += kTwoPi;
  return a;
}

// Joint values from the DH angles theta_i = q_i + off_i of one solution, each in (-pi, pi].
inline void storeSolution(double t1, double t2, double t3, double t4, double t5, double t6,
                          const double off[6], JointValues& q) {
  q[0] = wrapPi(t1 - off[0]);
  q[1] = wrapPi(t2 - off[1]);
  q[2] = wrapPi(t3 - off[2]);
  q[3] = wrapPi(t4 - off[3]);
  q[4] = wrapPi(t5 - off[4]);
  q[5] = wrapPi(t6 - off[5]);
}

// Clamp a cosine/sine that roundoff pushed slightly beyond [-1, 1]; false when it is truly out.
inline bool clampUnit(double& v) {
  constexpr double kSlack = 1e-9;
  if (v > 1) {
    if (v > 1 + kSlack) return false;
    v = 1;
  } else if (v < -1) {
    if (v < -1 - kSlack) return false;
    v = -1;
  }
  return true;
}
}  // namespace

bool isUrFamily(const DhTable& dh) {
  constexpr double eps = 1e-9;
  const double alpha[6] = {kPi / 2, 0, 0, kPi / 2, -kPi / 2, 0};
  for (int i = 0; i < 6; ++i) {
    const DhRow& r = dh[i];
    if (!std::isfinite(r.thetaOffset) || !std::isfinite(r.d) || !std::isfinite(r.a) ||
        !std::isfinite(r.alpha)) {
      return false;
    }
    if (std::abs(r.alpha - alpha[i]) > eps) return false;
  }
  return std::abs(dh[0].a) <= eps && std::abs(dh[3].a) <= eps && std::abs(dh[4].a) <= eps &&
         std::abs(dh[5].a) <= eps && std::abs(dh[1].d) <= eps && std::abs(dh[2].d) <= eps &&
         std::abs(dh[1].a) > eps && std::abs(dh[2].a) > eps && std::abs(dh[5].d) > eps;
}

// Derivation (theta_i = q_i + thetaOffset_i; R = [x6 y6 z6], p = flange origin):
//  * Joints 2, 3, 4 are parallel to z1 = (sin t1, -cos t1, 0). Every translation from frame 1 to
//    the wrist point p5 = p - d6 z6 (origin of frame 5) lies in the plane normal to z1 except d4,
//    so p5 . z1 = d4: r sin(t1 - phi) = d4 with (r, phi) the polar form of p5's x, y. Shoulder bit:
//    t1 = phi + asin(d4 / r) or phi + pi - asin(d4 / r).
//  * z1 is (0, 1, 0) in frame 4 and (s5 c6, -s5 s6, c5) in frame 6 (z5 = z6), so
//    c5 = z6 . z1, s5 = +-|(x6 . z1, y6 . z1)| (wrist bit: the sign) and
//    (c6, s6) = (x6 . z1, -y6 . z1) / s5. Reading t5 with atan2 from the orientation keeps it
//    accurate near the wrist singularity; the position constraint p . z1 = d4 + d6 c5 holds by the
//    choice of t1. At s5 = 0 joint 6 is parallel to joints 2-4 and t6 is free: t6 = 0. The other
//    wrist branch is (-t5, t6 + pi).
//  * In the base frame z4 = -s6 x6 - c6 y6 and x4 = c5 c6 x6 - c5 s6 y6 - s5 z6; the origin of
//    frame 4 is o4 = p5 - d5 z4. In frame 1 (origin (0, 0, d1), x1 = (c1, s1, 0), y1 = (0, 0, 1))
//    o4 = (a2 c2 + a3 c23, a2 s2 + a3 s23) and x4 = (cos t234, sin t234): a planar two-link arm.
//    Elbow bit selects the sign of t3 = +-acos((x^2 + y^2 - a2^2 - a3^2) / (2 a2 a3)).
int urInverse(const DhTable& dh, const Eigen::Matrix4d& flange, JointValues solutions[8],
              int branches[8]) {
  return urInverseBranches(dh, flange, 0xff, solutions, branches);
}

int urInverseBranches(const DhTable& dh, const Eigen::Matrix4d& flange, int branchMask,
                      JointValues solutions[8], int branches[8]) {
  // Branches wanted per shoulder (bits 0, 2, 4, 6 are shoulder 0) and per shoulder + wrist.
  auto wanted = [branchMask](int fixedBits, int fixedValue) {
    for (int b = 0; b < 8; ++b) {
      if ((branchMask >> b & 1) && (b & fixedBits) == fixedValue) return true;
    }
    return false;
  };
  const double d1 = dh[0].d, a2 = dh[1].a, a3 = dh[2].a, d4 = dh[3].d, d5 = dh[4].d,
               d6 = dh[5].d;
  const double x6[3] = {flange(0, 0), flange(1, 0), flange(2, 0)};
  const double y6[3] = {flange(0, 1), flange(1, 1), flange(2, 1)};
  const double z6[3] = {flange(0, 2), flange(1, 2), flange(2, 2)};
  const double p[3] = {flange(0, 3), flange(1, 3), flange(2, 3)};
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(x6[i]) || !std::isfinite(y6[i]) || !std::isfinite(z6[i]) ||
        !std::isfinite(p[i])) {
      return 0;
    }
  }
  const double p5[3] = {p[0] - d6 * z6[0], p[1] - d6 * z6[1], p[2] - d6 * z6[2]};
  const double r = std::sqrt(p5[0] * p5[0] + p5[1] * p5[1]);  // hypot() is slow
  // Shoulder singularity: the wrist point on the base axis (only reachable when d4 = 0); joint 1
  // is then free and 0 is the consistent choice.
  double s14 = 0;
  double phi = 0, cphi = 1, sphi = 0;
  if (r > 1e-12) {
    s14 = d4 / r;
    if (!clampUnit(s14)) return 0;
    phi = std::atan2(p5[1], p5[0]);
    cphi = p5[0] / r;
    sphi = p5[1] / r;
  } else if (std::abs(d4) > 1e-12) {
    return 0;
  }
  const double as = std::asin(s14);
  const double cas = std::sqrt(std::max(0.0, 1 - s14 * s14));
  const double off[6] = {dh[0].thetaOffset, dh[1].thetaOffset, dh[2].thetaOffset,
                         dh[3].thetaOffset, dh[4].thetaOffset, dh[5].thetaOffset};
  const double a2sq = a2 * a2, a3sq = a3 * a3, twoA2A3 = 2 * a2 * a3;
  int n = 0;
  for (int shoulder = 0; shoulder < 2; ++shoulder) {
    if (!wanted(1, shoulder)) continue;
    // cos and sin of t1 from those of phi and asin(d4 / r), without calling cos/sin.
    const double t1 = shoulder == 0 ? phi + as : phi + kPi - as;
    const double c1 = shoulder == 0 ? cphi * cas - sphi * s14 : -(cphi * cas + sphi * s14);
    const double s1 = shoulder == 0 ? sphi * cas + cphi * s14 : -(sphi * cas - cphi * s14);
    // z1 = (s1, -c1, 0)
    const double x6z1 = x6[0] * s1 - x6[1] * c1;
    const double y6z1 = y6[0] * s1 - y6[1] * c1;
    const double c5 = z6[0] * s1 - z6[1] * c1;
    const double s5abs = std::sqrt(x6z1 * x6z1 + y6z1 * y6z1);
    const double t5abs = std::atan2(s5abs, c5);
    double t6base = 0, c6base = 1, s6base = 0;
    if (s5abs > 1e-12) {
      c6base = x6z1 / s5abs;
      s6base = -y6z1 / s5abs;
      t6base = std::atan2(s6base, c6base);
    }
    double t234base = 0;
    bool haveT234 = false;
    for (int wrist = 0; wrist < 2; ++wrist) {
      if (!wanted(3, shoulder | wrist << 1)) continue;
      // Wrist 1: s5 -> -s5 flips (c6, s6), i.e. t6 + pi.
      const double sign = wrist == 0 ? 1.0 : -1.0;
      const double t5 = sign * t5abs, s5 = sign * s5abs;
      const double c6 = sign * c6base, s6 = sign * s6base;
      const double t6 = wrist == 0 ? t6base : t6base + kPi;
      // z4, x4 in the base frame.
      double z4[3], x4[3];
      for (int i = 0; i < 3; ++i) {
        z4[i] = -s6 * x6[i] - c6 * y6[i];
        x4[i] = c5 * c6 * x6[i] - c5 * s6 * y6[i] - s5 * z6[i];
      }
      const double o4[3] = {p5[0] - d5 * z4[0], p5[1] - d5 * z4[1], p5[2] - d5 * z4[2]};
      const double px = o4[0] * c1 + o4[1] * s1;  // (o4 - o1) . x1
      const double py = o4[2] - d1;               // (o4 - o1) . y1
      // x4 flips sign with the wrist branch (every term does), so t234 just gains pi.
      double t234;
      if (!haveT234) {
        t234 = std::atan2(x4[2], x4[0] * c1 + x4[1] * s1);
        t234base = wrist == 0 ? t234 : t234 - kPi;
        haveT234 = true;
      } else {
        t234 = t234base + kPi;  // wrist 1 after wrist 0
      }
      double c3 = (px * px + py * py - a2sq - a3sq) / twoA2A3;
      if (!clampUnit(c3)) continue;
      const double t3abs = std::acos(c3);
      const double s3abs = std::sqrt(std::max(0.0, 1 - c3 * c3));
      const double base = std::atan2(py, px);
      const double beta = std::atan2(a3 * s3abs, a2 + a3 * c3);
      for (int elbow = 0; elbow < 2; ++elbow) {
        const int b = shoulder | (wrist << 1) | (elbow << 2);
        if (!(branchMask >> b & 1)) continue;
        const double t3 = elbow == 0 ? t3abs : -t3abs;
        const double t2 = elbow == 0 ? base - beta : base + beta;
        const double t4 = t234 - t2 - t3;
        storeSolution(t1, t2, t3, t4, t5, t6, off, solutions[n]);
        branches[n] = b;
        ++n;
      }
    }
  }
  return n;
}

bool isSphericalWrist(const DhTable& dh) {
  constexpr double eps = 1e-9;
  for (const DhRow& r : dh) {
    if (!std::isfinite(r.thetaOffset) || !std::isfinite(r.d) || !std::isfinite(r.a) ||
        !std::isfinite(r.alpha)) {
      return false;
    }
  }
  auto quarter = [&](double a) { return std::abs(std::abs(a) - kPi / 2) <= eps; };
  return quarter(dh[0].alpha) && std::abs(dh[1].alpha) <= eps && quarter(dh[2].alpha) &&
         quarter(dh[3].alpha) && quarter(dh[4].alpha) && std::abs(dh[1].d) <= eps &&
         std::abs(dh[2].d) <= eps && std::abs(dh[4].d) <= eps && std::abs(dh[3].a) <= eps &&
         std::abs(dh[4].a) <= eps && std::abs(dh[5].a) <= eps && std::abs(dh[1].a) > eps &&
         std::hypot(dh[2].a, dh[3].d) > eps;
}

// Derivation (theta_i = q_i + thetaOffset_i, s_i = sin(alpha_i); R = [x6 y6 z6], p = flange):
//  * The wrist centre c = p - d6 z6 is the origin of frames 4 and 5 (a4 = a5 = d5 = 0). With
//    d2 = d3 = 0 every link from frame 1 to it lies in the plane of the base axis and
//    x1 = (c1, s1, 0), so t1 = atan2(c_y, c_x) (shoulder 0) or that + pi (shoulder 1).
//  * In frame 1 (origin (a1 c1, a1 s1, d1), x1, y1 = (0, 0, s_1)) joints 2 and 3 turn about
//    z1 = z2; c - o1 = a2 (cos t2, sin t2) + a3 (cos t23, sin t23) + d4 s_3 (sin t23, -cos t23):
//    a two-link arm with lengths a2 and L = |(a3, -d4 s_3)| at angle t23 + delta,
//    delta = atan2(-d4 s_3, a3). Elbow bit: the sign of phi = t3 + delta.
//  * M = R3^T R Rx(alpha6)^T = Rz(t4) Rx(alpha4) Rz(t5) Rx(alpha5) Rz(t6). Its last column is
//    (s_5 c4 sin t5, s_5 s4 sin t5, -s_4 s_5 cos t5) and its last row
//    (s_4 sin t5 c6, -s_4 sin t5 s6, -s_4 s_5 cos t5): t5 from both (wrist bit: the sign of
//    sin t5), then t4 and t6. At sin t5 = 0 only t4 + t6 (or t4 - t6) is fixed: t4 = 0.
int sphericalWristInverseBranches(const DhTable& dh, const Eigen::Matrix4d& flange, int branchMask,
                                  JointValues solutions[8], int branches[8]) {
  if (!flange.allFinite()) return 0;
  const double d1 = dh[0].d, a1 = dh[0].a, a2 = dh[1].a, a3 = dh[2].a, d4 = dh[3].d, d6 = dh[5].d;
  const double sA1 = dh[0].alpha > 0 ? 1 : -1, sA3 = dh[2].alpha > 0 ? 1 : -1;
  const double sA4 = dh[3].alpha > 0 ? 1 : -1, sA5 = dh[4].alpha > 0 ? 1 : -1;
  const Eigen::Matrix3d rot = flange.topLeftCorner<3, 3>();
  const Eigen::Vector3d c = flange.topRightCorner<3, 1>() - d6 * rot.col(2);
  const double e = d4 * sA3;
  const double len = std::hypot(a3, e), delta = std::atan2(-e, a3);
  const double rxy = std::hypot(c.x(), c.y());
  // The wrist centre on the base axis: joint 1 is free there; 0 is the consistent choice.
  const double azimuth = rxy > 1e-12 ? std::atan2(c.y(), c.x()) : 0.0;
  // Rx(alpha6)^T, applied on the right.
  const Eigen::Matrix3d rx6T = Eigen::AngleAxisd(-dh[5].alpha, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const double off[6] = {dh[0].thetaOffset, dh[1].thetaOffset, dh[2].thetaOffset,
                         dh[3].thetaOffset, dh[4].thetaOffset, dh[5].thetaOffset};
  int n = 0;
  for (int shoulder = 0; shoulder < 2; ++shoulder) {
    if (!(branchMask & (shoulder ? 0xaa : 0x55))) continue;
    const double t1 = shoulder == 0 ? azimuth : azimuth + kPi;
    const double rho = shoulder == 0 ? rxy : -rxy;  // signed distance along x1
    const double u = rho - a1, v = sA1 * (c.z() - d1);
    double cphi = (u * u + v * v - a2 * a2 - len * len) / (2 * a2 * len);
    if (!clampUnit(cphi)) continue;
    const double phiAbs = std::acos(cphi);
    for (int elbow = 0; elbow < 2; ++elbow) {
      const int fixedBits = shoulder | elbow << 2;
      if (!(branchMask >> fixedBits & 1) && !(branchMask >> (fixedBits | 2) & 1)) continue;
      const double phi = elbow == 0 ? phiAbs : -phiAbs;
      const double t2 = std::atan2(v, u) - std::atan2(len * std::sin(phi), a2 + len * std::cos(phi));
      const double t3 = phi - delta;
      // R3 = Rz(t1) Rx(alpha1) Rz(t2 + t3) Rx(alpha3) (alpha2 = 0).
      const Eigen::Matrix3d r3 =
          (Eigen::AngleAxisd(t1, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(dh[0].alpha, Eigen::Vector3d::UnitX()) *
           Eigen::AngleAxisd(t2 + t3, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(dh[2].alpha, Eigen::Vector3d::UnitX()))
              .toRotationMatrix();
      const Eigen::Matrix3d m = r3.transpose() * rot * rx6T;
      const double cos5 = -m(2, 2) * sA4 * sA5;
      const double sin5Abs = std::hypot(m(0, 2), m(1, 2));
      for (int wrist = 0; wrist < 2; ++wrist) {
        const int b = shoulder | wrist << 1 | elbow << 2;
        if (!(branchMask >> b & 1)) continue;
        const double sin5 = wrist == 0 ? sin5Abs : -sin5Abs;
        const double t5 = std::atan2(sin5, cos5);
        double t4, t6;
        if (sin5Abs > 1e-12) {
          t4 = std::atan2(m(1, 2) * sA5 * sin5, m(0, 2) * sA5 * sin5);
          t6 = std::atan2(-m(2, 1) * sA4 * sin5, m(2, 0) * sA4 * sin5);
        } else {
          // Rz(t6) = (Rx(alpha4) Rz(t5) Rx(alpha5))^T M with t4 = 0.
          t4 = 0;
          const Eigen::Matrix3d head = (Eigen::AngleAxisd(dh[3].alpha, Eigen::Vector3d::UnitX()) *
                                        Eigen::AngleAxisd(t5, Eigen::Vector3d::UnitZ()) *
                                        Eigen::AngleAxisd(dh[4].alpha, Eigen::Vector3d::UnitX()))
                                           .toRotationMatrix();
          const Eigen::Matrix3d r6 = head.transpose() * m;
          t6 = std::atan2(r6(1, 0), r6(0, 0));
        }
        storeSolution(t1, t2, t3, t4, t5, t6, off, solutions[n]);
        branches[n] = b;
        ++n;
      }
    }
  }
  return n;
}

int armInverseBranches(const DhTable& dh, const Eigen::Matrix4d& flange, int branchMask,
                       JointValues solutions[8], int branches[8]) {
  if (isUrFamily(dh)) return urInverseBranches(dh, flange, branchMask, solutions, branches);
  if (isSphericalWrist(dh)) return sphericalWristInverseBranches(dh, flange, branchMask, solutions, branches);
  return 0;
}

bool hasAnalyticInverse(const DhTable& dh) { return isUrFamily(dh) || isSphericalWrist(dh); }

Eigen::Matrix<double, 6, 6> armJacobian(const DhTable& dh, const JointValues& q) {
  const std::array<Eigen::Matrix4d, 7> f = armFrames(dh, q);
  const Eigen::Vector3d pe = f[6].topRightCorner<3, 1>();
  Eigen::Matrix<double, 6, 6> j;
  for (int i = 0; i < 6; ++i) {
    const Eigen::Vector3d z = f[i].block<3, 1>(0, 2);
    const Eigen::Vector3d o = f[i].topRightCorner<3, 1>();
    j.block<3, 1>(0, i) = z.cross(pe - o) * 1e-3;  // mm -> m per radian
    j.block<3, 1>(3, i) = z;
  }
  return j;
}

double singularityMeasure(const Eigen::Matrix<double, 6, 6>& jacobian) {
  if (!jacobian.allFinite()) return 0;
  const Eigen::JacobiSVD<Eigen::Matrix<double, 6, 6>> svd(jacobian);
  const auto s = svd.singularValues();  // descending
  if (!(s[0] > 0)) return 0;
  double prod = 1;
  for (int i = 0; i < 6; ++i) prod *= std::max(0.0, s[i]);
  // sqrt(prod) / (sqrt(s1) / sqrt(s6)) = sqrt(prod * s6 / s1)
  return std::sqrt(prod * std::max(0.0, s[5]) / s[0]);
}

}  // namespace omnislice
