// SPDX-License-Identifier: MIT
// Internal to the multidir decomposition: local refinement of the planes a search line found
// (beyond paper 000: its Section VI-C names it as future work). Coordinate descent moves one plane
// at a time to a nearby normal and offset while the exact J_G drops and Criteria II-IV hold; the
// iterated local search perturbs one plane at a time and refines again. Both evaluate J_G
// exactly (faces clipped by the planes) and give the same planes natively and in wasm.
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "common/progress.h"
#include "multidir/decomposition.h"
#include "multidir/decomposition_model.h"

namespace omnislice::decomposition_detail {

// Coordinate descent on the planes (paper VI-C names it as future work): plane k moves to a
// nearby normal and an offset within +-4 mm (half steps) when the exact J_G of the whole
// sequence drops and Criteria II-IV still hold. Returns the number of (normal, offset) pairs
// evaluated. Reports progress (stage "decompose") at `fraction` before each plane; sets
// `cancelled` and returns when the report asks to stop.
size_t refinePlanes(const Model& m, const MultidirOptions& o, bool fourDof, const Vec3& axis,
                    std::vector<Vec3>& ns, std::vector<double>& ds, const ProgressFn& progress,
                    double fraction, bool& cancelled);

// Iterated local search on the refined planes (o.perturbations moves, each kept when the exact
// J_G, `jg`, drops; stops at J_G <= delta0). Returns the number of moves kept; counts the moves
// and the refinement's evaluations in `stats`. Progress from fractionFrom to fractionTo.
size_t perturbPlanes(const Model& m, const MultidirOptions& o, bool fourDof, const Vec3& axis,
                     std::vector<Vec3>& ns, std::vector<double>& ds, double& jg, const ProgressFn& progress,
                     double fractionFrom, double fractionTo, bool& cancelled, MultidirStats& stats);

}  // namespace omnislice::decomposition_detail
