// SPDX-License-Identifier: MIT
#include "multidir/multidir_parts.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "multidir/risky_faces.h"

namespace omnislice {

// Why reach across: where a later part's base plane crosses the earlier
// part's layers steeply (beta near 90 degrees), the earlier part's outer beads end w/2 inside the
// plane and the later part's first tips lie h/2 above it: w/2 + h/2 apart, beyond the 1.5 h that
// holds a bead. Reaching across brings them within it. The bound keeps the later part's nozzle
// clear: the earlier part's layers stand out of their cut by up to (h/2)|cos beta|, so with
// halfHeightScale <= h/2 they stay under the later part's first tip. Report volumes are the
// exact pieces'.
Outcome reachAcross(const Mesh& model, const std::vector<Plane>& planes, int planeIndex, const Eigen::Vector3d& d,
                    double halfHeightScale, Mesh& reaching, double& deepest) {
  const size_t bound = planeIndex < 0 ? planes.size() : static_cast<size_t>(planeIndex);
  reaching = Mesh();
  deepest = 0;
  if (bound == 0) return {};
  Mesh s;
  if (planeIndex >= 0) {
    ClipResult c = clipByPlane(model, planes[static_cast<size_t>(planeIndex)]);
    if (!c.ok()) return c;
    s = std::move(c.above);
  } else {
    s = model;
  }
  for (size_t j = 0; j < bound && !s.empty(); ++j) {
    const double len = planes[j].normal.norm();
    const Eigen::Vector3d n = planes[j].normal / len;
    const Plane shifted{n, planes[j].offset / len + halfHeightScale * (1 - std::abs(n.dot(d)))};
    double highest = -std::numeric_limits<double>::infinity();
    for (size_t v = 0; v < s.vertexCount(); ++v) highest = std::max(highest, n.dot(s.vertex(v)));
    if (highest <= shifted.offset) continue;  // wholly below: nothing to cut
    if (highest > planes[j].offset / len) deepest = std::max(deepest, shifted.offset - planes[j].offset / len);
    ClipResult c = clipByPlane(s, shifted);
    if (!c.ok()) return c;
    s = std::move(c.below);
  }
  reaching = std::move(s);
  return {};
}

void riskyFlags(const Mesh& part, const std::vector<Plane>& planes, double alphaMaxDeg, double bandMm,
                std::vector<uint8_t>& riskyBefore, std::vector<uint8_t>& riskyAfter) {
  const double sinAlpha = sinAlphaMax(alphaMaxDeg);
  const size_t nf = part.faceCount();
  riskyBefore.assign(nf, 0);
  riskyAfter.assign(nf, 0);
  for (size_t f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = part.vertex(part.triangles[3 * f]);
    const Eigen::Vector3d b = part.vertex(part.triangles[3 * f + 1]);
    const Eigen::Vector3d c = part.vertex(part.triangles[3 * f + 2]);
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    if (!(cross.norm() > 0)) continue;  // degenerate: never risky
    const Eigen::Vector3d n = cross.normalized();
    const Eigen::Vector3d centroid = (a + b + c) / 3;
    const bool onPlatform = centroid.z() < bandMm;
    const bool riskyUp = !onPlatform && riskyAlong(n, Eigen::Vector3d::UnitZ(), sinAlpha);
    riskyBefore[f] = riskyUp ? 1 : 0;
    bool after = riskyUp;
    for (const Plane& q : planes) {
      const double len = q.normal.norm();
      if (!(len > 0)) continue;
      const Eigen::Vector3d d = q.normal / len;
      if (d.dot(centroid) >= q.offset / len) {
        after = riskyAlong(n, d, sinAlpha);
        break;
      }
    }
    riskyAfter[f] = after ? 1 : 0;
  }
}

}  // namespace omnislice
