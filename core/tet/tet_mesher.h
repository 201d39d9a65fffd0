// SPDX-License-Identifier: MIT
// Tetrahedral meshing of a closed triangle solid, in the core (paper 002 used the commercial
// HyperMesh; Omnislice meshes in the browser). Method: isosurface stuffing on a body-centred cubic
// lattice (Labelle and Shewchuk 2007) — lattice vertices classified inside/outside the solid
// (column parity, linear in the lattice), exact crossings of the surface with the lattice edges
// (cut points), lattice vertices closer to a cut point than the paper's alpha (0.24999 of a long
// edge, 0.41189 of a short one) warped onto it, then every lattice tet filled by the stencil of
// its sign pattern — so the cost is linear in the number of tets. Quadrilaterals on lattice faces
// are split from their lower-id lattice vertex (consistent between neighbours, never cyclic);
// this is our rule, not the paper's parity rule, so the paper's proven bounds [10.7, 164.8] deg
// are not claimed: measured on bunny, kitten and fertility at 5k-150k tets in 4 orientations,
// wherever nothing below happened, the dihedral angles stay within [11.0, 159] deg (tests assert
// [10, 165]). Where the surface comes back within about a cell (crevices, ears close to the
// body, touching parts) warping can pinch the boundary; the warped vertices of such edges are
// put back (`unwarped`), which keeps the boundary edge-manifold but leaves slivers next to their
// cut points; interior vertices of tets under 10 deg are then moved (toward their neighbours or
// away from the surface) when that raises the smallest angle around them (`smoothed`), which
// lifts the worst angle from about 2-5 to 6-12 deg on the bunny and kitten; on branches_16
// (struts two cells across) slivers under 1 deg remain.
// Then the boundary vertices off the surface by more than roundoff (cut points are kept 1e-3 of
// an edge from lattice vertices) are moved onto it (closest point), each move shortened or undone
// if it would flatten or invert a tet; `boundaryTolerance` decides what counts as unsnapped.
// The result's tets are positively oriented (validateTetMesh holds, nothing flipped); the
// boundary (tetBoundary) is closed, edge-manifold and consistently oriented. Measured at 60k tets
// on a loaded shared 2-core machine, native / wasm -O3 in Node 20 (warm; the first calls in a
// fresh wasm module take 0.13-0.35 s while the engine tiers up): bunny 40-60 / 64-74 ms, kitten
// 46-60 / 68-82 ms, branches_16 (crevices, 3 re-fills) 0.37-0.47 / 0.60-0.76 s.
#pragma once

#include <cstddef>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "tet/tet_mesh.h"

namespace omnislice {

struct TetMesherOptions {
  double cellSize = 0;          // mm, BCC lattice spacing (edge of the cubic cells); 0 = chosen so
                                // the mesh has about targetTets tets (estimated from volume and
                                // area, then up to 3 re-meshes while the count is off by > 25 %)
  size_t targetTets = 60000;    // used when cellSize = 0
  size_t maxTets = 3000000;     // refuse (InvalidOption) rather than build more
  double boundaryTolerance = 0; // mm, boundary vertices end within this of the input surface;
                                // 0 = 0.05 x cellSize
  bool snap = true;             // false = leave the stuffed boundary as it is (for comparison)
};

struct TetMesherResult : Outcome {
  TetMesh mesh;
  double cellSize = 0;            // mm, the spacing used
  size_t boundaryVertices = 0;    // vertices on the boundary surface
  double maxBoundaryDistance = 0; // mm, max distance of a boundary vertex to the input surface
  size_t unsnapped = 0;           // boundary vertices left farther than boundaryTolerance
  size_t unwarped = 0;            // warped lattice vertices put back to keep the boundary manifold
  size_t smoothed = 0;            // moves of interior vertices of slivers (improving them)
  size_t pinchedEdges = 0;        // boundary edges left on more than two boundary faces (0 normally)
  double volumeRatio = 0;         // tet volume / input solid volume
  TetQuality quality;
  double classifyMs = 0, stuffMs = 0, snapMs = 0;
};

// solid: a closed, consistently outward-oriented triangle mesh (as prepareMesh leaves it). Every
// connected piece of the solid larger than a few cells is meshed; thinner features than about a
// cell may be lost (reported through volumeRatio). Progress stage "tetmesh".
// Statuses: EmptyInput (no triangles), NonFiniteVertex, InvalidOption (cellSize < 0 or not
// finite, boundaryTolerance < 0, targetTets or maxTets 0, more than maxTets tets needed — the
// message gives the count and the size that fits — or a lattice over 16M vertices), OpenMesh
// (a lattice column enters the surface more often than it leaves: not closed), DegenerateInput
// (index out of range, no enclosed volume, no tet inside: the solid is thinner than the
// lattice), Cancelled.
TetMesherResult tetrahedralize(const Mesh& solid, const TetMesherOptions& options = {},
                               const ProgressFn& progress = {});

}  // namespace omnislice
