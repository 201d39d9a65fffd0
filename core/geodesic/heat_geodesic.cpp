// SPDX-License-Identifier: MIT
// Heat-method geodesic distance on a tetrahedral mesh (paper 002 Section 2.1, Eq. 1-9).
//
// Sign conventions. Eq. 5 gives L_c with off-diagonals w_ij (Eq. 3) and diagonal -sum w_ik, so
// L_c is negative semi-definite; we store K = -L_c (positive semi-definite) and solve
//   heat (Eq. 6 times V):   (V + t K) u = V u0,
//   Poisson (Eq. 9):        K phi = -b,   b_i = sum_k -(S_k n_k . g_k) / 3   (Eq. 8),
// (heat: symmetric Gauss-Seidel sweeps in order of distance from the sources, or the sparse LDLT
// reference, HeatSolver; Poisson: IC-preconditioned conjugate gradients, see the header)
// where g_k is the normalised gradient of u in tet k (Eq. 7, g_k / |g_k|) and S_k n_k the outward
// area vector of the face of tet k opposite vertex i. (The header's X = -grad u / |grad u| is -g_k;
// the two readings give the same phi, growing away from the sources.) K is singular (constants):
// the sources are held at distance 0 (their rows and columns replaced by the identity, a Dirichlet
// condition), and so is one vertex of each component without a source, which keeps the system
// positive definite for the incomplete Cholesky preconditioner. (Solving K free and shifting the
// field so the sources' mean distance is 0 leaves the rim of a source face above 0: on the shared
// Yoga at 0.6 mm the iso-surface at 1.2 mm then reached the platform 2-4 mm outside the sole; the
// first layers of the Yoga and bunny head read 51 and 47 deg of average overhang, 17 and 21 deg
// with the sources held (igds_test.cpp); errors against the exact distance from a box's and a
// cylinder's bottom face fall by a quarter to a third, heat_geodesic_test.cpp.)
#include "geodesic/heat_geodesic.h"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <string>

#include "common/disjoint_sets.h"
#include "common/stopwatch.h"

