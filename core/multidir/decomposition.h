// SPDX-License-Identifier: MIT
// Support-effective decomposition for multi-directional printing (paper 000, Wu et al. 2019,
// Sections III-IV): a sequence of clipping planes gamma_1..gamma_{N-1} cuts the placed solid into
// N parts; the part cut off by gamma_k is printed along the plane's normal, in the inverse order
// of clipping, after everything below it. The search minimises J_G (Eq. 4), the area of risky
// faces (Eq. 1) summed over the parts, under Criteria II-IV of Section III-C.
//
// Conventions (part frame, mm): the platform is z = 0 and up is +Z. A plane is {x : n . x = d};
// "above" is n . x > d (printed along n), "below" is n . x <= d (kept). A face lying in a plane
// counts as above it. A face f is risky along d when n_f . d + sin(alphaMax) < 0 (Eq. 1). Faces
// of the platform part (the remaining model, printed first along +Z) whose centroid lies below
// z = platformBandMm rest on the platform and are never risky.
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

// The search schemes of Section IV: greedy (Eq. 8-9), constrained greedy (Eq. 10-11), beam
// (IV-B: beam-guided with progressive relaxation).
enum class SearchScheme { Greedy, Constrained, Beam };

// The machine's freedom: 5dof (a tilting table or a robot: normals on the sphere within a tilt)
// or 4dof (one rotary axis: normals on the great circle across it).
enum class DofMode { FiveDof, FourDof };

const char* searchSchemeName(SearchScheme scheme);  // "greedy", "constrained", "beam"
const char* dofModeName(DofMode dof);                // "5dof", "4dof"

struct MultidirOptions {
  double alphaMaxDeg = 45;          // maximal self-supporting angle alpha_max, degrees, in (0, 90)
  int samples = 250;                // candidate normals: points on the whole Gaussian sphere
                                    // (Fibonacci) before the tilt filter (5dof), or on the whole
                                    // circle (4dof, spacing 360/samples when stepAngleDeg = 0); >= 1
  double offsetStepMm = 1;          // plane offsets d = k * offsetStepMm (k integer) along each
                                    // normal, within the remaining model's extent; > 0
  DofMode dof = DofMode::FiveDof;
  double maxTiltDeg = 90;           // 5dof: largest angle between a normal and +Z, degrees, in
                                    // (0, 180]; 90 = never print downward (180 = whole sphere)
  Eigen::Vector3d rotationAxis{1, 0, 0};  // 4dof: the rotary axis r, horizontal (r.z = 0), any
                                          // length; normals lie on the great circle n . r = 0
  int axisSearch = 0;               // 4dof: > 0 = try this many horizontal axes at 180/axisSearch
                                    // degree spacing and keep the least J_G (paper VI-C: 180);
                                    // 0 = use rotationAxis only
  int axisFullSearches = 4;         // 4dof axis search with the beam scheme: every axis is screened
                                    // by the constrained greedy line (half grid resolution, half
                                    // the normals), the beam runs on this many best axes at least
                                    // 3 deg apart (0 = on every axis); >= 0
  double stepAngleDeg = 0;          // 4dof: stepper angle, degrees; > 0 keeps only rotations that
                                    // are multiples of it (0 = off, spacing 360/samples)
  double rangeDeg = 90;             // 4dof: largest rotation from +Z, degrees, in (0, 180]
                                    // (the paper's rotary platform: 60)
  std::vector<Eigen::Vector3d> candidateNormals;  // non-empty: exactly these normals (normalised;
                                                  // zero or non-finite -> InvalidOption) replace the
                                                  // sampling of either dof; the tilt filter of 5dof
                                                  // still applies
  double w = 10;                    // Criterion IV: a part smaller than V(M)/w is refused, and a
                                    // remaining model smaller than V(M)/w ends a beam; >= 1
  int beamWidth = 8;                // b, beams kept per level (beam scheme), >= 1 (paper: "b";
                                    // 8 measured: the Kitten reaches J_G ~0.03 mm^2 at 8 and
                                    // 10, ~2-4 mm^2 at 3 and 5)
  int restarts = 3;                 // 5dof beam: the search runs up to this many times, restart
                                    // j on the sphere of normals turned about Z by
                                    // 2 pi frac(j (sqrt 2 - 1)) (the first with the greedy lines,
                                    // the others the beam line only), stopping once a line ends
                                    // at J_G <= delta0; every line's best end is refined and the
                                    // least J_G wins. In [1, 64]; ignored with candidateNormals
  double delta0 = 0.1;              // first risk bound delta of the progressive relaxation, mm^2,
                                    // > 0; also the "R = 0" tolerance of the constrained greedy
  double relaxFactor = 5;           // delta *= relaxFactor until the b beams are filled, > 1
  SearchScheme scheme = SearchScheme::Beam;
  double platformMarginMm = 5;      // Criterion III: the platform P is the model's footprint
                                    // (vertices below platformBandMm, projected on z = 0) grown by
                                    // this margin, mm, >= 0 ...
  double platformRadiusMm = 0;      // ... or, when > 0, the disc of this radius around x = y = 0
  double platformBandMm = 2;        // faces of the platform part with centroid z below this rest
                                    // on the platform (not risky), mm, >= 0
  double similarityFraction = 0.25; // two beam results are "close" when the volume kept by one
                                    // and not the other (coarse grid samples) is at most this
                                    // fraction of the smaller volume their last planes cut off;
                                    // >= 0 (0 = equal remaining models only)
  double similarityAngleDeg = 5;    // ... or when they share a parent, their normals are within
                                    // this angle (degrees) and ...
  double similarityOffsetMm = 3;    // ... their offsets within this distance (either 0 = off)
  bool refine = true;               // after the search, move each plane to a nearby normal
                                    // (5dof: within 12 deg; 4dof: a few degrees or stepper steps
                                    // about the axis) and offset (+-4 mm, half steps) while the
                                    // exact J_G drops and Criteria II-IV hold (paper VI-C's
                                    // "future work"); false = the sampled planes as found
  int perturbations = 60;           // beam scheme, with refine: iterated local search on the
                                    // refined best sequence: this many times one plane moves
                                    // 6-20 deg and up to 8 offset steps (fixed pseudo-random
                                    // sequence), the planes are refined again and the move kept
                                    // when the exact J_G drops; stops at J_G <= delta0.
                                    // In [0, 10000]; 0 = off
  int gridResolution = 100;         // solid occupancy grid (volumes, Criterion II): cells along
                                    // the longest bounding-box side, in [8, 1000]
  double floatingToleranceCells = 2;  // Criterion II: remaining cells cut off from the platform,
                                      // at most this many in all, are grid noise (a cell centre in
                                      // a sliver thinner than a cell) and tolerated; >= 0
};

