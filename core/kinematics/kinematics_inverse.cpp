// SPDX-License-Identifier: MIT
// Inverse maps of PROGRAM-FORMAT.md for every machine kind (kinematics.h): part-frame tip and
// nozzle axis -> every candidate set of machine values within the limits.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "kinematics/kinematics.h"
#include "common/math_constants.h"
#include "kinematics/axis_rotations.h"
#include "kinematics/robot_arm.h"

namespace omnislice {

namespace {
using detail::rotX;
using detail::rotY;
using detail::rotZ;
constexpr double kDeg = kPi / 180.0;
constexpr double kLimitSlack = 1e-9;  // value units (mm, degrees, radians)


inline bool inside(double v, const std::pair<double, double>& l) {
  return v >= l.first - kLimitSlack && v <= l.second + kLimitSlack;
}

// Among v + k * period, the value inside the limits nearest `target`; false when none is inside.
bool nearestAlias(double v, double period, double target, const std::pair<double, double>& l,
                  double& out) {
  if (!std::isfinite(l.first) || !std::isfinite(l.second)) {
    out = std::abs(target - v) <= 0.5 * period ? v : v + period * std::round((target - v) / period);
    return true;
  }
  // Fast path: v itself is the nearest alias (urInverse values in (-pi, pi], target 0).
  const double k0 = std::abs(target - v) <= 0.5 * period ? 0.0 : std::round((target - v) / period);
  double best = 0;
  double bestDist = std::numeric_limits<double>::infinity();
  // The alias nearest the target, or, when it is outside, the nearest one inside the limits
  // (the limits span few periods: scan from the first alias above the lower limit).
  const double c0 = v + period * k0;
  if (inside(c0, l)) {
    out = c0;
    return true;
  }
  const double kLo = std::ceil((l.first - kLimitSlack - v) / period);
  for (double k = kLo; v + period * k <= l.second + kLimitSlack; k += 1) {
    const double c = v + period * k;
    const double d = std::abs(c - target);
    if (d < bestDist) {
      bestDist = d;
      best = c;
    }
    if (k - kLo > 1e6) break;  // absurd limits: never loop for long
  }
  if (!std::isfinite(bestDist)) return false;
  out = best;
  return true;
}

bool linearInside(const std::vector<std::pair<double, double>>& limits, const Eigen::Vector3d& m) {
  return inside(m.x(), limits[0]) && inside(m.y(), limits[1]) && inside(m.z(), limits[2]);
}

IkResult inverseCartesian(const MachineProfile& machine, const Eigen::Vector3d& tip,
                          const Eigen::Vector3d& u, const IkOptions& options) {
  IkResult r;
  if (std::hypot(u.x(), u.y()) > options.axisTolerance || u.z() <= 0) {
    r.orientationFeasible = false;
    return r;
  }
  const auto limits = machineLimits(machine);
  if (!linearInside(limits, tip)) {
    r.outOfLimits = 1;
    return r;
  }
  IkCandidate c;
  c.values = {tip.x(), tip.y(), tip.z(), 0, 0, 0};
  r.candidates.push_back(c);
  return r;
}

IkResult inverseRotary(const MachineProfile& machine, const Eigen::Vector3d& tip,
                       const Eigen::Vector3d& u, const IkOptions& options) {
  IkResult r;
  // u = Rx(A)^T z = (0, sin A, cos A).
  if (std::abs(u.x()) > options.axisTolerance) {
    r.orientationFeasible = false;
    return r;
  }
  double a = std::atan2(u.y(), u.z()) / kDeg;
  const double step = machine.stepAngleDegrees;
  if (step > 0) {
    const double k = std::round(a / step);
    if (std::abs(a - k * step) > 1e-6) {
      r.orientationFeasible = false;
      return r;
    }
    a = k * step;
  }
  const auto limits = machineLimits(machine);
  const auto& la = limits[3];
  // Every 360-degree alias inside the limits, nearest the reference (or 0) first.
  const double target = options.reference ? (*options.reference)[3] : 0.0;
  std::vector<double> aliases;
  if (std::isfinite(la.first) && std::isfinite(la.second)) {
    const double kLo = std::ceil((la.first - kLimitSlack - a) / 360.0);
    for (double k = kLo; a + 360.0 * k <= la.second + kLimitSlack && aliases.size() < 64; k += 1) {
      aliases.push_back(a + 360.0 * k);
    }
  } else {
    double v = 0;
    nearestAlias(a, 360.0, target, la, v);
    aliases.push_back(v);
  }
  if (step > 0) {
    // A stepper counts whole steps: an alias is reachable only when it is a step multiple too
    // (360 need not be one).
    aliases.erase(std::remove_if(aliases.begin(), aliases.end(),
                                 [&](double v) {
                                   return std::abs(v - step * std::round(v / step)) > 1e-6;
                                 }),
                  aliases.end());
  }
  if (aliases.empty()) {
    r.orientationFeasible = false;
    r.outOfLimits = 1;
    return r;
  }
  std::sort(aliases.begin(), aliases.end(), [&](double x, double y) {
    return std::abs(x - target) < std::abs(y - target);
  });
  const Eigen::Vector3d& p = machine.pivot;
  const Eigen::Vector3d m = p + rotX(a) * (tip - p);
  if (!linearInside(limits, m)) {
    r.outOfLimits = 1;
    return r;
  }
  for (double v : aliases) {
    IkCandidate c;
    c.values = {m.x(), m.y(), m.z(), v, 0, 0};
    r.candidates.push_back(c);
  }
  return r;
}

// table5 and head5: B and C from the axis, in two branches, then the linear axes.
//   table5: u = Rz(-C) Ry(-B) z = (-sin B cos C, sin B sin C, cos B); m = P + Ry(B) Rz(C)(q - P).
//   head5:  u = Rz(C) Ry(B) z = (sin B cos C, sin B sin C, cos B); (X,Y,Z) = q - Rz(C) Ry(B) o.
// Branches (B, C) with B >= 0 and (-B, C + 180).
IkResult inverseTwoRotary(const MachineProfile& machine, const Eigen::Vector3d& tip, const Eigen::Vector3d& u,
                          const IkOptions& options) {
  IkResult r;
  const bool head = machine.kind == MachineKind::Head5;
  const double sinB = std::hypot(u.x(), u.y());
  const double bAbs = std::atan2(sinB, u.z()) / kDeg;  // [0, 180]
  const auto limits = machineLimits(machine);
  const double refC = options.reference ? (*options.reference)[4] : 0.0;
  struct Branch {
    double b, c;
    int index;
  };
  Branch branches[2];
  int nb = 0;
  // Within 1e-4 rad of the C axis the azimuth of u is rounding noise of the tool-path's axis
  // filtering (B of a few 1e-6 degrees), and following it would spin C through the singularity
  // inside one move: treat u as on the axis (orientation error < 1e-4 rad).
  if (sinB <= 1e-4) {
    // B = 0 (or 180): C is free; keep the reference C so the motion does not spin C.
    const double b = u.z() > 0 ? 0.0 : 180.0;
    branches[nb++] = {b, refC, 0};
    if (b != 0) branches[nb++] = {-b, refC, 1};
  } else {
    const double c = std::atan2(u.y(), head ? u.x() : -u.x()) / kDeg;
    branches[nb++] = {bAbs, c, 0};
    branches[nb++] = {-bAbs, c + 180.0, 1};
  }
  bool anyOrientation = false;
  const Eigen::Vector3d& p = machine.pivot;
  for (int i = 0; i < nb; ++i) {
    const Branch& br = branches[i];
    double cv = 0;
    if (!inside(br.b, limits[3]) || !nearestAlias(br.c, 360.0, refC, limits[4], cv)) {
      ++r.outOfLimits;
      continue;
    }
    anyOrientation = true;
    const Eigen::Vector3d m = head ? Eigen::Vector3d(tip - rotZ(cv) * rotY(br.b) * machine.tipOffset)
                                   : Eigen::Vector3d(p + rotY(br.b) * rotZ(cv) * (tip - p));
    if (!linearInside(limits, m)) {
      ++r.outOfLimits;
      continue;
    }
    IkCandidate cand;
    cand.values = {m.x(), m.y(), m.z(), br.b, cv, 0};
    cand.branch = br.index;
    r.candidates.push_back(cand);
  }
  r.orientationFeasible = anyOrientation;
  return r;
}

// head4: the nozzle leans tau from +Z and C turns it, so only the azimuth of u is the machine's to
// choose: C = atan2(u.y, u.x) (tau < 0 turns the other way: C + 180), the reference's C where u is
// within 1e-4 rad of vertical (a planar print keeps C still). The candidate's axis is the head's,
// u turned onto the cone of half-angle tau within its vertical plane; the tip is exact.
IkResult inverseHeadFixedTilt(const MachineProfile& machine, const Eigen::Vector3d& tip, const Eigen::Vector3d& u,
                              const IkOptions& options) {
  IkResult r;
  const auto limits = machineLimits(machine);
  const double refC = options.reference ? (*options.reference)[3] : 0.0;
  double c = refC;
  if (std::hypot(u.x(), u.y()) > 1e-4) {
    c = std::atan2(u.y(), u.x()) / kDeg + (machine.tiltDegrees < 0 ? 180.0 : 0.0);
  }
  double cv = 0;
  if (!nearestAlias(c, 360.0, refC, limits[3], cv)) {
    r.orientationFeasible = false;
    r.outOfLimits = 1;
    return r;
  }
  const Eigen::Vector3d m = tip - rotZ(cv) * rotY(machine.tiltDegrees) * machine.tipOffset;
  if (!linearInside(limits, m)) {
    r.outOfLimits = 1;
    return r;
  }
  IkCandidate cand;
  cand.values = {m.x(), m.y(), m.z(), cv, 0, 0};
  r.candidates.push_back(cand);
  return r;
}

// Rotation taking unit vector `from` onto unit vector `to` about from x to (Rodrigues); a half
// turn about an axis normal to `from` when they are opposite.
Eigen::Matrix3d rotationBetween(const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  const Eigen::Vector3d v = from.cross(to);
  const double c = from.dot(to);
  if (c < -1 + 1e-12) {
    Eigen::Vector3d n = from.cross(Eigen::Vector3d::UnitX());
    if (n.norm() < 1e-6) n = from.cross(Eigen::Vector3d::UnitY());
    n.normalize();
    return 2 * n * n.transpose() - Eigen::Matrix3d::Identity();
  }
  Eigen::Matrix3d k;
  k << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return Eigen::Matrix3d::Identity() + k + k * k / (1 + c);
}

IkResult inverseRobot(const MachineProfile& machine, const Eigen::Vector3d& tip,
                      const Eigen::Vector3d& u, const IkOptions& options) {
  IkResult r;
  if (!hasAnalyticInverse(machine.dh)) {
    r.status = Status::InvalidOption;
    r.message = "robot6 inverse kinematics needs a UR-family or spherical-wrist DH table";
    return r;
  }
  const int samples = std::max(1, options.freeRotationSamples);
  const RobotFreeRotation frame = robotFreeRotation(machine, tip, u);
  const auto limits = machineLimits(machine);
  const MachineValues* ref = options.reference;
  r.candidates.reserve(static_cast<size_t>(8 * samples));
  JointValues sol[8];
  int br[8];
  bool any = false;
  for (int k = 0; k < samples; ++k) {
    const double g = robotFreeAngle(k, samples);
    const Eigen::Matrix4d f = robotFlangeForFreeAngle(frame, g);
    const int ns = armInverseBranches(machine.dh, f, options.branchMask & machine.ikBranches & 0xff, sol, br);
    for (int s = 0; s < ns; ++s) {
      any = true;
      IkCandidate c;
      bool ok = true;
      for (int j = 0; j < 6 && ok; ++j) {
        const double target = ref ? (*ref)[j] : 0.0;
        ok = nearestAlias(sol[s][j], 2 * kPi, target, limits[j], c.values[j]);
      }
      if (!ok) {
        ++r.outOfLimits;
        continue;
      }
      c.branch = br[s];
      c.freeAngle = g;
      r.candidates.push_back(c);
    }
  }
  // Unreachable everywhere: the tip or the axis cannot be realised by this arm placement.
  r.orientationFeasible = any;
  return r;
}
}  // namespace

RobotFreeRotation robotFreeRotation(const MachineProfile& machine, const Eigen::Vector3d& tip,
                                    const Eigen::Vector3d& axis) {
  // Platform rotation R with R u = n: R = Rh Rz(g) Rmin, where Rmin takes u onto the platform's
  // +Z (smooth in u except for u = -Z, which no printable orientation uses) and Rh takes the
  // platform's +Z onto the nozzle axis; Rh Rz(g) = Rn(g) Rh is the free rotation about the nozzle.
  RobotFreeRotation f;
  f.rMin = rotationBetween(axis, Eigen::Vector3d::UnitZ());
  f.rH = rotationBetween(Eigen::Vector3d::UnitZ(), machine.nozzleAxis.normalized());
  const Eigen::Matrix4d& t = machine.flangeToPlatform;
  // inverse(T) of a rigid transform.
  f.tRt = t.topLeftCorner<3, 3>().transpose();
  f.tInvP = -f.tRt * t.topRightCorner<3, 1>();
  f.tip = tip;
  f.nozzleTip = machine.nozzleTip;
  return f;
}

Eigen::Matrix4d robotFlangeForFreeAngle(const RobotFreeRotation& frame, double angle) {
  const double cg = std::cos(angle), sg = std::sin(angle);
  Eigen::Matrix3d rz;
  rz << cg, -sg, 0, sg, cg, 0, 0, 0, 1;
  const Eigen::Matrix3d rw = frame.rH * rz * frame.rMin;
  const Eigen::Vector3d pw = frame.nozzleTip - rw * frame.tip;
  // Flange F = W T^-1.
  Eigen::Matrix4d f = Eigen::Matrix4d::Identity();
  f.topLeftCorner<3, 3>() = rw * frame.tRt;
  f.topRightCorner<3, 1>() = rw * frame.tInvP + pw;
  return f;
}

double robotFreeAngle(int k, int samples) { return -kPi + 2 * kPi * k / samples; }

IkResult inverseMap(const MachineProfile& machine, const Eigen::Vector3d& tip,
                    const Eigen::Vector3d& axis, const IkOptions& options) {
  IkResult bad;
  bad.status = Status::InvalidOption;
  if (!tip.allFinite() || !axis.allFinite()) {
    bad.message = "inverseMap: non-finite tip or axis";
    return bad;
  }
  const double len = axis.norm();
  if (std::abs(len - 1) > 1e-6) {
    bad.message = "inverseMap: the nozzle axis must be a unit vector";
    return bad;
  }
  if (options.reference) {
    for (double v : *options.reference) {
      if (!std::isfinite(v)) {
        bad.message = "inverseMap: non-finite reference values";
        return bad;
      }
    }
  }
  const Eigen::Vector3d u = axis / len;
  switch (machine.kind) {
    case MachineKind::Cartesian3: return inverseCartesian(machine, tip, u, options);
    case MachineKind::Rotary4: return inverseRotary(machine, tip, u, options);
    case MachineKind::Table5:
    case MachineKind::Head5: return inverseTwoRotary(machine, tip, u, options);
    case MachineKind::Head4: return inverseHeadFixedTilt(machine, tip, u, options);
    case MachineKind::Robot6: break;
  }
  return inverseRobot(machine, tip, u, options);
}

}  // namespace omnislice
