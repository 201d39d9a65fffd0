// SPDX-License-Identifier: MIT
// Iso-planar NL curves (Algorithm 2): straight, exactly spaced curves on a flat square; adaptive
// spacing on a saddle within the width criterion (no gaps, no overlap); points on the surface,
// chord error bounded; coverage; several components and closed loops per plane; the number of
// planes against the extent along q over a theta sweep; the printing-time estimate; bad input.
#include "isoplanar/isoplanar_paths.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <algorithm>
#include <functional>
#include <map>
#include <limits>
#include <random>

#include "isoplanar/effective_width.h"
#include "isoplanar/surface_samples.h"
#include "surface/surface_test_meshes.h"
#include "test_support.h"

namespace omnislice {
namespace {

using test::pointSegmentDistance;

// Per-point analytic geometry: unit normal and the shape tensor (normal curvature along a unit
// tangent t is t^T T t, > 0 convex).
using GeometryFn = std::function<void(const Eigen::Vector3d& p, Eigen::Vector3d& n, Eigen::Matrix3d& T)>;

std::vector<SurfaceSample> analyticSamples(const Mesh& m, const GeometryFn& fn, double height) {
  std::vector<SurfaceSample> out(m.vertexCount());
  for (size_t v = 0; v < m.vertexCount(); ++v) {
    Eigen::Vector3d n;
    Eigen::Matrix3d T;
    fn(m.vertex(v), n, T);
    SurfaceSample& s = out[v];
    s.position = m.vertex(v);
    s.normal = n.normalized();
    const Eigen::Vector3d helper = std::abs(s.normal.x()) < 0.9 ? Eigen::Vector3d::UnitX()
                                                                : Eigen::Vector3d::UnitY();
    s.tangentU = (helper - helper.dot(s.normal) * s.normal).normalized();
    s.tangentV = s.normal.cross(s.tangentU);
    Eigen::Matrix<double, 3, 2> B;
    B.col(0) = s.tangentU;
    B.col(1) = s.tangentV;
    s.shape = B.transpose() * T * B;
    s.height = height;
  }
  return out;
}

// Height field z = g(x, y) with gradient and Hessian: n = (-gx, -gy, 1) / W, kappa along a unit
// tangent t = -(t_xy^T H t_xy) / W.
struct HeightField {
  std::function<double(double, double)> g;
  std::function<void(double, double, double&, double&, double&, double&, double&)> derivatives;
};

GeometryFn heightFieldGeometry(const HeightField& hf) {
  return [hf](const Eigen::Vector3d& p, Eigen::Vector3d& n, Eigen::Matrix3d& T) {
    double gx, gy, gxx, gxy, gyy;
    hf.derivatives(p.x(), p.y(), gx, gy, gxx, gxy, gyy);
    const double W = std::sqrt(1 + gx * gx + gy * gy);
    n = Eigen::Vector3d(-gx, -gy, 1) / W;
    T.setZero();
    T(0, 0) = -gxx / W;
    T(0, 1) = T(1, 0) = -gxy / W;
    T(1, 1) = -gyy / W;
  };
}

HeightField saddleField(double R) {
  HeightField hf;
  hf.g = [R](double x, double y) { return (x * x - y * y) / R; };
  hf.derivatives = [R](double x, double y, double& gx, double& gy, double& gxx, double& gxy, double& gyy) {
    gx = 2 * x / R;
    gy = -2 * y / R;
    gxx = 2 / R;
    gxy = 0;
    gyy = -2 / R;
  };
  return hf;
}

// Regular grid over [-half, half]^2 with n x n vertices, alternating diagonals, mapped by g.
Mesh gridMesh(double half, int n, const std::function<double(double, double)>& g) {
  Mesh m;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double x = -half + 2 * half * i / (n - 1), y = -half + 2 * half * j / (n - 1);
      m.positions.insert(m.positions.end(), {x, y, g ? g(x, y) : 0.0});
    }
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      if ((i + j) % 2 == 0) {
        m.triangles.insert(m.triangles.end(), {a, b, d, a, d, c});
      } else {
        m.triangles.insert(m.triangles.end(), {a, b, c, b, d, c});
      }
    }
  }
  return m;
}

GeometryFn flatGeometry() {
  return [](const Eigen::Vector3d&, Eigen::Vector3d& n, Eigen::Matrix3d& T) {
    n = Eigen::Vector3d::UnitZ();
    T.setZero();
  };
}

// Closed form of the equilibrium spacing on a circle of curvature kappa (the bead area over the
// arc spacing at mid-height): a = pi s / (4 (1 - kappa h / 2)).
WidthFn closedFormWidth(double s) {
  return [s](double kappa, double h) { return M_PI * s / (4 * (1 - kappa * h / 2)); };
}

// Samples of the surface by the real fit (surface_samples.h).
std::vector<SurfaceSample> fittedSamples(const Mesh& m, double h) {
  SurfaceSamplesResult r = surfaceSamples(m, h);
  EXPECT_TRUE(r.ok()) << r.message;
  return std::move(r.samples);
}

double distanceToPolyline(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& poly) {
  double d = std::numeric_limits<double>::infinity();
  if (poly.size() == 1) return (p - poly[0]).norm();
  for (size_t i = 0; i + 1 < poly.size(); ++i) d = std::min(d, pointSegmentDistance(p, poly[i], poly[i + 1]));
  return d;
}

Eigen::Vector3d driveNormal(double thetaDegrees) {
  const double t = thetaDegrees * M_PI / 180;
  return {-std::sin(t), std::cos(t), 0};
}

// Independent cut of the mesh by the plane q.x = c: the crossing points of edges whose ends lie
// strictly on opposite sides.
std::vector<Eigen::Vector3d> rawCrossings(const Mesh& m, const Eigen::Vector3d& q, double c) {
  std::vector<Eigen::Vector3d> out;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = m.vertex(m.triangles[3 * f + k]);
      const Eigen::Vector3d b = m.vertex(m.triangles[3 * f + (k + 1) % 3]);
      const double da = q.dot(a) - c, db = q.dot(b) - c;
      if ((da < 0 && db > 0) || (da > 0 && db < 0)) out.push_back(a + da / (da - db) * (b - a));
    }
  }
  return out;
}

// Curves grouped by plane, planes in sweep order (the print order follows chains, so a plane's
// curves need not be contiguous), each plane's curves in print order.
std::vector<std::vector<size_t>> byPlane(const IsoplanarResult& r) {
  std::map<double, std::vector<size_t>> planes;
  for (size_t i = 0; i < r.curves.size(); ++i) planes[r.curves[i].plane].push_back(i);
  std::vector<std::vector<size_t>> out;
  for (auto& [c, v] : planes) out.push_back(std::move(v));
  // Sweep order: by the plane offsets (the sweep goes from low to high q.x).
  return out;
}

