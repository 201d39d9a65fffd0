// SPDX-License-Identifier: MIT
// IGDS extraction and metrics (paper 002 Section 2.2, Eq. 10-11, Fig. 10): exact planes,
// cylinders and spheres on structured tet boxes, known overhangs on slanted prisms and frusta,
// invariants (edge-manifold, closed or ending on the boundary, no self-intersection, successive
// layers never cross, edge lengths, angles, distance to the interpolated surface) on the shared
// tet models, the Fermat-spiral fill on real regions, bad input, cancellation and timings.
#include "geodesic/igds.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <limits>
#include <string>
#include <functional>
#include <map>
#include <memory>
#include <unordered_map>

#include "../test_meshes.h"
#include "../test_support.h"
#include "geodesic/heat_geodesic.h"
#include "geometry/aabb_tree.h"
#include "surface/fermat_spiral.h"
#include "tet/tet_mesh.h"

namespace omnislice {
namespace {

using test::gridTets;

std::vector<double> fieldOf(const TetMesh& m, const std::function<double(const Eigen::Vector3d&)>& f) {
  std::vector<double> d(m.vertexCount());
  for (size_t i = 0; i < d.size(); ++i) d[i] = f(m.vertex(i));
  return d;
}

// ---- geometric helpers written for the tests ----

struct EdgeCheck {
  size_t nonManifold = 0, inconsistent = 0, boundaryEdges = 0;
  std::vector<uint8_t> boundaryVertex;
};

EdgeCheck checkEdges(const Mesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, std::vector<int>> edges;  // +1 lo->hi, -1 hi->lo
  for (size_t f = 0; f < m.faceCount(); ++f)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = m.triangles[3 * f + k], b = m.triangles[3 * f + (k + 1) % 3];
      edges[{std::min(a, b), std::max(a, b)}].push_back(a < b ? 1 : -1);
    }
  EdgeCheck c;
  c.boundaryVertex.assign(m.vertexCount(), 0);
  for (const auto& [e, dirs] : edges) {
    if (dirs.size() > 2) ++c.nonManifold;
    if (dirs.size() == 2 && dirs[0] == dirs[1]) ++c.inconsistent;
    if (dirs.size() == 1) {
      ++c.boundaryEdges;
      c.boundaryVertex[e.first] = c.boundaryVertex[e.second] = 1;
    }
  }
  return c;
}

using Tri = std::array<Eigen::Vector3d, 3>;

// Segment pq crosses triangle t in its relative interior (both ends strictly on opposite sides).
bool segmentHitsTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Tri& t,
                         double eps) {
  const Eigen::Vector3d n = (t[1] - t[0]).cross(t[2] - t[0]);
  const double nn = n.norm();
  if (nn <= 0) return false;
  const double dp = n.dot(p - t[0]) / nn, dq = n.dot(q - t[0]) / nn;
  if ((dp > eps && dq > eps) || (dp < -eps && dq < -eps)) return false;
  if (std::abs(dp) <= eps && std::abs(dq) <= eps) return false;  // coplanar: handled apart
  const Eigen::Vector3d x = p + (q - p) * (dp / (dp - dq));
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = t[(k + 1) % 3] - t[k];
    if (n.dot(e.cross(x - t[k])) / nn < -eps * e.norm()) return false;
  }
  return true;
}

// 2D overlap of coplanar triangles (strict: touching within eps is not an overlap).
bool coplanarOverlap(const Tri& a, const Tri& b, const Eigen::Vector3d& n, double eps) {
  int ax = 0;
  n.cwiseAbs().maxCoeff(&ax);
  const int u = (ax + 1) % 3, v = (ax + 2) % 3;
  auto to2 = [&](const Eigen::Vector3d& p) { return Eigen::Vector2d(p[u], p[v]); };
  Eigen::Vector2d A[3], B[3];
  for (int k = 0; k < 3; ++k) {
    A[k] = to2(a[k]);
    B[k] = to2(b[k]);
  }
  // Separating axis test over the six edge normals.
  auto separated = [&](const Eigen::Vector2d* P, const Eigen::Vector2d* Q) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d e = P[(k + 1) % 3] - P[k];
      const Eigen::Vector2d nrm(-e.y(), e.x());
      double pmin = 1e300, pmax = -1e300, qmin = 1e300, qmax = -1e300;
      for (int j = 0; j < 3; ++j) {
        pmin = std::min(pmin, nrm.dot(P[j]));
        pmax = std::max(pmax, nrm.dot(P[j]));
        qmin = std::min(qmin, nrm.dot(Q[j]));
        qmax = std::max(qmax, nrm.dot(Q[j]));
      }
      const double tol = eps * nrm.norm();
      if (pmax <= qmin + tol || qmax <= pmin + tol) return true;
    }
    return false;
  };
  return !separated(A, B) && !separated(B, A);
}

bool trianglesIntersect(const Tri& a, const Tri& b, double eps) {
  const Eigen::Vector3d na = (a[1] - a[0]).cross(a[2] - a[0]);
  const Eigen::Vector3d nb = (b[1] - b[0]).cross(b[2] - b[0]);
  if (na.norm() > 0 && nb.norm() > 0 && na.cross(nb).norm() <= 1e-9 * na.norm() * nb.norm() &&
      std::abs(na.normalized().dot(b[0] - a[0])) <= eps)
    return coplanarOverlap(a, b, na, eps);
  for (int k = 0; k < 3; ++k) {
    if (segmentHitsTriangle(a[k], a[(k + 1) % 3], b, eps)) return true;
    if (segmentHitsTriangle(b[k], b[(k + 1) % 3], a, eps)) return true;
  }
  return false;
}

// Pairs of intersecting triangles, grid-accelerated. group[i] tags triangle i; pairs are tested
// when crossGroups is false (same group, sharing no vertex id) or true (different groups).
struct TriSoup {
  std::vector<Tri> tris;
  std::vector<std::array<int64_t, 3>> ids;
  std::vector<int> group;
};

size_t countIntersections(const TriSoup& s, bool crossGroups, double cell, double eps,
                          Eigen::Vector3d* where = nullptr) {
  struct H {
    size_t operator()(const std::array<int64_t, 3>& k) const {
      return size_t(k[0] * 73856093 ^ k[1] * 19349663 ^ k[2] * 83492791);
    }
  };
  std::unordered_map<std::array<int64_t, 3>, std::vector<uint32_t>, H> grid;
  auto cellOf = [&](double x) { return int64_t(std::floor(x / cell)); };
  std::vector<std::array<int64_t, 6>> box(s.tris.size());
  for (size_t i = 0; i < s.tris.size(); ++i) {
    Eigen::Vector3d lo = s.tris[i][0], hi = lo;
    for (int k = 1; k < 3; ++k) {
      lo = lo.cwiseMin(s.tris[i][k]);
      hi = hi.cwiseMax(s.tris[i][k]);
    }
    box[i] = {cellOf(lo.x()), cellOf(lo.y()), cellOf(lo.z()), cellOf(hi.x()), cellOf(hi.y()), cellOf(hi.z())};
    for (int64_t x = box[i][0]; x <= box[i][3]; ++x)
      for (int64_t y = box[i][1]; y <= box[i][4]; ++y)
        for (int64_t z = box[i][2]; z <= box[i][5]; ++z) grid[{x, y, z}].push_back(uint32_t(i));
  }
  size_t hits = 0;
  std::vector<uint32_t> stamp(s.tris.size(), UINT32_MAX);
  for (size_t i = 0; i < s.tris.size(); ++i) {
    for (int64_t x = box[i][0]; x <= box[i][3]; ++x)
      for (int64_t y = box[i][1]; y <= box[i][4]; ++y)
        for (int64_t z = box[i][2]; z <= box[i][5]; ++z)
          for (uint32_t j : grid[{x, y, z}]) {
            if (j <= i || stamp[j] == i) continue;
            stamp[j] = uint32_t(i);
            if (crossGroups != (s.group[i] != s.group[j])) continue;
            if (!crossGroups) {
              bool shared = false;
              for (int64_t a : s.ids[i])
                for (int64_t b : s.ids[j]) shared = shared || a == b;
              if (shared) continue;
            }
            if (trianglesIntersect(s.tris[i], s.tris[j], eps)) {
              if (where && hits == 0) *where = (s.tris[i][0] + s.tris[i][1] + s.tris[i][2]) / 3;
              ++hits;
            }
          }
  }
  return hits;
}