namespace omnislice {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// The four faces of tet (a, b, c, d) = vertices 0..3: face f is opposite vertex f, listed so
// that its normal by the right-hand rule points outward for a positively oriented tet.
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// The six edges (i, j) of a tet and their opposite edges (p, q).
constexpr int kEdge[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                             {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};

// Preconditioned conjugate gradients on a symmetric positive definite matrix, with a progress /
// cancel check every few iterations. Returns the iteration count, -1 when cancelled, -2 when not
// converged within maxIterations.
template <class Precond>
int pcg(const SpMat& A, const Precond& M, const Eigen::VectorXd& b, Eigen::VectorXd& x,
        double tolerance, int maxIterations, const ProgressFn& progress, double f0, double f1) {
  const double bNorm = b.norm();
  if (bNorm == 0) {
    x.setZero();
    return 0;
  }
  Eigen::VectorXd r = b - A * x;
  const double threshold = tolerance * tolerance * bNorm * bNorm;
  if (r.squaredNorm() <= threshold) return 0;
  Eigen::VectorXd z = M.solve(r);
  Eigen::VectorXd p = z;
  Eigen::VectorXd Ap(b.size());
  double rz = r.dot(z);
  for (int it = 1; it <= maxIterations; ++it) {
    Ap.noalias() = A * p;
    const double pAp = p.dot(Ap);
    if (!(pAp > 0)) return -2;
    const double alpha = rz / pAp;
    x.noalias() += alpha * p;
    r.noalias() -= alpha * Ap;
    if (r.squaredNorm() <= threshold) return it;
    z = M.solve(r);
    const double rzNew = r.dot(z);
    p = z + (rzNew / rz) * p;
    rz = rzNew;
    if (it % 16 == 0 && progress) {
      // Convergence is roughly geometric: report the log-residual progress.
      const double ratio = std::sqrt(r.squaredNorm() / (bNorm * bNorm));
      const double done = std::clamp(std::log(ratio) / std::log(tolerance), 0.0, 1.0);
      if (!reportProgress(progress, "field", f0 + (f1 - f0) * done)) return -1;
    }
  }
  return -2;
}

// Order in which the heat sweeps visit the vertices: increasing edge-path length from the sources
// (Dijkstra on the matrix graph). Vertices no source reaches (other components, unused ones) are
// left out: their heat stays 0.
std::vector<uint32_t> sweepOrder(const SpMat& A, const std::vector<double>& vertexVolume,
                                 const std::vector<uint32_t>& sources,
                                 const std::vector<double>& positions) {
  const size_t n = size_t(A.rows());
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  using Item = std::pair<double, uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (uint32_t s : sources)
    if (dist[s] != 0) {
      dist[s] = 0;
      queue.push({0.0, s});
    }
  std::vector<uint32_t> order;
  order.reserve(n);
  std::vector<uint8_t> done(n, 0);
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (done[i]) continue;
    done[i] = 1;
    order.push_back(i);
    for (SpMat::InnerIterator e(A, Eigen::Index(i)); e; ++e) {
      const auto j = uint32_t(e.row());
      if (j == i || done[j] || !(vertexVolume[j] > 0)) continue;
      const double dx = positions[3 * j] - positions[3 * i], dy = positions[3 * j + 1] - positions[3 * i + 1],
                   dz = positions[3 * j + 2] - positions[3 * i + 2];
      const double nd = d + std::sqrt(dx * dx + dy * dy + dz * dz);
      if (nd < dist[j]) {
        dist[j] = nd;
        queue.push({nd, j});
      }
    }
  }
  return order;
}

// Over-relaxation of the heat sweeps (symmetric SOR; any weight in (0, 2) converges on the SPD
// heat matrix). Measured on the bench bunny (60k tets): 94 -> 47 sweeps at t = h^2, 940 -> 552
// at t = 30 h^2 (field 437 -> 307 ms); 1.8 is slower than 1.5 on both.
constexpr double kOverRelaxation = 1.5;

// Eq. 6 by symmetric (over-relaxed) Gauss-Seidel: a forward sweep in order of distance from the
// sources, then a backward one, until the largest change of any vertex relative to its own value is below
// tolerance. Heat flows outward from the sources, so the forward sweep carries it across the whole
// part in one pass; each vertex is solved from its own row, which keeps the relative accuracy of
// the exponentially small far-field values (the heat matrix V + h^2 K is symmetric positive
// definite, so the sweeps converge). Returns the number of symmetric sweeps, -1 when cancelled,
// -2 when not converged in maxSweeps.
int heatSweeps(const SpMat& A, const std::vector<double>& invDiagonal,
               const std::vector<double>& vertexVolume, const std::vector<uint32_t>& sources,
               const Eigen::VectorXd& b, Eigen::VectorXd& u, double tolerance, int maxSweeps,
               const ProgressFn& progress, const std::vector<double>& positions) {
  const std::vector<uint32_t> order = sweepOrder(A, vertexVolume, sources, positions);
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* value = A.valuePtr();
  auto relax = [&](uint32_t i) {
    double s = b[i];
    for (int k = outer[i]; k < outer[i + 1]; ++k)
      if (uint32_t(inner[k]) != i) s -= value[k] * u[inner[k]];
    const double next = u[i] + kOverRelaxation * (s * invDiagonal[i] - u[i]);
    const double change = std::abs(next - u[i]);
    u[i] = next;
    return next != 0 ? change / std::abs(next) : 0.0;
  };
  for (int sweep = 1; sweep <= maxSweeps; ++sweep) {
    double largest = 0;
    for (uint32_t i : order) largest = std::max(largest, relax(i));
    for (auto r = order.rbegin(); r != order.rend(); ++r) largest = std::max(largest, relax(*r));
    if (sweep > 1 && largest <= tolerance) return sweep;
    if (progress && sweep % 4 == 0) {
      const double done = std::clamp(std::log(std::max(largest, 1e-300)) / std::log(tolerance), 0.0, 1.0);
      if (!reportProgress(progress, "field", 0.4 * done)) return -1;
    }
  }
  return -2;
}

}  // namespace