void expectPointsOnMesh(const Mesh& m, const IsoplanarResult& r, const Eigen::Vector3d& q) {
  for (const NlCurve& c : r.curves) {
    ASSERT_EQ(c.points.size(), c.normals.size());
    ASSERT_EQ(c.points.size(), c.edgeA.size());
    ASSERT_EQ(c.points.size(), c.edgeB.size());
    ASSERT_EQ(c.points.size(), c.edgeT.size());
    ASSERT_EQ(c.points.size(), c.width.size());
    for (size_t i = 0; i < c.points.size(); ++i) {
      const Eigen::Vector3d onEdge =
          (1 - c.edgeT[i]) * m.vertex(c.edgeA[i]) + c.edgeT[i] * m.vertex(c.edgeB[i]);
      EXPECT_LT((onEdge - c.points[i]).norm(), 1e-5) << "point not on its mesh edge";
      EXPECT_NEAR(q.dot(c.points[i]), c.plane, 1e-9) << "point not on its drive plane";
      EXPECT_NEAR(c.normals[i].norm(), 1.0, 1e-12);
      EXPECT_GT(c.width[i], 0);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Flat square, constant width: straight curves parallel to the drive plane, spaced exactly the
// side step, the first and last half a step from the boundary, alternating directions, joined
// along the boundary into one path, total length = area / step (+ joins).
TEST(IsoplanarPaths, FlatSquareConstantWidth) {
  const Mesh m = gridMesh(10, 41, nullptr);
  const auto samples = analyticSamples(m, flatGeometry(), 0.5);
  const double w = 0.8;
  const WidthFn width = [w](double, double) { return w; };
  IsoplanarOptions o;
  o.thetaDegrees = 0;
  const IsoplanarResult r = isoplanarPaths(m, samples, width, o);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_EQ(r.planes, 25u);  // (20 - 0.8) / 0.8 + 1
  ASSERT_EQ(r.curves.size(), 25u);
  EXPECT_NEAR(r.curves.front().plane, -10 + w / 2, 1e-12);
  EXPECT_NEAR(r.curves.back().plane, 10 - w / 2, 1e-12);
  double curveLength = 0;
  for (size_t i = 0; i < r.curves.size(); ++i) {
    const NlCurve& c = r.curves[i];
    ASSERT_EQ(c.points.size(), 2u) << "a straight cut keeps only its ends";
    EXPECT_FALSE(c.closed);
    for (const Eigen::Vector3d& p : c.points) {
      EXPECT_NEAR(p.y(), c.plane, 1e-12);
      EXPECT_NEAR(std::abs(p.x()), 10, 1e-12) << "ends on the boundary";
    }
    // Zig-zag: +x on even planes, -x on odd ones.
    EXPECT_EQ(c.points.back().x() > c.points.front().x(), i % 2 == 0) << "curve " << i;
    if (i + 1 < r.curves.size()) {
      EXPECT_NEAR(c.sideStep, w, 1e-12);
      EXPECT_NEAR(r.curves[i + 1].plane - c.plane, c.sideStep, 1e-12);
    } else {
      EXPECT_EQ(c.sideStep, 0);
    }
    curveLength += (c.points.back() - c.points.front()).norm();
  }
  EXPECT_NEAR(curveLength, 25 * 20, 1e-9);
  EXPECT_NEAR(curveLength * w / 400, 1.0, 0.05) << "length ~ area / step";
  EXPECT_NEAR(r.minSideStep, w, 1e-12);
  EXPECT_NEAR(r.maxSideStep, w, 1e-12);
  ASSERT_EQ(r.paths.size(), 1u) << "every turn is a join along the boundary";
  ASSERT_EQ(r.joins.size(), 24u);
  for (const IsoplanarJoin& j : r.joins) EXPECT_NEAR(j.length, w, 1e-12);
  EXPECT_NEAR(r.pathMm, 25 * 20 + 24 * w, 1e-9);
  size_t joinInterior = 0;
  for (const IsoplanarJoin& j : r.joins) joinInterior += j.points.size() - 2;
  EXPECT_EQ(r.paths[0].points.size(), 50u + joinInterior);
  ASSERT_EQ(r.pathCurves[0].size(), 25u);
  expectPointsOnMesh(m, r, driveNormal(0));
}

// Non-integer number of steps: the last plane sits half a step before the far extreme and the
// offset to it is shortened; the others are the full step.
TEST(IsoplanarPaths, FlatSquareLastPlaneHalfStepInside) {
  const Mesh m = gridMesh(10, 21, nullptr);
  const auto samples = analyticSamples(m, flatGeometry(), 0.5);
  const double w = 0.7;
  IsoplanarOptions o;
  o.thetaDegrees = 90;  // q = (-1, 0, 0): planes x = const, c = -x
  const IsoplanarResult r = isoplanarPaths(m, samples, [w](double, double) { return w; }, o);
  ASSERT_TRUE(r.ok()) << r.message;
  const size_t expected = static_cast<size_t>(std::ceil((20 - w) / w)) + 1;
  ASSERT_EQ(r.planes, expected);
  EXPECT_NEAR(r.curves.front().plane, -10 + w / 2, 1e-12);
  EXPECT_NEAR(r.curves.back().plane, 10 - w / 2, 1e-12);
  for (size_t i = 0; i + 2 < r.curves.size(); ++i) EXPECT_NEAR(r.curves[i].sideStep, w, 1e-12);
  EXPECT_LE(r.curves[r.curves.size() - 2].sideStep, w + 1e-12);
  EXPECT_GT(r.curves[r.curves.size() - 2].sideStep, 0);
  // The range of side steps leaves the shortened last offset out.
  EXPECT_NEAR(r.minSideStep, w, 1e-12);
  EXPECT_NEAR(r.maxSideStep, w, 1e-12);
  expectPointsOnMesh(m, r, driveNormal(90));
}

// Degenerate: every drive plane passes exactly through a row of grid vertices (w = 1 on a 0.5
// grid starting at -10). The vertex counts as above the plane, so each plane still gives one
// simple straight curve ending at boundary vertices (edgeA == edgeB there).
TEST(IsoplanarPaths, FlatSquarePlanesThroughVertices) {
  const Mesh m = gridMesh(10, 41, nullptr);
  const auto samples = analyticSamples(m, flatGeometry(), 0.5);
  IsoplanarOptions o;
  o.thetaDegrees = 0;
  const IsoplanarResult r = isoplanarPaths(m, samples, [](double, double) { return 1.0; }, o);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_EQ(r.planes, 20u);
  ASSERT_EQ(r.curves.size(), 20u);
  for (const NlCurve& c : r.curves) {
    ASSERT_EQ(c.points.size(), 2u);
    EXPECT_NEAR(std::abs(c.points.front().x() - c.points.back().x()), 20, 1e-12);
    EXPECT_EQ(c.edgeA.front(), c.edgeB.front());
    EXPECT_EQ(c.edgeA.back(), c.edgeB.back());
  }
  EXPECT_EQ(r.paths.size(), 1u);
  expectPointsOnMesh(m, r, driveNormal(0));
}

// Tilt correction of Eq. 14 (header): on a plane sloping across the curves (z = 3 x, planes
// x = const), the plane offset is w |k.q| and the curves lie exactly w apart on the surface;
// with the floor minCross above |k.q| they lie w minCross / |k.q| apart.
TEST(IsoplanarPaths, TiltedPlaneSpacingIsTheWidthOnTheSurface) {
  const double slope = 3;
  const Mesh m = gridMesh(5, 21, [slope](double x, double) { return slope * x; });
  const auto samples = analyticSamples(
      m,
      [slope](const Eigen::Vector3d&, Eigen::Vector3d& n, Eigen::Matrix3d& T) {
        n = Eigen::Vector3d(-slope, 0, 1).normalized();
        T.setZero();
      },
      0.5);
  const double w = 0.8, kq = 1 / std::sqrt(1 + slope * slope);
  for (double minCross : {0.2, 0.5}) {
    IsoplanarOptions o;
    o.thetaDegrees = 90;
    o.minCross = minCross;
    const IsoplanarResult r = isoplanarPaths(m, samples, [w](double, double) { return w; }, o);
    ASSERT_TRUE(r.ok()) << r.message;
    const double offset = w * std::max(kq, minCross);
    for (size_t i = 0; i + 2 < r.curves.size(); ++i) {
      EXPECT_NEAR(r.curves[i].sideStep, offset, 1e-12);
      for (const Eigen::Vector3d& p : r.curves[i + 1].points) {
        EXPECT_NEAR(distanceToPolyline(p, r.curves[i].points), offset / kq, 1e-9);
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Saddle z = (x^2 - y^2) / R with the closed-form width: adjacent curves within the criterion.
TEST(IsoplanarPaths, SaddleSpacingWithinWidthCriterion) {
  const double R = 30, half = 15, s = 1, h = 0.5;
  const HeightField hf = saddleField(R);
  const Mesh m = makeSaddleSurface(R, half, 61 * 61);
  const auto samples = fittedSamples(m, h);
  // The closed form and the real cusp-area width (table).
  const WidthFn closedForm = closedFormWidth(s);
  const WidthFn table = EffectiveWidthTable(s, 0.2, 0.8).function();
  for (double theta : {0.0, 30.0, 158.0}) {
   for (const WidthFn* widthPtr : {&closedForm, &table}) {
    const WidthFn& width = *widthPtr;
    IsoplanarOptions o;
    o.thetaDegrees = theta;
    o.chordError = 0.02;
    const IsoplanarResult r = isoplanarPaths(m, samples, width, o);
    ASSERT_TRUE(r.ok()) << r.message;
    const Eigen::Vector3d q = driveNormal(theta);
    expectPointsOnMesh(m, r, q);
    const auto planes = byPlane(r);
    ASSERT_EQ(planes.size(), r.planes);
    ASSERT_GT(planes.size(), 10u);
    // Normals agree with the analytic ones (blended vertex normals).
    for (const NlCurve& c : r.curves) {
      for (size_t i = 0; i < c.points.size(); ++i) {
        Eigen::Vector3d n;
        Eigen::Matrix3d T;
        heightFieldGeometry(hf)(c.points[i], n, T);
        EXPECT_GT(c.normals[i].dot(n), 0.998);
      }
    }
    // tol = 0.1: the width varies by the curvature between the curves, the polyline is within
    // chordError of the cut.
    const double tol = 0.1;
    size_t checked = 0;
    double worstLow = 1e9, worstHigh = 0;
    for (size_t j = 0; j + 1 < planes.size(); ++j) {
      ASSERT_EQ(planes[j].size(), 1u) << "one component per plane on the saddle";
      const NlCurve& a = r.curves[planes[j][0]];
      const NlCurve& b = r.curves[planes[j + 1][0]];
      // The side step is the min over the curve of w_eff |k.q| (recomputed from the analytic
      // normals): exactly the plane offset except for the shortened last one.
      double minStep = 1e9;
      for (size_t i = 0; i < a.points.size(); ++i) {
        Eigen::Vector3d n;
        Eigen::Matrix3d T;
        heightFieldGeometry(hf)(a.points[i], n, T);
        minStep = std::min(minStep, a.width[i] * std::max(n.cross(q).norm(), o.minCross));
      }
      if (j + 2 < planes.size()) {
        EXPECT_NEAR(a.sideStep, minStep, 0.02 * minStep);
      }
      for (size_t i = 0; i < b.points.size(); ++i) {
        const Eigen::Vector3d& p = b.points[i];
        if (std::abs(p.x()) > half - 3 || std::abs(p.y()) > half - 3) continue;
        const double d = distanceToPolyline(p, a.points);
        EXPECT_GE(d, (1 - 1e-9) * a.sideStep) << "overlap beyond the criterion";
        EXPECT_LE(d, (1 + tol) * b.width[i] + o.chordError) << "gap beyond the width";
        worstLow = std::min(worstLow, d / a.sideStep);
        worstHigh = std::max(worstHigh, d / b.width[i]);
        ++checked;
      }
    }
    EXPECT_GT(checked, 100u);
    std::printf("saddle theta %.0f: planes %zu, side step [%.3f, %.3f], d/step >= %.3f, d/w <= %.3f\n",
                theta, r.planes, r.minSideStep, r.maxSideStep, worstLow, worstHigh);
    // On a tilted surface the plane offset is below the width (|k.q| < 1).
    EXPECT_LT(r.minSideStep, 0.95 * M_PI * s / 4);
   }
  }
}

// Chord error: every crossing of the plane with the mesh (an independent cut) lies within
// delta_c of the kept polyline; crossings are dropped (fewer points than crossings); no kept
// segment spanning dropped crossings is longer than l_f of Eq. 12 at its start.
TEST(IsoplanarPaths, SaddleChordErrorAndForwardStep) {
  const double R = 20, half = 15;
  const HeightField hf = saddleField(R);
  const Mesh m = makeSaddleSurface(R, half, 61 * 61);
  const auto samples = fittedSamples(m, 0.5);
  for (double dc : {0.5, 0.05}) {
    IsoplanarOptions o;
    o.thetaDegrees = 30;
    o.chordError = dc;
    const IsoplanarResult r = isoplanarPaths(m, samples, closedFormWidth(1), o);
    ASSERT_TRUE(r.ok()) << r.message;
    const Eigen::Vector3d q = driveNormal(30);
    size_t kept = 0, raw = 0;
    double worst = 0;
    for (size_t ci = 0; ci < r.curves.size(); ci += 3) {
      const NlCurve& c = r.curves[ci];
      const auto crossings = rawCrossings(m, q, c.plane);
      raw += crossings.size() / 2 + 1;  // each interior crossing is seen from two triangles
      kept += c.points.size();
      for (const Eigen::Vector3d& p : crossings) {
        const double d = distanceToPolyline(p, c.points);
        worst = std::max(worst, d);
        EXPECT_LE(d, dc + 1e-9) << "dropped crossing farther than delta_c from its chord";
      }
      // l_f of Eq. 12 at a point (analytic normal curvature along the section).
      auto forwardStep = [&](const Eigen::Vector3d& p) {
        Eigen::Vector3d n;
        Eigen::Matrix3d T;
        heightFieldGeometry(hf)(p, n, T);
        const Eigen::Vector3d f = n.cross(q).normalized();
        const double kf = std::abs(f.dot(T * f));
        return kf > 1e-12 ? std::sqrt(std::max(0.0, 8 * dc / kf - 4 * dc * dc)) : 1e9;
      };
      for (size_t i = 0; i + 1 < c.points.size(); ++i) {
        // The curve may be printed reversed: the step was taken from one of the two ends.
        const double lf = std::max(forwardStep(c.points[i]), forwardStep(c.points[i + 1]));
        const double len = (c.points[i + 1] - c.points[i]).norm();
        EXPECT_LE(len, std::max(1.05 * lf, 1.5)) << "forward step beyond Eq. 12";
      }
    }
    std::printf("chord %.2f: kept %zu of %zu crossings, worst deviation %.4f\n", dc, kept, raw, worst);
    EXPECT_LT(kept, raw / 2) << "intermediate crossings are dropped";
  }
}

// Coverage: every vertex farther than w_eff from the boundary is within 0.6 w_eff of a curve.
TEST(IsoplanarPaths, SaddleCoverage) {
  const double R = 30, half = 15;
  const Mesh m = makeSaddleSurface(R, half, 61 * 61);
  const auto samples = fittedSamples(m, 0.5);
  const WidthFn width = EffectiveWidthTable(1, 0.2, 0.8).function();
  for (double theta : {0.0, 45.0, 120.0}) {
    IsoplanarOptions o;
    o.thetaDegrees = theta;
    o.chordError = 0.05;
    const IsoplanarResult r = isoplanarPaths(m, samples, width, o);
    ASSERT_TRUE(r.ok()) << r.message;
    std::mt19937 rng(7);
    size_t checked = 0;
    for (int k = 0; k < 600; ++k) {
      const size_t v = rng() % m.vertexCount();
      const Eigen::Vector3d p = m.vertex(v);
      const double w = width(0, 0.5) * 1.1;
      if (std::abs(p.x()) > half - 1.5 * w || std::abs(p.y()) > half - 1.5 * w) continue;
      double d = 1e9;
      for (const NlCurve& c : r.curves) d = std::min(d, distanceToPolyline(p, c.points));
      EXPECT_LE(d, 0.6 * width(0, 0.5)) << "vertex " << v << " uncovered at theta " << theta;
      ++checked;
    }
    EXPECT_GT(checked, 300u);
  }
}

// The bicycle-seat surface (pear outline, convex across) with the real samples and width:
// points on the mesh, adjacent curves within the width criterion away from the boundary, and
// coverage of the vertices farther than w_eff from the boundary.
TEST(IsoplanarPaths, SeatSpacingAndCoverage) {
  const Mesh m = makeSeatSurface(110, 8000);
  ASSERT_FALSE(m.empty());
  const auto samples = fittedSamples(m, 0.5);
  const WidthFn width = EffectiveWidthTable(1, 0.2, 0.8).function();
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boundary;
  for (const auto& e : test::boundaryEdges(m)) boundary.emplace_back(m.vertex(e.first), m.vertex(e.second));
  auto boundaryDistance = [&](const Eigen::Vector3d& p) {
    double d = 1e9;
    for (const auto& b : boundary) d = std::min(d, pointSegmentDistance(p, b.first, b.second));
    return d;
  };
  for (double theta : {39.0, 90.0}) {
    IsoplanarOptions o;
    o.thetaDegrees = theta;
    o.chordError = 0.05;
    const IsoplanarResult r = isoplanarPaths(m, samples, width, o);
    ASSERT_TRUE(r.ok()) << r.message;
    expectPointsOnMesh(m, r, driveNormal(theta));
    const auto planes = byPlane(r);
    size_t checked = 0;
    for (size_t j = 0; j + 1 < planes.size(); ++j) {
      std::vector<const NlCurve*> prev;
      for (size_t i : planes[j]) prev.push_back(&r.curves[i]);
      for (size_t i : planes[j + 1]) {
        const NlCurve& b = r.curves[i];
        for (size_t k = 0; k < b.points.size(); ++k) {
          if (boundaryDistance(b.points[k]) < 4) continue;
          double d = 1e9;
          for (const NlCurve* a : prev) d = std::min(d, distanceToPolyline(b.points[k], a->points));
          EXPECT_GE(d, (1 - 1e-9) * prev[0]->sideStep);
          EXPECT_LE(d, 1.1 * b.width[k] + o.chordError) << "gap at plane " << j + 1;
          ++checked;
        }
      }
    }
    EXPECT_GT(checked, 200u);
    size_t covered = 0;
    for (size_t v = 0; v < m.vertexCount(); v += 13) {
      const Eigen::Vector3d p = m.vertex(v);
      if (boundaryDistance(p) < 1.2 * width(0, 0.5)) continue;
      double d = 1e9;
      for (const NlCurve& c : r.curves) d = std::min(d, distanceToPolyline(p, c.points));
      EXPECT_LE(d, 0.6 * width(0, 0.5)) << "vertex " << v;
      ++covered;
    }
    EXPECT_GT(covered, 200u);
    std::printf("seat theta %.0f: planes %zu, curves %zu, paths %zu, side step [%.3f, %.3f]\n", theta,
                r.planes, r.curves.size(), r.paths.size(), r.minSideStep, r.maxSideStep);
  }
}

// ---------------------------------------------------------------------------------------------
// Several components per plane: a U shape (planes across both arms) and an annulus.
TEST(IsoplanarPaths, UShapeTwoComponentsPerPlane) {
  // U: [0, 30] x [0, 20] minus [10, 20] x [5, 21]; planes y = c cross both arms above y = 5.
  const Mesh m = test::meshImplicit2D(
      [](const Eigen::Vector2d& p) {
        return std::max(test::boxSdf(p, {0, 0}, {30, 20}), -test::boxSdf(p, {10, 5}, {20, 21}));
      },
      Eigen::Vector2d(-0.5, -0.5), Eigen::Vector2d(30.5, 20.5), 0.5);
  const auto samples = analyticSamples(m, flatGeometry(), 0.5);
  const double w = 0.8;
  IsoplanarOptions o;
  o.thetaDegrees = 0;
  const IsoplanarResult r = isoplanarPaths(m, samples, [w](double, double) { return w; }, o);
  ASSERT_TRUE(r.ok()) << r.message;
  const auto planes = byPlane(r);
  ASSERT_EQ(planes.size(), r.planes);
  size_t two = 0;
  for (const auto& pc : planes) {
    const double y = r.curves[pc[0]].plane;
    const size_t expected = y > 5 + 1e-6 ? 2 : 1;
    ASSERT_EQ(pc.size(), expected) << "plane y = " << y;
    if (expected == 2) {
      ++two;
      for (size_t i : pc) {
        const NlCurve& c = r.curves[i];
        const double x0 = std::min(c.points.front().x(), c.points.back().x());
        const double x1 = std::max(c.points.front().x(), c.points.back().x());
        EXPECT_TRUE((std::abs(x0) < 1e-9 && std::abs(x1 - 10) < 1e-9) ||
                    (std::abs(x0 - 20) < 1e-9 && std::abs(x1 - 30) < 1e-9))
            << "arm [" << x0 << ", " << x1 << "]";
      }
    }
  }
  EXPECT_GT(two, 10u);
  // Boustrophedon chains: the base and one arm form one zig-zag, the other arm another; inside
  // a path consecutive curves are on adjacent planes, alternate directions and are joined by a
  // short walk along the boundary.
  EXPECT_EQ(r.paths.size(), 2u);
  size_t inPaths = 0;
  for (size_t p = 0; p < r.pathCurves.size(); ++p) {
    const auto& pc = r.pathCurves[p];
    inPaths += pc.size();
    ASSERT_EQ(r.pathJoins[p].size() + 1, pc.size());
    for (size_t k = 0; k + 1 < pc.size(); ++k) {
      const NlCurve& a = r.curves[pc[k]];
      const NlCurve& b = r.curves[pc[k + 1]];
      EXPECT_NEAR(b.plane - a.plane, a.sideStep, 1e-12);
      EXPECT_NE(a.points.back().x() > a.points.front().x(), b.points.back().x() > b.points.front().x());
      const IsoplanarJoin& j = r.joins[r.pathJoins[p][k]];
      EXPECT_EQ(j.fromCurve, pc[k]);
      EXPECT_EQ(j.toCurve, pc[k + 1]);
      EXPECT_LE(j.length, o.connectFactor * w + 1e-9);
      EXPECT_EQ(j.points.front(), a.points.back());
      EXPECT_EQ(j.points.back(), b.points.front());
    }
  }
  EXPECT_EQ(inPaths, r.curves.size());
  expectPointsOnMesh(m, r, driveNormal(0));
}

TEST(IsoplanarPaths, AnnulusComponentsAndCoverage) {
  const double r0 = 4, r1 = 10;
  const Mesh m = test::makeAnnulus(r0, r1, 0.4);
  const auto samples = analyticSamples(m, flatGeometry(), 0.5);
  const double w = 0.6;
  IsoplanarOptions o;
  o.thetaDegrees = 25;
  const IsoplanarResult r = isoplanarPaths(m, samples, [w](double, double) { return w; }, o);
  ASSERT_TRUE(r.ok()) << r.message;
  const auto planes = byPlane(r);
  for (const auto& pc : planes) {
    const double c = r.curves[pc[0]].plane;
    // The boundary is polygonal (mesh spacing 0.4): skip planes grazing the hole.
    if (std::abs(std::abs(c) - r0) < 0.1) continue;
    EXPECT_EQ(pc.size(), std::abs(c) < r0 ? 2u : 1u) << "plane " << c;
  }
  for (size_t v = 0; v < m.vertexCount(); v += 7) {
    const Eigen::Vector3d p = m.vertex(v);
    const double rho = std::hypot(p.x(), p.y());
    if (rho < r0 + w || rho > r1 - w) continue;
    double d = 1e9;
    for (const NlCurve& c : r.curves) d = std::min(d, distanceToPolyline(p, c.points));
    EXPECT_LE(d, 0.6 * w);
  }
  // Chains: the part below the hole continues up one side and over the top; the other side is
  // a second chain (and polygonal-boundary corners may break one more).
  std::printf("annulus: planes %zu, curves %zu, paths %zu\n", r.planes, r.curves.size(), r.paths.size());
  EXPECT_LE(r.paths.size(), 4u);
  expectPointsOnMesh(m, r, driveNormal(25));
}

// Closed loops: a cylinder band (axis y) cut by planes y = c gives circles.
TEST(IsoplanarPaths, CylinderBandClosedLoops) {
  const double R = 10, L = 8;
  const int na = 120, ny = 17;
  Mesh m;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < na; ++i) {
      const double phi = 2 * M_PI * i / na, y = L * j / (ny - 1);
      m.positions.insert(m.positions.end(), {R * std::sin(phi), y, R * std::cos(phi)});
    }
  }
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i < na; ++i) {
      const uint32_t a = j * na + i, b = j * na + (i + 1) % na, c = a + na, d = b + na;
      m.triangles.insert(m.triangles.end(), {a, c, b, b, c, d});
    }
  }
  const auto samples = analyticSamples(
      m,
      [R](const Eigen::Vector3d& p, Eigen::Vector3d& n, Eigen::Matrix3d& T) {
        n = Eigen::Vector3d(p.x(), 0, p.z()).normalized();
        T = (Eigen::Matrix3d::Identity() - n * n.transpose() -
             Eigen::Vector3d::UnitY() * Eigen::Vector3d::UnitY().transpose()) / R;
      },
      0.5);
  IsoplanarOptions o;
  o.thetaDegrees = 0;
  o.chordError = 0.05;
  const IsoplanarResult r = isoplanarPaths(m, samples, closedFormWidth(1), o);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.closedCurves, r.curves.size());
  EXPECT_EQ(r.curves.size(), r.planes);
  // Across a circle cut k is along the axis (flat): w = pi s / 4.
  EXPECT_NEAR(r.curves.front().plane, M_PI / 8, 1e-9);
  const double polygon = 2 * na * R * std::sin(M_PI / na);
  // Chords with sagitta up to delta_c on the circle: half-angle alpha, length ratio sin a / a.
  const double alpha = std::acos(1 - o.chordError / R);
  for (const NlCurve& c : r.curves) {
    ASSERT_TRUE(c.closed);
    ASSERT_GE(c.points.size(), 4u);
    EXPECT_LT((c.points.front() - c.points.back()).norm(), 1e-12) << "loop closes";
    double len = 0;
    for (size_t i = 0; i + 1 < c.points.size(); ++i) len += (c.points[i + 1] - c.points[i]).norm();
    EXPECT_LE(len, polygon + 1e-9);
    EXPECT_GT(len, polygon * std::sin(alpha) / alpha - 1e-9);
    for (const Eigen::Vector3d& p : c.points) {
      const double rho = std::hypot(p.x(), p.z());
      EXPECT_LE(rho, R + 1e-9);
      EXPECT_GE(rho, R * std::cos(M_PI / na) - 1e-9);
    }
    // The width across a circle cut (k along the axis: flat) is pi s / 4.
    for (double wi : c.width) EXPECT_NEAR(wi, M_PI / 4, 1e-9);
  }
  // Consecutive loops: the next starts near the previous end.
  for (size_t i = 0; i + 1 < r.curves.size(); ++i) {
    EXPECT_LT((r.curves[i + 1].points.front() - r.curves[i].points.back()).norm(), 1.5);
  }
  // Loops are chained by short straight moves (one step along the axis): one path.
  EXPECT_EQ(r.paths.size(), 1u);
  ASSERT_EQ(r.joins.size(), r.curves.size() - 1);
  for (const IsoplanarJoin& j : r.joins) {
    ASSERT_EQ(j.points.size(), 2u);
    EXPECT_NEAR(j.length, r.curves[j.fromCurve].sideStep, 0.3);
  }
  // Without joins every loop is its own path.
  IsoplanarOptions noJoin = o;
  noJoin.connectFactor = 0;
  EXPECT_EQ(isoplanarPaths(m, samples, closedFormWidth(1), noJoin).paths.size(), r.curves.size());
  // Cut along the axis instead: two straight open lines per plane (top and bottom), closed 0.
  o.thetaDegrees = 90;
  const IsoplanarResult r2 = isoplanarPaths(m, samples, closedFormWidth(1), o);
  ASSERT_TRUE(r2.ok()) << r2.message;
  EXPECT_EQ(r2.closedCurves, 0u);
  for (const auto& pc : byPlane(r2)) EXPECT_EQ(pc.size(), 2u);
}

// A closed surface (sphere): every cut is a loop, down to the tiny ones next to the extremes
// (kept whole when within the chord error); loops lie on the sphere; coverage away from the two
// points where the drive planes are tangent (the minCross floor spaces the loops wider there).
TEST(IsoplanarPaths, ClosedSphereLoops) {
  const double R = 10;
  const int nu = 64, nv = 32;
  Mesh m;
  m.positions.insert(m.positions.end(), {0, 0, R});
  for (int j = 1; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const double th = M_PI * j / nv, ph = 2 * M_PI * i / nu;
      m.positions.insert(m.positions.end(), {R * std::sin(th) * std::cos(ph), R * std::sin(th) * std::sin(ph), R * std::cos(th)});
    }
  }
  m.positions.insert(m.positions.end(), {0, 0, -R});
  const uint32_t south = static_cast<uint32_t>(m.vertexCount() - 1);
  auto id = [&](int j, int i) { return static_cast<uint32_t>(1 + (j - 1) * nu + (i % nu)); };
  for (int i = 0; i < nu; ++i) m.triangles.insert(m.triangles.end(), {0, id(1, i), id(1, i + 1)});
  for (int j = 1; j + 1 < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      m.triangles.insert(m.triangles.end(), {id(j, i), id(j + 1, i), id(j + 1, i + 1), id(j, i), id(j + 1, i + 1), id(j, i + 1)});
    }
  }
  for (int i = 0; i < nu; ++i) m.triangles.insert(m.triangles.end(), {south, id(nv - 1, i + 1), id(nv - 1, i)});
  const auto samples = analyticSamples(
      m,
      [R](const Eigen::Vector3d& p, Eigen::Vector3d& n, Eigen::Matrix3d& T) {
        n = p.normalized();
        T = (Eigen::Matrix3d::Identity() - n * n.transpose()) / R;
      },
      0.5);
  IsoplanarOptions o;
  o.thetaDegrees = 30;
  o.chordError = 0.05;
  const WidthFn width = closedFormWidth(1);
  const IsoplanarResult r = isoplanarPaths(m, samples, width, o);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.closedCurves, r.curves.size());
  EXPECT_EQ(r.curves.size(), r.planes);
  expectPointsOnMesh(m, r, driveNormal(30));
  const double inner = R * std::cos(M_PI / nv) * std::cos(M_PI / nu);  // polygon inradius bound
  for (const NlCurve& c : r.curves) {
    ASSERT_GE(c.points.size(), 4u);
    EXPECT_EQ(c.points.front(), c.points.back());
    for (const Eigen::Vector3d& p : c.points) {
      EXPECT_LE(p.norm(), R + 1e-9);
      EXPECT_GE(p.norm(), inner - 1e-9);
    }
  }
  const Eigen::Vector3d q = driveNormal(30);
  const double w = width(1 / R, 0.5);
  size_t checked = 0;
  for (size_t v = 0; v < m.vertexCount(); v += 3) {
    const Eigen::Vector3d p = m.vertex(v);
    if (std::abs(p.normalized().dot(q)) > 0.9) continue;
    double d = 1e9;
    for (const NlCurve& c : r.curves) d = std::min(d, distanceToPolyline(p, c.points));
    EXPECT_LE(d, 0.6 * w) << "vertex " << v;
    ++checked;
  }
  EXPECT_GT(checked, 300u);
  // The time estimate's geodesic curvature: a small circle of radius rho at q.x = c on the
  // sphere has |k_g| = |c| / (R rho). The 3-point estimate on the faceted loop scatters (unequal
  // chords): compare the mean over each loop, within 5%.
  std::map<long, std::pair<double, int>> perLoop;
  std::map<long, double> expectedKg;
  const FeedFn probe = [&](uint32_t a, uint32_t b, double t, const Eigen::Vector3d& dir, double kg) {
    const Eigen::Vector3d p = (1 - t) * m.vertex(a) + t * m.vertex(b);
    const double c = q.dot(p), rho = std::sqrt(std::max(0.0, R * R - c * c));
    EXPECT_NEAR(dir.norm(), 1, 1e-9);
    if (kg != 0 && rho > 3) {
      const long key = std::lround(c * 1e6);
      perLoop[key].first += std::abs(kg);
      ++perLoop[key].second;
      expectedKg[key] = std::abs(c) / (R * rho);
    }
    return 10.0;
  };
  estimateIsoplanarTime(r, probe, 0, 100);
  EXPECT_GT(perLoop.size(), 20u);
  for (const auto& [key, sum] : perLoop) {
    EXPECT_NEAR(sum.first / sum.second, expectedKg[key], 0.05 * expectedKg[key] + 0.003)
        << "loop at " << key * 1e-6;
  }
  std::printf("sphere: planes %zu, loops %zu, paths %zu, side step [%.3f, %.3f]\n", r.planes,
              r.curves.size(), r.paths.size(), r.minSideStep, r.maxSideStep);
}