void addRegion(TriSoup& s, const LayerRegion& r, int group, int64_t idBase) {
  const Mesh& m = r.mesh;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    s.tris.push_back({m.vertex(m.triangles[3 * f]), m.vertex(m.triangles[3 * f + 1]),
                      m.vertex(m.triangles[3 * f + 2])});
    s.ids.push_back({idBase + m.triangles[3 * f], idBase + m.triangles[3 * f + 1],
                     idBase + m.triangles[3 * f + 2]});
    s.group.push_back(group);
  }
}

double minAngleDegrees(const Mesh& m, size_t f) {
  const Eigen::Vector3d p[3] = {m.vertex(m.triangles[3 * f]), m.vertex(m.triangles[3 * f + 1]),
                                m.vertex(m.triangles[3 * f + 2])};
  double best = 180;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
    const double n1 = e1.norm(), n2 = e2.norm();
    if (n1 <= 0 || n2 <= 0) return 0;
    best = std::min(best, std::acos(std::clamp(e1.dot(e2) / (n1 * n2), -1.0, 1.0)) * 180 / M_PI);
  }
  return best;
}

// Topology of a region: Euler characteristic V - E + F and the number of boundary loops.
std::pair<long, long> topology(const Mesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  std::vector<uint8_t> used(m.vertexCount(), 0);
  for (size_t f = 0; f < m.faceCount(); ++f)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = m.triangles[3 * f + k], b = m.triangles[3 * f + (k + 1) % 3];
      ++edges[{std::min(a, b), std::max(a, b)}];
      used[a] = 1;
    }
  long v = 0;
  for (uint8_t u : used) v += u;
  std::vector<uint32_t> parent(m.vertexCount());
  for (size_t i = 0; i < parent.size(); ++i) parent[i] = uint32_t(i);
  std::function<uint32_t(uint32_t)> find = [&](uint32_t x) {
    return parent[x] == x ? x : parent[x] = find(parent[x]);
  };
  std::vector<uint8_t> onBoundary(m.vertexCount(), 0);
  for (const auto& [e, n] : edges)
    if (n == 1) {
      onBoundary[e.first] = onBoundary[e.second] = 1;
      parent[find(e.first)] = find(e.second);
    }
  long loops = 0;
  for (size_t i = 0; i < parent.size(); ++i) loops += (onBoundary[i] && find(uint32_t(i)) == i) ? 1 : 0;
  return {v - long(edges.size()) + long(m.faceCount()), loops};
}

Mesh mergeLayer(const CurvedLayer& layer) {
  Mesh m;
  for (const LayerRegion& r : layer.regions) m = test::append(m, r.mesh);
  return m;
}

// Per-region structural checks shared by every case: edge-manifold, consistent orientation,
// boundary flags equal the topological boundary, area equals the triangles' area.
void expectWellFormed(const IgdsResult& r, const std::string& what) {
  size_t regions = 0, triangles = 0;
  for (const CurvedLayer& layer : r.layers)
    for (const LayerRegion& region : layer.regions) {
      ++regions;
      triangles += region.mesh.faceCount();
      const EdgeCheck c = checkEdges(region.mesh);
      EXPECT_EQ(c.nonManifold, 0u) << what << " layer " << layer.isoValue;
      EXPECT_EQ(c.inconsistent, 0u) << what << " layer " << layer.isoValue;
      ASSERT_EQ(region.boundaryVertex.size(), region.mesh.vertexCount()) << what;
      EXPECT_TRUE(c.boundaryVertex == region.boundaryVertex) << what << " layer " << layer.isoValue;
      double area = 0;
      for (size_t f = 0; f < region.mesh.faceCount(); ++f) {
        const Eigen::Vector3d a = region.mesh.vertex(region.mesh.triangles[3 * f]),
                              b = region.mesh.vertex(region.mesh.triangles[3 * f + 1]),
                              cc = region.mesh.vertex(region.mesh.triangles[3 * f + 2]);
        area += 0.5 * (b - a).cross(cc - a).norm();
      }
      EXPECT_NEAR(area, region.area, 1e-9 * std::max(1.0, area)) << what;
    }
  EXPECT_EQ(regions, r.regionCount) << what;
  EXPECT_EQ(triangles, r.triangleCount) << what;
}

// Every triangle's normal (unit) dotted with a reference direction field.
double minNormalAlignment(const IgdsResult& r,
                          const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& dir) {
  double worst = 1;
  for (const CurvedLayer& layer : r.layers)
    for (const LayerRegion& region : layer.regions)
      for (size_t f = 0; f < region.mesh.faceCount(); ++f) {
        const Mesh& m = region.mesh;
        const Eigen::Vector3d a = m.vertex(m.triangles[3 * f]), b = m.vertex(m.triangles[3 * f + 1]),
                              c = m.vertex(m.triangles[3 * f + 2]);
        const Eigen::Vector3d n = (b - a).cross(c - a);
        if (n.norm() <= 1e-14) continue;
        worst = std::min(worst, n.normalized().dot(dir((a + b + c) / 3).normalized()));
      }
  return worst;
}

// ---- synthetic cases ----

