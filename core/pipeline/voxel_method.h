// SPDX-License-Identifier: MIT
// The voxel method of paper 001 as one pipeline step: placed solid -> voxel grid -> growing field
// (with supports under missed voxels when asked) -> curved layers -> Fermat spirals -> part-frame
// Toolpath with nozzle axes and local bead heights. Internal to core/pipeline.
#pragma once
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

struct VoxelMethodOutput : Outcome {
  Toolpath toolpath;
  std::string reportJson;    // the report's "voxel" object
  double layerHeight = 0;    // mean measured layer thickness (nominal where unmeasured), mm
  int layers = 0;            // curved layers with at least one path
  std::vector<std::pair<std::string, double>> timingsMs;  // voxelize, peeling, growth, layers,
                                                          // toolpath (pipeline stage names)
  PreviewBuffers preview;    // only the surface and voxel fields are filled
  std::string isoplanarJson; // fill = isoplanar: the report's "isoplanar" object
};

// part: the placed, validated solid (min z = 0). Progress stages "voxelize", "peeling", "growth",
// "layers", "toolpath".
// machine: the resolved profile (its tilt range bounds the nozzle axes).
VoxelMethodOutput runVoxelMethod(const Mesh& part, const Settings& settings,
                                 const MachineProfile& machine, const ProgressFn& progress);

}  // namespace omnislice