// ---------------------------------------------------------------------------------------------
// Theta sweep: planes x side step match the extent along q (flat disc, constant width: exactly;
// saddle: first/last half steps and the sum of offsets).
TEST(IsoplanarPaths, ThetaSweepPlanesMatchExtent) {
  const Mesh disc = test::makeDisc(10, 0.5);
  const auto flat = analyticSamples(disc, flatGeometry(), 0.5);
  const double w = 0.9;
  for (double theta : {0.0, 17.0, 45.0, 90.0, 133.0, 179.0}) {
    IsoplanarOptions o;
    o.thetaDegrees = theta;
    const IsoplanarResult r = isoplanarPaths(disc, flat, [w](double, double) { return w; }, o);
    ASSERT_TRUE(r.ok()) << r.message;
    const Eigen::Vector3d q = driveNormal(theta);
    double dmin = 1e9, dmax = -1e9;
    for (size_t v = 0; v < disc.vertexCount(); ++v) {
      dmin = std::min(dmin, q.dot(disc.vertex(v)));
      dmax = std::max(dmax, q.dot(disc.vertex(v)));
    }
    const double extent = dmax - dmin;
    EXPECT_NEAR(r.curves.front().plane - dmin, w / 2, 1e-9);
    // The last bead reaches the far extreme or stops short of it by at most a quarter step (a
    // sliver the squeezed bead covers; another plane would nearly duplicate the last curve).
    const double endGap = dmax - r.curves.back().plane;
    EXPECT_GE(endGap, w / 2 - 1e-9);
    EXPECT_LE(endGap, 0.75 * w + 1e-9);
    const double span = extent - w / 2 - endGap;
    EXPECT_EQ(r.planes, static_cast<size_t>(std::ceil(span / w - 1e-9)) + 1);
    double sum = 0;
    for (const auto& pc : byPlane(r)) sum += r.curves[pc[0]].sideStep;
    EXPECT_NEAR(sum, span, 1e-9);
  }
  const Mesh saddle = makeSaddleSurface(25, 12, 49 * 49);
  const auto samples = fittedSamples(saddle, 0.5);
  for (double theta : {10.0, 60.0, 100.0, 158.0}) {
    IsoplanarOptions o;
    o.thetaDegrees = theta;
    const IsoplanarResult r = isoplanarPaths(saddle, samples, closedFormWidth(1), o);
    ASSERT_TRUE(r.ok()) << r.message;
    const Eigen::Vector3d q = driveNormal(theta);
    double dmin = 1e9, dmax = -1e9;
    for (size_t v = 0; v < saddle.vertexCount(); ++v) {
      dmin = std::min(dmin, q.dot(saddle.vertex(v)));
      dmax = std::max(dmax, q.dot(saddle.vertex(v)));
    }
    const auto planes = byPlane(r);
    const double first = r.curves[planes[0][0]].sideStep;
    EXPECT_NEAR(r.curves.front().plane - dmin, first / 2, 0.02 * first);
    double sum = 0;
    for (const auto& pc : planes) sum += r.curves[pc[0]].sideStep;
    const double lastOffset = r.curves[planes[planes.size() - 2][0]].sideStep;
    (void)lastOffset;
    EXPECT_NEAR(r.curves.front().plane + sum, r.curves.back().plane, 1e-9);
    EXPECT_LE(dmax - r.curves.back().plane, 0.75 * r.maxSideStep + 1e-9);
    EXPECT_GE(dmax - r.curves.back().plane, r.minSideStep / 2 - 1e-9);
    EXPECT_GE(static_cast<double>(r.planes), (dmax - dmin) / r.maxSideStep);
    EXPECT_LE(static_cast<double>(r.planes), (dmax - dmin) / r.minSideStep + 2);
  }
}

