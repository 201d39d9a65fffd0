// SPDX-License-Identifier: MIT
#include "surface/boundary_distance.h"

#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "common/disjoint_sets.h"
#include "mesh/mesh_topology.h"

namespace omnislice {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

// Eigen's AMDOrdering as SimplicialLDLT uses it, less one step. The solver hands the ordering the
// full symmetric matrix (expanded from the lower triangle, indices sorted in every column), and
// AMDOrdering first forms its pattern plus its transpose's (a transpose and a sparse sum: the
// same pattern again). The minimum degree routine reads only the pattern and reuses the matrix as
// workspace, so it gets the expanded matrix itself: the same permutation (~0.35 s of wasm on the
// voxel bunny 540k).
struct SymmetricAmdOrdering {
  using PermutationType = Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>;
  void operator()(SparseMatrix& symmetric, PermutationType& perm) const {
    Eigen::internal::minimum_degree_ordering(symmetric, perm);
  }
};
using LdltSolver = Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, SymmetricAmdOrdering>;

BoundaryDistance fail(Status s, std::string message) {
  BoundaryDistance r;
  r.status = s;
  r.message = std::move(message);
  return r;
}

// Intrinsic geometry of one triangle from its (mollified) edge lengths: l[i] is the length of the
// edge opposite corner i. The corners are laid out in 2D (p0 at the origin, p1 on +x) so the
// gradient and divergence operators need no extrinsic normal, and a degenerate input triangle
// stays well defined once the lengths satisfy the triangle inequality strictly.
struct IntrinsicTriangle {
  double area = 0;
  double cot[3] = {0, 0, 0};
  Eigen::Vector2d p[3];
};

IntrinsicTriangle layoutTriangle(const double l[3]) {
  IntrinsicTriangle t;
  // Heron's formula in Kahan's stable ordering (a >= b >= c).
  double s[3] = {l[0], l[1], l[2]};
  std::sort(s, s + 3, std::greater<double>());
  const double a = s[0], b = s[1], c = s[2];
  const double q = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  t.area = 0.25 * std::sqrt(std::max(q, 0.0));
  if (t.area <= 0) return t;
  for (int i = 0; i < 3; ++i) {
    const double li = l[i], lj = l[(i + 1) % 3], lk = l[(i + 2) % 3];
    t.cot[i] = (lj * lj + lk * lk - li * li) / (4.0 * t.area);
  }
  t.p[0] = {0, 0};
  t.p[1] = {l[2], 0};
  const double x = (l[1] * l[1] + l[2] * l[2] - l[0] * l[0]) / (2.0 * l[2]);
  t.p[2] = {x, 2.0 * t.area / l[2]};
  return t;
}

}  // namespace

