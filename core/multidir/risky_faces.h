// SPDX-License-Identifier: MIT
// The risky-face test of paper 000 (Wu et al. 2019, Eq. 1), one definition for the plane search
// (decomposition), the projected supports and the multidir method's preview flags: a face with
// unit normal n_f printed along d is risky (needs support) when n_f . d + sin(alpha_max) < 0,
// i.e. it faces down along d by more than 90 deg - alpha_max.
#pragma once
#include <Eigen/Core>

#include "common/det_math.h"
#include "common/math_constants.h"

namespace omnislice {

// sin(alpha_max) of a maximal self-supporting angle in degrees, the same bits natively and in
// wasm (det::sin).
inline double sinAlphaMax(double alphaMaxDeg) { return det::sin(alphaMaxDeg * kPi / 180); }

// Eq. 1: a face of unit normal unitNormal is risky along the printing direction d (unit) when
// unitNormal . d + sinAlpha < 0, sinAlpha = sinAlphaMax(alphaMaxDeg). A zero normal (a degenerate
// face) is never risky since sinAlpha > 0 for alpha_max in (0, 90).
inline bool riskyAlong(const Eigen::Vector3d& unitNormal, const Eigen::Vector3d& d, double sinAlpha) {
  return unitNormal.dot(d) + sinAlpha < 0;
}

}  // namespace omnislice
