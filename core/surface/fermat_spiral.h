// SPDX-License-Identifier: MIT
// Fermat-spiral tool-paths on a curved surface region (paper 001 Section 5.1, after Zhao et al.
// 2016 "Connected Fermat Spirals"): iso-contours of the boundary geodesic distance at the bead
// spacing (first at spacing/2), organised in a contour tree, each nested run of contours turned
// into a Fermat spiral (in on every other contour, out on the others), runs joined at the tree's
// branches into one continuous polyline, re-sampled at a fixed step.
//
// Details (fermat_spiral.cpp): the contour tree is the bipartite tree of contours and "pieces"
// (connected components of the bands between consecutive levels). Runs of contours joined by
// pieces with exactly two contours (nested bands, or the ridge of an annulus) form one spiral;
// every contour is cut at break points aligned by successive closest points, the in-hops and
// out-hops run as two families of parallel diagonals through gaps two beads wide, so they never
// cross. At a branch (a piece bounded by 3+ contours) the contours are joined by a minimum
// spanning tree of their distances; each child spiral, whose two ends lie one bead apart at its
// outer contour, is spliced into its host contour through a two-bead gap at the host point
// closest to the child. Result: one polyline per connected component of {distance >= spacing/2}
// (more than one only where a neck narrower than one bead separates parts of the region).
// Hops: Fermat hops span two contours diagonally (~2.8 spacing long), splice hops 1-2 spacing;
// hops are traced on the surface (points projected). The level step: levels sit at arbitrary
// heights under the field's ridges (medial axis), and a ridge just above a level makes a loop
// thinner than half a bead (or specks around the field's noise). Steps in [0.85, 1.05] x spacing
// are ranked by the area of ridge vertices (|grad| < 0.5) within 0.3 spacing above a level (or
// more than 0.8 spacing above it); the best two and the step that puts the last level spacing/2
// under the highest ridge are built, and the path overlapping itself least is kept.
// Measured (tests/core/surface/fermat_spiral_test.cpp, spacing 0.45, h 0.3-0.4 mm): one polyline
// on disc, square, annulus, L, dumbbell, plate with 3 holes, 5-arm star, spherical cap and two
// real open shells; >= 97 % of points farther than spacing/2 from the boundary within 0.75
// spacing of the path; 98.5-100 % of path points free of overlap; length = area/spacing +-11 %.
// 20k-vertex region: 180-300 ms native (distance 130-230 ms: 3 sparse factorisations), ~315 ms
// in a standalone em++ -O3 build under node. Bunny stand-in (60 mm, planar sections every
// 0.8 mm meshed at 0.8 mm: 75 regions, 97k vertices): 1.1 s native (DISABLED_ benchmark test).
// Limitations: gaps and local overlaps near the medial axis (as Zhao et al. report), worst where
// ridges of very different heights coexist (the star's arms vs its hub); regions narrower than
// 1.5 beads get one centre line per ridge loop (a branched narrow region is covered along one
// branch pair only); surfaces of genus > 0 may yield extra polylines.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "common/status.h"
#include "mesh/mesh.h"
#include "surface/boundary_distance.h"

namespace omnislice {

struct SpiralOptions {
  double spacing = 0.45;    // bead spacing (line width), mm, > 0
  double resample = 1.0;    // output point spacing along the path, mm (paper: 1 mm), > 0
  double timeFactor = 1.0;  // heat-method t factor (boundary_distance.h)
  // Heat boundary condition of the distance. Dirichlet-only is as accurate on average and ~35 %
  // faster, but its ridges are noisier: the top contours break into more specks (annulus test
  // 98.0 % overlap-free, plate with holes 98.8 %, against 99.3 % and 99.2 % with the average).
  HeatBoundaryCondition heatBoundary = HeatBoundaryCondition::Average;
};

// A polyline on the surface with the surface normal at every point (unit; orientation of the
// region's triangles).
struct SurfacePath {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;
  std::vector<uint32_t> curves;  // optional, per point: the segment ending at the point lies on
                                 // iso-planar NL curve curves[i] (1-based; 0 = a join)
  double width = 0;              // bead width of this path, mm (0 = the tool-path's line width);
                                 // a narrow region's centre line: the region's width, at most the spacing
};

struct SpiralResult : Outcome {
  std::vector<SurfacePath> paths;  // one per region when the contour tree could be joined
  int contours = 0;                // iso-contours extracted
  double distanceMs = 0, contourMs = 0, connectMs = 0;
};

// region: one connected layer region (triangles, with boundary; edge-manifold; bit-identical
// positions are welded first, so an unwelded region is fine). Regions narrower
// than about 1.5 beads (max distance D < 0.75 spacing) give a single centre-line path of width
// min(2 D, spacing) when D exceeds spacing/16, else no path (not an error). Points lie on the region (contour
// points on its edges, hops projected onto it), consecutive points at most `resample` apart,
// corners kept within 0.05 mm. Statuses: those of boundaryGeodesicDistance, InvalidOption for
// spacing/resample <= 0 or not finite, or a spacing too small for the region (> 20000 levels).
SpiralResult fermatSpiralPaths(const Mesh& region, const SpiralOptions& options);

}  // namespace omnislice
