// SPDX-License-Identifier: MIT
// Iso-planar printing paths on a layer surface (paper 003 Section 3, Algorithm 2): the surface is
// cut by parallel vertical drive planes with normal q = (-sin theta, cos theta, 0); each cut is a
// nozzle-location (NL) curve sampled with the forward step of Eq. 12; the next plane is placed by
// the side step of Eq. 14; the curves are joined in a zig-zag; nozzle axis = surface normal;
// extrusion by Eq. 13 (done by the tool-path builder from the bead model).
//
// Side step (Eq. 14, made exact for tilted surfaces): moving a drive plane by d moves its curve
// along the surface by d / |k.q| at a point whose cross direction is k (k = n x f). The paper adds
// w_s* = min w_eff to the plane offset, which on a surface sloping across the path spaces the
// curves wider than w_eff (gaps). Here the next plane offset is c + min over the curve's points of
// w_eff(p) |k(p).q| (|k.q| floored at minCross), so on the surface no point of the next curve is
// farther than its w_eff from the current one, and the paper's rule is recovered where k is along
// q (a horizontal surface). The first plane sits half a side step inside the extreme plane of S,
// and the last one half a side step before the opposite extreme (bead edges on the boundary).
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "isoplanar/effective_width.h"
#include "isoplanar/surface_samples.h"
#include "mesh/mesh.h"
#include "surface/fermat_spiral.h"

