// SPDX-License-Identifier: MIT
// `method = surface` (paper 003's experiments): an open surface printed as one layer of iso-planar
// paths on a support base. The surface is lifted so the base under it is at least
// surface.base_mm thick; the base (the solid between z = 0 and the surface moved down by the
// layer height along its normals, core/surface/height_field_solid) is printed with planar layers
// first, then the surface layer with the nozzle along the surface normal. The part `verify`
// checks is the solid between z = 0 and the surface (the same construction from the program's
// placement). Internal to core/pipeline.
#pragma once
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "pipeline/pipeline.h"
#include "pipeline/settings.h"
#include "machine/machine.h"
#include "toolpath/toolpath.h"

namespace omnislice {

struct SurfaceMethodOutput : Outcome {
  Toolpath toolpath;
  Eigen::Matrix4d lift = Eigen::Matrix4d::Identity();  // applied after the placement
  Mesh part;                 // the solid under the surface, part frame (after the lift)
  std::string reportJson;    // the report's "isoplanar" object (+ "surface" fields)
  int layers = 0;            // planar base layers + 1
  size_t baseLayers = 0;
  std::vector<std::pair<std::string, double>> timingsMs;
  PreviewBuffers preview;    // only the surface fields are filled
};

// surface: the placed open surface (min z = 0). Progress stages "slice", "toolpath", "feed",
// "direction", "paths", "benchmark".
SurfaceMethodOutput runSurfaceMethod(const Mesh& surface, const Settings& settings,
                                     const MachineProfile& machine, const ProgressFn& progress);

// The solid `verify` checks for a surface program: heightFieldSolid(placedSurface, 0).solid.
struct SurfacePartResult : Outcome {
  Mesh part;
};
SurfacePartResult surfacePart(const Mesh& placedSurface);

}  // namespace omnislice
