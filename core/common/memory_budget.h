// SPDX-License-Identifier: MIT
// The memory budget (setting memory_mb): before a big structure is allocated (the voxel grid and
// its fields, the tet mesh with the heat method's matrices, the machine motion with the program
// text, verify's path samples), its size is estimated from counts known beforehand and the job is
// refused with Status::OutOfMemory, naming the figure and the settings that change it, when the
// estimate exceeds the budget. Each structure is checked on its own against the whole budget: a
// guard against settings or models that cannot fit (a wasm heap ends at 4 GB, a browser tab often
// earlier), not an accounting of the peak. The per-item figures below were measured (peak RSS of
// the native CLI on shared models, 2026-11-30) and rounded up.
#pragma once
#include <string>

#include "common/status.h"

namespace omnislice {

// Default memory_mb: fits a 32-bit wasm heap (4 GB) with room for the browser's own copies.
constexpr double kDefaultMemoryBudgetMb = 2048;

namespace memory_cost {
// Voxel method: dense per-cell arrays (state, growth field, layer field, masks) ...
constexpr double kVoxelCellBytes = 16;
// ... and, per solid voxel, the curved layers, their regions, paths and tool path (measured
// 0.70 KB: 171 MB at 180k voxels, 604 MB at 803k).
constexpr double kSolidVoxelBytes = 800;
// Geodesic method: per tet, the tet mesh, the heat method's Laplacian and factorisations, the
// field and its iso-surfaces (measured 1.1 KB: 321 MB at 61k tets, 525 MB at 242k).
constexpr double kTetBytes = 1200;
// Motion and program: per tool-path move, the machine path's poses and chords and the program
// text (the planar bunny at 150 mm, 0.1 mm layers: 894k moves, 34 MB of text, 546 MB peak for the
// whole slice, of which the slicing holds part).
constexpr double kMoveBytes = 400;
// Verify: per byte of program text, the parsed program (its moves cut into machine pieces, 160
// bytes each, in a deque: no vector doubling). Measured 1.2-5.3x: the Kitten at 30 mm planar
// cartesian3 4.0, voxel table5 5.3 (rotary pieces), geodesic head5 4.3, multidir rotary4 3.2;
// UR5 CSV 1.8, URScript 1.3, KRL 1.2, RAPID 1.6; geodesic table5 at 100 mm 3.4 (100 MB of text,
// 2.08M pieces). Before the moves were compact (a heap vector of axes per move) and in a vector,
// 6-12x was measured, and 16 refused the geodesic Bunny at 100 mm (145 MB of text) ...
constexpr double kProgramTextBytes = 8;
// ... then per path sample (the sample, its cell buckets, the pieces' grid) and per coverage grid
// point (measured beyond the parsed program: 237 MB for 1.68M samples and 24.2M grid points,
// 29 MB for 467k and 0.72M).
constexpr double kVerifySampleBytes = 64;
constexpr double kVerifyGridPointBytes = 8;
}  // namespace memory_cost

// Ok when `bytes` fits `budgetMb` (<= 0: no budget); otherwise OutOfMemory: "<what> needs about
// N MB, more than the memory budget (memory_mb = B MB); <lever>".
Outcome checkMemoryBudget(double bytes, double budgetMb, const std::string& what, const std::string& lever);

// The parsed form of a program of `textBytes` bytes (read to be verified) within the budget.
Outcome checkProgramReadBudget(double textBytes, double budgetMb);

// The message of an allocation that failed while `doing` (e.g. "slicing"): OutOfMemory, naming
// the budget and what lowers the need.
Outcome allocationFailed(const std::string& doing);

}  // namespace omnislice
