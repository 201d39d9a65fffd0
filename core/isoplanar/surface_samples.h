// SPDX-License-Identifier: MIT
// Local differential geometry of a layer surface at sample points (paper 003 Section 2: the
// local frame f_p-n_p-k_p, the normal curvature across the path for w_eff, the curvature radius
// along the path for the forward step of Eq. 12), and the test surfaces of the paper's experiments.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

// One sample point of a surface: position, unit normal on the nozzle side, an orthonormal tangent
// basis (tangentU x tangentV = normal) and the second fundamental form in that basis. The normal
// curvature along a unit tangent t = a tangentU + b tangentV is [a b] shape [a b]^T, with the
// sign of effective_width.h: > 0 convex (the surface bends away from the normal side).
struct SurfaceSample {
  Eigen::Vector3d position{0, 0, 0};
  Eigen::Vector3d normal{0, 0, 1};
  Eigen::Vector3d tangentU{1, 0, 0};
  Eigen::Vector3d tangentV{0, 1, 0};
  Eigen::Matrix2d shape = Eigen::Matrix2d::Zero();  // 1/mm
  double height = 0.2;                              // local layer thickness h, mm
};

// The shape operator as a symmetric 3x3 tensor in the part frame, T = [tU tV] shape [tU tV]^T:
// normal curvature along any unit tangent t is t^T T t. Tensors of neighbouring samples can be
// blended linearly (points on mesh edges).
Eigen::Matrix3d shapeTensor(const SurfaceSample& sample);

// Normal curvature of the sample along a unit part-frame direction (projected onto the tangent
// plane and normalised first; 0 when the direction is along the normal).
double normalCurvature(const SurfaceSample& sample, const Eigen::Vector3d& direction);

struct SurfaceSamplesResult : Outcome {
  std::vector<SurfaceSample> samples;  // one per mesh vertex, index = vertex index
};

// Per-vertex samples of a triangle surface (open or closed, edge-manifold, consistently
// oriented): the area-weighted face normal gives the side (the triangles' orientation) and the
// fitting frame; a least-squares quadric w = Q(u, v, w) over that frame (a quadric height field
// with implicit terms) fitted to the vertex's 2-ring (grown up to the 4-ring where that does not
// determine the fit, e.g. on a boundary row of a cylinder) gives the normal (the fitted one; the
// area-weighted one when they differ by more than ~37 degrees) and the second fundamental form
// (shape = -Hessian of w on the tangent plane, so a dome seen from its normal side is > 0),
// every sample's height = layerHeight. Exact (to rounding) on spheres and on quadrics
// z = (x^2 - y^2) / R sampled at the vertex, for any triangulation. Statuses: EmptyInput (also a
// triangle index out of range), NonFiniteVertex, InvalidOption (layerHeight <= 0).
SurfaceSamplesResult surfaceSamples(const Mesh& surface, double layerHeight);

// The sample at a point on the edge (a, b) at parameter t in [0, 1] (p = (1-t) a + t b): position
// and normal blended and renormalised, shape tensor blended and re-expressed in a tangent basis
// of the blended normal, height blended.
SurfaceSample blendSamples(const SurfaceSample& a, const SurfaceSample& b, double t);

// Test surfaces of the paper's experiments (open triangle meshes, normals up, counter-clockwise
// seen from +Z), regular grids of about `vertices` vertices:
//  - saddle S1: z = (x^2 - y^2) / R over the square [-half, half]^2;
//  - bicycle-seat-like S2: symmetric about the x axis, a pear-shaped outline (narrow nose at +x,
//    wide rear), convex across (falls toward the sides), a shallow dip along x, nose rising;
//    `length` along x, the rear width about 0.55 x length.
Mesh makeSaddleSurface(double radius = 100, double half = 37.5, int vertices = 20000);
Mesh makeSeatSurface(double length = 110, int vertices = 20000);

}  // namespace omnislice