struct HeatGeodesic::Impl {
  Outcome status;
  HeatGeodesicOptions options;
  TetMesh mesh;
  size_t n = 0;
  double meanEdge = 0, timeStep = 0;
  std::vector<double> vertexVolume;       // V_i (Eq. 2)
  std::vector<double> areaVectors;        // per tet, 4 faces x 3: S n outward (face opposite vertex)
  std::vector<double> invThreeVolume;     // per tet 1 / (3 vol)
  std::vector<uint32_t> pinned;           // one vertex per connected component, plus unused ones
  std::vector<uint32_t> component;        // per vertex: its component's pinned vertex
  SpMat heatMatrix;                       // V + t K
  SpMat laplacian;                        // L_c (Eq. 5), kept for tests and diagnostics
  Eigen::SimplicialLDLT<SpMat> heatSolver;  // HeatSolver::Direct only
  std::vector<double> invDiagonal;          // of heatMatrix (HeatSolver::Sweep)
  double setupMs = 0;

  bool fail(Status s, std::string message) {
    status.status = s;
    status.message = std::move(message);
    return false;
  }
  bool build(const TetMesh& input, const HeatGeodesicOptions& opt);
};

TetLaplacian tetCotanLaplacian(const TetMesh& mesh) {
  TetLaplacian out;
  auto fail = [&out](std::string message) {
    out.status = Status::DegenerateInput;
    out.message = std::move(message);
    out.cotan.resize(0, 0);
    out.vertexVolume.clear();
    return out;
  };
  const size_t n = mesh.vertexCount(), T = mesh.tetCount();
  if (mesh.positions.size() % 3 != 0 || mesh.tets.size() % 4 != 0)
    return fail("heat geodesic: positions or tets are not whole vertices / tets");
  if (T == 0 || n == 0) return fail("heat geodesic: the mesh has no tets");
  for (double c : mesh.positions)
    if (!std::isfinite(c)) return fail("heat geodesic: a vertex coordinate is not finite");
  for (size_t k = 0; k < mesh.tets.size(); ++k)
    if (mesh.tets[k] >= n)
      return fail("heat geodesic: tet " + std::to_string(k / 4) +
                  " has a vertex index out of range");
  // Scale for the degeneracy test: the bounding box diagonal.
  Eigen::Vector3d lo = mesh.vertex(0), hi = lo;
  for (size_t i = 1; i < n; ++i) {
    lo = lo.cwiseMin(mesh.vertex(i));
    hi = hi.cwiseMax(mesh.vertex(i));
  }
  const double diag = (hi - lo).norm();
  const double minVolume = 1e-15 * diag * diag * diag;

  out.vertexVolume.assign(n, 0.0);
  std::vector<Eigen::Triplet<double>> lc;  // off-diagonal entries; the diagonal is summed apart
  lc.reserve(T * 12 + n);
  std::vector<double> diagonal(n, 0.0);
  for (size_t k = 0; k < T; ++k) {
    const uint32_t* t = &mesh.tets[4 * k];
    Eigen::Vector3d v[4];
    for (int c = 0; c < 4; ++c) v[c] = mesh.vertex(t[c]);
    const double vol = std::abs((v[1] - v[0]).dot((v[2] - v[0]).cross(v[3] - v[0]))) / 6.0;
    if (!(vol > minVolume)) return fail("heat geodesic: tet " + std::to_string(k) + " has zero volume");
    Eigen::Vector3d normal[4];  // unit normals of the faces opposite each vertex (outward when
                                // positively oriented; both flip otherwise, which cancels below)
    for (int f = 0; f < 4; ++f) {
      const Eigen::Vector3d& a = v[kFace[f][0]];
      normal[f] = (v[kFace[f][1]] - a).cross(v[kFace[f][2]] - a).normalized();
    }
    for (int c = 0; c < 4; ++c) out.vertexVolume[t[c]] += vol / 4.0;
    // Eq. 3: for edge (i, j), l = |v_p - v_q| and theta the dihedral angle at edge (p, q), between
    // the faces (p, q, i) and (p, q, j), i.e. the faces opposite j and i.
    for (const auto& e : kEdge) {
      const int i = e[0], j = e[1], p = e[2], q = e[3];
      const double l = (v[p] - v[q]).norm();
      const double cosTheta = -normal[i].dot(normal[j]);  // interior angle from outward normals
      const double sinTheta = normal[i].cross(normal[j]).norm();
      const double w = l * (cosTheta / sinTheta) / 6.0;
      lc.emplace_back(t[i], t[j], w);
      lc.emplace_back(t[j], t[i], w);
      diagonal[t[i]] -= w;
      diagonal[t[j]] -= w;
    }
  }
  for (size_t i = 0; i < n; ++i) lc.emplace_back(i, i, diagonal[i]);
  out.cotan.resize(Eigen::Index(n), Eigen::Index(n));
  out.cotan.setFromTriplets(lc.begin(), lc.end());
  // Mean edge length over the unique edges: the strictly lower entries of L_c (setFromTriplets
  // keeps an entry even when its weights sum to zero, so every edge is there once).
  double sum = 0;
  size_t edgeCount = 0;
  for (Eigen::Index c = 0; c < out.cotan.outerSize(); ++c)
    for (SpMat::InnerIterator it(out.cotan, c); it; ++it)
      if (it.row() > it.col()) {
        sum += (mesh.vertex(size_t(it.row())) - mesh.vertex(size_t(it.col()))).norm();
        ++edgeCount;
      }
  out.meanEdge = sum / double(edgeCount);
  return out;
}