// phi = z on a 10 x 8 x 6 box (1 mm cubes): every IGDS is the plane z = i d, one region of area
// 80 mm^2, normals +z, boundary on the box sides, overhang 0, thickness exactly d.
TEST(Igds, PlanarBoxGivesExactPlanes) {
  const TetMesh box = gridTets(10, 8, 6, [](double u, double v, double w) {
    return Eigen::Vector3d(10 * u, 8 * v, 6 * w);
  });
  // d = 0.7 (no iso-value on a grid plane) and d = 1 (iso-values exactly on vertex planes: the
  // points snap onto tet vertices, see IsoExtractor).
  for (double d : {0.7, 1.0}) {
    const std::vector<double> phi = fieldOf(box, [](const Eigen::Vector3d& p) { return p.z(); });
    IgdsOptions o;
    o.interval = d;
    const IgdsResult r = extractIgds(box, phi, o);
    ASSERT_TRUE(r.ok()) << r.message;
    const size_t expected = d == 0.7 ? 8 : 5;  // i d < 6
    ASSERT_EQ(r.layers.size(), expected) << d;
    expectWellFormed(r, "planar box");
    for (size_t i = 0; i < r.layers.size(); ++i) {
      const CurvedLayer& layer = r.layers[i];
      EXPECT_DOUBLE_EQ(layer.isoValue, double(i + 1) * d);
      ASSERT_EQ(layer.regions.size(), 1u) << "d " << d << " layer " << i;
      const LayerRegion& region = layer.regions[0];
      EXPECT_NEAR(region.area, 80.0, 1e-9) << "d " << d << " layer " << i;
      for (size_t v = 0; v < region.mesh.vertexCount(); ++v) {
        const Eigen::Vector3d p = region.mesh.vertex(v);
        EXPECT_NEAR(p.z(), layer.isoValue, 1e-12);
        const bool onSide = std::abs(p.x()) < 1e-9 || std::abs(p.x() - 10) < 1e-9 ||
                            std::abs(p.y()) < 1e-9 || std::abs(p.y() - 8) < 1e-9;
        EXPECT_EQ(bool(region.boundaryVertex[v]), onSide) << p.transpose();
      }
    }
    EXPECT_GT(minNormalAlignment(r, [](const Eigen::Vector3d&) { return Eigen::Vector3d(0, 0, 1); }),
              1 - 1e-9);
    const IgdsMetrics mt = igdsMetrics(r.layers, d, 0.5);
    ASSERT_EQ(mt.layers.size(), r.layers.size());
    for (const IgdsLayerMetrics& lm : mt.layers) {
      EXPECT_NEAR(lm.boundaryLengthMm, 36.0, 1e-9);
      EXPECT_EQ(lm.overhangLengthMm, 0.0);
      EXPECT_EQ(lm.overhangRatio, 0.0);
      EXPECT_EQ(lm.overhangAverageDegrees, 0.0);
      EXPECT_GT(lm.thicknessSamples, 250u);  // ~80 / 0.25
      EXPECT_NEAR(lm.thicknessMeanMm, d, 1e-9);
      EXPECT_LT(lm.thicknessMaxDeviationPercent, 1e-6);
    }
    EXPECT_LT(mt.thicknessMaxDeviationPercent, 1e-6);
    EXPECT_EQ(mt.overhangAverageDegrees, 0.0);
  }
}

// phi = distance to the z axis in a 12 x 12 x 4 box centred on the axis: IGDS are cylinders
// r = i d (open tubes ending on the bottom and top faces for r < 6, arcs cut by the sides
// beyond). After remeshing, vertices stay within the interpolation error of the analytic surface.
TEST(Igds, CylindersAroundAnAxisStayOnTheAnalyticSurface) {
  const TetMesh box = gridTets(24, 24, 8, [](double u, double v, double w) {
    return Eigen::Vector3d(12 * u - 6, 12 * v - 6, 4 * w);
  });
  const std::vector<double> phi =
      fieldOf(box, [](const Eigen::Vector3d& p) { return std::hypot(p.x(), p.y()); });
  IgdsOptions o;
  o.interval = 0.9;
  const IgdsResult r = extractIgds(box, phi, o);
  ASSERT_TRUE(r.ok()) << r.message;
  expectWellFormed(r, "cylinders");
  // Linear interpolation of r along a tet edge of length l at radius r is off by at most about
  // l^2 / (8 r) (the chord of the field); the longest edge projected on the xy plane is the cell
  // diagonal 0.5 sqrt(2). Remeshed vertices lie on the interpolated surface, whose triangles
  // (chords again) add the same order: bound 2 l^2 / (8 r).
  double worstExcess = -1, worst = 0;
  for (const CurvedLayer& layer : r.layers) {
    if (layer.isoValue < 1.5) continue;  // the axis: curvature radius below 3 cells
    const double bound = 2 * 0.5 / (8 * layer.isoValue);
    for (const LayerRegion& region : layer.regions)
      for (size_t v = 0; v < region.mesh.vertexCount(); ++v) {
        const Eigen::Vector3d p = region.mesh.vertex(v);
        const double err = std::abs(std::hypot(p.x(), p.y()) - layer.isoValue);
        worst = std::max(worst, err);
        worstExcess = std::max(worstExcess, err - bound);
      }
  }
  std::printf("cylinders: %zu layers, %zu regions, %zu -> %zu triangles, max |r - phi_i| %.4f mm "
              "(cell 0.5 mm), worst excess over the bound %.4f mm\n",
              r.layers.size(), r.regionCount, r.interpolatedTriangles, r.triangleCount, worst,
              worstExcess);
  EXPECT_LT(worstExcess, 0.0);
  EXPECT_EQ(r.keptInterpolated, 0u);  // every region was remeshed
  // Normals point away from the axis (increasing phi).
  EXPECT_GT(minNormalAlignment(r, [](const Eigen::Vector3d& p) { return Eigen::Vector3d(p.x(), p.y(), 0); }),
            0.8);
}

// phi = distance to the centre of a 10 mm cube: closed spheres for r < 5 (no boundary at all),
// caps cut by the faces beyond.
TEST(Igds, SpheresAroundAPointAreClosedAndOnTheAnalyticSurface) {
  const TetMesh box = gridTets(20, 20, 20, [](double u, double v, double w) {
    return Eigen::Vector3d(10 * u - 5, 10 * v - 5, 10 * w - 5);
  });
  const std::vector<double> phi = fieldOf(box, [](const Eigen::Vector3d& p) { return p.norm(); });
  IgdsOptions o;
  o.interval = 0.8;
  const IgdsResult r = extractIgds(box, phi, o);
  ASSERT_TRUE(r.ok()) << r.message;
  expectWellFormed(r, "spheres");
  // Bound as for the cylinders, with the longest tet edge (cell diagonal 0.5 sqrt(3)).
  double worst = 0, worstExcess = -1;
  for (const CurvedLayer& layer : r.layers) {
    if (layer.isoValue < 4.9) {
      ASSERT_EQ(layer.regions.size(), 1u) << layer.isoValue;
      const LayerRegion& region = layer.regions[0];
      EXPECT_EQ(checkEdges(region.mesh).boundaryEdges, 0u) << "closed sphere " << layer.isoValue;
      // Closed and oriented outward: the enclosed volume is positive, within 10 % of 4/3 pi r^3
      // (inscribed triangles about one mean tet edge long).
      const double rr = layer.isoValue, exact = 4.0 / 3.0 * M_PI * rr * rr * rr;
      if (rr > 2.5) {
        EXPECT_NEAR(test::meshVolume(region.mesh), exact, 0.1 * exact) << rr;
      } else {
        EXPECT_GT(test::meshVolume(region.mesh), 0.0) << rr;
      }
    }
    if (layer.isoValue < 1.5) continue;
    const double bound = 2 * 0.75 / (8 * layer.isoValue);
    for (const LayerRegion& region : layer.regions)
      for (size_t v = 0; v < region.mesh.vertexCount(); ++v) {
        const double err = std::abs(region.mesh.vertex(v).norm() - layer.isoValue);
        worst = std::max(worst, err);
        worstExcess = std::max(worstExcess, err - bound);
      }
  }
  std::printf("spheres: %zu layers, %zu regions (%zu kept as interpolated), %zu -> %zu "
              "triangles, max |r - phi_i| %.4f mm (cell 0.5 mm), worst excess over the bound "
              "%.4f mm\n",
              r.layers.size(), r.regionCount, r.keptInterpolated, r.interpolatedTriangles,
              r.triangleCount, worst, worstExcess);
  EXPECT_LT(r.keptInterpolated, r.regionCount / 4);
  EXPECT_LT(worstExcess, 0.0);
}

