// SPDX-License-Identifier: MIT
// The growing field G of paper 001 Section 4: convex-front advancing (Section 4.2, Constraints 1-2,
// Definition 1 AM-stable neighbours), shadow prevention (Section 4.3: the incremental
// Dijkstra-ordered scheme and the recursive PCA split into shadow-free sets, Appendix B idea),
// the inverse peeling field F-bar (Section 4.4, Eq. 1) and the field-governed growth of
// Algorithm 1 (PG-SP-GCFA). G(v) = tau is the index of the layer of voxels v was added in.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "voxel/voxel_grid.h"

namespace omnislice {

enum class GrowthStrategy {
  Gcfa,      // greedy convex-front advancing (Section 4.2)
  SpGcfa,    // + shadow prevention (Section 4.3)
  PgGcfa,    // field-governed by F-bar, no shadow prevention
  PgSpGcfa,  // Algorithm 1: field-governed + shadow prevention (the default)
};
enum class ShadowScheme { Incremental, RecursivePca };

const char* growthStrategyName(GrowthStrategy s);  // "gcfa", "sp-gcfa", "pg-gcfa", "pg-sp-gcfa"
const char* shadowSchemeName(ShadowScheme s);      // "incremental", "recursive"
bool parseGrowthStrategy(const std::string& text, GrowthStrategy& out);
bool parseShadowScheme(const std::string& text, ShadowScheme& out);

struct GrowthOptions {
  GrowthStrategy strategy = GrowthStrategy::PgSpGcfa;
  ShadowScheme shadowScheme = ShadowScheme::RecursivePca;
  double peelStep = 1;      // delta f of Algorithm 1, in F-bar units (peeling sheets), > 0
  double epsilon = 1.0;     // eps of Definitions 2-3, in voxel widths, >= 0 (see below)
  uint32_t seed = 1;        // source voxel choice of the incremental scheme (deterministic)
};

struct GrowthField : Outcome {
  // Per grid cell (VoxelGrid::index order): G = tau >= 1 for grown voxels (printable cells),
  // 0 for Empty/Platform cells, -1 for printable cells never reached (missed).
  std::vector<int32_t> g;
  // Per grid cell: F-bar of Eq. 1 (>= 1) for printable cells when a PG strategy ran, else empty.
  std::vector<int32_t> peel;
  int32_t layers = 0;       // max G
  size_t grown = 0;         // printable cells with G >= 1
  size_t missed = 0;        // printable cells with G = -1
  size_t shadowChecks = 0;  // hull containment tests made by shadow prevention
  size_t hullBuilds = 0;
  double peelingMs = 0, shadowMs = 0, totalMs = 0;
};

// Inverse peeling field F-bar (Eq. 1): peel sheets of voxels within eps of the convex hull of the
// remaining printable voxels and the platform, rank F per sheet; F-bar = 1 + max F - F.
// Per cell; 0 for non-printable cells.
std::vector<int32_t> inversePeelingField(const VoxelGrid& grid, double epsilon,
                                         const ProgressFn& progress = {});

// Grow G over the printable cells of grid. Progress stages "peeling" then "growth" (fraction =
// grown voxels / printable voxels). Invariants (tested): the first layer is the printable cells
// resting on Platform cells; every voxel of layer tau > 1 has an AM-stable neighbour with
// 1 <= G < tau; no voxel of layer tau is inside (by eps) the hull of the platform and all voxels
// of layers < tau.
GrowthField growField(const VoxelGrid& grid, const GrowthOptions& options,
                      const ProgressFn& progress = {});

}  // namespace omnislice