bool HeatGeodesic::Impl::build(const TetMesh& input, const HeatGeodesicOptions& opt) {
  const auto t0 = Clock::now();
  options = opt;
  if (!(opt.timeFactor > 0) || !std::isfinite(opt.timeFactor))
    return fail(Status::InvalidOption, "heat geodesic: timeFactor must be a positive number");
  if (!(opt.tolerance > 0 && opt.tolerance < 1))
    return fail(Status::InvalidOption, "heat geodesic: tolerance must be in (0, 1)");
  if (!(opt.heatTolerance > 0 && opt.heatTolerance < 1))
    return fail(Status::InvalidOption, "heat geodesic: heatTolerance must be in (0, 1)");
  if (opt.maxIterations < 1)
    return fail(Status::InvalidOption, "heat geodesic: maxIterations must be at least 1");
  if (opt.alignPasses < 0 || opt.alignPasses > 100)
    return fail(Status::InvalidOption, "heat geodesic: alignPasses must be in 0-100");
  if (opt.renormalizations < 0 || opt.renormalizations > 10)
    return fail(Status::InvalidOption, "heat geodesic: renormalizations must be in 0-10");
  TetLaplacian lap = tetCotanLaplacian(input);
  if (!lap.ok()) return fail(lap.status, lap.message);
  mesh = input;
  n = mesh.vertexCount();
  const size_t T = mesh.tetCount();
  vertexVolume = std::move(lap.vertexVolume);
  laplacian = std::move(lap.cotan);
  meanEdge = lap.meanEdge;
  timeStep = opt.timeFactor * meanEdge * meanEdge;

  areaVectors.assign(T * 12, 0.0);
  invThreeVolume.assign(T, 0.0);
  DisjointSets components(n);
  for (size_t k = 0; k < T; ++k) {
    uint32_t* t = &mesh.tets[4 * k];
    Eigen::Vector3d v[4];
    for (int c = 0; c < 4; ++c) v[c] = mesh.vertex(t[c]);
    double vol = (v[1] - v[0]).dot((v[2] - v[0]).cross(v[3] - v[0])) / 6.0;
    if (vol < 0) {  // tolerate negatively oriented tets: swap two vertices of our copy
      std::swap(t[2], t[3]);
      std::swap(v[2], v[3]);
      vol = -vol;
    }
    invThreeVolume[k] = 1.0 / (3.0 * vol);
    for (int f = 0; f < 4; ++f) {
      const Eigen::Vector3d& a = v[kFace[f][0]];
      const Eigen::Vector3d area = 0.5 * (v[kFace[f][1]] - a).cross(v[kFace[f][2]] - a);
      for (int d = 0; d < 3; ++d) areaVectors[12 * k + 3 * f + d] = area[d];
    }
    for (int c = 1; c < 4; ++c) components.unite(t[0], t[c]);
  }

  component.resize(n);
  for (uint32_t i = 0; i < n; ++i) component[i] = components.find(i);
  for (uint32_t i = 0; i < n; ++i)
    if (vertexVolume[i] <= 0 || components.find(i) == i) pinned.push_back(i);

  // Heat matrix V - t L_c = V + t K; unused vertices get identity rows.
  std::vector<Eigen::Triplet<double>> heat;
  heat.reserve(size_t(laplacian.nonZeros()) + n);
  for (int c = 0; c < laplacian.outerSize(); ++c)
    for (SpMat::InnerIterator it(laplacian, c); it; ++it)
      heat.emplace_back(it.row(), it.col(), -timeStep * it.value());
  for (uint32_t i = 0; i < n; ++i) heat.emplace_back(i, i, vertexVolume[i] > 0 ? vertexVolume[i] : 1.0);
  heatMatrix.resize(Eigen::Index(n), Eigen::Index(n));
  heatMatrix.setFromTriplets(heat.begin(), heat.end());

  if (opt.heatSolver == HeatSolver::Direct) {
    heatSolver.compute(heatMatrix);
    if (heatSolver.info() != Eigen::Success)
      return fail(Status::Internal, "heat geodesic: LDLT factorisation failed");
  } else {
    invDiagonal.assign(n, 0.0);
    for (int c = 0; c < heatMatrix.outerSize(); ++c)
      for (SpMat::InnerIterator it(heatMatrix, c); it; ++it)
        if (it.row() == it.col()) invDiagonal[size_t(c)] = 1.0 / it.value();
  }
  setupMs = msSince(t0);
  return true;
}