// Structure invariants over 36 directions on the seat (one preparation): every curve in exactly
// one path, paths = curves + interior join points concatenated, joins start at a curve's end and
// end at the next one's start, pathMm = curves + joins, side steps positive but the last.
TEST(IsoplanarPaths, SeatDirectionSweepInvariants) {
  const Mesh m = makeSeatSurface(110, 5000);
  const auto samples = fittedSamples(m, 0.4);
  const IsoplanarSurface prepared = prepareIsoplanarSurface(m, samples);
  ASSERT_TRUE(prepared.ok()) << prepared.message;
  const WidthFn width = EffectiveWidthTable(0.8, 0.2, 0.6).function();
  for (int k = 0; k < 36; ++k) {
    IsoplanarOptions o;
    o.thetaDegrees = 5.0 * k;
    const IsoplanarResult r = isoplanarPaths(prepared, width, o);
    ASSERT_TRUE(r.ok()) << r.message;
    ASSERT_EQ(r.paths.size(), r.pathCurves.size());
    ASSERT_EQ(r.paths.size(), r.pathJoins.size());
    std::vector<int> seen(r.curves.size(), 0);
    double maxWidth = 0;
    for (const NlCurve& c : r.curves) {
      for (double wi : c.width) maxWidth = std::max(maxWidth, wi);
    }
    double length = 0;
    size_t joins = 0;
    for (size_t p = 0; p < r.paths.size(); ++p) {
      std::vector<Eigen::Vector3d> expected;
      const auto& pc = r.pathCurves[p];
      ASSERT_EQ(r.pathJoins[p].size() + 1, pc.size());
      for (size_t j = 0; j < pc.size(); ++j) {
        const NlCurve& c = r.curves[pc[j]];
        ++seen[pc[j]];
        ASSERT_GE(c.points.size(), 2u);
        for (size_t i = 0; i + 1 < c.points.size(); ++i) length += (c.points[i + 1] - c.points[i]).norm();
        if (j > 0) {
          const IsoplanarJoin& jn = r.joins[r.pathJoins[p][j - 1]];
          ++joins;
          EXPECT_EQ(jn.points.front(), r.curves[pc[j - 1]].points.back());
          EXPECT_EQ(jn.points.back(), c.points.front());
          // Within connectFactor x the side step computed on the planes (<= w_eff there).
          EXPECT_LE(jn.length, o.connectFactor * maxWidth + 1e-9);
          for (const Eigen::Vector3d& n : jn.normals) EXPECT_NEAR(n.norm(), 1, 1e-9);
          for (size_t i = 0; i < jn.points.size(); ++i) {
            const Eigen::Vector3d onEdge = (1 - jn.edgeT[i]) * m.vertex(jn.edgeA[i]) + jn.edgeT[i] * m.vertex(jn.edgeB[i]);
            EXPECT_LT((onEdge - jn.points[i]).norm(), 1e-5);
          }
          length += jn.length;
          expected.insert(expected.end(), jn.points.begin() + 1, jn.points.end() - 1);
        }
        expected.insert(expected.end(), c.points.begin(), c.points.end());
      }
      ASSERT_EQ(r.paths[p].points.size(), expected.size());
      ASSERT_EQ(r.paths[p].normals.size(), expected.size());
      ASSERT_EQ(r.pathPointCurve[p].size(), expected.size());
      for (size_t i = 0; i < expected.size(); ++i) {
        const uint32_t ci = r.pathPointCurve[p][i];
        if (ci > 0) {  // the point is one of its curve's points
          const auto& cp = r.curves[ci - 1].points;
          EXPECT_NE(std::find(cp.begin(), cp.end(), expected[i]), cp.end());
        }
      }
      for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(r.paths[p].points[i], expected[i]);
    }
    EXPECT_EQ(joins, r.joins.size());
    for (int c : seen) EXPECT_EQ(c, 1);
    EXPECT_NEAR(r.pathMm, length, 1e-6 * length);
    for (const auto& pc : byPlane(r)) {
      for (size_t i : pc) EXPECT_EQ(r.curves[i].sideStep, r.curves[pc[0]].sideStep);
    }
    const auto planes = byPlane(r);
    for (size_t j = 0; j + 1 < planes.size(); ++j) EXPECT_GT(r.curves[planes[j][0]].sideStep, 0);
    EXPECT_EQ(r.curves[planes.back()[0]].sideStep, 0);
    expectPointsOnMesh(m, r, driveNormal(o.thetaDegrees));
  }
}

