// SPDX-License-Identifier: MIT
#include "program/interpolate_machine_move.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "geometry/segment.h"
#include "kinematics/kinematics.h"

namespace omnislice {

namespace {

constexpr double kPi = 3.14159265358979323846;

double angleBetween(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

MachineValues lerpValues(const MachineValues& a, const MachineValues& b, double s) {
  MachineValues out{};
  for (size_t i = 0; i < out.size(); ++i) out[i] = s >= 1.0 ? b[i] : a[i] + s * (b[i] - a[i]);
  return out;
}

MoveInterpolation interpolateMachineMove(const MachineProfile& machine, const MachineValues& a,
                                         const MachineValues& b, const InterpolateOptions& options) {
  MoveInterpolation r;
  const int n = machineAxisCount(machine.kind);
  auto fail = [&](const std::string& msg) {
    MoveInterpolation f;
    f.status = Status::InvalidOption;
    f.message = msg;
    return f;
  };
  if (n == 0) return fail("unknown machine kind '" + machine.kind + "'");
  Eigen::Vector3d tipA, axisA, tipB, axisB;
  if (!forwardMap(machine, a, tipA, axisA) || !forwardMap(machine, b, tipB, axisB)) {
    return fail("machine values cannot be mapped to the part frame");
  }
  // Largest and summed change of the angular values, in radians.
  const double toRad = machine.kind == "robot6" ? 1.0 : kPi / 180.0;
  double angular = 0, angularSum = 0;
  for (int i = 0; i < n; ++i) {
    if (!isAngularAxis(machine.kind, i)) continue;
    const double d = std::abs(b[i] - a[i]) * toRad;
    angular = std::max(angular, d);
    angularSum += d;
  }
  r.t = {0.0};
  r.tips = {tipA};
  r.axes = {axisA};
  if (angular == 0) {
    r.t.push_back(1.0);
    r.tips.push_back(tipB);
    r.axes.push_back(axisB);
    r.length = (tipB - tipA).norm();
    return r;
  }
  const double axisStep = std::max(1e-6, options.maxAxisStepDegrees * kPi / 180.0);
  const double cap = double(std::max<size_t>(2, options.maxPieces));
  // Start with pieces of at most 2 degrees of summed rotation (the platform turns by at most the
  // summed joint change), then bisect where the tolerances are not met.
  const int initial = int(std::min(cap / 2, std::max(1.0, std::ceil(angularSum / (2 * kPi / 180.0)))));
  struct Point {
    double t;
    Eigen::Vector3d tip, axis;
  };
  auto eval = [&](double t, Point& p) {
    p.t = t;
    return forwardMap(machine, lerpValues(a, b, t), p.tip, p.axis);
  };
  std::vector<Point> done;
  done.reserve(initial + 1);
  done.push_back({0.0, tipA, axisA});
  size_t pieces = 0;
  // Depth-first bisection of each initial piece, in order.
  std::vector<std::pair<Point, int>> stack;
  for (int k = 1; k <= initial; ++k) {
    Point end;
    if (k == initial) {
      end = {1.0, tipB, axisB};
    } else if (!eval(double(k) / initial, end)) {
      return fail("machine values cannot be mapped to the part frame");
    }
    stack.push_back({end, 0});
    while (!stack.empty()) {
      const Point& start = done.back();
      const Point stop = stack.back().first;
      const int depth = stack.back().second;
      bool split = false;
      Point mid;
      if (depth < 40 && double(pieces + stack.size()) < cap) {
        if (!eval(0.5 * (start.t + stop.t), mid)) {
          return fail("machine values cannot be mapped to the part frame");
        }
        split = angleBetween(start.axis, stop.axis) > axisStep ||
                std::sqrt(pointSegmentDistance2(mid.tip, start.tip, stop.tip)) > options.chordTolerance;
        for (double q : {0.25, 0.75}) {
          if (split) break;
          Point p;
          if (!eval(start.t + q * (stop.t - start.t), p)) {
            return fail("machine values cannot be mapped to the part frame");
          }
          split = std::sqrt(pointSegmentDistance2(p.tip, start.tip, stop.tip)) > options.chordTolerance;
        }
      }
      if (split) {
        stack.push_back({mid, depth + 1});
      } else {
        done.push_back(stop);
        ++pieces;
        stack.pop_back();
      }
    }
  }
  r.t.clear();
  r.tips.clear();
  r.axes.clear();
  for (size_t i = 0; i < done.size(); ++i) {
    r.t.push_back(done[i].t);
    r.tips.push_back(done[i].tip);
    r.axes.push_back(done[i].axis);
    if (i > 0) r.length += (done[i].tip - done[i - 1].tip).norm();
  }
  return r;
}

}  // namespace omnislice
