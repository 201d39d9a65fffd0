// SPDX-License-Identifier: MIT
// Heat-method boundary distance against exact distances on flat and developable/curved domains.
#include "surface/boundary_distance.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "surface/surface_test_meshes.h"
#include "test_meshes.h"
#include "test_support.h"

namespace omnislice {
namespace {

using test::boxSdf;

double meanEdgeLength(const Mesh& m) {
  double sum = 0;
  size_t n = 0;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      sum += (m.vertex(m.triangles[3 * f + k]) - m.vertex(m.triangles[3 * f + (k + 1) % 3])).norm();
      ++n;
    }
  }
  return sum / static_cast<double>(n);
}

struct ErrorStats {
  double meanAbs = 0, maxAbs = 0, meanRel = 0, maxRel = 0, h = 0, maxExact = 0;
};

// exact: per-vertex exact distance. Relative errors over vertices farther than 2h from the boundary.
ErrorStats compare(const char* name, const Mesh& m, const std::vector<double>& exact,
                   const BoundaryDistanceOptions& options = {}) {
  const BoundaryDistance d = boundaryGeodesicDistance(m, options);
  EXPECT_TRUE(d.ok()) << d.message;
  ErrorStats s;
  s.h = meanEdgeLength(m);
  if (!d.ok()) return s;
  size_t nRel = 0;
  for (size_t v = 0; v < m.vertexCount(); ++v) {
    const double err = std::abs(d.distance[v] - exact[v]);
    s.meanAbs += err;
    s.maxAbs = std::max(s.maxAbs, err);
    s.maxExact = std::max(s.maxExact, exact[v]);
    if (exact[v] > 2 * s.h) {
      s.meanRel += err / exact[v];
      s.maxRel = std::max(s.maxRel, err / exact[v]);
      ++nRel;
    }
  }
  s.meanAbs /= static_cast<double>(m.vertexCount());
  s.meanRel /= static_cast<double>(std::max<size_t>(nRel, 1));
  std::printf("[heat] %-22s V=%6zu h=%.3f maxDist=%.2f  mean|err|=%.4f (%.3f h)  max|err|=%.4f (%.2f h)  "
              "rel mean=%.4f max=%.3f\n",
              name, m.vertexCount(), s.h, s.maxExact, s.meanAbs, s.meanAbs / s.h, s.maxAbs,
              s.maxAbs / s.h, s.meanRel, s.maxRel);
  return s;
}

std::vector<double> exactToBoundaryPolyline(const Mesh& m) {
  const auto edges = test::boundaryEdges(m);
  std::vector<double> exact(m.vertexCount());
  for (size_t v = 0; v < m.vertexCount(); ++v) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& [a, b] : edges) {
      best = std::min(best, test::pointSegmentDistance(m.vertex(v), m.vertex(a), m.vertex(b)));
    }
    exact[v] = best;
  }
  return exact;
}

// Justified bound: the heat method's smoothing (t = h^2) and first-order gradients give errors of
// order h near the medial axis and much less elsewhere; mean below 0.5 h and max below 3 h
// would both fail for a wrong sign, a wrong scale, a missing boundary pin or a bad divergence.
void expectAccurate(const ErrorStats& s) {
  EXPECT_LT(s.meanAbs, 0.5 * s.h);
  EXPECT_LT(s.maxAbs, 3.0 * s.h);
  EXPECT_LT(s.meanRel, 0.05);
}

// All three heat boundary conditions, each held to the same bound; returns the default's stats.
ErrorStats compareAll(const std::string& name, const Mesh& m, const std::vector<double>& exact) {
  BoundaryDistanceOptions o;
  o.boundaryCondition = HeatBoundaryCondition::Neumann;
  expectAccurate(compare((name + " Neumann").c_str(), m, exact, o));
  o.boundaryCondition = HeatBoundaryCondition::Dirichlet;
  expectAccurate(compare((name + " Dirichlet").c_str(), m, exact, o));
  const ErrorStats s = compare((name + " average").c_str(), m, exact);
  expectAccurate(s);
  return s;
}

