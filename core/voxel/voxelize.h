// SPDX-License-Identifier: MIT
// Conservative voxelisation of a closed solid (paper 001 Section 4.1, H subset of H~): a cell is
// Solid when its cube meets the solid with volume, i.e. its open cube meets the open solid (its
// centre is inside, or a surface triangle meets the open cube: exact separating-axis
// triangle/box test where touching counts as separated). Cells that touch the solid only along a
// face, edge or corner hold no material and stay Empty: a box whose faces lie on cell boundaries
// gives exactly the cells it covers. Cells lie on the world lattice of pitch w (multiples of w
// are cell boundaries on every axis). The platform T is one layer of
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
// "voxelize". Inside-ness by the non-zero winding rule (either orientation). The platform disc
// takes the cells whose centre is within platformRadius of the footprint centre (mean of the
// footprint cell centres). Cost: one column query per (i, j) plus one triangle/box test per cell
// of each triangle's bounding box. Statuses: EmptyInput (no triangles), NonFiniteVertex,
// ParseError (index out of range), InvalidOption (width not finite or <= 0, margin < 2,
// platformRadius < 0, mesh below z = 0, coordinates beyond 5e8 cells, a grid over maxCells: the
// message names the count), DegenerateInput (no cell holds volume), Cancelled.
VoxelizeResult voxelizeSolid(const Mesh& mesh, const VoxelizeOptions& options,
                             const ProgressFn& progress = {});

// Support for missed voxels (paper 001 Fig. 14c): below every missed cell (missed[index] != 0),
// cells of an straight downward column (-z) that are Empty become Support, down to the first
// Solid/Support/Platform cell or to the platform layer (where a new Platform cell is added).
// Returns the number of Support cells added (0 when missed.size() != grid.cellCount()).
size_t addSupportColumns(VoxelGrid& grid, const std::vector<uint8_t>& missed);

}  // namespace omnislice
