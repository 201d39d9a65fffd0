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
// Details (igds.cpp, igds_remesh.cpp): a vertex exactly at phi_i makes every crossing edge ending
// there snap to one point welded by that vertex (degenerate and doubled faces dropped), so planes
// through grid vertices stay manifold. Faces are oriented on the sign field of the tet (never
// degenerate). Remeshing per region at L = targetEdge (sqrt(area / 10) for regions under 10 L^2);
// collapses obey the link condition and never turn a face over, flips and moves likewise; every
// split / collapse / relaxation / smoothing position is projected back (the interpolated
// triangles, or the boundary polyline for boundary vertices, by AABB trees). Guards, measured
// necessary on the shared models: a remeshed region whose triangle centroids stray farther than
// d / 2 from its interpolated IGDS (strongly curved caps where L is ~5 d: such chords crossed the
// next IGDS) or whose triangles intersect each other is remeshed once more at L / 2, else kept as
// interpolated (IgdsResult::regionTargetEdge, keptInterpolated). Then boundary ears folded
// against their region (an apex of one triangle, turned > 45 degrees from the triangle across its
// base, within a quarter of the base from it) are dropped: they lie in a flat wall of the part,
// and their normal across the layer misled the collision envelope (IgdsResult::droppedEars).
// Measured at d = 0.6 mm on the shared tet models (52k-71k tets, 188-263 iso-values,
// 290k-390k interpolated triangles -> 69k-123k, L ~3 mm, 2-7 regions kept as interpolated), on
// 2 cores shared with other jobs (load 2-3): extraction + remeshing native 0.85-1.5 s (test run),
// 1.35-2.2 s under load 3; a standalone em++ -O3 build in Node 20 under the same load 1.75-2.75 s
// (wasm / native 1.2-1.3; remeshing ~70 %, interpolation ~10 %, smoothing ~10 %). Five remeshing
// rounds instead of three cost ~25 % more for the same quality. No self-intersection, no crossing
// of successive IGDS, region topology kept, >= 99.8 % of remeshed edges in [L/2, 2L], mean
// minimum angle 32 -> 51 degrees (tests/core/geodesic/igds_test.cpp).
//
// Metrics: average overhang angle and overhang ratio of Eq. 11 along each IGDS boundary, layer
// thickness deviation (Fig. 10). A boundary point P whose nearest point on the previous layer's
// surface is inside that surface (nearer than its boundary curve B_i) stands on it and has
// alpha = 0: this is where a layer splits at a saddle of the field, and Fig. 8's P' on B_i would
// lie across a branch (the Kitten's ears read 63-68 degrees on that layer otherwise).
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
  // The iso-values, if not empty (strictly increasing, finite, > 0; those >= max phi dropped):
  // layers at these instead of i d (surfaceLimitedIsoValues). d still scales the remesher's
  // deviation limit, taken as half the smaller of the steps to the neighbouring iso-values.
  std::vector<double> isoValues;
  double minRegionArea = 0.05;   // mm^2, smaller connected IGDS are dropped (slivers)
  bool remesh = true;            // isotropic remeshing + Laplacian smoothing
  double targetEdge = 0;         // mm, remeshing edge length; 0 = the tet mesh's mean edge length
  int remeshIterations = 3;      // split / collapse / flip / relax rounds (5 costs ~25 % more
                                 // time for no measurable gain on the shared models)
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
  // Remeshing length per region (same shape as layers[i].regions): L, or a shorter one for
  // regions under 10 L^2 or strongly curved (chords farther than d / 2 from the interpolated
  // IGDS at L, or self-intersecting: retried once at half the length), or 0 where the region
  // was kept as interpolated (remeshing could not keep its chords within d / 2 and free of
  // self-intersections at lengths >= L / 4). keptInterpolated counts those 0 (remesh on).
  std::vector<std::vector<double>> regionTargetEdge;
  size_t keptInterpolated = 0;
  size_t droppedEars = 0;            // boundary ears folded against their region, dropped
                                     // (dropFoldedEars in igds.cpp)
  double interpolationMs = 0, remeshMs = 0, smoothMs = 0;
};

// mesh: a validated tet mesh; distance: one value per vertex (HeatGeodesic::distanceFrom).
// Progress stage "igds". Statuses: InvalidOption (sizes differ, interval <= 0 or not finite, more
// than maxLayers iso-values, negative options), NonFiniteVertex (a non-finite distance or
// coordinate), EmptyInput (no tets or no IGDS), DegenerateInput (a tet index out of range),
// Cancelled.
IgdsResult extractIgds(const TetMesh& mesh, const std::vector<double>& distance,
                       const IgdsOptions& options = {}, const ProgressFn& progress = {});

