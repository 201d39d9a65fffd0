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
// epsilon, measured (PG-SP-GCFA, w = 0.8 mm, models fitted to 80 mm, centre-inside grids plus a
// one-cell dilation, native, one core; missed voxels / layers / time):
//   eps        1.0            0.75           0.5             0.3             0.1
//   Fertility  0/154/0.14 s   0/155/0.16 s   21/290/3.0 s    14/331/3.7 s    2585/688/9.2 s
//   Kitten     0/129/0.48 s   0/369/1.7 s    0/812/8.2 s     0/888/6.4 s     0/367/3.3 s
//   Bunny      0/300/2.6 s    0/875/9.8 s    0/1610/18.6 s   0/1244/31.4 s   0/530/11.1 s
// Below ~0.8 a voxel one cell behind a sloped front already counts as shadowed, so voxels left
// behind by the F-bar threshold block the front: many more (thinner) layers and 10-20x more
// shadow work. eps = 1 (one layer of tolerance: the layer being deposited) has zero missed voxels
// on all three, the fewest layers and the lowest time, so it is the default. A flat hull (dimension < 3) counts points within eps as inside.
// The peeling field uses min(epsilon, 0.57): its hulls are built from boundary voxels only, which
// is exact below 1/sqrt(3).

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
// Per cell; 0 for non-printable cells. Each hull is built from the remaining voxels with a
// non-remaining face neighbour (the others are >= 1/sqrt(3) deep) and each sheet is found by
// rasterising the eps band of every hull triangle, so a sheet costs ~ hull area, not
// voxels x planes. eps is clamped to 0.57. Empty result for an inconsistent grid, a negative or
// non-finite eps, or when progress cancels ("peeling").
std::vector<int32_t> inversePeelingField(const VoxelGrid& grid, double epsilon,
                                         const ProgressFn& progress = {});

// Grow G over the printable cells of grid. Progress stages "peeling" then "growth" (fraction =
// grown voxels / printable voxels). Invariants (tested): the first layer is the printable cells
// resting on Platform cells; every voxel of layer tau > 1 has an AM-stable neighbour with
// 1 <= G < tau; no voxel of layer tau is inside (by eps) the hull of the platform and all voxels
// of layers < tau (layer 1 is exempt: it is the platform contact).
// Deviations from Algorithm 1 (which never re-seeds once L_c is empty): when the front stops, the
// candidates are every unprocessed voxel with an ASN in V not inside C_prev (and F-bar <= f_tau),
// so voxels deferred by shadow prevention or the threshold are found again; step (6)'s sacrifice
// is only taken when even that whole frontier, at f_tau > F-bar max, cannot grow shadow-free.
// Rejected voxels of L_next lying inside or on the accepted hull are added back (free).
// Shadow checks: cached separating planes per voxel (plane registry + hull stamps), S_p computed
// once per layer, a half-space pre-test before building C_t, and a per-voxel "blocker" memo.
// Speed (PG-SP-GCFA, eps 1, voxelizeSolid grids of the shared Bunny fitted to 80 mm): 217k voxels
// (w 0.8) 2.1 s native / 4.4 s wasm (Node 20); 506k voxels (w 0.6) 2.6 s native / 4.4 s wasm,
// 131 MB peak RSS of the whole wasm run; memory is linear in the grid (per-cell index, per-voxel
// state) plus hulls and a plane registry capped at 500k planes.
// Statuses: InvalidOption (grid dims/state mismatch, eps < 0, peelStep <= 0, non-finite),
// EmptyInput (no printable cell), Cancelled. Printable cells not connected to the platform are
// missed (g = -1), not an error.
GrowthField growField(const VoxelGrid& grid, const GrowthOptions& options,
                      const ProgressFn& progress = {});

}  // namespace omnislice
