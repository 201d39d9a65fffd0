// SPDX-License-Identifier: MIT
// The voxel method's layer field (paper 001 Section 4.5): the scalar field over the grown voxels
// whose iso-surfaces are the curved layers. The growth gives G (growth steps); the layers may
// follow G itself, the generations (fronts counted through AM-stable steps) or the growth
// distance (shortest path from the platform through the growth order), optionally smoothed, and
// the iso step for a target thickness comes from the field's measured gradient.
#pragma once
#include <cstdint>
#include <vector>

#include "voxel/voxel_grid.h"

namespace omnislice {

enum class LayerField {
  Distance,     // shortest path from the platform through the growth order, kept above earlier
                // neighbours (the default: layers keep their thickness where the growth waited)
  Steps,        // G itself, the growth steps (the paper)
  Generations,  // fronts counted through AM-stable steps
};

// "distance", "steps", "generations".
const char* layerFieldName(LayerField field);

// The layer field of growth steps g (values <= 0 kept: platform, empty, missed), smoothed by
// smoothIterations Jacobi passes when > 0: integer values (16 per voxel width for the distance
// and the smoothed fields), for extractCurvedLayers.
std::vector<int32_t> layerFieldOf(const VoxelGrid& grid, const std::vector<int32_t>& g, LayerField field,
                                  int smoothIterations);

// Generations: 1 + the largest generation of the AM-stable neighbours added at earlier steps.
std::vector<int32_t> generationField(const VoxelGrid& grid, const std::vector<int32_t>& g);

// Growth distance in voxel widths x scale, rounded; each voxel at least orderMargin voxels above
// every neighbour grown earlier.
std::vector<int32_t> growthDistanceField(const VoxelGrid& grid, const std::vector<int32_t>& g, double scale,
                                         double orderMargin);

// Jacobi smoothing over valued face neighbours, scaled by `scale` and rounded.
std::vector<int32_t> smoothedField(const VoxelGrid& grid, const std::vector<int32_t>& g, int iterations,
                                   int32_t scale);

// Millimetres per field unit as the layers will measure it (V / integral |grad G| dV); 0 for a
// field without gradient.
double millimetresPerFieldUnit(const VoxelGrid& grid, const std::vector<int32_t>& g);

}  // namespace omnislice
