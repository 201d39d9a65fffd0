// SPDX-License-Identifier: MIT
// Vertex welding: merge vertices with identical (or, with a tolerance, nearby) positions.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesh/mesh.h"

namespace omnislice {

struct WeldResult {
  std::vector<uint32_t> remap;    // #V: old vertex index -> index into positions below
  std::vector<double> positions;  // welded vertices (#W*3), in order of first occurrence
  size_t merged = 0;              // #V - #W: vertices that were mapped onto an earlier one
};

// Weld mesh.positions. tolerance 0: merge bit-identical coordinates (+0 and -0 are equal) with
// one hash probe per vertex, O(#V). tolerance > 0 (mm): a vertex is mapped onto an
// earlier kept vertex within that distance (uniform grid of cell = tolerance, 27 cells probed);
// greedy, so not transitive. Non-finite vertices are never merged. mesh.triangles is ignored.
WeldResult weldVertices(const Mesh& mesh, double tolerance = 0);

}  // namespace omnislice