namespace omnislice {

struct IsoplanarOptions {
  double thetaDegrees = 0;     // drive-plane angle theta
  double chordError = 0.5;     // delta_c* of Eq. 12, mm (> 0)
  double maxStep = 0;          // longest forward step, mm (0 = no limit beyond Eq. 12)
  double minCross = 0.2;       // floor of |k.q| in the side step
  double connectFactor = 3;    // zig-zag: consecutive curve ends closer than this x the side step
                               // (measured along the boundary) are joined by a printed move along
                               // the surface; farther ends start a new path (a travel)
};

// One NL curve: the connected cut of the surface by one drive plane, in the order printed.
struct NlCurve {
  std::vector<Eigen::Vector3d> points;   // on the surface (mesh edges), part frame
  std::vector<Eigen::Vector3d> normals;  // unit surface normals (nozzle axes)
  std::vector<uint32_t> edgeA, edgeB;    // per point: the mesh edge it lies on ...
  std::vector<float> edgeT;              // ... at (1 - t) a + t b (a == b: at a vertex)
  std::vector<double> width;             // per point: w_eff(theta) there, mm
  double plane = 0;                      // drive-plane offset c (q.x = c), mm
  double sideStep = 0;                   // offset to the next plane (Eq. 14 as above), mm; 0 last
  bool closed = false;                   // the cut is a closed loop (first point repeated last)
};

// A printed zig-zag join: the walk along a boundary loop of the surface from the end of one curve
// to the start of the next one (both end points included; points on boundary edges / vertices),
// or a short straight move from or to a closed loop (two points).
struct IsoplanarJoin {
  uint32_t fromCurve = 0, toCurve = 0;   // indices into IsoplanarResult::curves
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;  // unit (blended vertex normals)
  std::vector<uint32_t> edgeA, edgeB;    // as in NlCurve
  std::vector<float> edgeT;
  double length = 0;                     // mm
};

struct IsoplanarResult : Outcome {
  std::vector<NlCurve> curves;          // in print order (chains of adjacent planes, zig-zag)
  std::vector<SurfacePath> paths;       // the curves joined: one path per zig-zag run
  std::vector<std::vector<uint32_t>> pathCurves;  // per path: indices of its curves, in order
  std::vector<IsoplanarJoin> joins;     // printed joins, in print order
  std::vector<std::vector<uint32_t>> pathJoins;   // per path: index into joins between its
                                                  // consecutive curves (pathCurves[p].size() - 1)
  std::vector<std::vector<uint32_t>> pathPointCurve;  // per path, per point: 1 + index of its
                                                      // curve, 0 for a join's interior point
  size_t planes = 0;                    // drive planes used
  double pathMm = 0;                    // printed length (curves + printed joins), mm
  double minSideStep = 0, maxSideStep = 0;  // plane offsets, mm, but the shortened one to the
                                            // last plane (one plane: its computed step)
  size_t closedCurves = 0;              // curves that are closed loops
  double ms = 0;
};

// Algorithm 2 on `surface` (open or closed triangle mesh, ideally edge-manifold) with its per-vertex
// samples (surface_samples.h; curvature and height for w_eff) and w_eff = width(kappa, h) with
// kappa the normal curvature across the curve. Statuses: EmptyInput, InvalidOption (options out
// of range, samples not one per vertex, a triangle index out of range, a width that is not
// positive and finite, or so small that more than 2e6 planes would be needed), NonFiniteVertex
// (positions or samples), Cancelled. Progress stage "paths". A surface lying in one drive plane
// gives Ok and no curve. Bit-identical vertices are welded (an unwelded mesh cuts like the
// welded one; edge indices are those of the first of equal vertices); an edge of more than two
// triangles pairs them in order (a curve may end there, without a boundary join).
// Planes: the first at the extreme + its own side step / 2 (fixed point), then c += side step;
// once c + step would pass the far extreme - step / 2, the last plane is put there (that offset
// is shorter than the step), and a plane whose step / 2 reaches the far extreme is the last.
// A plane meeting no triangle (a gap between parts along q) jumps to the next triangle's start +
// half the last step.
//
// Cut: a vertex with q.x == c counts as above the plane (symbolic perturbation), so every plane
// meets each triangle in at most one segment and the crossings link into simple polylines (open
// ones end on boundary edges; a plane may give several components and closed loops). Forward
// step: from a kept crossing p_i the curve jumps to the farthest crossing p_j with
// |p_j - p_i| <= l_f(p_i) (Eq. 12 with r_f = 1 / |normal curvature along f|; also <= maxStep when
// set) such that every crossing between them lies within chordError of the chord; crossings are
// never moved off the mesh edges (a single triangle crossing longer than l_f is kept whole, the
// mesh being flat there). Print order (zig-zag as boustrophedon chains): a chain starts on the
// lowest plane with curves left, at the curve end nearest the previous path's end, and goes on to
// the next plane's curve whose end it can join: open curves whose ends lie on one boundary loop
// within connectFactor x the side step along it are joined along that boundary; when one of them
// is a closed loop, by a straight move that short if the normals at its ends agree within about
// 25 degrees (the move leaves the surface by its sagitta only; the loop starts at its crossing
// nearest the previous end). Directions alternate along a chain; a plane cutting the surface in
// several components continues one chain and leaves the others to later chains (no travel across
// a hole on every plane). Curves are sampled in +u order (u = (cos theta, sin theta, 0)) and
// reversed when printed the other way.
IsoplanarResult isoplanarPaths(const Mesh& surface, const std::vector<SurfaceSample>& samples,
                               const WidthFn& width, const IsoplanarOptions& options,
                               const ProgressFn& progress = {});

// The direction-independent part of isoplanarPaths (validation, edges, boundary loops, shape
// tensors), prepared once to plan many directions on one surface (the benchmark over theta).
// Holds a copy of the mesh and samples. Statuses as isoplanarPaths for the mesh and samples.
struct IsoplanarSurface : Outcome {
  struct Data;
  std::shared_ptr<const Data> data;
  double ms = 0;
};
IsoplanarSurface prepareIsoplanarSurface(const Mesh& surface,
                                         const std::vector<SurfaceSample>& samples);

// isoplanarPaths on a prepared surface: the same result as the call on its mesh and samples.
IsoplanarResult isoplanarPaths(const IsoplanarSurface& surface, const WidthFn& width,
                               const IsoplanarOptions& options, const ProgressFn& progress = {});

// f* for a move at a point on the mesh edge (a, b) at t along unit `direction` with geodesic
// curvature `geodesicCurvature` (feed_rate.h's feedLimit blended over the edge's two vertices).
using FeedFn = std::function<double(uint32_t a, uint32_t b, double t,
                                    const Eigen::Vector3d& direction, double geodesicCurvature)>;

struct IsoplanarTime {
  double printS = 0;      // along the NL curves at f* (each segment at the smaller f* of its ends)
  size_t unreachableSegments = 0;  // printed segments timed at minFeed (f* 0 or not finite)
  double joinS = 0;       // printed zig-zag joins
  double travelS = 0;     // between paths at travelSpeed (straight line)
  double totalS = 0;
  double pathMm = 0;      // printed length
  double travelMm = 0;
  double meanFeed = 0;    // printed length / (printS + joinS), mm/s
};

// Printing time of the result under the kinematic limits: every printed segment takes
// length / min(f* at its ends, maxFeed); f* from `feed` (0, NaN, or infinite with no maxFeed =
// unreachable: the segment is timed at minFeed and counted). Direction = the segment's; geodesic
// curvature at a point from its two neighbours on the polyline (0 at the ends). maxFeed <= 0 = no
// cap. Joins (IsoplanarResult::joins) are timed like curves; travels between paths go straight
// at travelSpeed (<= 0: not timed, the length still counted).
IsoplanarTime estimateIsoplanarTime(const IsoplanarResult& paths, const FeedFn& feed,
                                    double maxFeed, double travelSpeed, double minFeed = 1);

}  // namespace omnislice
