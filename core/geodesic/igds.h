// SPDX-License-Identifier: MIT
// Iso-geodesic distance surfaces (IGDS) of paper 002 Section 2.2 and their metrics.
//
// Extraction: for phi_i = i d (i = 1, 2, ... while i d < max phi), interpolation points on the tet
// edges with phi_a < phi_i < phi_b by Eq. 10 (a vertex exactly at phi_i is treated as above it, so
// no point is doubled), one triangle per tet with three points, two per tet with four (the
// quadrilateral split along its shorter diagonal), points welded by tet edge; connected IGDS by
// growing over shared edges (Section 2.2); then isotropic remeshing (Botsch and Kobbelt 2004:
// split long edges, collapse short ones, flip toward valence 6, tangential relaxation with
// projection back onto the interpolated surface) and Laplacian smoothing (Vollmer et al. 1999,
// projected back likewise). Boundary vertices stay on the IGDS boundary curve (which lies on the
// tet mesh's boundary surface): they move only along it, corners kept.
//
// Metrics: average overhang angle and overhang ratio of Eq. 11 along each IGDS boundary, layer
// thickness deviation (Fig. 10).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "surface/surface_layers.h"
#include "tet/tet_mesh.h"

namespace omnislice {

struct IgdsOptions {
  double interval = 1.0;         // d, mm (> 0): phi_i = i d
  double minRegionArea = 0.05;   // mm^2, smaller connected IGDS are dropped (slivers)
  bool remesh = true;            // isotropic remeshing + Laplacian smoothing
  double targetEdge = 0;         // mm, remeshing edge length; 0 = the tet mesh's mean edge length
  int remeshIterations = 5;      // split / collapse / flip / relax rounds
  int smoothIterations = 3;      // Laplacian smoothing rounds after remeshing
  size_t maxLayers = 100000;     // refuse (InvalidOption) above this many iso-values
};

struct IgdsResult : Outcome {
  // layers[i] is phi_i (isoValue = i d, i from 1; layers with no region left are kept empty so
  // the index is i - 1); regions are connected, edge-manifold, oriented so their normals point
  // toward increasing phi (the nozzle side); boundaryVertex = 1 on the open boundary (on the tet
  // mesh's boundary surface). area is the remeshed area.
  std::vector<CurvedLayer> layers;
  size_t regionCount = 0;
  size_t interpolatedTriangles = 0;  // before remeshing
  size_t triangleCount = 0;          // after
  double interpolationMs = 0, remeshMs = 0, smoothMs = 0;
};

// mesh: a validated tet mesh; distance: one value per vertex (HeatGeodesic::distanceFrom).
// Progress stage "igds". Statuses: InvalidOption (sizes differ, interval <= 0 or not finite, more
// than maxLayers iso-values, negative options), NonFiniteVertex (a non-finite distance or
// coordinate), EmptyInput (no tets or no IGDS), Cancelled.
IgdsResult extractIgds(const TetMesh& mesh, const std::vector<double>& distance,
                       const IgdsOptions& options = {}, const ProgressFn& progress = {});

// Eq. 11 and Fig. 10 per layer (layers as extractIgds returns them).
struct IgdsLayerMetrics {
  double isoValue = 0;
  double boundaryLengthMm = 0;      // integral of ds over the layer's IGDS boundaries (S_c)
  double overhangLengthMm = 0;      // S_o, boundary length with alpha(s) > 0
  double overhangAverageDegrees = 0;// alpha-bar, 0 when S_o = 0
  double overhangRatio = 0;         // r = S_o / S_c
  double overhangMaxDegrees = 0;
  // Thickness: distances from points sampled on this layer's IGDS to the previous layer's IGDS
  // (the platform z = 0 for the first layer), relative to the interval d.
  size_t thicknessSamples = 0;
  double thicknessMeanMm = 0, thicknessMinMm = 0, thicknessMaxMm = 0;
  double thicknessMaxDeviationPercent = 0;   // max |t - d| / d x 100
  double thicknessMeanDeviationPercent = 0;  // mean |t - d| / d x 100
};

struct IgdsMetrics {
  std::vector<IgdsLayerMetrics> layers;  // one per layer
  double overhangAverageDegrees = 0;     // length-weighted over all overhanging boundary
  double overhangMaxLayerDegrees = 0;    // max over layers of the layer's alpha-bar
  double thicknessMaxDeviationPercent = 0;
};

// alpha(s) at a boundary point P of an IGDS of layer i: P' the closest point on the boundary
// curves of layer i - 1 (for the first layer, the footprint: P projected to z = 0), alpha the
// angle between P'P and the IGDS normal n(P) when P lies outward of P' (P - P' has a positive
// component along the outward conormal of the IGDS at P), else 0 (Fig. 8). Boundary points are
// the boundary edges' midpoints weighted by their length; thickness points are sampled about
// every sampleSpacing mm over the area (deterministic). interval is d.
IgdsMetrics igdsMetrics(const std::vector<CurvedLayer>& layers, double interval,
                        double sampleSpacing = 1.0);

}  // namespace omnislice