// phi = z on a prism sheared by 30 degrees (x' = x + z tan 30): the +x wall overhangs by 30
// degrees, the -x wall leans inward (no overhang), the y walls are vertical. From the second
// layer on, the overhanging boundary is exactly the +x side: alpha = 30, r = Ly / perimeter.
TEST(Igds, SlantedPrismOverhangIsThirtyDegreesOnTheOutwardWall) {
  const double t30 = std::tan(30 * M_PI / 180);
  const double lx = 8, ly = 6, h = 7;
  const TetMesh prism = gridTets(16, 12, 14, [&](double u, double v, double w) {
    return Eigen::Vector3d(lx * u + h * w * t30, ly * v, h * w);
  });
  const std::vector<double> phi = fieldOf(prism, [](const Eigen::Vector3d& p) { return p.z(); });
  IgdsOptions o;
  o.interval = 0.7;
  const IgdsResult r = extractIgds(prism, phi, o);
  ASSERT_TRUE(r.ok()) << r.message;
  expectWellFormed(r, "prism");
  const IgdsMetrics mt = igdsMetrics(r.layers, o.interval, 0.5);
  ASSERT_EQ(mt.layers.size(), r.layers.size());
  // First layer: P' is P's footprint on the platform, straight below: no overhang.
  EXPECT_EQ(mt.layers[0].overhangLengthMm, 0.0);
  for (size_t i = 1; i < mt.layers.size(); ++i) {
    const IgdsLayerMetrics& lm = mt.layers[i];
    EXPECT_NEAR(lm.boundaryLengthMm, 2 * (lx + ly), 1e-6) << i;
    EXPECT_NEAR(lm.overhangLengthMm, ly, 1e-6) << i;
    EXPECT_NEAR(lm.overhangRatio, ly / (2 * (lx + ly)), 1e-6) << i;
    EXPECT_NEAR(lm.overhangAverageDegrees, 30.0, 1e-6) << i;
    EXPECT_NEAR(lm.overhangMaxDegrees, 30.0, 1e-6) << i;
  }
  EXPECT_NEAR(mt.overhangAverageDegrees, 30.0, 1e-6);
  EXPECT_NEAR(mt.overhangMaxLayerDegrees, 30.0, 1e-6);
}

// Frusta (square-to-disc map): widening upward by 30 degrees every boundary point overhangs
// (r ~ 1, alpha ~ 30); narrowing upward none does (r = 0).
TEST(Igds, FrustumWallsOutwardThirtyDegreesInwardZero) {
  const double t30 = std::tan(30 * M_PI / 180);
  for (int sign : {+1, -1}) {
    const double r0 = sign > 0 ? 3.0 : 7.0, h = 6;
    const TetMesh frustum = gridTets(14, 14, 12, [&](double u, double v, double w) {
      const double x = 2 * u - 1, y = 2 * v - 1;
      const double rad = r0 + sign * h * w * t30;
      return Eigen::Vector3d(rad * x * std::sqrt(1 - y * y / 2), rad * y * std::sqrt(1 - x * x / 2),
                             h * w);
    });
    const std::vector<double> phi = fieldOf(frustum, [](const Eigen::Vector3d& p) { return p.z(); });
    IgdsOptions o;
    o.interval = 0.7;
    const IgdsResult r = extractIgds(frustum, phi, o);
    ASSERT_TRUE(r.ok()) << r.message;
    expectWellFormed(r, "frustum");
    const IgdsMetrics mt = igdsMetrics(r.layers, o.interval, 0.5);
    for (size_t i = 1; i < mt.layers.size(); ++i) {
      const IgdsLayerMetrics& lm = mt.layers[i];
      if (sign > 0) {
        EXPECT_GT(lm.overhangRatio, 0.97) << i;
        EXPECT_NEAR(lm.overhangAverageDegrees, 30.0, 1.5) << i;
      } else {
        EXPECT_EQ(lm.overhangRatio, 0.0) << i;
        EXPECT_EQ(lm.overhangAverageDegrees, 0.0) << i;
      }
    }
    std::printf("frustum %s: layer 2 alpha %.2f deg ratio %.3f; overall %.2f deg\n",
                sign > 0 ? "widening" : "narrowing", mt.layers[1].overhangAverageDegrees,
                mt.layers[1].overhangRatio, mt.overhangAverageDegrees);
  }
}

// A U: a bar 30 x 40 x 4 with two 3 mm prongs up to 16 mm (grid tets with the slot between the
// prongs removed), phi = z. Every wall is vertical, so no boundary overhangs. Where the layer splits
// into the two prongs, the new inner walls stand on the previous layer's interior while the
// nearest boundary point of that layer is on the outer wall behind the prong, 3 mm away and
// "outward" of the inner wall: that must not count as overhang (it read 77 degrees before).
TEST(Igds, LayerSplittingIntoTwoProngsHasNoOverhang) {
  const TetMesh full = gridTets(30, 20, 16, [](double u, double v, double w) {
    return Eigen::Vector3d(30 * u, 40 * v, 16 * w);
  });
  TetMesh u;
  u.positions = full.positions;
  for (size_t k = 0; k < full.tetCount(); ++k) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int j = 0; j < 4; ++j) c += full.vertex(full.tets[4 * k + j]) / 4;
    if (c.x() > 3 && c.x() < 27 && c.z() > 4) continue;
    u.tets.insert(u.tets.end(), full.tets.begin() + 4 * k, full.tets.begin() + 4 * k + 4);
  }
  const std::vector<double> phi = fieldOf(u, [](const Eigen::Vector3d& p) { return p.z(); });
  IgdsOptions o;
  o.interval = 0.7;
  const IgdsResult r = extractIgds(u, phi, o);
  ASSERT_TRUE(r.ok()) << r.message;
  const IgdsMetrics mt = igdsMetrics(r.layers, o.interval, 0.5);
  size_t split = 0;
  for (size_t i = 0; i < r.layers.size(); ++i) {
    if (r.layers[i].regions.size() == 2 && !split) split = i;
    EXPECT_EQ(mt.layers[i].overhangLengthMm, 0.0) << "layer " << i;
    EXPECT_EQ(mt.layers[i].overhangAverageDegrees, 0.0) << "layer " << i;
  }
  EXPECT_GT(split, 0u);  // the split happens (layers below it are one region)
  EXPECT_EQ(r.layers[split - 1].regions.size(), 1u);
  EXPECT_EQ(mt.overhangMaxLayerDegrees, 0.0);
}

// ---- bad input, cancellation ----