// Degenerate: two squares touching at one vertex (a bowtie: non-manifold vertex, manifold
// edges). Every plane through the shared vertex still gives simple curves; no crash.
TEST(IsoplanarPaths, BowtieSharedVertex) {
  Mesh m;
  m.positions = {0, 0, 0, 5, 0, 0, 5, 5, 0, 0, 5, 0, 10, 5, 0, 10, 10, 0, 5, 10, 0};
  m.triangles = {0, 1, 2, 0, 2, 3, 2, 4, 5, 2, 5, 6};
  const auto samples = analyticSamples(m, flatGeometry(), 0.5);
  for (double theta : {0.0, 45.0, 90.0, 135.0}) {
    IsoplanarOptions o;
    o.thetaDegrees = theta;
    const IsoplanarResult r = isoplanarPaths(m, samples, [](double, double) { return 0.5; }, o);
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_GT(r.curves.size(), 10u);
    expectPointsOnMesh(m, r, driveNormal(theta));
    double length = 0;
    for (const NlCurve& c : r.curves) length += (c.points.back() - c.points.front()).norm();
    EXPECT_NEAR(length * 0.5 / 50, 1.0, 0.15) << "length ~ area / step at theta " << theta;
  }
}

// ---------------------------------------------------------------------------------------------
TEST(IsoplanarPaths, EstimateTime) {
  const Mesh m = test::meshImplicit2D(
      [](const Eigen::Vector2d& p) {
        return std::max(test::boxSdf(p, {0, 0}, {30, 20}), -test::boxSdf(p, {10, 5}, {20, 21}));
      },
      Eigen::Vector2d(-0.5, -0.5), Eigen::Vector2d(30.5, 20.5), 0.5);
  const auto samples = analyticSamples(m, flatGeometry(), 0.5);
  IsoplanarOptions o;
  o.thetaDegrees = 0;
  const IsoplanarResult r = isoplanarPaths(m, samples, [](double, double) { return 0.8; }, o);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_GT(r.joins.size(), 0u);
  ASSERT_GT(r.paths.size(), 1u);
  double curveLen = 0, joinLen = 0, travel = 0;
  size_t segments = 0;
  for (const NlCurve& c : r.curves) {
    for (size_t i = 0; i + 1 < c.points.size(); ++i, ++segments) curveLen += (c.points[i + 1] - c.points[i]).norm();
  }
  for (const IsoplanarJoin& j : r.joins) {
    joinLen += j.length;
    for (size_t i = 0; i + 1 < j.points.size(); ++i) segments += (j.points[i + 1] - j.points[i]).norm() > 0;
  }
  for (size_t p = 1; p < r.paths.size(); ++p) travel += (r.paths[p].points.front() - r.paths[p - 1].points.back()).norm();
  EXPECT_NEAR(r.pathMm, curveLen + joinLen, 1e-9);
  const FeedFn constant = [](uint32_t, uint32_t, double, const Eigen::Vector3d&, double) { return 10.0; };
  const IsoplanarTime t = estimateIsoplanarTime(r, constant, 0, 100);
  EXPECT_NEAR(t.printS, curveLen / 10, 1e-9);
  EXPECT_NEAR(t.joinS, joinLen / 10, 1e-9);
  EXPECT_NEAR(t.travelMm, travel, 1e-9);
  EXPECT_NEAR(t.travelS, travel / 100, 1e-9);
  EXPECT_NEAR(t.totalS, (curveLen + joinLen) / 10 + travel / 100, 1e-9);
  EXPECT_NEAR(t.pathMm, r.pathMm, 1e-9);
  EXPECT_NEAR(t.meanFeed, 10, 1e-9);
  EXPECT_EQ(t.unreachableSegments, 0u);
  // The cap.
  const IsoplanarTime capped = estimateIsoplanarTime(r, constant, 4, 100);
  EXPECT_NEAR(capped.printS + capped.joinS, (curveLen + joinLen) / 4, 1e-9);
  // Direction-dependent feed: each segment at the smaller f* of its ends (same here).
  const FeedFn directional = [](uint32_t, uint32_t, double, const Eigen::Vector3d& d, double) {
    return 5 + 5 * std::abs(d.y());
  };
  double expected = 0;
  for (const NlCurve& c : r.curves) {
    for (size_t i = 0; i + 1 < c.points.size(); ++i) {
      const Eigen::Vector3d d = c.points[i + 1] - c.points[i];
      expected += d.norm() / (5 + 5 * std::abs(d.normalized().y()));
    }
  }
  EXPECT_NEAR(estimateIsoplanarTime(r, directional, 0, 100).printS, expected, 1e-9);
  // Feed depending on the point: the slower end wins.
  const FeedFn byVertex = [&](uint32_t a, uint32_t b, double t, const Eigen::Vector3d&, double) {
    const Eigen::Vector3d p = (1 - t) * m.vertex(a) + t * m.vertex(b);
    return 2 + p.x();
  };
  double expectedV = 0;
  for (const NlCurve& c : r.curves) {
    for (size_t i = 0; i + 1 < c.points.size(); ++i) {
      const double f = 2 + std::min(c.points[i].x(), c.points[i + 1].x());
      expectedV += (c.points[i + 1] - c.points[i]).norm() / f;
    }
  }
  EXPECT_NEAR(estimateIsoplanarTime(r, byVertex, 0, 100).printS, expectedV, 1e-4);
  // Unreachable everywhere: timed at minFeed and counted.
  const FeedFn zero = [](uint32_t, uint32_t, double, const Eigen::Vector3d&, double) { return 0.0; };
  const IsoplanarTime u = estimateIsoplanarTime(r, zero, 0, 100, 2);
  EXPECT_EQ(u.unreachableSegments, segments);
  EXPECT_NEAR(u.printS + u.joinS, (curveLen + joinLen) / 2, 1e-9);
}

