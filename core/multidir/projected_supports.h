// SPDX-License-Identifier: MIT
// Projected supports for multi-directional printing (paper 000, Section V, Algorithm 2, Eq. 13).
//
// The clipping planes gamma_1..gamma_{N-1} (clipping order) split space into convex subspaces
// (Eq. 7): subspace k (k < N-1) = below gamma_1..gamma_{k-1} and above gamma_k, printed along
// gamma_k's normal; the platform subspace N-1 = below every plane, printed along +Z. A point's
// subspace is the first plane whose above side (n . x > d) holds it, else the platform's.
//
// What stays risky (Eq. 1, alpha_max) in each subspace gets support printed in that subspace with
// its part, and the support is projected on into the subspaces printed before it:
// - Overhang samples: the risky faces of each subspace (along its direction) sampled on a square
//   grid of spacing R in the plane orthogonal to the direction (face overhangs), plus the lowest
//   vertex of every connected risky patch the grid missed (small face and edge overhangs) and every
//   vertex lower than all its neighbours (point overhangs). Samples of the platform subspace lower
//   than platformBandMm rest on the platform.
// - Progressive projection: from a sample, a straight strut runs along -d of its subspace until it
//   lands on the model (the part printed in that subspace), reaches the platform, or leaves the
//   subspace through its base plane; there it continues along -d of the subspace below. A strut
//   that would leave through a plane into a subspace printed later cannot be printed before its
//   overhang: its sample is counted as blocked and gets no strut.
// - Strut diameters by Eq. 13: D = (1 + lambda |sum_i V_i (c_i - t) x g_i|) R / 4 over the strut
//   pieces above (V_i volume, c_i centroid, g_i gravity -9.81 d while piece i is printed, t the top
//   of this piece), floored at minDiameterMm so that a bead fits (paper: R / 4 with a 0.8 mm
//   nozzle).
// - Roofs: each risky face (piece in the subspace) gets a prism roofMm thick below it along -d, so
//   the first layers under an overhang are solid support rather than the tops of sparse struts.
// - Trees (Vanek et al., as the paper): within each subspace, from the highest node down, a node
//   joins its nearest neighbour (within 4 R, horizontally) at the highest point both reach with
//   branches at most mergeAngleDeg (30) from -d, when both branches keep half a diameter + 0.2 mm
//   off the model, the meeting point stays in the subspace, and two branches plus one trunk are
//   shorter than two straight struts. The joined node continues like a sample; a blocked trunk
//   blocks its whole tree. Eq. 13 then sums the torque of every branch above a piece.
// Differences from the paper: trees merge within a subspace only; below its base plane a trunk
// runs straight on.
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/clip_mesh.h"
#include "mesh/mesh.h"

namespace omnislice {

struct SupportOptions {
  double samplingMm = 2;        // R, sampling interval of overhangs, mm, > 0 (paper: 2 for a
                                // 0.4 mm nozzle, 3 for 0.8 mm)
  double alphaMaxDeg = 45;      // overhangs steeper than this from the direction need support
  double platformBandMm = 2;    // samples of the platform subspace below this height rest on it
  double lambda = 1e-6;         // Eq. 13
  double minDiameterMm = 0.9;   // strut diameter floor, mm, >= 0
  double roofMm = 0.4;          // roof thickness below risky faces, mm, >= 0 (0 = no roofs)
  double mergeAngleDeg = 30;    // tree branches at most this far from -d; 0 = straight struts
};

struct SupportStrut {
  Eigen::Vector3d top{0, 0, 0}, bottom{0, 0, 0};  // part frame, mm; top - bottom along +d
  double diameterMm = 0;
  int subspace = 0;  // index into the subspaces (planes.size() = platform subspace)
  int trace = 0;     // the tree (or, without merging, the sample) it belongs to
};

struct SupportRoof {
  Eigen::Vector3d a{0, 0, 0}, b{0, 0, 0}, c{0, 0, 0};  // the risky face (outward orientation)
  int subspace = 0;
};

struct SupportResult : Outcome {
  std::vector<SupportStrut> struts;
  std::vector<SupportRoof> roofs;
  std::vector<Eigen::Vector3d> directions;  // per subspace (unit), platform subspace +Z last
  size_t samples = 0;        // overhang samples (grid + patch lowest points + point overhangs)
  size_t pointOverhangs = 0; // of which vertices lower than all their neighbours
  size_t patchSamples = 0;   // of which lowest points of patches the grid missed
  size_t landedOnModel = 0;  // traces ending on the model
  size_t landedOnPlatform = 0;
  size_t blocked = 0;        // samples whose strut would cross into a later subspace (no strut)
  size_t merges = 0;         // pairs of nodes joined into one trunk (tree merging)
  size_t mergeSteps = 0;     // nodes visited by the merging
  double riskyAreaMm2 = 0;   // risky area that the roofs cover (per subspace, Eq. 1)
  double strutVolumeMm3 = 0; // sum over struts of pi D^2 / 4 times the height along d (overlaps
                             // counted twice)
  double roofVolumeMm3 = 0;  // sum over roofs of the projected area times roofMm
};

// Subspace of a point for planes in clipping order (unit normals): the first k with
// n_k . x > d_k, else planes.size().
int subspaceOf(const Eigen::Vector3d& x, const std::vector<Plane>& planes);

// Supports for a closed outward mesh in the part frame (platform z = 0) cut by planes (clipping
// order; normals need not be unit). No planes = one fixed direction (+Z): ordinary 3-axis
// supports. Statuses: InvalidOption (options out of range, a zero or non-finite plane),
// EmptyInput, Cancelled (progress stage "supports").
SupportResult projectedSupports(const Mesh& mesh, const std::vector<Plane>& planes,
                                const SupportOptions& options = {}, const ProgressFn& progress = {});

// The support primitives of one subspace as one closed, outward-oriented triangle soup (possibly
// overlapping shells, to be united by slicing with the non-zero rule): each strut a prism with
// `sides` sides, each roof a triangular prism. Empty when the subspace has none.
Mesh supportMesh(const SupportResult& supports, int subspace, const SupportOptions& options, int sides = 8);

}  // namespace omnislice
