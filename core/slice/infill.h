// SPDX-License-Identifier: MIT
// Internal to core/slice: parallel fill lines clipped to a region (skin and sparse infill).
#pragma once
#include <clipper.hpp>

#include <vector>

namespace omnislice {

// Straight lines at each of anglesDegrees (in the layer plane, from e1 towards e2) spaced
// spacingMm apart, anchored on the layer-frame origin (line k passes at offset (k + 1/2) * spacing
// from it, so the same angle gives the same lines on every layer), clipped to `region` (closed
// Clipper paths, non-zero fill), one clipping pass per angle. Pieces shorter than minLengthMm are dropped.
// Returns two-point open paths. Precondition: spacingMm > 0.
ClipperLib::Paths fillLines(const ClipperLib::Paths& region, const std::vector<double>& anglesDegrees,
                            double spacingMm, double minLengthMm);

}  // namespace omnislice