// ---------------------------------------------------------------------------------------------
TEST(IsoplanarPaths, BadInput) {
  const Mesh m = gridMesh(5, 11, nullptr);
  const auto samples = analyticSamples(m, flatGeometry(), 0.5);
  const WidthFn w = [](double, double) { return 0.8; };
  IsoplanarOptions o;
  // Empty mesh.
  EXPECT_EQ(isoplanarPaths(Mesh{}, {}, w, o).status, Status::EmptyInput);
  // One sample per vertex.
  std::vector<SurfaceSample> fewer(samples.begin(), samples.end() - 1);
  EXPECT_EQ(isoplanarPaths(m, fewer, w, o).status, Status::InvalidOption);
  // Non-finite or out-of-range options.
  for (int k = 0; k < 6; ++k) {
    IsoplanarOptions bad;
    if (k == 0) bad.thetaDegrees = std::nan("");
    if (k == 1) bad.chordError = 0;
    if (k == 2) bad.chordError = std::numeric_limits<double>::infinity();
    if (k == 3) bad.minCross = 0;
    if (k == 4) bad.maxStep = -1;
    if (k == 5) bad.connectFactor = std::nan("");
    EXPECT_EQ(isoplanarPaths(m, samples, w, bad).status, Status::InvalidOption) << k;
  }
  // A width that is not positive.
  EXPECT_EQ(isoplanarPaths(m, samples, [](double, double) { return 0.0; }, o).status,
            Status::InvalidOption);
  EXPECT_EQ(isoplanarPaths(m, samples, [](double, double) { return std::nan(""); }, o).status,
            Status::InvalidOption);
  // Non-finite vertex.
  Mesh nan = m;
  nan.positions[4] = std::nan("");
  EXPECT_EQ(isoplanarPaths(nan, samples, w, o).status, Status::NonFiniteVertex);
  // Index out of range.
  Mesh outOfRange = m;
  outOfRange.triangles[5] = 100000;
  EXPECT_EQ(isoplanarPaths(outOfRange, samples, w, o).status, Status::InvalidOption);
  // Non-manifold edge: a third triangle on an interior edge.
  Mesh fin = m;
  fin.positions.insert(fin.positions.end(), {0.1, 0.1, 3});
  fin.triangles.insert(fin.triangles.end(), {fin.triangles[0], fin.triangles[2],
                                             static_cast<uint32_t>(fin.vertexCount() - 1)});
  auto finSamples = samples;
  finSamples.push_back(samples[0]);
  // Tolerated: the cut pairs the edge's triangles; points stay on the mesh.
  const IsoplanarResult finResult = isoplanarPaths(fin, finSamples, w, o);
  ASSERT_TRUE(finResult.ok()) << finResult.message;
  EXPECT_GT(finResult.curves.size(), 5u);
  expectPointsOnMesh(fin, finResult, driveNormal(0));
  // Cancel.
  int calls = 0;
  const IsoplanarResult c = isoplanarPaths(m, samples, w, o, [&](const char* stage, double) {
    EXPECT_STREQ(stage, "paths");
    return ++calls < 3;
  });
  EXPECT_EQ(c.status, Status::Cancelled);
  // Degenerate triangles only.
  Mesh degenerate;
  degenerate.positions = {0, 0, 0, 1, 0, 0};
  degenerate.triangles = {0, 1, 1};
  EXPECT_EQ(isoplanarPaths(degenerate, std::vector<SurfaceSample>(2), w, o).status, Status::EmptyInput);
  // A surface lying in a drive plane (y = 0 with theta = 0): no curve, not an error.
  Mesh wall = gridMesh(5, 5, nullptr);
  for (size_t v = 0; v < wall.vertexCount(); ++v) std::swap(wall.positions[3 * v + 1], wall.positions[3 * v + 2]);
  const IsoplanarResult inPlane = isoplanarPaths(wall, analyticSamples(wall, flatGeometry(), 0.5), w, o);
  EXPECT_TRUE(inPlane.ok()) << inPlane.message;
  EXPECT_TRUE(inPlane.curves.empty());
  // Tiny width against a large surface: refused, not hung.
  EXPECT_EQ(isoplanarPaths(m, samples, [](double, double) { return 1e-9; }, o).status,
            Status::InvalidOption);
}