struct MultidirPlane {
  Eigen::Vector3d normal{0, 0, 1};  // unit; the printing direction of the part above
  double offsetMm = 0;              // d of {x : normal . x = d}
};

struct MultidirPart {
  Eigen::Vector3d direction{0, 0, 1};  // printing direction (+Z for the platform part)
  int plane = -1;                      // index of its base plane in planes, -1 = platform part
  double riskyAreaMm2 = 0;             // exact risky area of its share of the surface (Eq. 11)
  double volumeMm3 = 0;                // approximate: occupancy-grid cells inside the part
};

struct MultidirStats {
  size_t normals = 0;               // candidate normals (per axis in 4dof)
  size_t candidatesEvaluated = 0;   // (state, normal, offset) planes whose J_L and R were summed
  size_t candidatesChecked = 0;     // planes tested against Criteria II/IV and similarity
  size_t connectivityChecks = 0;    // Criterion II flood fills and union-find sweeps
  size_t refusedFloating = 0;       // refused by Criterion II
  size_t refusedSmall = 0;          // refused by Criterion IV
  size_t refusedSimilar = 0;        // discarded as close to a result already in the beam
  size_t beams = 0;                 // search nodes created (every beam entry of every level)
  size_t levels = 0;                // levels expanded
  std::vector<double> jgPerLevel;   // J_G (mm^2) after each plane of the returned sequence,
                                    // jgPerLevel[0] = J_G before
  double searchJgMm2 = 0;           // J_G of the returned decomposition as the search summed it
                                    // for its planes before refinement (= jgAfterMm2 when
                                    // refine is false)
  size_t gridCells = 0;             // solid cells of the occupancy grid
  double cellMm = 0;                // its cell width
  size_t orphanCells = 0;           // solid cells not connected to the platform in the grid
                                    // (dropped: thinner than a cell or floating in the input)
  size_t axesTried = 0;             // 4dof axis search
  size_t restartsRun = 0;           // 5dof: searches run (<= restarts: they stop at J_G <= delta0)
  double msPrepare = 0;             // faces, grid, platform
  double msNormals = 0;             // per-normal tables
  double msSweep = 0;               // J_L / R prefix sums of all candidates
  double msChecks = 0;              // volumes, similarity, flood fills
  size_t refineEvaluated = 0;       // (plane, normal, offset) variants summed by the refinement
  double msRefine = 0;              // refinement
  size_t perturbations = 0;         // moves tried by the iterated local search ...
  size_t perturbationsKept = 0;     // ... and kept (each lowered J_G)
  double msPerturb = 0;             // iterated local search (its refinement included)
  double msExact = 0;               // final exact evaluation
  double msTotal = 0;
};