// A field that slows down above z = 6 (phi = 6 + 0.7 (z - 6)): uniform iso-values i d stand
// d / 0.7 = 1.43 d apart up there; surfaceLimitedIsoValues steps by 0.805 d from the first band
// that reaches z = 6, so the planes stand at most 1.15 d apart, and exactly at i d below.
TEST(Igds, SurfaceLimitedStepsKeepLayersWithinTheRatio) {
  const TetMesh box = gridTets(10, 8, 12, [](double u, double v, double w) {
    return Eigen::Vector3d(10 * u, 8 * v, 12 * w);
  });
  auto phiOfZ = [](double z) { return z <= 6 ? z : 6 + 0.7 * (z - 6); };
  const std::vector<double> phi = fieldOf(box, [&](const Eigen::Vector3d& p) { return phiOfZ(p.z()); });
  const double d = 0.5, maxPhi = phiOfZ(12);
  // Plane heights of the extracted layers (no remeshing: exact planes).
  auto heights = [&](const std::vector<double>& iso) {
    IgdsOptions o;
    o.interval = d;
    o.remesh = false;
    o.isoValues = iso;
    const IgdsResult r = extractIgds(box, phi, o);
    EXPECT_TRUE(r.ok()) << r.message;
    std::vector<double> z;
    for (const CurvedLayer& layer : r.layers) {
      EXPECT_EQ(layer.regions.size(), 1u);
      double lo = 1e9, hi = -1e9;
      for (const LayerRegion& region : layer.regions)
        for (size_t v = 0; v < region.mesh.vertexCount(); ++v) {
          lo = std::min(lo, region.mesh.vertex(v).z());
          hi = std::max(hi, region.mesh.vertex(v).z());
        }
      EXPECT_LT(hi - lo, 1e-9);
      z.push_back(lo);
    }
    return z;
  };
  auto maxGap = [](const std::vector<double>& z) {
    double g = z.empty() ? 0 : z[0];
    for (size_t i = 1; i < z.size(); ++i) g = std::max(g, z[i] - z[i - 1]);
    return g;
  };
  const std::vector<double> uniform = heights({});
  EXPECT_NEAR(maxGap(uniform), d / 0.7, 1e-9);  // what the paper's i d gives

  const std::vector<double> iso = surfaceLimitedIsoValues(box, phi, d, 1.15);
  ASSERT_GT(iso.size(), 20u);
  EXPECT_LT(iso.back(), maxPhi);
  EXPECT_GT(iso.back() + d, maxPhi);
  double previous = 0;
  for (double c : iso) {
    const double step = c - previous;
    if (c + d < 6) {
      EXPECT_NEAR(step, d, 1e-12) << c;  // unit speed: i d
    }
    if (previous >= 6) {
      EXPECT_NEAR(step, 0.805 * d, 1e-12) << c;
    }
    EXPECT_GE(step, 0.805 * d - 1e-12);
    EXPECT_LE(step, d + 1e-12);
    previous = c;
  }
  const std::vector<double> z = heights(iso);
  ASSERT_EQ(z.size(), iso.size());
  EXPECT_LE(maxGap(z), 1.15 * d + 1e-9);
  for (size_t i = 0; i < z.size(); ++i) EXPECT_NEAR(phiOfZ(z[i]), iso[i], 1e-9);
  // Thickness deviation is relative to each layer's step: the planes are exact.
  IgdsOptions o;
  o.interval = d;
  o.remesh = false;
  o.isoValues = iso;
  const IgdsMetrics mt = igdsMetrics(extractIgds(box, phi, o).layers, d, 0.5);
  for (size_t i = 0; i < mt.layers.size(); ++i) {
    const double step = iso[i] - (i ? iso[i - 1] : 0.0);
    const double expected = (z[i] - (i ? z[i - 1] : 0.0)) / step;  // 1 below z = 6
    EXPECT_NEAR(mt.layers[i].thicknessMeanMm, z[i] - (i ? z[i - 1] : 0.0), 1e-9) << i;
    EXPECT_NEAR(mt.layers[i].thicknessMaxDeviationPercent, std::abs(expected - 1) * 100, 1e-6) << i;
  }

  // A unit-speed field gives the paper's i d; bad arguments give nothing.
  const std::vector<double> zphi = fieldOf(box, [](const Eigen::Vector3d& p) { return p.z(); });
  const std::vector<double> plain = surfaceLimitedIsoValues(box, zphi, d, 1.15);
  ASSERT_EQ(plain.size(), 23u);  // i d < 12
  for (size_t i = 0; i < plain.size(); ++i) EXPECT_NEAR(plain[i], double(i + 1) * d, 1e-12);
  EXPECT_TRUE(surfaceLimitedIsoValues(box, zphi, 0.0, 1.15).empty());
  EXPECT_TRUE(surfaceLimitedIsoValues(box, zphi, d, std::nan("")).empty());
  EXPECT_TRUE(surfaceLimitedIsoValues(box, std::vector<double>(3, 1.0), d, 1.15).empty());

  // A field slow everywhere (phi = 0.7 z): every step is 0.7 d but the first, a whole interval
  // (the platform carries the first layer; a shorter first step laid beads closer to the bed
  // than half their height where the field dips at the surface).
  const std::vector<double> slow = fieldOf(box, [](const Eigen::Vector3d& p) { return 0.7 * p.z(); });
  const std::vector<double> steps = surfaceLimitedIsoValues(box, slow, d, 1.0);
  ASSERT_GT(steps.size(), 10u);
  EXPECT_NEAR(steps[0], d, 1e-12);
  for (size_t i = 1; i < steps.size(); ++i) EXPECT_NEAR(steps[i] - steps[i - 1], 0.7 * d, 1e-9) << i;
}

TEST(Igds, BadInputReturnsDocumentedStatuses) {
  const TetMesh box = gridTets(3, 3, 3, [](double u, double v, double w) {
    return Eigen::Vector3d(3 * u, 3 * v, 3 * w);
  });
  const std::vector<double> phi = fieldOf(box, [](const Eigen::Vector3d& p) { return p.z(); });
  IgdsOptions o;
  // Size mismatch.
  EXPECT_EQ(extractIgds(box, std::vector<double>(phi.begin(), phi.end() - 1), o).status,
            Status::InvalidOption);
  // NaN distance / coordinate.
  std::vector<double> nan = phi;
  nan[5] = std::nan("");
  EXPECT_EQ(extractIgds(box, nan, o).status, Status::NonFiniteVertex);
  TetMesh badCoord = box;
  badCoord.positions[7] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(extractIgds(badCoord, phi, o).status, Status::NonFiniteVertex);
  // Interval <= 0 or not finite.
  for (double d : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    o.interval = d;
    EXPECT_EQ(extractIgds(box, phi, o).status, Status::InvalidOption) << d;
  }
  // Too many iso-values.
  o.interval = 1e-6;
  o.maxLayers = 1000;
  const IgdsResult many = extractIgds(box, phi, o);
  EXPECT_EQ(many.status, Status::InvalidOption);
  EXPECT_FALSE(many.message.empty());
  // Negative options.
  o = IgdsOptions{};
  o.minRegionArea = -1;
  EXPECT_EQ(extractIgds(box, phi, o).status, Status::InvalidOption);
  o = IgdsOptions{};
  o.remeshIterations = -1;
  EXPECT_EQ(extractIgds(box, phi, o).status, Status::InvalidOption);
  // No tets; a field below one interval; an index out of range.
  EXPECT_EQ(extractIgds(TetMesh{}, {}, IgdsOptions{}).status, Status::EmptyInput);
  EXPECT_EQ(extractIgds(box, std::vector<double>(phi.size(), 0.5), IgdsOptions{}).status,
            Status::EmptyInput);
  TetMesh badIndex = box;
  badIndex.tets[3] = 999;
  EXPECT_EQ(extractIgds(badIndex, phi, IgdsOptions{}).status, Status::DegenerateInput);
  // Given iso-values that do not increase, or are not finite and positive; those beyond max phi
  // are dropped, and none left is EmptyInput.
  for (const std::vector<double>& bad :
       {std::vector<double>{1.0, 0.5}, {1.0, 1.0}, {0.0, 1.0}, {1.0, std::nan("")}}) {
    o = IgdsOptions{};
    o.isoValues = bad;
    EXPECT_EQ(extractIgds(box, phi, o).status, Status::InvalidOption);
  }
  o = IgdsOptions{};
  o.isoValues = {1.5, 2.5, 3.5, 4.5};
  const IgdsResult given = extractIgds(box, phi, o);
  ASSERT_TRUE(given.ok()) << given.message;
  ASSERT_EQ(given.layers.size(), 2u);
  EXPECT_EQ(given.layers[1].isoValue, 2.5);
  o.isoValues = {3.5};
  EXPECT_EQ(extractIgds(box, phi, o).status, Status::EmptyInput);
  // Metrics with a bad interval: empty.
  EXPECT_TRUE(igdsMetrics({}, 1.0).layers.empty());
  EXPECT_TRUE(igdsMetrics(extractIgds(box, phi).layers, 0.0).layers.empty());
}

