// SPDX-License-Identifier: MIT
// Planar slicing of a closed solid along an arbitrary direction d.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "geometry/polygon2.h"
#include "mesh/mesh.h"

namespace omnislice {

// Right-handed frame of the slicing planes: a layer point (x, y) at height z maps to the part
// frame as origin + x*e1 + y*e2 + z*d.
struct SliceFrame {
  Eigen::Vector3d origin{0, 0, 0};
  Eigen::Vector3d e1{1, 0, 0};
  Eigen::Vector3d e2{0, 1, 0};
  Eigen::Vector3d d{0, 0, 1};
  Eigen::Vector3d toPart(const Eigen::Vector2d& p, double z) const {
    return origin + p.x() * e1 + p.y() * e2 + z * d;
  }
};

// Frame with d normalised, e1 = the unit vector most orthogonal to d among X, Y (projected),
// e2 = d x e1; origin = (0,0,0).
SliceFrame makeSliceFrame(const Eigen::Vector3d& direction);

struct SliceLayer {
  double bottom = 0;                 // layer bottom height along d (mm, from min projection)
  double top = 0;                    // layer top height
  double sliceHeight = 0;            // height of the cutting plane (middle of the layer)
  std::vector<ExPolygon2> islands;   // closed regions of the section
};

struct SliceOptions {
  Eigen::Vector3d direction{0, 0, 1};  // d, need not be unit (must be non-zero, finite)
  double layerHeight = 0.2;            // mm, > 0
  double firstLayerHeight = 0;         // mm, 0 = layerHeight
  double closingRadius = 0;            // mm, morphological close of tiny gaps, 0 = off
  double baseHeight = std::numeric_limits<double>::quiet_NaN();  // finite: layer 0's bottom at
                                       // this height along d (mm, same origin as minHeight) instead
                                       // of the mesh's lowest point, so the layers line up with
                                       // another mesh's (supports with their part); what lies
                                       // below it is not sliced, and a mesh wholly below gives no
                                       // layers (ok)
  size_t maxLayers = 0;                // > 0: at most this many layers (from the bottom)
};

struct SliceResult : Outcome {
  SliceFrame frame;
  double minHeight = 0;              // min over vertices of dot(p, d): layer 0 bottom sits here
  std::vector<SliceLayer> layers;    // bottom to top
  size_t openChains = 0;             // segment chains that failed to close (0 for a closed mesh)
};

// Slice a closed, oriented, welded mesh (output of prepareMesh) with planes normal to
// options.direction. Layer i spans [minHeight + b_i, minHeight + t_i]; the plane sits mid-layer.
// Layer count: ceil((H - first) / h) + 1 for a part of height H, minus a last layer whose plane
// would be at or above the top (the part fills at most half of it): the printed height is within
// h/2 of H. A part thinner than first/2 gets one layer cut at H/2.
// Vertices and faces exactly on a plane are handled by symbolic perturbation (a vertex on the plane
// counts as above it, so a plane through a horizontal face gives the section just below it), so
// every contour is closed. Loops that do not close (open meshes) are dropped and counted in
// openChains. Sections are united with the non-zero rule, so overlapping shells give one region.
// Coordinates are snapped to a 10 nm grid. Statuses: EmptyInput (no triangles, zero extent along
// d), InvalidOption (bad direction/heights, index out of range, |coordinate| > 1e6 mm, > 2e6
// layers), NonFiniteVertex, Cancelled, Internal (clipping failure).
SliceResult sliceMesh(const Mesh& mesh, const SliceOptions& options,
                      const ProgressFn& progress = {});

// Signed area of a polygon (positive when counter-clockwise).
double polygonArea(const Polygon2& polygon);
// Area of an island: contour minus holes.
double islandArea(const ExPolygon2& island);

}  // namespace omnislice
