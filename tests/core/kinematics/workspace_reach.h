// SPDX-License-Identifier: MIT
// A robot6 profile's reach over the build volume, shared by the UR5 and industrial-arm tests: every
// tip of a 100 mm cube on the platform (x, y in [-50, 50], z in [0, 100], 25 mm grid) with the
// nozzle axis vertical or tilted 30 and 60 degrees in 8 directions, through inverseMap(); per pose
// the best singularity measure w_PS over its candidates.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/math_constants.h"
#include "kinematics/kinematics.h"
#include "kinematics/robot_arm.h"
#include "machine/machine.h"

namespace omnislice {

struct WorkspaceReach {
  int points = 0;
  int unreachable = 0;                   // poses without a candidate
  int outsideLimits = 0;                 // candidates' joint values outside the profile's ranges
  double minBest = 1e300;                // min over poses of the best candidate's w_PS
  Eigen::Vector3d worstTip = Eigen::Vector3d::Zero();
  Eigen::Vector3d worstAxis = Eigen::Vector3d::Zero();
};

inline WorkspaceReach workspaceReach(const MachineProfile& m) {
  std::vector<Eigen::Vector3d> axes{Eigen::Vector3d::UnitZ()};
  for (int tilt : {30, 60}) {
    for (int k = 0; k < 8; ++k) {
      const double t = tilt * kPi / 180, a = k * kPi / 4;
      axes.emplace_back(std::sin(t) * std::cos(a), std::sin(t) * std::sin(a), std::cos(t));
    }
  }
  WorkspaceReach r;
  for (int ix = 0; ix <= 4; ++ix) {
    for (int iy = 0; iy <= 4; ++iy) {
      for (int iz = 0; iz <= 4; ++iz) {
        const Eigen::Vector3d tip(-50 + 25 * ix, -50 + 25 * iy, 25 * iz);
        for (const Eigen::Vector3d& u : axes) {
          const IkResult ik = inverseMap(m, tip, u);
          EXPECT_TRUE(ik.ok()) << ik.message;
          ++r.points;
          double best = 0;
          for (const IkCandidate& c : ik.candidates) {
            best = std::max(best, singularityMeasure(armJacobian(m.dh, c.values)));
            for (int j = 0; j < 6; ++j) {
              r.outsideLimits += c.values[j] < m.jointLimits[j].first - 1e-12 ||
                                 c.values[j] > m.jointLimits[j].second + 1e-12;
            }
          }
          if (ik.candidates.empty()) ++r.unreachable;
          if (best < r.minBest) r.minBest = best, r.worstTip = tip, r.worstAxis = u;
        }
      }
    }
  }
  return r;
}

}  // namespace omnislice