TEST(Igds, CancellationStopsEarly) {
  const TetMesh box = gridTets(10, 10, 20, [](double u, double v, double w) {
    return Eigen::Vector3d(10 * u, 10 * v, 20 * w);
  });
  const std::vector<double> phi = fieldOf(box, [](const Eigen::Vector3d& p) { return p.z(); });
  int calls = 0;
  bool sawStage = true;
  const IgdsResult r = extractIgds(box, phi, IgdsOptions{}, [&](const char* stage, double) {
    sawStage = sawStage && std::string(stage) == "igds";
    return ++calls < 5;
  });
  EXPECT_EQ(r.status, Status::Cancelled);
  EXPECT_TRUE(r.layers.empty());
  EXPECT_EQ(calls, 5);
  EXPECT_TRUE(sawStage);
}

// ---- shared tet models ----

struct Model {
  TetMesh mesh;
  std::vector<double> phi;
  double maxPhi = 0;
  double fieldMs = 0;
};

// Reads a shared .tet (Y-up), rotates +Y to +Z (x, y, z) -> (x, -z, y) (a proper rotation, tets
// stay positive), puts the lowest point on z = 0 and computes the heat geodesic distance from the
// platform vertices (within 1 mm of the bottom).
const Model& model(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Model>> cache;
  auto& slot = cache[name];
  if (slot) return *slot;
  slot = std::make_unique<Model>();
  const std::vector<uint8_t> bytes = test::readBytes(test::sharedModelsDir() / name);
  TetMeshResult read = readTetMesh(bytes.data(), bytes.size());
  EXPECT_TRUE(read.ok()) << name << ": " << read.message;
  TetMesh& m = read.mesh;
  double minZ = 1e300;
  for (size_t i = 0; i < m.vertexCount(); ++i) {
    const double y = m.positions[3 * i + 1], z = m.positions[3 * i + 2];
    m.positions[3 * i + 1] = -z;
    m.positions[3 * i + 2] = y;
    minZ = std::min(minZ, y);
  }
  for (size_t i = 0; i < m.vertexCount(); ++i) m.positions[3 * i + 2] -= minZ;
  slot->mesh = m;
  const HeatGeodesic hg(slot->mesh);
  EXPECT_TRUE(hg.status().ok()) << hg.status().message;
  const std::vector<uint32_t> sources = platformVertices(slot->mesh, 1.0);
  const GeodesicField f = hg.distanceFrom(sources, heightsAboveLowest(slot->mesh, sources));
  EXPECT_TRUE(f.ok()) << f.message;
  slot->phi = f.distance;
  slot->maxPhi = f.maxDistance;
  slot->fieldMs = f.setupMs + f.heatMs + f.gradientMs + f.poissonMs;
  return *slot;
}

const char* kModels[] = {"reinforcedfdm_YogaNew.tet", "reinforcedfdm_bunnyhead.tet",
                         "reinforcedfdm_topopt_new.tet"};

struct Extraction {
  IgdsResult remeshed, interpolated;
  double ms = 0;
};

const Extraction& extraction(const std::string& name, double interval) {
  static std::map<std::pair<std::string, double>, std::unique_ptr<Extraction>> cache;
  auto& slot = cache[{name, interval}];
  if (slot) return *slot;
  slot = std::make_unique<Extraction>();
  const Model& m = model(name);
  IgdsOptions o;
  o.interval = interval;
  const auto t0 = std::chrono::steady_clock::now();
  slot->remeshed = extractIgds(m.mesh, m.phi, o);
  slot->ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  o.remesh = false;
  slot->interpolated = extractIgds(m.mesh, m.phi, o);
  return *slot;
}

