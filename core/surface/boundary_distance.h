// SPDX-License-Identifier: MIT
// Boundary geodesic distance on a triangle surface with boundary (paper 001 Section 5.1 uses exact
// MMP; Omnislice uses the heat method of Crane et al. on the surface with the whole boundary
// polyline as the source, t = h^2, averaged Neumann/Dirichlet solutions, direct sparse
// factorisation). Also used for the filling paths of paper 002 Section 3.2.
#pragma once
#include <vector>

#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

// Boundary condition of the heat step. Average (default) blends the Neumann solution (heat
// source = the boundary curve, no flux through it) and the Dirichlet one (boundary held at 1),
// each scaled to mean 1 on the boundary, as Crane et al. recommend near boundaries.
enum class HeatBoundaryCondition { Average, Neumann, Dirichlet };

struct BoundaryDistanceOptions {
  double timeFactor = 1.0;  // t = timeFactor * (mean edge length)^2, > 0
  HeatBoundaryCondition boundaryCondition = HeatBoundaryCondition::Average;
};

struct BoundaryDistance : Outcome {
  std::vector<double> distance;  // per vertex, mm, 0 on the boundary
  double maxDistance = 0;
};

// surface: a connected, edge-manifold triangle mesh with at least one boundary loop.
// Closed surfaces -> InvalidOption (no boundary to measure from).
BoundaryDistance boundaryGeodesicDistance(const Mesh& surface,
                                          const BoundaryDistanceOptions& options = {});

}  // namespace omnislice