TEST(BoundaryDistance, FlatDiscMatchesRadiusMinusR) {
  const double R = 10;
  const Mesh m = test::makeDisc(R, 0.4);
  std::vector<double> exact(m.vertexCount());
  for (size_t v = 0; v < m.vertexCount(); ++v) exact[v] = R - m.vertex(v).head<2>().norm();
  const ErrorStats s = compareAll("disc R10", m, exact);
  // Refinement lowers the worst error (the mean stays near 0.02 mm: with t = h^2 the heat method's
  // smoothing error does not vanish with h, as Crane et al. note).
  const Mesh fine = test::makeDisc(R, 0.2);
  std::vector<double> exactFine(fine.vertexCount());
  for (size_t v = 0; v < fine.vertexCount(); ++v) exactFine[v] = R - fine.vertex(v).head<2>().norm();
  const ErrorStats sf = compare("disc R10 fine", fine, exactFine);
  EXPECT_LT(sf.maxAbs, s.maxAbs);
  EXPECT_LT(sf.meanAbs, 0.5 * sf.h);
}

TEST(BoundaryDistance, FlatRectangleMatchesNearestSide) {
  const double w = 20, hgt = 12;
  const Mesh m = test::makeRectangle(w, hgt, 0.4);
  std::vector<double> exact(m.vertexCount());
  for (size_t v = 0; v < m.vertexCount(); ++v) {
    exact[v] = std::max(0.0, -boxSdf(m.vertex(v).head<2>(), {0, 0}, {w, hgt}));
  }
  compareAll("rectangle 20x12", m, exact);
}

TEST(BoundaryDistance, LShapeMatchesEuclideanDistanceToBoundary) {
  // In a planar domain the nearest boundary point is always visible, so the geodesic distance to
  // the boundary equals the Euclidean distance to the boundary polyline, also at the reflex corner.
  const Mesh m = test::makeLShape(8, 0.4);
  compareAll("L shape a=8", m, exactToBoundaryPolyline(m));
}

TEST(BoundaryDistance, DevelopableCylinderPatchMatchesUnrolledDistance) {
  const double w = 20, hgt = 12, radius = 6;
  auto wrap = [=](const Eigen::Vector2d& p) {
    return Eigen::Vector3d(radius * std::sin(p.x() / radius), p.y(), radius * std::cos(p.x() / radius));
  };
  const Mesh flat = test::makeRectangle(w, hgt, 0.4);
  const Mesh m = test::makeRectangle(w, hgt, 0.4, wrap);
  ASSERT_EQ(flat.vertexCount(), m.vertexCount());
  std::vector<double> exact(m.vertexCount());
  for (size_t v = 0; v < m.vertexCount(); ++v) {
    exact[v] = std::max(0.0, -boxSdf(flat.vertex(v).head<2>(), {0, 0}, {w, hgt}));
  }
  compareAll("cylinder patch r=6", m, exact);
}

TEST(BoundaryDistance, SphericalCapMatchesGeodesicDistanceToRim) {
  const double R = 12, rho = 10;  // the cap spans 48 degrees of polar angle
  const Mesh m = test::makeSphericalCap(R, rho, 0.4);
  std::vector<double> exact(m.vertexCount());
  for (size_t v = 0; v < m.vertexCount(); ++v) {
    const double polar = std::acos(std::clamp(m.vertex(v).z() / R, -1.0, 1.0));
    exact[v] = rho - R * polar;
  }
  compareAll("spherical cap R12", m, exact);
}

