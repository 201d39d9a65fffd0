// SPDX-License-Identifier: MIT
// Internal to the connected Fermat spirals (fermat_spiral.cpp): the iso-contours of the boundary
// distance phi and the band pieces between them (steps 2 and 3 of fermat_spiral.cpp's comment),
// contours as closed polylines with the positions the spiral construction cuts them at, and the
// consistently oriented face normals they are seen against.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "mesh/mesh.h"
#include "mesh/mesh_topology.h"

namespace omnislice::fermat_detail {

// A child chain spliced into a host contour through a gap.
struct Splice {
  double pos = 0;  // arc position on the host contour
  int chain = -1;  // child chain spliced in
  int side = 1;    // +1: the child lies on the host's left, -1: on its right
};

struct Contour {
  std::vector<Eigen::Vector3d> pts;  // closed polyline; segment i runs pts[i] -> pts[i+1 mod n]
  std::vector<int> tri;              // triangle of segment i
  std::vector<double> cum;           // arc length at pts[i]; cum[n] = length
  int level = 0;
  int lower = -1, upper = -1;  // pieces below / above (phi smaller / larger)
  bool dropped = false;        // too short to carry gaps
  int chain = -1;
  int forward = -1;            // the piece ahead in its chain (on the contour's left)
  double breakPos = 0;         // arc position of the Fermat break (cut line)
  double gap = 0;              // half width of the gaps cut in this contour
  std::vector<Splice> splices;

  double length() const { return cum.back(); }
  size_t size() const { return pts.size(); }
  // Point at arc position s (taken modulo the length) and the segment it lies on.
  Eigen::Vector3d at(double s, size_t* segment = nullptr) const {
    const double L = length();
    s = std::fmod(s, L);
    if (s < 0) s += L;
    size_t i = static_cast<size_t>(std::upper_bound(cum.begin(), cum.end(), s) - cum.begin());
    i = std::min(std::max<size_t>(i, 1), pts.size()) - 1;
    const double segLen = cum[i + 1] - cum[i];
    const double t = segLen > 0 ? (s - cum[i]) / segLen : 0.0;
    if (segment) *segment = i;
    return pts[i] + t * (pts[(i + 1) % pts.size()] - pts[i]);
  }
  void reverse() {
    const size_t n = pts.size();
    std::vector<Eigen::Vector3d> p(n);
    std::vector<int> t(n);
    for (size_t i = 0; i < n; ++i) {
      p[i] = pts[(n - i) % n];
      t[i] = tri[(2 * n - 1 - i) % n];  // new segment i = old segment between old n-i and n-i-1
    }
    pts.swap(p);
    tri.swap(t);
    computeArcLength();
  }
  void computeArcLength() {
    cum.assign(pts.size() + 1, 0.0);
    for (size_t i = 0; i < pts.size(); ++i) {
      cum[i + 1] = cum[i] + (pts[(i + 1) % pts.size()] - pts[i]).norm();
    }
  }
  // Arc position of the closest point of the contour to q.
  double closestPosition(const Eigen::Vector3d& q) const {
    double best = std::numeric_limits<double>::infinity(), pos = 0;
    const size_t n = pts.size();
    for (size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d a = pts[i], b = pts[(i + 1) % n];
      const Eigen::Vector3d ab = b - a;
      const double len2 = ab.squaredNorm();
      const double t = len2 > 0 ? std::clamp((q - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      const double d = (a + t * ab - q).squaredNorm();
      if (d < best) {
        best = d;
        pos = cum[i] + t * (cum[i + 1] - cum[i]);
      }
    }
    return pos;
  }
};

struct ContourSet {
  std::vector<Contour> contours;
  int pieces = 0;
  std::vector<int> pieceBand;
};

// Consistent face normals: breadth-first over manifold edges, flipping a neighbour that runs the
// shared edge the same way; each component keeps its majority orientation.
std::vector<Eigen::Vector3d> orientedFaceNormals(const Mesh& mesh, const MeshEdges& edges);

// Marching-triangles contours of phi at the given increasing levels and the band pieces.
// Convention: a vertex is "above" level v when phi >= v, so a level through a vertex is handled
// as if the vertex were infinitesimally above it.
ContourSet extractContours(const Mesh& mesh, const MeshEdges& edges, const std::vector<double>& phi,
                           const std::vector<double>& levels);

// Orient a contour so that larger phi lies on its left (seen against the face normals).
void orientUpLeft(Contour& c, const Mesh& mesh, const std::vector<double>& phi,
                  const std::vector<Eigen::Vector3d>& faceNormal);

}  // namespace omnislice::fermat_detail