// A prepared surface gives the same result as the direct call (several directions on one
// preparation, as the benchmark does); an unprepared one is refused.
TEST(IsoplanarPaths, PreparedSurfaceSameResult) {
  const HeightField hf = saddleField(30);
  const Mesh m = gridMesh(10, 41, hf.g);
  const auto samples = analyticSamples(m, heightFieldGeometry(hf), 0.5);
  const IsoplanarSurface prepared = prepareIsoplanarSurface(m, samples);
  ASSERT_TRUE(prepared.ok()) << prepared.message;
  for (double theta : {0.0, 70.0, 140.0}) {
    IsoplanarOptions o;
    o.thetaDegrees = theta;
    const IsoplanarResult a = isoplanarPaths(m, samples, closedFormWidth(1), o);
    const IsoplanarResult b = isoplanarPaths(prepared, closedFormWidth(1), o);
    ASSERT_TRUE(a.ok() && b.ok());
    ASSERT_EQ(a.curves.size(), b.curves.size());
    EXPECT_EQ(a.pathMm, b.pathMm);
    for (size_t i = 0; i < a.curves.size(); ++i) {
      ASSERT_EQ(a.curves[i].points.size(), b.curves[i].points.size());
      for (size_t k = 0; k < a.curves[i].points.size(); ++k) {
        EXPECT_EQ(a.curves[i].points[k], b.curves[i].points[k]);
      }
    }
  }
  EXPECT_EQ(isoplanarPaths(IsoplanarSurface{}, closedFormWidth(1), IsoplanarOptions{}).status,
            Status::EmptyInput);
  EXPECT_EQ(prepareIsoplanarSurface(Mesh{}, {}).status, Status::EmptyInput);
}

