// SPDX-License-Identifier: MIT
// Geodesic distance inside a solid by the heat method on a tetrahedral mesh, exactly as paper 002
// Section 2.1 (after Crane et al.): cotangent weights w_ij = 1/6 sum_k l_k cot(theta_k) (Eq. 3,
// l_k the opposite edge's length, theta_k its dihedral angle), vertex volumes V_i = 1/4 of the
// incident tets' volume, L = V^-1 L_c (Eq. 4-5), heat step (I - t V^-1 L_c) u = u0 (Eq. 6, solved
// as (V - t L_c) u = V u0, symmetric positive definite) with t = h^2 (h the mean edge length,
// times timeFactor), per-tet gradients (Eq. 7) normalised to -grad u / |grad u|, integrated
// divergence (Eq. 8), Poisson L_c phi = b (Eq. 9) with the sources held at distance 0.
// Solvers chosen by measurement. The heat step: conjugate gradients were tried first
// (../shared/TOOLCHAIN.md: on tet Laplacians they beat direct Cholesky 25-100x), but a relative
// residual of 1e-8 cannot resolve the heat far from point-like sources (u decays like exp(-d/h),
// e^-100 at 100 edges): on the ../shared/models tet meshes the field then fell up to 69 mm below
// the Euclidean distance. A sparse LDLT keeps those values but fills in badly on compact solids
// (12k-vertex bunny: 2.6M entries, 580 ms native). The default is symmetric Gauss-Seidel (over-relaxed, 1.5) in the
// order of distance from the sources (HeatSolver::Sweep): each vertex is solved from its own row,
// so a tiny value keeps its relative accuracy, and sweeps stop when no vertex changes by more than
// 1e-7 of itself. Against LDLT: distances within 3e-6 mm on the real tet models, 110-330 sweeps,
// 10-400 ms native and no factorisation. The Poisson step (a smooth, well-scaled right-hand side)
// uses conjugate gradients with an incomplete-Cholesky preconditioner (measured against
// diagonal: 5-11 % faster on the three real meshes, 3.5-4x fewer iterations).
// A HeatGeodesic object keeps the heat matrix for solves from other sources; the Poisson matrix
// and its preconditioner depend on the sources (their rows are fixed) and are built per solve
// (12k-vertex tet models: 15-25 ms native).
#pragma once
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "tet/tet_mesh.h"

namespace omnislice {

// How the heat step (Eq. 6) is solved. Sweep: symmetric Gauss-Seidel sweeps in the order of the
// vertices' edge-path distance from the sources, until no vertex's value changes by more than
// heatTolerance relative to itself (each vertex is solved from its own row, so the exponentially
// small far-field values keep their relative accuracy, which a residual norm cannot see). Direct:
// a sparse LDLT factorisation at construction (the reference the sweeps are tested against).
enum class HeatSolver { Sweep, Direct };

struct HeatGeodesicOptions {
  double timeFactor = 1.0;      // t = timeFactor * h^2
  double tolerance = 1e-8;      // relative residual of the conjugate-gradient (Poisson) solve
  int maxIterations = 5000;     // of the Poisson solve, and of the heat sweeps
  HeatSolver heatSolver = HeatSolver::Sweep;
  double heatTolerance = 1e-7;  // largest relative change of a vertex's heat in the last sweep
  // Passes after Eq. 9 (0-10) that take X from the solved field itself, X = grad phi / |grad phi|,
  // and solve Eq. 9 again. The heat gradient's directions are not a gradient field; the Poisson
  // fit turns that into |grad phi| well away from 1, so iso-surfaces an interval apart in phi lie
  // up to 1.7 intervals apart in space. One pass takes most of it out (measured in
  // heat_geodesic_test.cpp and on the Kitten's programs); each costs one more Poisson solve.
  // 0 (the paper's method) by default: near a point source it does harm (a box corner's mean
  // error 0.33 -> 0.34 mm, max 1.2 -> 1.6 mm); the pipeline's platform sources take 1.
  int renormalizations = 0;
  // Smoothing passes over the unit directions X of Eq. 7 before the divergence (0-100; 0 = the
  // paper). Where fronts from two branches merge (the cut locus) X turns by up to 180 degrees
  // between neighbouring tets and the iso-surfaces meet at a sharp crease no nozzle reaches;
  // averaging X there aligns the merging geodesics (paper 002's future work) and rounds the
  // crease, and leaves X alone where it is already uniform. Each pass: per vertex the sum of its
  // tets' X, per tet the normalised sum over its four vertices.
  int alignPasses = 0;
};

struct GeodesicField : Outcome {
  std::vector<double> distance;   // per vertex, mm
  double maxDistance = 0;
  int heatIterations = 0, poissonIterations = 0;  // heat: symmetric sweeps (0 for Direct)
  double setupMs = 0, heatMs = 0, gradientMs = 0, poissonMs = 0;
};

// The discrete operators of Eq. 2-5: L_c (n x n, w_ij off the diagonal, -sum_j w_ij on it; negative
// semi-definite), the vertex volumes V_i (a quarter of the incident tets' volumes; 0 for vertices
// in no tet) and the mean edge length h. Tet orientation does not matter. Statuses: DegenerateInput
// (no tets, index out of range, non-finite coordinate, zero-volume tet).
struct TetLaplacian : Outcome {
  Eigen::SparseMatrix<double> cotan;  // L_c
  std::vector<double> vertexVolume;   // mm^3
  double meanEdge = 0;                // mm
};
TetLaplacian tetCotanLaplacian(const TetMesh& mesh);

// Prepared operators of one tet mesh (matrices and preconditioners built once).
class HeatGeodesic {
 public:
  // Statuses through status(): DegenerateInput (no tets, zero-volume tets, bad index, non-finite
  // coordinate), InvalidOption (options out of range), Internal (a factorisation failed).
  // Negatively oriented tets are accepted. The sources are held at distance 0 in the Poisson
  // solve (a Dirichlet condition); components holding no source get distance 0 (no heat reaches
  // them).
  HeatGeodesic(const TetMesh& mesh, const HeatGeodesicOptions& options = {});
  ~HeatGeodesic();
  HeatGeodesic(HeatGeodesic&&) noexcept;
  HeatGeodesic& operator=(HeatGeodesic&&) noexcept;
  const Outcome& status() const;

  // Distance from the source vertices (indices; at least one, all in range) — InvalidOption
  // otherwise; Cancelled through progress (stage "field"); Internal if a solve does not converge
  // or the Poisson preconditioner cannot be built. sourceDistance, if given, holds each source's
  // own distance (one finite value >= 0 per source, e.g. its height above the platform when the
  // sources are taken within a tolerance of it); the sources are held at it, else at 0.
  GeodesicField distanceFrom(const std::vector<uint32_t>& sources,
                             const ProgressFn& progress = {}) const;
  GeodesicField distanceFrom(const std::vector<uint32_t>& sources,
                             const std::vector<double>& sourceDistance,
                             const ProgressFn& progress = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Vertices on the platform: boundary vertices with z <= minZ + tolerance (the default heat
// source of paper 002, "the vertices at the bottom face").
std::vector<uint32_t> platformVertices(const TetMesh& mesh, double tolerance = 1e-6);
// Each vertex's height above the lowest of them (z - min z): the distance of platform vertices
// taken within a tolerance from the platform.
std::vector<double> heightsAboveLowest(const TetMesh& mesh, const std::vector<uint32_t>& vertices);

}  // namespace omnislice
