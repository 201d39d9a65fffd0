// SPDX-License-Identifier: MIT
// Tetrahedral meshing of a closed triangle solid, in the core (paper 002 used the commercial
// HyperMesh; Omnislice meshes in the browser). Method: isosurface stuffing on a body-centred cubic
// lattice (Labelle and Shewchuk 2007) — lattice vertices classified inside/outside the solid
// (column parity, linear in the lattice), lattice vertices close to the surface warped onto it,
// the remaining lattice tets cut by the surface along their edges and filled by stencils — so the
// cost is linear in the number of tets and the dihedral angles stay bounded. Then the boundary
// vertices are moved onto the input surface (closest point) so the boundary conforms within
// `boundaryTolerance`, with every move that would flatten or invert a tet undone or shortened.
// The result's tets are positively oriented (validateTetMesh holds).
#pragma once

#include <cstddef>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "tet/tet_mesh.h"

namespace omnislice {

struct TetMesherOptions {
  double cellSize = 0;          // mm, BCC lattice spacing (edge of the cubic cells); 0 = chosen so
                                // the mesh has about targetTets tets
  size_t targetTets = 60000;    // used when cellSize = 0
  size_t maxTets = 3000000;     // refuse (InvalidOption) rather than build more
  double boundaryTolerance = 0; // mm, boundary vertices end within this of the input surface;
                                // 0 = 0.05 x cellSize
};

struct TetMesherResult : Outcome {
  TetMesh mesh;
  double cellSize = 0;            // mm, the spacing used
  size_t boundaryVertices = 0;    // vertices on the boundary surface
  double maxBoundaryDistance = 0; // mm, max distance of a boundary vertex to the input surface
  size_t unsnapped = 0;           // boundary vertices left farther than boundaryTolerance
  double volumeRatio = 0;         // tet volume / input solid volume
  TetQuality quality;
  double classifyMs = 0, stuffMs = 0, snapMs = 0;
};

// solid: a closed, consistently outward-oriented triangle mesh (as prepareMesh leaves it). Every
// connected piece of the solid larger than a few cells is meshed; thinner features than about a
// cell may be lost (reported through volumeRatio). Progress stage "tetmesh".
// Statuses: EmptyInput (no triangles), NonFiniteVertex, InvalidOption (cellSize < 0 or not
// finite, more than maxTets tets needed — the message gives the count and the size that fits),
// DegenerateInput (no tet inside: the solid is thinner than the lattice), Cancelled.
TetMesherResult tetrahedralize(const Mesh& solid, const TetMesherOptions& options = {},
                               const ProgressFn& progress = {});

}  // namespace omnislice