// An unwelded mesh (every triangle with its own three vertices) cuts like the welded one.
TEST(IsoplanarPaths, UnweldedMeshSameAsWelded) {
  const Mesh m = makeSaddleSurface(30, 10, 41 * 41);
  const auto samples = fittedSamples(m, 0.5);
  Mesh loose;
  std::vector<SurfaceSample> looseSamples;
  for (uint32_t v : m.triangles) {
    const Eigen::Vector3d p = m.vertex(v);
    loose.positions.insert(loose.positions.end(), {p.x(), p.y(), p.z()});
    loose.triangles.push_back(static_cast<uint32_t>(looseSamples.size()));
    looseSamples.push_back(samples[v]);
  }
  for (double theta : {0.0, 65.0}) {
    IsoplanarOptions o;
    o.thetaDegrees = theta;
    const IsoplanarResult a = isoplanarPaths(m, samples, closedFormWidth(1), o);
    const IsoplanarResult b = isoplanarPaths(loose, looseSamples, closedFormWidth(1), o);
    ASSERT_TRUE(a.ok() && b.ok()) << b.message;
    EXPECT_EQ(a.curves.size(), b.curves.size());
    EXPECT_EQ(a.paths.size(), b.paths.size());
    EXPECT_NEAR(a.pathMm, b.pathMm, 1e-9 * a.pathMm);
    expectPointsOnMesh(loose, b, driveNormal(theta));
  }
}

// Timings (native): 5k and 20k vertex saddles.
TEST(IsoplanarPaths, SaddleTiming) {
  for (int n : {71, 141}) {  // 5041 and 19881 vertices
    const Mesh m = makeSaddleSurface(100, 37.5, n * n);
    const auto samples = fittedSamples(m, 0.5);
    const WidthFn width = EffectiveWidthTable(1, 0.2, 0.8).function();
    IsoplanarResult r;
    for (double theta : {0.0, 37.0, 158.0}) {
      IsoplanarOptions o;
      o.thetaDegrees = theta;
      const auto t0 = std::chrono::steady_clock::now();
      r = isoplanarPaths(m, samples, width, o);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      ASSERT_TRUE(r.ok()) << r.message;
      std::printf("saddle %zu vertices theta %.0f: %.2f ms, planes %zu, curves %zu, paths %zu, path %.1f mm\n",
                  m.vertexCount(), theta, ms, r.planes, r.curves.size(), r.paths.size(), r.pathMm);
    }
    // The benchmark's way: one preparation, 36 directions (s = 1 and s = 0.4).
    const IsoplanarSurface prepared = prepareIsoplanarSurface(m, samples);
    ASSERT_TRUE(prepared.ok());
    for (double s : {1.0, 0.4}) {
      const WidthFn table = EffectiveWidthTable(s, 0.1, 0.6).function();
      const auto t0 = std::chrono::steady_clock::now();
      size_t planes = 0;
      for (int k = 0; k < 36; ++k) {
        IsoplanarOptions o;
        o.thetaDegrees = 5.0 * k;
        const IsoplanarResult rk = isoplanarPaths(prepared, table, o);
        ASSERT_TRUE(rk.ok());
        planes += rk.planes;
      }
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      std::printf("saddle %zu vertices, s %.1f: prepare %.2f ms, %.2f ms per direction (mean %zu planes)\n",
                  m.vertexCount(), s, prepared.ms, ms / 36, planes / 36);
    }
  }
}

}  // namespace
}  // namespace omnislice
