// SPDX-License-Identifier: MIT
#include "toolpath/bead.h"

#include <algorithm>

#include "common/math_constants.h"

namespace omnislice {

double filamentForBead(double widthMm, double heightMm, double lengthMm, double filamentDiameterMm) {
  // The rounded sides belong to the smaller dimension: a bead narrower than it is tall (a sliver of
  // a curved layer, or a thick spot of a variable-height layer) is the same stadium turned upright.
  const double lo = std::min(widthMm, heightMm), hi = std::max(widthMm, heightMm);
  const double bead = (hi - lo) * lo + kPi * lo * lo / 4.0;
  const double filament = kPi * filamentDiameterMm * filamentDiameterMm / 4.0;
  return bead * lengthMm / filament;
}

double ellipseBeadFilament(double widthMm, double heightMm, double lengthMm, double filamentDiameterMm) {
  return widthMm * heightMm * lengthMm / (filamentDiameterMm * filamentDiameterMm);
}

}  // namespace omnislice
