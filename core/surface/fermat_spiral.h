// SPDX-License-Identifier: MIT
// Fermat-spiral tool-paths on a curved surface region (paper 001 Section 5.1, after Zhao et al.
// 2016 "Connected Fermat Spirals"): iso-contours of the boundary geodesic distance at the bead
// spacing (first at spacing/2), organised in a contour tree, each nested run of contours turned
// into a Fermat spiral (in on every other contour, out on the others), runs joined at the tree's
// branches into one continuous polyline, re-sampled at a fixed step.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

struct SpiralOptions {
  double spacing = 0.45;    // bead spacing (line width), mm, > 0
  double resample = 1.0;    // output point spacing along the path, mm (paper: 1 mm), > 0
  double timeFactor = 1.0;  // heat-method t factor (boundary_distance.h)
};

// A polyline on the surface with the surface normal at every point (unit; orientation of the
// region's triangles).
struct SurfacePath {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;
};

struct SpiralResult : Outcome {
  std::vector<SurfacePath> paths;  // one per region when the contour tree could be joined
  int contours = 0;                // iso-contours extracted
  double distanceMs = 0, contourMs = 0, connectMs = 0;
};

// region: one connected layer region (triangles, with boundary). Regions narrower than one bead
// give a single centre-line path when possible, else no path (not an error).
SpiralResult fermatSpiralPaths(const Mesh& region, const SpiralOptions& options);

}  // namespace omnislice
