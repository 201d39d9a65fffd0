// SPDX-License-Identifier: MIT
#include "program/interpolate_machine_move.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Geometry>

#include "common/math_constants.h"
#include "geometry/segment.h"
#include "kinematics/kinematics.h"

namespace omnislice {

namespace {


double angleBetween(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

MachineValues lerpValues(const MachineValues& a, const MachineValues& b, double s) {
  MachineValues out{};
  for (size_t i = 0; i < out.size(); ++i) out[i] = s >= 1.0 ? b[i] : a[i] + s * (b[i] - a[i]);
  return out;
}

namespace {

struct Point {
  double t;
  Eigen::Vector3d tip, axis;
};

// The pieces of the move a -> b: emit(point) for each end point in order, from a's (t = 0) to b's
// (t = 1). tipA/axisA and tipB/axisB are forwardMap of a and b. Returns false when a value cannot
// be mapped. No allocation: the bisection stack is at most 41 deep.
template <class Emit>
bool walkMove(const MachineProfile& machine, const MachineValues& a, const MachineValues& b,
              const InterpolateOptions& options, const Point& first, const Point& last, Emit&& emit) {
  const int n = machineAxisCount(machine.kind);
  // Largest and summed change of the angular values, in radians.
  const double toRad = machine.kind == MachineKind::Robot6 ? 1.0 : kPi / 180.0;
  double angular = 0, angularSum = 0;
  for (int i = 0; i < n; ++i) {
    if (!isAngularAxis(machine.kind, i)) continue;
    const double d = std::abs(b[i] - a[i]) * toRad;
    angular = std::max(angular, d);
    angularSum += d;
  }
  emit(first);
  if (angular == 0) {
    emit(last);
    return true;
  }
  const double axisStep = std::max(1e-6, options.maxAxisStepDegrees * kPi / 180.0);
  const double cap = double(std::max<size_t>(2, options.maxPieces));
  // Start with pieces of at most 2 degrees of summed rotation (the platform turns by at most the
  // summed joint change), then bisect where the tolerances are not met.
  const int initial = int(std::min(cap / 2, std::max(1.0, std::ceil(angularSum / (2 * kPi / 180.0)))));
  auto eval = [&](double t, Point& p) {
    p.t = t;
    return forwardMap(machine, lerpValues(a, b, t), p.tip, p.axis);
  };
  constexpr int kMaxDepth = 40;
  std::array<std::pair<Point, int>, kMaxDepth + 2> stack;
  size_t top = 0;  // entries in stack
  Point start = first;
  size_t pieces = 0;
  // Depth-first bisection of each initial piece, in order.
  for (int k = 1; k <= initial; ++k) {
    Point end;
    if (k == initial) {
      end = last;
    } else if (!eval(double(k) / initial, end)) {
      return false;
    }
    stack[top++] = {end, 0};
    while (top > 0) {
      const Point stop = stack[top - 1].first;
      const int depth = stack[top - 1].second;
      bool split = false;
      Point mid;
      if (depth < kMaxDepth && double(pieces + top) < cap) {
        if (!eval(0.5 * (start.t + stop.t), mid)) return false;
        split = angleBetween(start.axis, stop.axis) > axisStep ||
                std::sqrt(pointSegmentDistance2(mid.tip, start.tip, stop.tip)) > options.chordTolerance;
        for (double q : {0.25, 0.75}) {
          if (split) break;
          Point p;
          if (!eval(start.t + q * (stop.t - start.t), p)) return false;
          split = std::sqrt(pointSegmentDistance2(p.tip, start.tip, stop.tip)) > options.chordTolerance;
        }
      }
      if (split) {
        stack[top++] = {mid, depth + 1};
      } else {
        emit(stop);
        start = stop;
        ++pieces;
        --top;
      }
    }
  }
  return true;
}

const char* const kUnmapped = "machine values cannot be mapped to the part frame";

}  // namespace

MoveInterpolation interpolateMachineMove(const MachineProfile& machine, const MachineValues& a,
                                         const MachineValues& b, const InterpolateOptions& options) {
  MoveInterpolation r;
  auto fail = [&](const std::string& msg) {
    MoveInterpolation f;
    f.status = Status::InvalidOption;
    f.message = msg;
    return f;
  };
  Point first{0.0, {}, {}}, last{1.0, {}, {}};
  if (!forwardMap(machine, a, first.tip, first.axis) || !forwardMap(machine, b, last.tip, last.axis)) {
    return fail(kUnmapped);
  }
  const bool ok = walkMove(machine, a, b, options, first, last, [&](const Point& p) {
    if (!r.tips.empty()) r.length += (p.tip - r.tips.back()).norm();
    r.t.push_back(p.t);
    r.tips.push_back(p.tip);
    r.axes.push_back(p.axis);
  });
  if (!ok) return fail(kUnmapped);
  return r;
}

double interpolatedTipLength(const MachineProfile& machine, const MachineValues& a,
                             const MachineValues& b, const Eigen::Vector3d& tipA,
                             const Eigen::Vector3d& axisA, const Eigen::Vector3d& tipB,
                             const Eigen::Vector3d& axisB, const InterpolateOptions& options) {
  double length = 0;
  Eigen::Vector3d previous = tipA;
  const bool ok = walkMove(machine, a, b, options, Point{0.0, tipA, axisA}, Point{1.0, tipB, axisB},
                           [&](const Point& p) {
                             length += (p.tip - previous).norm();
                             previous = p.tip;
                           });
  return ok ? length : -1;
}

}  // namespace omnislice