HeatGeodesic::HeatGeodesic(const TetMesh& mesh, const HeatGeodesicOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->build(mesh, options);
}
HeatGeodesic::~HeatGeodesic() = default;
HeatGeodesic::HeatGeodesic(HeatGeodesic&&) noexcept = default;
HeatGeodesic& HeatGeodesic::operator=(HeatGeodesic&&) noexcept = default;

const Outcome& HeatGeodesic::status() const {
  static const Outcome moved{Status::Internal, "heat geodesic: object was moved from"};
  return impl_ ? impl_->status : moved;
}

GeodesicField HeatGeodesic::distanceFrom(const std::vector<uint32_t>& sources,
                                         const ProgressFn& progress) const {
  return distanceFrom(sources, {}, progress);
}

GeodesicField HeatGeodesic::distanceFrom(const std::vector<uint32_t>& sources,
                                         const std::vector<double>& sourceDistance,
                                         const ProgressFn& progress) const {
  GeodesicField out;
  auto fail = [&out](Status s, std::string message) {
    out.status = s;
    out.message = std::move(message);
    out.distance.clear();
    out.maxDistance = 0;
    return out;
  };
  if (!impl_) return fail(Status::Internal, "heat geodesic: object was moved from");
  const Impl& m = *impl_;
  if (!m.status.ok()) return fail(m.status.status, m.status.message);
  if (sources.empty()) return fail(Status::InvalidOption, "heat geodesic: no source vertices");
  for (uint32_t s : sources)
    if (s >= m.n)
      return fail(Status::InvalidOption, "heat geodesic: source vertex " + std::to_string(s) +
                                             " is out of range (" + std::to_string(m.n) +
                                             " vertices)");
  for (uint32_t s : sources)
    if (m.vertexVolume[s] <= 0)
      return fail(Status::InvalidOption, "heat geodesic: source vertex " + std::to_string(s) +
                                             " belongs to no tet");
  if (!sourceDistance.empty() && sourceDistance.size() != sources.size())
    return fail(Status::InvalidOption, "heat geodesic: " + std::to_string(sourceDistance.size()) +
                                           " source distances for " +
                                           std::to_string(sources.size()) + " sources");
  for (double d : sourceDistance)
    if (!(d >= 0) || !std::isfinite(d))
      return fail(Status::InvalidOption, "heat geodesic: a source distance is negative or not finite");
  out.setupMs = m.setupMs;
  if (!reportProgress(progress, "field", 0)) return fail(Status::Cancelled, "cancelled");

  // Eq. 6: (V + t K) u = V u0, u0 = 1 at the sources.
  auto t0 = Clock::now();
  const Eigen::Index n = Eigen::Index(m.n);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
  for (uint32_t s : sources) rhs[s] = m.vertexVolume[s];
  Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
  int it = 0;
  if (m.options.heatSolver == HeatSolver::Direct)
    u = m.heatSolver.solve(rhs);
  else
    it = heatSweeps(m.heatMatrix, m.invDiagonal, m.vertexVolume, sources, rhs, u,
                    m.options.heatTolerance, m.options.maxIterations, progress,
                    m.mesh.positions);
  if (it == -1) return fail(Status::Cancelled, "cancelled");
  if (it < 0)
    return fail(Status::Internal, "heat geodesic: the heat solve did not converge in " +
                                      std::to_string(m.options.maxIterations) + " iterations");
  out.heatIterations = it;
  out.heatMs = msSince(t0);

  // Eq. 7-8: normalised per-tet gradients and the integrated divergence b, of a per-vertex field
  // f (g = sign grad f / |grad f|; sign -1 for the renormalisation passes below, whose X is the
  // solved distance's own gradient).
  const size_t T = m.mesh.tetCount();
  auto divergence = [&](const Eigen::VectorXd& f, double sign) {
    Eigen::VectorXd div = Eigen::VectorXd::Zero(n);
    std::vector<Eigen::Vector3d> X(T, Eigen::Vector3d::Zero());
    for (size_t k = 0; k < T; ++k) {
      const uint32_t* t = &m.mesh.tets[4 * k];
      const double* a = &m.areaVectors[12 * k];
      // grad f = sum_c f_c grad(lambda_c), grad(lambda_c) = -S_c n_c / (3 vol) (= Eq. 7).
      Eigen::Vector3d g = Eigen::Vector3d::Zero();
      for (int c = 0; c < 4; ++c) g -= f[t[c]] * Eigen::Vector3d(a[3 * c], a[3 * c + 1], a[3 * c + 2]);
      g *= sign * m.invThreeVolume[k];
      const double len = g.norm();
      if (!(len > 0) || !std::isfinite(len)) continue;  // no heat reached this tet
      X[k] = g / len;
    }
    // HeatGeodesicOptions::alignPasses: each tet's direction becomes the normalised sum of the
    // directions around its four vertices (the heat's X only; the renormalisation passes take
    // phi's own gradient, already smooth).
    if (sign > 0) {
      for (int pass = 0; pass < m.options.alignPasses; ++pass) {
        std::vector<Eigen::Vector3d> vx(n, Eigen::Vector3d::Zero());
        for (size_t k = 0; k < T; ++k)
          for (int c = 0; c < 4; ++c) vx[m.mesh.tets[4 * k + c]] += X[k];
        for (size_t k = 0; k < T; ++k) {
          if (X[k].squaredNorm() == 0) continue;
          Eigen::Vector3d s = Eigen::Vector3d::Zero();
          for (int c = 0; c < 4; ++c) s += vx[m.mesh.tets[4 * k + c]];
          const double l = s.norm();
          if (l > 0) X[k] = s / l;
        }
      }
    }
    for (size_t k = 0; k < T; ++k) {
      if (X[k].squaredNorm() == 0) continue;
      const uint32_t* t = &m.mesh.tets[4 * k];
      const double* a = &m.areaVectors[12 * k];
      const Eigen::Vector3d& g = X[k];
      for (int c = 0; c < 4; ++c)
        div[t[c]] -= (a[3 * c] * g[0] + a[3 * c + 1] * g[1] + a[3 * c + 2] * g[2]) / 3.0;
    }
    return div;
  };
  t0 = Clock::now();
  const Eigen::VectorXd b = divergence(u, 1.0);
  out.gradientMs = msSince(t0);
  if (!reportProgress(progress, "field", 0.5)) return fail(Status::Cancelled, "cancelled");

  // Eq. 9: L_c phi = b, i.e. K phi = -b, with the sources held at distance 0 (Dirichlet rows), and
  // in a component without sources or a vertex in no tet, one vertex held at 0.
  t0 = Clock::now();
  std::vector<uint8_t> fixed(m.n, 0), hasSource(m.n, 0);
  Eigen::VectorXd held = Eigen::VectorXd::Zero(n);
  for (size_t k = 0; k < sources.size(); ++k) {
    fixed[sources[k]] = 1;
    hasSource[m.component[sources[k]]] = 1;
    if (!sourceDistance.empty()) held[sources[k]] = sourceDistance[k];
  }
  for (uint32_t i : m.pinned)
    if (m.vertexVolume[i] <= 0 || !hasSource[m.component[i]]) fixed[i] = 1;
  std::vector<Eigen::Triplet<double>> poisson;
  poisson.reserve(size_t(m.laplacian.nonZeros()) + m.n);
  Eigen::VectorXd rhs2 = -b;
  for (int c = 0; c < m.laplacian.outerSize(); ++c)
    for (SpMat::InnerIterator q(m.laplacian, c); q; ++q) {
      if (fixed[q.row()]) continue;
      if (fixed[q.col()])
        rhs2[q.row()] += q.value() * held[q.col()];  // K_fs held_s moved to the right-hand side
      else
        poisson.emplace_back(q.row(), q.col(), -q.value());
    }
  for (uint32_t i = 0; i < m.n; ++i)
    if (fixed[i]) {
      poisson.emplace_back(i, i, 1.0);
      rhs2[i] = held[i];
    }
  SpMat poissonMatrix(n, n);
  poissonMatrix.setFromTriplets(poisson.begin(), poisson.end());
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::AMDOrdering<int>> poissonPre;
  poissonPre.compute(poissonMatrix);
  if (poissonPre.info() != Eigen::Success)
    return fail(Status::Internal, "heat geodesic: incomplete Cholesky factorisation failed");
  Eigen::VectorXd phi = held;  // the held rows start (and stay) solved
  it = pcg(poissonMatrix, poissonPre, rhs2, phi, m.options.tolerance, m.options.maxIterations,
           progress, 0.5, 1.0);
  if (it == -1) return fail(Status::Cancelled, "cancelled");
  if (it < 0)
    return fail(Status::Internal, "heat geodesic: the Poisson solve did not converge in " +
                                      std::to_string(m.options.maxIterations) + " iterations");
  // Renormalisation passes (HeatGeodesicOptions::renormalizations): X from phi's own gradient
  // (the heat's X is -grad u, growing away from the sources; phi's is +grad phi).
  const Eigen::VectorXd coupling = rhs2 + b;  // the held rows and their couplings
  for (int pass = 0; pass < m.options.renormalizations && it >= 0; ++pass) {
    Eigen::VectorXd rhs3 = coupling - divergence(phi, -1.0);
    for (uint32_t i = 0; i < m.n; ++i)
      if (fixed[i]) rhs3[i] = held[i];
    const int more = pcg(poissonMatrix, poissonPre, rhs3, phi, m.options.tolerance,
                         m.options.maxIterations, progress, 0.5, 1.0);
    if (more == -1) return fail(Status::Cancelled, "cancelled");
    it = more < 0 ? more : it + more;
  }
  if (it < 0)
    return fail(Status::Internal, "heat geodesic: the Poisson solve did not converge in " +
                                      std::to_string(m.options.maxIterations) + " iterations");
  out.poissonIterations = it;
  out.poissonMs = msSince(t0);

  for (size_t i = 0; i < m.n; ++i) {
    if (fixed[i]) phi[Eigen::Index(i)] = held[Eigen::Index(i)];
    if (!hasSource[m.component[i]]) phi[Eigen::Index(i)] = 0;  // no heat reaches it
  }
  out.distance.resize(m.n);
  out.maxDistance = 0;
  for (size_t i = 0; i < m.n; ++i) {
    out.distance[i] = phi[Eigen::Index(i)];
    if (!std::isfinite(out.distance[i]))
      return fail(Status::Internal, "heat geodesic: non-finite distance");
    if (m.vertexVolume[i] > 0) out.maxDistance = std::max(out.maxDistance, out.distance[i]);
  }
  if (!reportProgress(progress, "field", 1.0)) return fail(Status::Cancelled, "cancelled");
  return out;
}

