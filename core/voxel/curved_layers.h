// SPDX-License-Identifier: MIT
// Curved layers of paper 001 Section 4.5 (Eq. 2): iso-surfaces of the growing field G at values
// g_i, extracted from the voxel-centre (dual) grid with G extended one ring beyond the printable
// cells so every surface reaches past the solid, then trimmed by the input solid (and support
// cells) so each layer's boundary lies on the part's surface, and split into connected regions.
#pragma once
#include <cstdint>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "surface/surface_layers.h"
#include "voxel/voxel_grid.h"

namespace omnislice {

struct CurvedLayersOptions {
  // Iso-value step in G units; 0 = Eq. 2's w/d (voxel width over nozzle diameter). g_i =
  // i * step (g = 0 on the bed's plane), i = 1 .. ceil(max G / step) + 1.
  double isoStep = 0;
  double nozzleDiameter = 0.4;   // d, mm (for Eq. 2)
  double trimTolerance = 0.005;  // mm, trimmed boundary points lie within this of the surface
  double minRegionArea = 0.05;   // mm^2, drop smaller connected regions (slivers of trimming)
  double collapseRatio = 0.3;    // x voxel width: interior edges shorter than this are collapsed
                                 // (manifold-safe) after trimming, removing the slivers of
                                 // marching tetrahedra; 0 = off
  // Bounded thickness (mm; 0 = off): where a layer lies further than this from the layer before
  // it, partial layers at iso-values between the two (halves, quarters, eighths of the step) are
  // laid over the thick region only, each kept where the two full layers around it lie further
  // apart than 0.95 x maxThickness x 2^(level - 1) (level 1 the half, 2 the quarters, 3 the
  // eighths), so the pieces measure at most maxThickness and at least about half of it.
  double maxThickness = 0;
  // Threads extracting the full layers side by side (common/parallel.h; the layers are the same on
  // any number).
  size_t threads = 1;
};

struct CurvedLayersResult : Outcome {
  std::vector<CurvedLayer> layers;  // in print order (increasing g_i); empty layers dropped
  size_t regionCount = 0;
  size_t triangleCount = 0;
  ThicknessStats thickness;
  size_t partialLayers = 0;         // layers with CurvedLayer::partial (maxThickness)
  double extractionMs = 0, trimmingMs = 0, thicknessMs = 0, partialMs = 0;
};

// grid and g (GrowthField::g, per cell; <= 0 means no value) as produced by growField; solid is
// the placed input solid (part frame) the layers are trimmed by. Progress stage "layers".
// Method: G on cell centres (a Platform cell under a grown cell = minus its value, so g = 0 on the
// bed's plane; layer i is the iso-surface g_i = i x isoStep) is extended over every cell within
// one cell of a valued one by linear extrapolation from its valued face neighbours (flat fields continue
// exactly); iso-surfaces by marching tetrahedra on the centre grid (Freudenthal 6-tetrahedron
// split: manifold, vertices welded by lattice edge, oriented towards increasing G), visiting only
// the cubes bucketed for each g_i; trimmed by the solid's winding test (support cells count as
// inside) with crossings snapped exactly onto the solid's triangles; short edges collapsed
// (collapseRatio); thickness statistics with sample spacing w. Regions are edge-manifold and
// consistently oriented; their open edges are the trimmed boundary (boundaryVertex = 1), except
// around missed cells (g = -1), where a surface stops one ring inside the missed region.
// Statuses: InvalidOption (grid/field sizes, options, over a million iso-values), EmptyInput (no
// solid triangles or no grown cells), NonFiniteVertex, Cancelled.
CurvedLayersResult extractCurvedLayers(const VoxelGrid& grid, const std::vector<int32_t>& g,
                                       const Mesh& solid, const CurvedLayersOptions& options,
                                       const ProgressFn& progress = {});


}  // namespace omnislice