// Iso-values whose layers stay at most maxRatio d thick where they meet the part's surface. The
// layers of paper 002 are phi_i = i d; they lie d / |grad phi| apart, and the heat field's
// gradient is weakest in the tets on the boundary (the full-size Kitten: median 0.90 there, 5 %
// below 0.76, against 1.02 and 0.89 inside), where the layers' edges then stand up to 1.3-1.4 d
// apart and a bead there is not carried by the one below. Here phi_0 = 0 and
// phi_{i+1} = phi_i + s, s = d min(1, max(1/2, maxRatio q)), q the area-weighted quantile
// (0..1) of |grad phi| (in the face's tet) over the boundary faces whose phi range meets
// (phi_i, phi_i + s], s found from d and refined twice; while phi < max phi. The first step is d
// (the platform carries the first layer). Where the field is
// unit-speed this is i d. Empty when d or maxRatio is not finite and positive, or the sizes differ.
// Measured (full-size Kitten, d = 0.2 mm, table5; verify's supported / layers / path): uniform
// 0.927 / 641 / 2.18 m; maxRatio 1.15: 0.982 / 716 / 2.42 m; 1.0: 0.994 / 824 / 2.78 m with
// quantile 0.05, 0.990 / 770 with 0.15, 0.9965 / 894 with 0.01 (the default). The full-size Yoga
// (.tet, robot6, 0.2 mm): quantile 0.05 0.988 / 926 layers, 0.02 0.989 / 953, 0.01 0.991 / 968;
// maxRatio 0.85 at 0.05: 0.994 / 1090. What stays unsupported there: beads of the outer ring
// whose layer below stands > d under them (the slowest few % of the boundary) and 0.2-0.3 mm
// aside, and the layers over tool path left out where the growth fronts meet. Taking
// the surface gradient on overhanging faces instead (the gap along the surface) changed nothing
// at 1.15 (0.982 / 721).
std::vector<double> surfaceLimitedIsoValues(const TetMesh& mesh, const std::vector<double>& distance,
                                            double interval, double maxRatio, double quantile = 0.01);

// Eq. 11 and Fig. 10 per layer (layers as extractIgds returns them).
struct IgdsLayerMetrics {
  double isoValue = 0;
  double boundaryLengthMm = 0;      // integral of ds over the layer's IGDS boundaries (S_c)
  double overhangLengthMm = 0;      // S_o, boundary length with alpha(s) > 0
  double overhangAverageDegrees = 0;// alpha-bar, 0 when S_o = 0
  double overhangRatio = 0;         // r = S_o / S_c
  double overhangMaxDegrees = 0;
  // Thickness: distances from points sampled on this layer's IGDS to the previous layer's IGDS
  // (the platform z = 0 for the first layer), relative to the layer's step in phi (its iso-value
  // minus the previous layer's; d for uniform layers).
  size_t thicknessSamples = 0;
  double thicknessMeanMm = 0, thicknessMinMm = 0, thicknessMaxMm = 0;
  double thicknessMaxDeviationPercent = 0;   // max |t - s| / s x 100, s the step
  double thicknessMeanDeviationPercent = 0;  // mean |t - s| / s x 100
};

struct IgdsMetrics {
  std::vector<IgdsLayerMetrics> layers;  // one per layer
  double overhangAverageDegrees = 0;     // length-weighted over all overhanging boundary
  double overhangMaxLayerDegrees = 0;    // max over layers of the layer's alpha-bar
  double thicknessMaxDeviationPercent = 0;
};

// alpha(s) at a boundary point P of an IGDS of layer i: P' the closest point on the boundary
// curves of layer i - 1 (for the first layer, or when layer i - 1 has no boundary, the
// footprint: P projected to z = 0), alpha the
// angle between P'P and the IGDS normal n(P) when P lies outward of P' (P - P' has a positive
// component along the outward conormal of the IGDS at P), else 0 (Fig. 8). Boundary points are
// the boundary edges' midpoints weighted by their length; thickness points are sampled about
// every sampleSpacing mm over the area (deterministic; no thickness samples on a layer following
// an empty one). A P - P' component along the conormal within 1e-6 |P - P'| counts as zero
// (vertical walls). interval is d (not > 0 or not finite: empty metrics).
IgdsMetrics igdsMetrics(const std::vector<CurvedLayer>& layers, double interval,
                        double sampleSpacing = 1.0);

}  // namespace omnislice