TEST(BoundaryDistance, DegenerateTrianglesStayFinite) {
  // A zero-area triangle (three collinear vertices) on the boundary and a face repeating a vertex:
  // the mollified intrinsic lengths keep every cotangent finite.
  Mesh m = test::makeDisc(5, 0.5);
  const auto edges = test::boundaryEdges(m);
  const auto [a, b] = edges.front();
  // Find the triangle on (a, b) and split the edge at its midpoint, keeping a sliver (a, b, mid).
  size_t face = 0;
  int k = 0;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    for (int j = 0; j < 3; ++j) {
      const uint32_t p = m.triangles[3 * f + j], q = m.triangles[3 * f + (j + 1) % 3];
      if ((p == a && q == b) || (p == b && q == a)) {
        face = f;
        k = j;
      }
    }
  }
  const uint32_t p = m.triangles[3 * face + k], q = m.triangles[3 * face + (k + 1) % 3],
                 r = m.triangles[3 * face + (k + 2) % 3];
  const Eigen::Vector3d mid = 0.5 * (m.vertex(p) + m.vertex(q));
  const uint32_t mi = static_cast<uint32_t>(m.vertexCount());
  m.positions.insert(m.positions.end(), {mid.x(), mid.y(), mid.z()});
  m.triangles[3 * face] = p;
  m.triangles[3 * face + 1] = mi;
  m.triangles[3 * face + 2] = r;
  m.triangles.insert(m.triangles.end(), {mi, q, r, q, mi, p, r, r, p});
  const BoundaryDistance d = boundaryGeodesicDistance(m);
  ASSERT_TRUE(d.ok()) << d.message;
  for (size_t v = 0; v < m.vertexCount(); ++v) {
    ASSERT_TRUE(std::isfinite(d.distance[v]));
    EXPECT_NEAR(d.distance[v], 5 - m.vertex(v).head<2>().norm(), 0.5);
  }
}

TEST(BoundaryDistance, InvalidInputsReturnStatus) {
  // Closed surface: no boundary to measure from.
  EXPECT_EQ(boundaryGeodesicDistance(test::makeBox(0, 0, 0, 1, 1, 1)).status, Status::InvalidOption);
  // A disc plus a separate closed box: the closed component has no boundary.
  {
    const Mesh m = test::append(test::makeDisc(3, 0.5), test::makeBox(10, 10, 0, 11, 11, 1));
    EXPECT_EQ(boundaryGeodesicDistance(m).status, Status::InvalidOption);
  }
  EXPECT_EQ(boundaryGeodesicDistance(Mesh{}).status, Status::EmptyInput);
  {
    Mesh m = test::makeDisc(3, 0.5);
    m.positions[4] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(boundaryGeodesicDistance(m).status, Status::NonFiniteVertex);
  }
  {
    Mesh m = test::makeDisc(3, 0.5);
    m.triangles.push_back(static_cast<uint32_t>(m.vertexCount()));
    m.triangles.push_back(0);
    m.triangles.push_back(1);
    EXPECT_EQ(boundaryGeodesicDistance(m).status, Status::InvalidOption);
  }
  {
    BoundaryDistanceOptions o;
    o.timeFactor = 0;
    EXPECT_EQ(boundaryGeodesicDistance(test::makeDisc(3, 0.5), o).status, Status::InvalidOption);
    o.timeFactor = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(boundaryGeodesicDistance(test::makeDisc(3, 0.5), o).status, Status::InvalidOption);
  }
  {
    // Three triangles on one edge.
    Mesh m;
    m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
    m.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    EXPECT_EQ(boundaryGeodesicDistance(m).status, Status::NonManifoldInput);
  }
  {
    Mesh m;
    m.positions = {0, 0, 0, 1, 0, 0};
    m.triangles = {0, 0, 1};
    EXPECT_EQ(boundaryGeodesicDistance(m).status, Status::DegenerateInput);
  }
}

TEST(BoundaryDistance, Timing20kVertices) {
  const Mesh m = test::makeDisc(20, 0.25);
  const auto t0 = std::chrono::steady_clock::now();
  const BoundaryDistance d = boundaryGeodesicDistance(m);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(d.ok()) << d.message;
  std::printf("[heat] %zu vertices: %.1f ms (average BC: 3 factorisations)\n", m.vertexCount(), ms);
  BoundaryDistanceOptions o;
  o.boundaryCondition = HeatBoundaryCondition::Dirichlet;
  const auto t1 = std::chrono::steady_clock::now();
  ASSERT_TRUE(boundaryGeodesicDistance(m, o).ok());
  std::printf("[heat] %zu vertices: %.1f ms (Dirichlet BC: 2 factorisations, one analysis)\n",
              m.vertexCount(),
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count());
  EXPECT_NEAR(d.maxDistance, 20, 0.5);
}

}  // namespace
}  // namespace omnislice