BoundaryDistance boundaryGeodesicDistance(const Mesh& surface, const BoundaryDistanceOptions& options) {
  if (!(options.timeFactor > 0) || !std::isfinite(options.timeFactor)) {
    return fail(Status::InvalidOption, "boundary distance: timeFactor must be finite and > 0");
  }
  if (surface.positions.size() % 3 != 0 || surface.triangles.size() % 3 != 0) {
    return fail(Status::InvalidOption, "boundary distance: positions/triangles not multiples of 3");
  }
  if (surface.triangles.empty()) return fail(Status::EmptyInput, "boundary distance: no triangles");
  for (double x : surface.positions) {
    if (!std::isfinite(x)) return fail(Status::NonFiniteVertex, "boundary distance: non-finite vertex");
  }
  const size_t nv = surface.vertexCount();
  // Faces repeating a vertex carry no area and no edge structure: drop them.
  Mesh mesh;
  mesh.positions = surface.positions;
  mesh.triangles.reserve(surface.triangles.size());
  for (size_t f = 0; f < surface.faceCount(); ++f) {
    const uint32_t a = surface.triangles[3 * f], b = surface.triangles[3 * f + 1],
                   c = surface.triangles[3 * f + 2];
    if (a >= nv || b >= nv || c >= nv) {
      return fail(Status::InvalidOption, "boundary distance: triangle index out of range");
    }
    if (a == b || b == c || a == c) continue;
    mesh.triangles.insert(mesh.triangles.end(), {a, b, c});
  }
  if (mesh.triangles.empty()) {
    return fail(Status::DegenerateInput, "boundary distance: every triangle repeats a vertex");
  }
  const size_t nf = mesh.faceCount();
  const MeshEdges edges = buildEdges(mesh);
  std::vector<uint8_t> onBoundary(nv, 0), referenced(nv, 0);
  std::vector<double> boundaryWeight(nv, 0.0);  // integrated delta of the boundary curve
  double lengthSum = 0;
  for (size_t e = 0; e < edges.edgeCount(); ++e) {
    const uint32_t a = static_cast<uint32_t>(edges.keys[e] >> 32);
    const uint32_t b = static_cast<uint32_t>(edges.keys[e] & 0xFFFFFFFFu);
    const double len = (mesh.vertex(a) - mesh.vertex(b)).norm();
    lengthSum += len;
    if (edges.faceCount[e] > 2) {
      return fail(Status::NonManifoldInput, "boundary distance: edge shared by more than two faces");
    }
    if (edges.faceCount[e] == 1) {
      onBoundary[a] = onBoundary[b] = 1;
      boundaryWeight[a] += 0.5 * len;
      boundaryWeight[b] += 0.5 * len;
    }
  }
  const double h = lengthSum / static_cast<double>(edges.edgeCount());
  if (!(h > 0)) return fail(Status::DegenerateInput, "boundary distance: zero mean edge length");
  for (uint32_t v : mesh.triangles) referenced[v] = 1;

  // Every connected component needs a boundary to measure from (else the Poisson problem has no
  // Dirichlet condition and the distance is undefined).
  {
    DisjointSets uf(nv);
    for (size_t f = 0; f < nf; ++f) {
      uf.unite(mesh.triangles[3 * f], mesh.triangles[3 * f + 1]);
      uf.unite(mesh.triangles[3 * f], mesh.triangles[3 * f + 2]);
    }
    std::vector<uint8_t> hasBoundary(nv, 0);
    for (size_t v = 0; v < nv; ++v) {
      if (onBoundary[v]) hasBoundary[uf.find(static_cast<uint32_t>(v))] = 1;
    }
    for (size_t v = 0; v < nv; ++v) {
      if (referenced[v] && !hasBoundary[uf.find(static_cast<uint32_t>(v))]) {
        return fail(Status::InvalidOption,
                    "boundary distance: the surface (or one of its components) is closed, no boundary "
                    "to measure from");
      }
    }
  }

  // Intrinsic edge lengths, mollified (Sharp & Crane 2020) so every triangle satisfies the triangle
  // inequality by at least eps: slivers and collinear triangles then have finite cotangents.
  std::vector<double> lengths(3 * nf);
  double worst = std::numeric_limits<double>::infinity();
  for (size_t f = 0; f < nf; ++f) {
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = mesh.triangles[3 * f + (i + 1) % 3], b = mesh.triangles[3 * f + (i + 2) % 3];
      lengths[3 * f + i] = (mesh.vertex(a) - mesh.vertex(b)).norm();
    }
    for (int i = 0; i < 3; ++i) {
      worst = std::min(worst, lengths[3 * f + (i + 1) % 3] + lengths[3 * f + (i + 2) % 3] -
                                  lengths[3 * f + i]);
    }
  }
  const double eps = 1e-4 * h;
  if (worst < eps) {
    const double add = eps - worst;
    for (double& l : lengths) l += add;
  }
  std::vector<IntrinsicTriangle> tri(nf);
  for (size_t f = 0; f < nf; ++f) tri[f] = layoutTriangle(&lengths[3 * f]);

  // Unknown numbering: every referenced vertex (Neumann), interior referenced vertices (Dirichlet).
  std::vector<int> fullIndex(nv, -1), interiorIndex(nv, -1);
  int nFull = 0, nInterior = 0;
  for (size_t v = 0; v < nv; ++v) {
    if (!referenced[v]) continue;
    fullIndex[v] = nFull++;
    if (!onBoundary[v]) interiorIndex[v] = nInterior++;
  }
  BoundaryDistance result;
  result.distance.assign(nv, 0.0);
  if (nInterior == 0) return result;  // every vertex is on the boundary: distance 0 everywhere

  // Cotangent Laplacian Lc (positive semi-definite, (Lc u)_i = sum_j w_ij (u_i - u_j)) and lumped
  // mass, on both numberings at once. The solvers read only the lower triangle (SimplicialLDLT
  // with Lower: the ordering, the permuted copy and the factorisation skip the upper entries), so
  // only it is built, in compressed columns directly: per column the diagonal, then one entry per
  // edge to a higher vertex (both numberings increase with the vertex, and the edges come sorted
  // by (min, max) vertex, so rows ascend). Values are summed in the order the triplets were
  // (faces in order, the mass last), starting from -0 (x + -0 == x): the same matrices bit for
  // bit as setFromTriplets gave, without the triplet lists and their sort (set_from_triplets and
  // emplace_back were ~3.5 % of the voxel bunny 540k, native).
  const double t = options.timeFactor * h * h;
  const auto bc = options.boundaryCondition;
  const bool useDirichlet = bc != HeatBoundaryCondition::Neumann;
  const bool useNeumann = bc != HeatBoundaryCondition::Dirichlet;
  const size_t ne = edges.edgeCount();
  SparseMatrix Af(nFull, nFull), Ai(nInterior, nInterior), Li(nInterior, nInterior);
  std::vector<int> edgeFull(ne), edgeInterior(ne, -1);  // value position of each edge's entry
  {
    std::vector<int> fullCount(nFull + 1, 0), interiorCount(nInterior + 1, 0);
    for (size_t v = 0; v < nv; ++v) {
      if (fullIndex[v] >= 0) ++fullCount[fullIndex[v] + 1];
      if (interiorIndex[v] >= 0) ++interiorCount[interiorIndex[v] + 1];
    }
    for (size_t e = 0; e < ne; ++e) {
      const uint32_t a = static_cast<uint32_t>(edges.keys[e] >> 32);
      const uint32_t b = static_cast<uint32_t>(edges.keys[e] & 0xFFFFFFFFu);
      ++fullCount[fullIndex[a] + 1];
      if (interiorIndex[a] >= 0 && interiorIndex[b] >= 0) ++interiorCount[interiorIndex[a] + 1];
    }
    for (int c = 0; c < nFull; ++c) fullCount[c + 1] += fullCount[c];
    for (int c = 0; c < nInterior; ++c) interiorCount[c + 1] += interiorCount[c];
    Af.resizeNonZeros(fullCount[nFull]);
    Ai.resizeNonZeros(interiorCount[nInterior]);
    std::copy(fullCount.begin(), fullCount.end(), Af.outerIndexPtr());
    std::copy(interiorCount.begin(), interiorCount.end(), Ai.outerIndexPtr());
    // Diagonals first (fullCount / interiorCount become each column's fill position).
    for (size_t v = 0; v < nv; ++v) {
      if (fullIndex[v] >= 0) Af.innerIndexPtr()[fullCount[fullIndex[v]]++] = fullIndex[v];
      if (interiorIndex[v] >= 0) Ai.innerIndexPtr()[interiorCount[interiorIndex[v]]++] = interiorIndex[v];
    }
    for (size_t e = 0; e < ne; ++e) {
      const uint32_t a = static_cast<uint32_t>(edges.keys[e] >> 32);
      const uint32_t b = static_cast<uint32_t>(edges.keys[e] & 0xFFFFFFFFu);
      edgeFull[e] = fullCount[fullIndex[a]]++;
      Af.innerIndexPtr()[edgeFull[e]] = fullIndex[b];
      if (interiorIndex[a] >= 0 && interiorIndex[b] >= 0) {
        edgeInterior[e] = interiorCount[interiorIndex[a]]++;
        Ai.innerIndexPtr()[edgeInterior[e]] = interiorIndex[b];
      }
    }
    std::fill(Af.valuePtr(), Af.valuePtr() + Af.nonZeros(), -0.0);
    std::fill(Ai.valuePtr(), Ai.valuePtr() + Ai.nonZeros(), -0.0);
    Li = Ai;  // same pattern, values -0
  }
  // The diagonal of column c is its first entry, at value position outer[c].
  double* const af = Af.valuePtr();
  double* const ai = Ai.valuePtr();
  double* const li = Li.valuePtr();
  const int* const afOuter = Af.outerIndexPtr();
  const int* const aiOuter = Ai.outerIndexPtr();
  std::vector<double> mass(nv, 0.0);
  // Couplings from interior vertices to boundary vertices (u_boundary = 1 for the Dirichlet heat).
  Eigen::VectorXd dirichletRhs = Eigen::VectorXd::Zero(nInterior);
  for (size_t f = 0; f < nf; ++f) {
    const IntrinsicTriangle& T = tri[f];
    for (int v = 0; v < 3; ++v) mass[mesh.triangles[3 * f + v]] += T.area / 3.0;
    for (int i = 0; i < 3; ++i) {
      const uint32_t a = mesh.triangles[3 * f + (i + 1) % 3], b = mesh.triangles[3 * f + (i + 2) % 3];
      const uint32_t e = edges.edgeOfHalfedge[3 * f + (i + 1) % 3];  // the half-edge a -> b
      const double w = 0.5 * T.cot[i];
      if (useNeumann) {
        af[afOuter[fullIndex[a]]] += t * w;
        af[afOuter[fullIndex[b]]] += t * w;
        af[edgeFull[e]] += -t * w;
      }
      const int ia = interiorIndex[a], ib = interiorIndex[b];
      if (ia >= 0) {
        ai[aiOuter[ia]] += t * w;
        li[aiOuter[ia]] += w;
      }
      if (ib >= 0) {
        ai[aiOuter[ib]] += t * w;
        li[aiOuter[ib]] += w;
      }
      if (ia >= 0 && ib >= 0) {
        ai[edgeInterior[e]] += -t * w;
        li[edgeInterior[e]] += -w;
      } else if (ia >= 0) {
        dirichletRhs[ia] += t * w;  // -(-t w) * u_b with u_b = 1
      } else if (ib >= 0) {
        dirichletRhs[ib] += t * w;
      }
    }
  }
  for (size_t v = 0; v < nv; ++v) {
    if (useNeumann && fullIndex[v] >= 0) af[afOuter[fullIndex[v]]] += mass[v];
    if (interiorIndex[v] >= 0) ai[aiOuter[interiorIndex[v]]] += mass[v];
  }

  // Heat flow from the boundary: u(x) decays away from it, its level sets follow the distance.
  std::vector<double> heat(nv, 0.0);
  LdltSolver interiorSolver;
  interiorSolver.analyzePattern(Ai);  // the Poisson matrix below has the same pattern
  if (useDirichlet) {
    interiorSolver.factorize(Ai);
    if (interiorSolver.info() != Eigen::Success) {
      return fail(Status::Internal, "boundary distance: Dirichlet heat factorisation failed");
    }
    const Eigen::VectorXd ui = interiorSolver.solve(dirichletRhs);
    for (size_t v = 0; v < nv; ++v) {
      if (interiorIndex[v] >= 0) heat[v] = ui[interiorIndex[v]];
      else if (onBoundary[v]) heat[v] = 1.0;
    }
  }
  if (useNeumann) {
    LdltSolver fullSolver(Af);
    if (fullSolver.info() != Eigen::Success) {
      return fail(Status::Internal, "boundary distance: Neumann heat factorisation failed");
    }
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nFull);
    for (size_t v = 0; v < nv; ++v) {
      if (fullIndex[v] >= 0) rhs[fullIndex[v]] = boundaryWeight[v];
    }
    const Eigen::VectorXd uf = fullSolver.solve(rhs);
    // Scale so the boundary mean is 1, as for the Dirichlet solution, before averaging.
    double boundaryMean = 0;
    int boundaryCount = 0;
    for (size_t v = 0; v < nv; ++v) {
      if (onBoundary[v] && fullIndex[v] >= 0) {
        boundaryMean += uf[fullIndex[v]];
        ++boundaryCount;
      }
    }
    boundaryMean /= std::max(boundaryCount, 1);
    if (!(boundaryMean > 0)) {
      return fail(Status::Internal, "boundary distance: Neumann heat solution vanished");
    }
    const double weight = useDirichlet ? 0.5 : 1.0;
    for (size_t v = 0; v < nv; ++v) {
      if (fullIndex[v] >= 0) {
        heat[v] = (useDirichlet ? 0.5 * heat[v] : 0.0) + weight * uf[fullIndex[v]] / boundaryMean;
      }
    }
  }

  // Unit field X = -grad u / |grad u| per triangle and its integrated divergence per vertex.
  Eigen::VectorXd divergence = Eigen::VectorXd::Zero(nInterior);
  for (size_t f = 0; f < nf; ++f) {
    const IntrinsicTriangle& T = tri[f];
    if (!(T.area > 0)) continue;
    Eigen::Vector2d grad(0, 0);
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector2d e = T.p[(i + 2) % 3] - T.p[(i + 1) % 3];  // edge opposite i, CCW
      grad += heat[mesh.triangles[3 * f + i]] * Eigen::Vector2d(-e.y(), e.x());
    }
    const double norm = grad.norm();
    if (!(norm > 0) || !std::isfinite(norm)) continue;
    const Eigen::Vector2d X = -grad / norm;
    for (int i = 0; i < 3; ++i) {
      const int ii = interiorIndex[mesh.triangles[3 * f + i]];
      if (ii < 0) continue;
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      divergence[ii] +=
          0.5 * (T.cot[k] * (T.p[j] - T.p[i]).dot(X) + T.cot[j] * (T.p[k] - T.p[i]).dot(X));
    }
  }

  // Poisson: Lc phi = -div X with phi = 0 on the boundary (the Dirichlet pin fixes the constant
  // and makes the distance exactly zero there). Same pattern as the interior heat matrix.
  interiorSolver.factorize(Li);
  if (interiorSolver.info() != Eigen::Success) {
    return fail(Status::Internal, "boundary distance: Laplacian factorisation failed");
  }
  const Eigen::VectorXd phi = interiorSolver.solve(-divergence);
  for (size_t v = 0; v < nv; ++v) {
    if (interiorIndex[v] < 0) continue;
    const double d = phi[interiorIndex[v]];
    if (!std::isfinite(d)) return fail(Status::Internal, "boundary distance: non-finite solution");
    result.distance[v] = d;
    result.maxDistance = std::max(result.maxDistance, d);
  }
  return result;
}

}  // namespace omnislice