std::vector<uint32_t> platformVertices(const TetMesh& mesh, double tolerance) {
  const size_t n = mesh.vertexCount(), T = mesh.tetCount();
  std::vector<std::array<uint32_t, 3>> faces;
  faces.reserve(T * 4);
  for (size_t k = 0; k < T; ++k) {
    const uint32_t* t = &mesh.tets[4 * k];
    bool valid = true;
    for (int c = 0; c < 4; ++c) valid = valid && t[c] < n;
    if (!valid) continue;
    for (const auto& f : kFace) {
      std::array<uint32_t, 3> key{t[f[0]], t[f[1]], t[f[2]]};
      std::sort(key.begin(), key.end());
      faces.push_back(key);
    }
  }
  std::sort(faces.begin(), faces.end());
  std::vector<uint8_t> boundary(n, 0);
  for (size_t i = 0; i < faces.size();) {
    size_t j = i;
    while (j < faces.size() && faces[j] == faces[i]) ++j;
    if (j - i == 1)
      for (uint32_t v : faces[i]) boundary[v] = 1;
    i = j;
  }
  double minZ = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < n; ++i)
    if (boundary[i]) minZ = std::min(minZ, mesh.positions[3 * i + 2]);
  std::vector<uint32_t> out;
  for (size_t i = 0; i < n; ++i)
    if (boundary[i] && mesh.positions[3 * i + 2] <= minZ + tolerance) out.push_back(uint32_t(i));
  return out;
}

std::vector<double> heightsAboveLowest(const TetMesh& mesh, const std::vector<uint32_t>& vertices) {
  double minZ = std::numeric_limits<double>::infinity();
  for (uint32_t v : vertices) minZ = std::min(minZ, mesh.positions[3 * size_t(v) + 2]);
  std::vector<double> out;
  out.reserve(vertices.size());
  for (uint32_t v : vertices) out.push_back(mesh.positions[3 * size_t(v) + 2] - minZ);
  return out;
}

}  // namespace omnislice
