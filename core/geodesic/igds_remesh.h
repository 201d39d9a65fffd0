// SPDX-License-Identifier: MIT
// Private to igds.cpp: isotropic remeshing (Botsch and Kobbelt 2004) and improved Laplacian
// smoothing (Vollmer et al. 1999) of one connected interpolated IGDS, every vertex projected back
// onto the interpolated surface (interior vertices) or onto its boundary polyline (boundary
// vertices; corners stay). Operations never break edge-manifoldness: collapses obey the link
// condition, no operation flips a triangle against its previous normal.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "common/progress.h"
#include "surface/surface_layers.h"

namespace omnislice {

struct RemeshInput {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::array<uint32_t, 3>> triangles;  // consistently oriented, edge-manifold
  std::vector<double> slope;  // per triangle (or empty): the field's |grad| there; the allowed
                              // deviation near it is maxDeviation / max(1, slope)
};

struct RemeshParams {
  double targetEdge = 1;      // L, mm
  int remeshIterations = 5;   // split / collapse / flip / relax rounds
  int smoothIterations = 3;   // HC Laplacian rounds
  double cornerDegrees = 40;  // boundary turning angle above which a boundary vertex is a corner
  double maxDeviation = 0;    // mm, centroid distance checked after remeshing (0 = no check),
                              // divided by the nearest input triangle's slope where above 1
};

struct RemeshStats {
  double remeshMs = 0, smoothMs = 0;
  bool deviates = false;  // a triangle centroid lies farther than maxDeviation from the surface
  bool cancelled = false;
  bool selfIntersecting = false;  // two triangles without a common vertex intersect
};

// Remeshes `in` into `out` (mesh, boundaryVertex, area). progress is polled between rounds (its
// fraction argument is `progressAt`).
RemeshStats remeshIgdsRegion(const RemeshInput& in, const RemeshParams& params, LayerRegion& out,
                             const ProgressFn& progress, double progressAt);

}  // namespace omnislice