// The paper's interval 0.6 mm: invariants of every region and between successive layers.
TEST(IgdsModels, InvariantsOnSharedTetModels) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  for (const char* name : kModels) {
    const Model& m = model(name);
    const Extraction& e = extraction(name, 0.6);
    const IgdsResult& r = e.remeshed;
    ASSERT_TRUE(r.ok()) << name << ": " << r.message;
    ASSERT_TRUE(e.interpolated.ok()) << name << ": " << e.interpolated.message;
    expectWellFormed(r, name);
    expectWellFormed(e.interpolated, std::string(name) + " (interpolated)");
    const double L = tetQuality(m.mesh).meanEdge;
    size_t nonEmpty = 0, closed = 0;
    for (const CurvedLayer& l : r.layers) nonEmpty += l.regions.empty() ? 0 : 1;
    std::printf("%s: %zu tets, max phi %.2f mm, field %.0f ms; d 0.6: %zu iso-values (%zu non-empty), "
                "%zu regions (%zu kept as interpolated), %zu interpolated -> %zu remeshed triangles (L %.2f mm); "
                "interpolation %.0f ms, remeshing %.0f ms, smoothing %.0f ms, total %.0f ms\n",
                name, m.mesh.tetCount(), m.maxPhi, m.fieldMs, r.layers.size(), nonEmpty,
                r.regionCount, r.keptInterpolated, r.interpolatedTriangles, r.triangleCount, L, r.interpolationMs,
                r.remeshMs, r.smoothMs, e.ms);
    // Open boundaries lie on the tet mesh's boundary surface.
    const AabbTree boundary(tetBoundary(m.mesh));
    double worstBoundary = 0;
    for (const CurvedLayer& l : r.layers)
      for (const LayerRegion& region : l.regions) {
        bool any = false;
        for (size_t v = 0; v < region.mesh.vertexCount(); ++v) {
          if (!region.boundaryVertex[v]) continue;
          any = true;
          worstBoundary = std::max(worstBoundary, boundary.closest(region.mesh.vertex(v)).distance);
        }
        closed += any ? 0 : 1;
      }
    EXPECT_LT(worstBoundary, 1e-6) << name;
    // No region intersects itself; no triangle of layer i meets one of layer i + 1.
    size_t selfHits = 0, crossHits = 0;
    for (size_t i = 0; i < r.layers.size(); ++i) {
      TriSoup own;
      int64_t base = 0;
      for (size_t k = 0; k < r.layers[i].regions.size(); ++k) {
        addRegion(own, r.layers[i].regions[k], int(k), base);
        base += int64_t(r.layers[i].regions[k].mesh.vertexCount());
      }
      // Regions of one layer are disjoint iso-surface pieces: test them all as one group.
      std::fill(own.group.begin(), own.group.end(), 0);
      Eigen::Vector3d where(0, 0, 0);
      const size_t self = countIntersections(own, false, 2 * L, 1e-9, &where);
      if (self > 0)
        std::printf("  layer %zu: %zu self-intersecting pairs near (%.2f %.2f %.2f)\n", i, self,
                    where.x(), where.y(), where.z());
      selfHits += self;
      if (i + 1 < r.layers.size()) {
        TriSoup pair;
        for (const LayerRegion& region : r.layers[i].regions) addRegion(pair, region, 0, 0);
        for (const LayerRegion& region : r.layers[i + 1].regions) addRegion(pair, region, 1, 0);
        const size_t cross = countIntersections(pair, true, 2 * L, 1e-9, &where);
        if (cross > 0)
          std::printf("  layers %zu/%zu: %zu crossing pairs near (%.2f %.2f %.2f)\n", i, i + 1,
                      cross, where.x(), where.y(), where.z());
        crossHits += cross;
      }
    }
    std::printf("%s: %zu closed regions, boundary vertices within %.2g mm of the tet boundary; "
                "%zu self-intersecting and %zu crossing triangle pairs\n",
                name, closed, worstBoundary, selfHits, crossHits);
    EXPECT_EQ(selfHits, 0u) << name;
    EXPECT_EQ(crossHits, 0u) << name;
    // Remeshing quality: edge lengths near L, better minimum angles, close to the interpolation.
    // Edge lengths against each region's own remeshing length (regions kept as interpolated,
    // length 0, are left out of the quality figures).
    ASSERT_EQ(r.regionTargetEdge.size(), r.layers.size());
    size_t edges = 0, inRange = 0, remeshedRegions = 0, remeshedTriangles = 0, atL = 0;
    double sumMinRemeshed = 0, sumMinInterp = 0;
    size_t below20Remeshed = 0, below20Interp = 0;
    for (size_t li = 0; li < r.layers.size(); ++li) {
      ASSERT_EQ(r.regionTargetEdge[li].size(), r.layers[li].regions.size());
      for (size_t k = 0; k < r.layers[li].regions.size(); ++k) {
        const double Lr = r.regionTargetEdge[li][k];
        if (Lr == 0) continue;
        EXPECT_LE(Lr, L * (1 + 1e-12));
        EXPECT_GE(Lr, 0.6 * (1 - 1e-12));
        ++remeshedRegions;
        atL += Lr == L ? 1 : 0;
        const Mesh& mm = r.layers[li].regions[k].mesh;
        remeshedTriangles += mm.faceCount();
        for (size_t f = 0; f < mm.faceCount(); ++f) {
          for (int c = 0; c < 3; ++c) {
            const double len = (mm.vertex(mm.triangles[3 * f + c]) -
                                mm.vertex(mm.triangles[3 * f + (c + 1) % 3]))
                                   .norm();
            ++edges;
            inRange += (len >= 0.5 * Lr && len <= 2 * Lr) ? 1 : 0;
          }
          const double a = minAngleDegrees(mm, f);
          sumMinRemeshed += a;
          below20Remeshed += a < 20 ? 1 : 0;
        }
      }
    }
    EXPECT_EQ(r.regionCount - remeshedRegions, r.keptInterpolated) << name;
    // Remeshing keeps each region's topology (Euler characteristic, boundary loops): regions
    // come in the same order as the interpolated ones.
    size_t topologyChanged = 0;
    for (size_t li = 0; li < r.layers.size(); ++li) {
      ASSERT_EQ(r.layers[li].regions.size(), e.interpolated.layers[li].regions.size()) << name;
      for (size_t k = 0; k < r.layers[li].regions.size(); ++k)
        if (topology(r.layers[li].regions[k].mesh) !=
            topology(e.interpolated.layers[li].regions[k].mesh))
          ++topologyChanged;
    }
    EXPECT_EQ(topologyChanged, 0u) << name;
    for (const CurvedLayer& l : e.interpolated.layers)
      for (const LayerRegion& region : l.regions)
        for (size_t f = 0; f < region.mesh.faceCount(); ++f) {
          const double a = minAngleDegrees(region.mesh, f);
          sumMinInterp += a;
          below20Interp += a < 20 ? 1 : 0;
        }
    const double fracInRange = double(inRange) / double(edges);
    const double meanMinR = sumMinRemeshed / double(remeshedTriangles),
                 meanMinI = sumMinInterp / double(e.interpolated.triangleCount);
    const double fracBadR = double(below20Remeshed) / double(remeshedTriangles),
                 fracBadI = double(below20Interp) / double(e.interpolated.triangleCount);
    // Distance of the remeshed surface (vertices and triangle centroids) to the interpolated one.
    double worstVertex = 0, worstCentroid = 0;
    ASSERT_EQ(r.layers.size(), e.interpolated.layers.size());
    for (size_t i = 0; i < r.layers.size(); ++i) {
      if (r.layers[i].regions.empty()) continue;
      const AabbTree interp(mergeLayer(e.interpolated.layers[i]));
      for (const LayerRegion& region : r.layers[i].regions) {
        const Mesh& mm = region.mesh;
        for (size_t v = 0; v < mm.vertexCount(); ++v)
          worstVertex = std::max(worstVertex, interp.closest(mm.vertex(v)).distance);
        for (size_t f = 0; f < mm.faceCount(); ++f) {
          const Eigen::Vector3d c = (mm.vertex(mm.triangles[3 * f]) + mm.vertex(mm.triangles[3 * f + 1]) +
                                     mm.vertex(mm.triangles[3 * f + 2])) / 3;
          worstCentroid = std::max(worstCentroid, interp.closest(c).distance);
        }
      }
    }
    std::printf("%s: %zu regions remeshed (%zu at L, the others shorter); their edges in [L/2, 2L] "
                "%.1f %%; mean min angle %.1f -> %.1f deg; triangles with "
                "min angle < 20 deg %.1f %% -> %.1f %%; distance to the interpolated IGDS: vertices "
                "<= %.2g mm, centroids <= %.3f mm\n",
                name, remeshedRegions, atL, 100 * fracInRange, meanMinI, meanMinR, 100 * fracBadI, 100 * fracBadR,
                worstVertex, worstCentroid);
    EXPECT_GT(fracInRange, 0.9) << name;
    EXPECT_GT(meanMinR, meanMinI + 5) << name;
    EXPECT_LT(fracBadR, 0.5 * fracBadI) << name;
    EXPECT_LT(worstVertex, 1e-6) << name;
    EXPECT_LT(worstCentroid, 0.25 * L) << name;
  }
}

