// SPDX-License-Identifier: MIT
// Conservative voxelisation of a closed solid (paper 001 Section 4.1, H subset of H~): a cell is
// Solid when its closed cube meets the solid (its centre is inside, or a surface triangle
// overlaps the cube: exact separating-axis triangle/box test). The platform T is one layer of
// Platform cells directly below the part: the footprint (below every Solid cell of the lowest part
// layer), or a disc of platformRadius around the footprint's centre (a real build plate, as
// VoxelMultiAxisAM adds its platform solid to every hull; ../shared/models/voxelmaam_platform.obj).
#pragma once
#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "voxel/voxel_grid.h"

namespace omnislice {

struct VoxelizeOptions {
  double width = 0.32;     // voxel width w, mm (paper: 0.8 x nozzle diameter), > 0
  int margin = 2;          // empty cells kept around everything, >= 2
  double platformRadius = 0;  // mm; 0 = footprint only, else a disc (plus the footprint)
  size_t maxCells = 400000000;  // refuse grids with more cells (InvalidOption, message says why)
};

struct VoxelizeResult : Outcome {
  VoxelGrid grid;
  size_t solidCount = 0;     // Solid cells
  size_t platformCount = 0;  // Platform cells
};

// mesh: closed, oriented solid in the part frame with min z = 0 (placed). Progress stage
// "voxelize". Empty mesh -> EmptyInput; a grid over maxCells -> InvalidOption.
VoxelizeResult voxelizeSolid(const Mesh& mesh, const VoxelizeOptions& options,
                             const ProgressFn& progress = {});

// Support for missed voxels (paper 001 Fig. 14c): below every missed cell (missed[index] != 0),
// cells of an straight downward column (-z) that are Empty become Support, down to the first
// Solid/Support/Platform cell or to the platform layer (where a new Platform cell is added).
// Returns the number of Support cells added.
size_t addSupportColumns(VoxelGrid& grid, const std::vector<uint8_t>& missed);

}  // namespace omnislice