struct MultidirResult : Outcome {
  std::vector<MultidirPlane> planes;  // clipping order gamma_1..gamma_{N-1}
  std::vector<MultidirPart> parts;    // parts[k] is cut off by planes[k] (k < planes.size());
                                      // parts.back() is the platform part. Printing order is
                                      // parts.back() first, then parts in reverse clipping order
  double jgBeforeMm2 = 0;             // J_G of the whole model along +Z (exact)
  double jgAfterMm2 = 0;              // J_G of the decomposition, exact w.r.t. the planes
  double volumeMm3 = 0;               // V(M) by the divergence theorem
  Eigen::Vector3d rotationAxis{0, 0, 0};  // 4dof: the axis used (unit); zero in 5dof
  MultidirStats stats;
};

// Search the clipping planes (Section IV) for a closed, outward-oriented solid in the part frame
// (placed: min z = 0). scheme "greedy" takes the valid plane of largest J_L (Eq. 8-9);
// "constrained" prefers planes whose part above has R < delta0 (Eq. 10-11); "beam" is the
// beam-guided search with progressive relaxation (Section IV-B, b = beamWidth). Every scheme
// applies Criteria II (the remaining model stays connected to the platform: no floating piece in
// the occupancy grid), III (the platform P lies below the plane) and IV (parts >= V/w) and stops
// on the terminal conditions (remaining volume < V/w, remaining self-supported, no valid plane).
// J_L, R and J_G are exact w.r.t. the planes (faces straddling a plane are split by area); volumes
// and connectivity come from an occupancy grid of cell centres inside the solid.
// The beam scheme also runs the greedy and constrained-greedy lines from the same root (two more
// beams of width 1); in 5dof the beam line runs options.restarts times on the sphere of normals
// turned about Z. Each level first gives every node of the frontier at most its fair share of the
// b beams, then fills the rest by priority. The best end of each line (least J_G; within delta0
// of it, fewest planes) is refined (options.refine) and the least exact J_G wins; with the beam
// scheme the winner then goes through options.perturbations moves of an iterated local search
// (each kept only when J_G drops), so the beam never ends above either greedy scheme. Native and
// wasm give the same planes. Cost (default options, 10k-face Kitten, one core of an unloaded
// 2-core VM): ~0.2 s native, ~0.3 s as wasm under Node 20 where the first search ends within
// delta0 (the Kitten as stored), ~0.35-0.8 s as wasm where all three restarts run (the Kitten
// turned about Z; the local search adds ~0.3 s where it runs to the end); 4dof over 180 axes
// ~2 s native, ~2.5 s wasm.
// Progress: stage "decompose". Each line reports its levels as they are done, each with a
// SearchLevelProgress (common/progress.h): level 0 (the root, J_G before) and every level it
// expands, named "greedy", "constrained" or "beam" (5dof: one "beam" line per restart; 4dof axis
// search: "screen" for each screened axis, then the lines of each fully searched axis); levels
// >= 1 of all lines number stats.levels. Last, at fraction 1, the returned sequence as "chosen" levels 0..N with J_G =
// stats.jgPerLevel[level]. Cancelling on any report stops the search.
// Statuses: EmptyInput (no triangles), ParseError (index out of range), NonFiniteVertex,
// InvalidOption (an option out of range or NaN, unknown dof/scheme, a non-horizontal rotation
// axis, the mesh below z = 0, over 20000 offsets along a normal), DegenerateInput (no grid cell
// centre inside the solid: walls thinner than the grid), Cancelled (progress stage "decompose").
MultidirResult searchDecomposition(const Mesh& mesh, const MultidirOptions& options = {},
                                   const ProgressFn& progress = {});

struct MultidirPlaneCheck {
  bool platformBelow = true;     // Criterion III
  bool connected = true;         // Criterion II: no piece of the remaining model floats (beyond
                                 // floatingToleranceCells)
  double floatingVolumeMm3 = 0;  // grid volume of the remaining cells cut off from the platform
  bool partLargeEnough = true;   // Criterion IV: the part above has >= V/w
  double partVolumeMm3 = 0;      // grid volume of the part above
};

struct MultidirEvaluation : Outcome {
  double jgBeforeMm2 = 0;
  double jgAfterMm2 = 0;              // exact (faces split by the planes)
  std::vector<MultidirPart> parts;    // as in MultidirResult
  std::vector<MultidirPlaneCheck> checks;  // one per plane, in clipping order
};

// J_G of a given plane sequence (clipping order), exact: each face is clipped by the planes in
// turn, the piece above gamma_k goes to part k (risky along its normal), the rest to the platform
// part (risky along +Z unless its face's centroid is below platformBandMm). Also checks each plane
// against Criteria II-IV with the same occupancy grid as the search (only alphaMaxDeg,
// platform*, w, gridResolution and floatingToleranceCells of the options are used). A normal
// need not be unit (plane and offset are scaled together). Statuses as searchDecomposition, plus
// InvalidOption for a zero or non-finite plane.
MultidirEvaluation evaluateDecomposition(const Mesh& mesh, const std::vector<MultidirPlane>& planes,
                                         const MultidirOptions& options = {});

}  // namespace omnislice