// The heat field is slowest at the part's surface; uniform iso-values leave the layers' edges
// farther apart there than the interval. surfaceLimitedIsoValues (ratio 1) keeps the 95th
// percentile of the edge-to-previous-layer distance near d (the quantile is by face area, this
// check by boundary vertex, hence 5 % slack) and below the uniform layers' on every model.
TEST(IgdsModels, SurfaceLimitedStepsThinTheEdgesOnRealFields) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const double d = 0.6;
  for (const char* name : kModels) {
    const Model& m = model(name);
    auto edgeGap95 = [&](const std::vector<double>& iso, size_t& layers) {
      IgdsOptions o;
      o.interval = d;
      o.remesh = false;
      o.isoValues = iso;
      const IgdsResult r = extractIgds(m.mesh, m.phi, o);
      EXPECT_TRUE(r.ok()) << r.message;
      layers = r.layers.size();
      std::vector<double> gaps;
      for (size_t i = 1; i < r.layers.size(); ++i) {
        if (r.layers[i - 1].regions.empty()) continue;
        const AabbTree below(mergeLayer(r.layers[i - 1]));
        for (const LayerRegion& region : r.layers[i].regions)
          for (size_t v = 0; v < region.mesh.vertexCount(); ++v)
            if (region.boundaryVertex[v]) gaps.push_back(below.closest(region.mesh.vertex(v)).distance);
      }
      std::sort(gaps.begin(), gaps.end());
      return gaps.empty() ? 0.0 : gaps[gaps.size() * 95 / 100];
    };
    size_t uniformLayers = 0, limitedLayers = 0;
    const double uniform = edgeGap95({}, uniformLayers);
    const std::vector<double> iso = surfaceLimitedIsoValues(m.mesh, m.phi, d, 1.0);
    const double limited = edgeGap95(iso, limitedLayers);
    std::printf("%s at %.1f mm: edge gap (95th pct) uniform %.3f mm (%zu layers), limited %.3f mm "
                "(%zu layers)\n",
                name, d, uniform, uniformLayers, limited, limitedLayers);
    EXPECT_LT(limited, 1.05 * d) << name;
    EXPECT_LT(limited, uniform) << name;
    EXPECT_GT(uniform, 1.1 * d) << name << ": the uniform layers' edges are too far apart";
    EXPECT_LT(double(limitedLayers), 2.0 * double(uniformLayers)) << name;
  }
}

// Paper Fig. 7: 44 layers at 1 mm on its Y model. Here the Yoga: floor(max phi / d) iso-values
// (i d < max phi), all kept; only the topmost few can be empty (regions below minRegionArea).
TEST(IgdsModels, YogaLayerCountAtOneMillimetre) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Model& m = model("reinforcedfdm_YogaNew.tet");
  const Extraction& e = extraction("reinforcedfdm_YogaNew.tet", 1.0);
  ASSERT_TRUE(e.remeshed.ok()) << e.remeshed.message;
  size_t expected = size_t(std::floor(m.maxPhi / 1.0));
  if (double(expected) * 1.0 >= m.maxPhi) --expected;
  EXPECT_EQ(e.remeshed.layers.size(), expected);
  size_t empty = 0;
  for (size_t i = 0; i < e.remeshed.layers.size(); ++i) {
    EXPECT_DOUBLE_EQ(e.remeshed.layers[i].isoValue, double(i + 1));
    if (e.remeshed.layers[i].regions.empty()) {
      ++empty;
      EXPECT_GT(double(i + 1), m.maxPhi - 2) << "only the top can be empty";
    }
  }
  std::printf("Yoga at 1 mm: max phi %.2f mm, %zu iso-values, %zu empty, %zu non-empty layers, "
              "%zu regions, %.0f ms\n",
              m.maxPhi, e.remeshed.layers.size(), empty, e.remeshed.layers.size() - empty,
              e.remeshed.regionCount, e.ms);
}

// Eq. 11 and Fig. 10 on the three models at 0.6 mm; the paper's claim (average overhang below 45
// degrees on its Y model and kitten) checked on the Yoga.
TEST(IgdsModels, OverhangAndThicknessMetrics) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  for (const char* name : kModels) {
    const Extraction& e = extraction(name, 0.6);
    ASSERT_TRUE(e.remeshed.ok()) << name << ": " << e.remeshed.message;
    const auto t0 = std::chrono::steady_clock::now();
    const IgdsMetrics mt = igdsMetrics(e.remeshed.layers, 0.6, 1.0);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_EQ(mt.layers.size(), e.remeshed.layers.size());
    size_t withBoundary = 0, below45 = 0;
    double meanRatio = 0, meanThickDev = 0;
    size_t thickLayers = 0;
    for (const IgdsLayerMetrics& lm : mt.layers) {
      EXPECT_GE(lm.overhangRatio, 0);
      EXPECT_LE(lm.overhangRatio, 1);
      EXPECT_LE(lm.overhangAverageDegrees, lm.overhangMaxDegrees + 1e-9);
      EXPECT_LE(lm.overhangMaxDegrees, 180);
      if (lm.boundaryLengthMm <= 0) continue;
      ++withBoundary;
      below45 += lm.overhangAverageDegrees < 45 ? 1 : 0;
      meanRatio += lm.overhangRatio;
      if (lm.thicknessSamples > 0) {
        meanThickDev += lm.thicknessMeanDeviationPercent;
        ++thickLayers;
      }
    }
    meanRatio /= double(std::max<size_t>(1, withBoundary));
    meanThickDev /= double(std::max<size_t>(1, thickLayers));
    std::printf("%s metrics (%.0f ms): average overhang %.1f deg, max layer average %.1f deg, "
                "layers with average < 45 deg: %zu / %zu, mean overhang ratio %.2f; thickness mean "
                "deviation %.1f %% (mean over layers), max deviation %.0f %%\n",
                name, ms, mt.overhangAverageDegrees, mt.overhangMaxLayerDegrees, below45,
                withBoundary, meanRatio, meanThickDev, mt.thicknessMaxDeviationPercent);
    std::printf("%s per-layer average overhang (deg):", name);
    for (size_t i = 0; i < mt.layers.size(); ++i) std::printf(" %.0f", mt.layers[i].overhangAverageDegrees);
    std::printf("\n");
    if (std::string(name) == "reinforcedfdm_YogaNew.tet") {
      EXPECT_GE(double(below45), 0.9 * double(withBoundary)) << name;
    }
    // Issue 6's target on the Yoga (and the bunny head): every layer's average overhang below
    // 45 deg, here at full size. Measured 21.4 and 21.3 deg; 51.3 and 47.2 deg (the first IGDS
    // over the sole reaching the platform outside it) before the sources were held.
    if (std::string(name) != "reinforcedfdm_topopt_new.tet") {
      EXPECT_LT(mt.overhangMaxLayerDegrees, 45) << name;
    }
  }
}

// The voxel method's Fermat-spiral fill consumes these regions as they are.
TEST(IgdsModels, FermatSpiralFillsRealRegions) {
  OMNISLICE_REQUIRE_SHARED_MODELS();
  const Extraction& e = extraction("reinforcedfdm_YogaNew.tet", 0.6);
  ASSERT_TRUE(e.remeshed.ok()) << e.remeshed.message;
  const size_t n = e.remeshed.layers.size();
  size_t tried = 0;
  for (size_t i : {size_t(0), n / 4, n / 2, 3 * n / 4, n - 2}) {
    for (const LayerRegion& region : e.remeshed.layers[i].regions) {
      if (region.area < 20) continue;
      SpiralOptions so;
      so.spacing = 0.8;
      const SpiralResult s = fermatSpiralPaths(region.mesh, so);
      ASSERT_TRUE(s.ok()) << "layer " << i << ": " << s.message;
      ASSERT_FALSE(s.paths.empty()) << "layer " << i;
      double length = 0;
      for (const SurfacePath& p : s.paths)
        for (size_t k = 1; k < p.points.size(); ++k) length += (p.points[k] - p.points[k - 1]).norm();
      // Length ~ area / spacing (the fill covers the region).
      EXPECT_GT(length, 0.6 * region.area / so.spacing) << "layer " << i;
      EXPECT_LT(length, 1.4 * region.area / so.spacing) << "layer " << i;
      ++tried;
    }
  }
  EXPECT_GE(tried, 4u);
}

}  // namespace
}  // namespace omnislice
