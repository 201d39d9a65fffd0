// SPDX-License-Identifier: MIT
// The Eq. 1 risky-face test of paper 000 (multidir/risky_faces.h), shared by the plane search,
// the projected supports and the multidir preview: which faces need support along a direction.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "common/math_constants.h"
#include "multidir/risky_faces.h"

namespace omnislice {
namespace {

TEST(RiskyFaces, SinAlphaMaxIsTheSineOfTheAngle) {
  for (double deg : {10.0, 30.0, 45.0, 60.0, 89.0}) {
    EXPECT_NEAR(sinAlphaMax(deg), std::sin(deg * kPi / 180), 1e-15) << deg << " deg";
  }
}

TEST(RiskyFaces, DownFacingFacesAreRiskyAlongTheirDirectionOnly) {
  const double s = sinAlphaMax(45);
  const Eigen::Vector3d up(0, 0, 1);
  EXPECT_TRUE(riskyAlong(-up, up, s)) << "a ceiling printed upward";
  EXPECT_FALSE(riskyAlong(up, up, s)) << "a floor printed upward";
  EXPECT_FALSE(riskyAlong(Eigen::Vector3d(1, 0, 0), up, s)) << "a vertical wall";
  // Printed along the ceiling's own downward normal, the ceiling faces up: not risky.
  EXPECT_FALSE(riskyAlong(-up, -up, s));
  // Along a tilted direction d, the face whose normal is -d is risky, the one whose normal is d
  // is not.
  const Eigen::Vector3d d = Eigen::Vector3d(1, 0, 1).normalized();
  EXPECT_TRUE(riskyAlong(-d, d, s));
  EXPECT_FALSE(riskyAlong(d, d, s));
}

TEST(RiskyFaces, OverhangSteeperThanAlphaMaxIsRisky) {
  // A face tilted theta from a vertical wall toward a ceiling has the normal
  // (cos theta, 0, -sin theta): risky along +Z exactly when theta > alpha_max.
  const double s = sinAlphaMax(45);
  const Eigen::Vector3d up(0, 0, 1);
  for (double theta : {10.0, 30.0, 44.0, 46.0, 60.0, 80.0}) {
    const double t = theta * kPi / 180;
    const Eigen::Vector3d n(std::cos(t), 0, -std::sin(t));
    EXPECT_EQ(riskyAlong(n, up, s), theta > 45) << theta << " deg below the horizontal";
  }
}

TEST(RiskyFaces, DegenerateFacesAreNeverRisky) {
  // A zero normal (degenerate face) gives 0 + sin(alpha_max) > 0.
  for (double deg : {1.0, 45.0, 89.0}) {
    EXPECT_FALSE(riskyAlong(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1), sinAlphaMax(deg)));
  }
}

}  // namespace
}  // namespace omnislice
