// SPDX-License-Identifier: MIT
// Support regions of a part's layers: a support mesh (closed primitives, possibly overlapping)
// sliced on exactly the part's layers, kept inside the part's subspace and off the part itself.
#pragma once
#include <vector>

#include "common/status.h"
#include "mesh/clip_mesh.h"
#include "mesh/mesh.h"
#include "slice/slice_mesh.h"

namespace omnislice {

struct SupportRegionsResult : Outcome {
  std::vector<std::vector<ExPolygon2>> layers;  // one per layer of the part's slices
  double volumeMm3 = 0;                         // sum of region area x layer thickness
};

// support sliced with partOptions' direction and heights, layer 0 at part.minHeight (what lies
// below the part's first layer is not sliced), then per layer intersected with the half-planes
// {normal . x <= offset} of keepBelow (the earlier clipping planes: support must not reach into a
// subspace printed later) and minus the part's section grown by gapMm. An empty support mesh
// gives empty layers. Statuses: those of sliceMesh, Internal (clipping failure).
SupportRegionsResult supportRegions(const Mesh& support, const SliceResult& part, const SliceOptions& partOptions,
                                    const std::vector<Plane>& keepBelow, double gapMm);

}  // namespace omnislice
