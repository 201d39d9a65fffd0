// SPDX-License-Identifier: MIT
#include "mesh/clip_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "geometry/triangulate_polygons.h"
#include "mesh/mesh_measures.h"
#include "mesh/mesh_topology.h"

namespace omnislice {
namespace {

inline uint32_t nextInFace(uint32_t h) { return h - h % 3 + (h % 3 + 1) % 3; }

// Farthest a vertex may lie from the plane, relative to the bounding-box diagonal, and still be
// taken as on it to avoid a sliver (see ClipResult::sliverSnaps).
constexpr double kSliverSnapRatio = 1e-5;

struct UnitPlane {
  Eigen::Vector3d n{0, 0, 1};
  double d = 0;
};

Outcome checkPlane(const Plane& plane, UnitPlane& out) {
  Outcome o;
  const double len = plane.normal.norm();
  if (!plane.normal.allFinite() || !std::isfinite(plane.offset) || !std::isfinite(len)) {
    o.status = Status::InvalidOption;
    o.message = "plane normal or offset is not finite";
  } else if (!(len > 0) || !(plane.normal / len).allFinite()) {
    o.status = Status::InvalidOption;
    o.message = "plane normal is zero";
  } else {
    out.n = plane.normal / len;
    out.d = plane.offset / len;
    if (!std::isfinite(out.d)) {
      o.status = Status::InvalidOption;
      o.message = "plane offset overflows once the normal is normalised";
    }
  }
  return o;
}

Outcome checkTolerance(double snapTolerance) {
  Outcome o;
  if (!(snapTolerance >= 0) || !std::isfinite(snapTolerance)) {
    o.status = Status::InvalidOption;
    o.message = "snap tolerance must be finite and >= 0, got " + std::to_string(snapTolerance);
  }
  return o;
}

// The twin of every half-edge: on a two-face edge its other half-edge; on an edge with more faces
// (solids touching along an edge, which a clip through a concave edge lying in the plane can
// leave) the faces are sorted by angle round the edge, and a face running u -> v is paired with
// the one just before it counter-clockwise about u -> v, across the solid wedge between them
// (faces that do not alternate that way, e.g. at one angle, are paired in order). Empty, with why
// set, when an edge has one face or more faces one way than the other.
std::vector<uint32_t> pairHalfedges(const Mesh& mesh, const MeshEdges& edges, std::string& why) {
  std::vector<uint32_t> twin(mesh.triangles.size(), kNoIndex);
  size_t boundary = 0, unpaired = 0, misoriented = 0;
  std::vector<std::pair<double, uint32_t>> fan;
  for (size_t e = 0; e < edges.edgeCount(); ++e) {
    const uint32_t n = edges.faceCount[e];
    const uint32_t h1 = edges.firstHalfedge[e];
    if (n == 1) {
      ++boundary;
      continue;
    }
    if (n == 2) {
      const uint32_t h2 = edges.nextHalfedge[h1];
      if (mesh.triangles[h1] == mesh.triangles[h2]) ++misoriented;
      twin[h1] = h2;
      twin[h2] = h1;
      continue;
    }
    const uint32_t u = static_cast<uint32_t>(edges.keys[e] >> 32);
    const Eigen::Vector3d pu = mesh.vertex(u);
    const Eigen::Vector3d d =
        (mesh.vertex(static_cast<uint32_t>(edges.keys[e] & 0xFFFFFFFFu)) - pu).normalized();
    const Eigen::Vector3d e1 = d.unitOrthogonal(), e2 = d.cross(e1);
    fan.clear();
    for (uint32_t h = h1; h != kNoIndex; h = edges.nextHalfedge[h]) {
      const Eigen::Vector3d r = mesh.vertex(mesh.triangles[h - h % 3 + (h % 3 + 2) % 3]) - pu;
      fan.push_back({std::atan2(r.dot(e2), r.dot(e1)), h});
    }
    std::sort(fan.begin(), fan.end());
    bool ok = n % 2 == 0;
    for (uint32_t i = 0; i < n && ok; ++i) {
      const uint32_t h = fan[i].second, g = fan[(i + n - 1) % n].second;
      if (fan[i].first == fan[(i + n - 1) % n].first) ok = false;
      if (mesh.triangles[h] != u) continue;  // v -> u faces are paired from their partner
      if (mesh.triangles[g] == u) ok = false;
      twin[h] = g;
      twin[g] = h;
    }
    if (!ok) {
      // Faces at one angle (a sliver far below any tolerance, left by many clips): pair the two
      // directions in order, which keeps the topology consistent, if they balance.
      std::vector<uint32_t> forward, backward;
      for (uint32_t h = h1; h != kNoIndex; h = edges.nextHalfedge[h]) {
        (mesh.triangles[h] == u ? forward : backward).push_back(h);
      }
      if (forward.size() != backward.size()) {
        ++unpaired;
        continue;
      }
      for (size_t i = 0; i < forward.size(); ++i) {
        twin[forward[i]] = backward[i];
        twin[backward[i]] = forward[i];
      }
    }
  }
  if (boundary > 0) {
    why = std::to_string(boundary) + " boundary edges: not a closed solid";
  } else if (unpaired > 0) {
    why = std::to_string(unpaired) + " edges run more often one way than the other";
  } else if (misoriented > 0) {
    why = std::to_string(misoriented) +
          " edges whose two faces run them the same way (not consistently oriented)";
  } else {
    return twin;
  }
  return {};
}

// The clipping preconditions that are cheap to check: indices, finite coordinates, every edge
// shared by exactly two faces running it in opposite directions, not inside out.
Outcome checkSolid(const Mesh& solid, MeshEdges& edges) {
  Outcome o;
  auto fail = [&](Status s, std::string m) {
    o.status = s;
    o.message = std::move(m);
    return o;
  };
  if (solid.triangles.empty()) return fail(Status::EmptyInput, "the solid has no triangles");
  if (solid.positions.size() % 3 != 0 || solid.triangles.size() % 3 != 0) {
    return fail(Status::InvalidOption, "positions or indices are not a multiple of 3");
  }
  const size_t nv = solid.vertexCount();
  for (size_t i = 0; i < solid.triangles.size(); ++i) {
    if (solid.triangles[i] >= nv) {
      return fail(Status::InvalidOption, "index " + std::to_string(solid.triangles[i]) +
                                             " out of range (" + std::to_string(nv) + " vertices)");
    }
  }
  for (size_t f = 0; f < solid.faceCount(); ++f) {
    const uint32_t* t = &solid.triangles[3 * f];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      return fail(Status::DegenerateInput, "face " + std::to_string(f) + " repeats a vertex");
    }
  }
  for (double x : solid.positions) {
    if (!std::isfinite(x))
      return fail(Status::NonFiniteVertex, "a vertex coordinate is not finite");
  }
  edges = buildEdges(solid);
  std::string why;
  if (pairHalfedges(solid, edges, why).empty()) {
    return fail(
        why.find("boundary") != std::string::npos ? Status::OpenMesh : Status::NonManifoldInput,
        why);
  }
  // Inside out: a volume clearly negative against the rounding of its own sum.
  const BoundingBox box = boundingBox(solid);
  const Eigen::Vector3d c = 0.5 * (box.min + box.max);
  double volume = 0, magnitude = 0;
  for (size_t f = 0; f < solid.faceCount(); ++f) {
    const double t = (solid.vertex(solid.triangles[3 * f]) - c)
                         .dot((solid.vertex(solid.triangles[3 * f + 1]) - c)
                                  .cross(solid.vertex(solid.triangles[3 * f + 2]) - c));
    volume += t;
    magnitude += std::abs(t);
  }
  if (volume < -1e-9 * magnitude) {
    return fail(Status::DegenerateInput,
                "negative volume " + std::to_string(volume / 6) + " mm^3: the solid is inside out");
  }
  return o;
}

// The faces of positions/triangles as a mesh of their referenced vertices only (increasing old
// index).
Mesh compactMesh(const std::vector<double>& positions, const std::vector<uint32_t>& triangles) {
  const size_t nv = positions.size() / 3;
  std::vector<uint32_t> index(nv, kNoIndex);
  for (uint32_t v : triangles) index[v] = 0;
  Mesh m;
  uint32_t next = 0;
  for (size_t v = 0; v < nv; ++v) {
    if (index[v] == kNoIndex) continue;
    index[v] = next++;
    m.positions.insert(m.positions.end(), positions.begin() + 3 * v, positions.begin() + 3 * v + 3);
  }
  m.triangles.reserve(triangles.size());
  for (uint32_t v : triangles) m.triangles.push_back(index[v]);
  return m;
}

// Shells of positive signed volume (solids; inward cavities and empty slivers not counted).
size_t countSolids(const Mesh& mesh) {
  if (mesh.empty()) return 0;
  const FaceComponents comp = edgeComponents(mesh, buildEdges(mesh));
  const BoundingBox box = boundingBox(mesh);
  const Eigen::Vector3d c = 0.5 * (box.min + box.max);
  std::vector<double> volume(comp.count, 0);
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    volume[comp.label[f]] += (mesh.vertex(mesh.triangles[3 * f]) - c)
                                 .dot((mesh.vertex(mesh.triangles[3 * f + 1]) - c)
                                          .cross(mesh.vertex(mesh.triangles[3 * f + 2]) - c));
  }
  return static_cast<size_t>(
      std::count_if(volume.begin(), volume.end(), [](double v) { return v > 0; }));
}

ClipResult clipChecked(const Mesh& solid, const MeshEdges& edges, const UnitPlane& pl, double tol) {
  ClipResult r;
  const size_t nv = solid.vertexCount();
  std::vector<double> s(nv, 0);
  std::vector<int8_t> sign(nv, 0);
  std::vector<uint8_t> referenced(nv, 0);
  for (uint32_t v : solid.triangles) referenced[v] = 1;
  for (size_t v = 0; v < nv; ++v) {
    s[v] = pl.n.dot(solid.vertex(v)) - pl.d;
    if (!std::isfinite(s[v])) {
      return failed<ClipResult>(Status::InvalidOption,
                                "the plane offset overflows against the vertex coordinates");
    }
    sign[v] = s[v] > tol ? 1 : s[v] < -tol ? -1 : 0;
  }
  const BoundingBox box = boundingBox(solid);
  const double diag2 = (box.max - box.min).squaredNorm();
  // prepareMesh drops faces of twice-area <= 2e-12 x squared diagonal as degenerate; a piece's
  // diagonal is at most the input's, and 2x covers rounding.
  const double sliverArea2 = 4e-12 * diag2;
  const double maxSliverSnap = kSliverSnapRatio * std::sqrt(diag2);

  Mesh split;
  std::vector<int8_t> side;  // per split face: +1 above, -1 below
  std::vector<uint32_t> cutVertex(edges.edgeCount(), kNoIndex);
  std::vector<double> newPositions;
  bool anyAbove = false, anyBelow = false;
  for (bool again = true; again;) {
    again = false;
    // New vertex for each edge whose ends lie strictly on opposite sides. A point that rounds
    // onto an end means that end is numerically on the plane: snap it and start again (signs only
    // move to 0, so this ends; normally after one pass).
    for (bool changed = true; changed;) {
      changed = false;
      newPositions.clear();
      std::fill(cutVertex.begin(), cutVertex.end(), kNoIndex);
      for (size_t e = 0; e < edges.edgeCount(); ++e) {
        const uint32_t a = static_cast<uint32_t>(edges.keys[e] >> 32);
        const uint32_t b = static_cast<uint32_t>(edges.keys[e] & 0xFFFFFFFFu);
        if (sign[a] * sign[b] >= 0) continue;
        const Eigen::Vector3d pa = solid.vertex(a), pb = solid.vertex(b);
        const double t = s[a] / (s[a] - s[b]);
        const Eigen::Vector3d p = pa + t * (pb - pa);
        if (p == pa) {
          sign[a] = 0;
          changed = true;
        } else if (p == pb) {
          sign[b] = 0;
          changed = true;
        } else {
          cutVertex[e] = static_cast<uint32_t>(nv + newPositions.size() / 3);
          newPositions.insert(newPositions.end(), {p.x(), p.y(), p.z()});
        }
      }
    }
    anyAbove = anyBelow = false;
    for (size_t v = 0; v < nv; ++v) {
      if (!referenced[v]) continue;
      anyAbove |= sign[v] > 0;
      anyBelow |= sign[v] < 0;
    }
    if (!anyAbove || !anyBelow) break;

    // Split every face into triangles lying wholly on one side.
    split.positions = solid.positions;
    split.positions.insert(split.positions.end(), newPositions.begin(), newPositions.end());
    split.triangles.clear();
    split.triangles.reserve(solid.triangles.size() + 2 * newPositions.size());
    side.clear();
    auto pos = [&](uint32_t v) { return split.vertex(v); };
    // A cut next to a vertex just beyond the tolerance leaves faces of near-zero area (a tiny
    // corner around it): such a vertex, if within maxSliverSnap, is then taken as on the plane
    // and the split redone (issue 7: every piece must pass prepareMesh without repairs).
    auto add = [&](uint32_t a, uint32_t b, uint32_t c, int8_t sd, const uint32_t* face) {
      split.triangles.insert(split.triangles.end(), {a, b, c});
      side.push_back(sd);
      if ((pos(b) - pos(a)).cross(pos(c) - pos(a)).norm() > sliverArea2) return;
      uint32_t nearest = kNoIndex;
      for (int k = 0; k < 3; ++k) {
        const uint32_t v = face[k];
        if (sign[v] != 0 && (nearest == kNoIndex || std::abs(s[v]) < std::abs(s[nearest])))
          nearest = v;
      }
      if (nearest != kNoIndex && std::abs(s[nearest]) <= maxSliverSnap) {
        sign[nearest] = 0;
        ++r.sliverSnaps;
        again = true;
      }
    };
    for (size_t f = 0; f < solid.faceCount(); ++f) {
      uint32_t v[3], cut[3];
      int8_t sg[3];
      int cuts = 0;
      for (int k = 0; k < 3; ++k) {
        v[k] = solid.triangles[3 * f + k];
        sg[k] = sign[v[k]];
        cut[k] = cutVertex[edges.edgeOfHalfedge[3 * f + k]];
        cuts += cut[k] != kNoIndex ? 1 : 0;
      }
      if (cuts == 0) {
        int8_t sd = 0;
        for (int k = 0; k < 3; ++k) sd = sg[k] != 0 ? sg[k] : sd;
        if (sd == 0) {
          // In the plane: the solid lies behind the face, so a face looking up closes the piece
          // below and a face looking down the piece above. Edge-on faces (flat within the band,
          // normal in the plane) go below.
          const double up = (pos(v[1]) - pos(v[0])).cross(pos(v[2]) - pos(v[0])).dot(pl.n);
          sd = up < 0 ? 1 : -1;
        }
        split.triangles.insert(split.triangles.end(), {v[0], v[1], v[2]});
        side.push_back(sd);
      } else if (cuts == 1) {
        // One vertex on the plane, the opposite edge crossing it.
        const int k = cut[0] != kNoIndex ? 0 : cut[1] != kNoIndex ? 1 : 2;
        const uint32_t a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3], m = cut[k];
        add(a, m, c, sg[k], v);
        add(m, b, c, sg[(k + 1) % 3], v);
      } else if (cuts == 2) {
        // Lone vertex l on one side; the quad on the other side gets its shorter diagonal.
        const int k0 = cut[0] == kNoIndex ? 0 : cut[1] == kNoIndex ? 1 : 2;  // uncut edge
        const int l = (k0 + 2) % 3;
        const uint32_t vl = v[l], v1 = v[(l + 1) % 3], v2 = v[(l + 2) % 3];
        const uint32_t c1 = cut[l], c2 = cut[(l + 2) % 3];
        add(vl, c1, c2, sg[l], v);
        const int8_t other = sg[(l + 1) % 3];
        if ((pos(c1) - pos(v2)).squaredNorm() <= (pos(v1) - pos(c2)).squaredNorm()) {
          add(c1, v1, v2, other, v);
          add(c1, v2, c2, other, v);
        } else {
          add(c1, v1, c2, other, v);
          add(v1, v2, c2, other, v);
        }
      } else {
        return failed<ClipResult>(
            Status::Internal, "face " + std::to_string(f) + " has three edges crossing the plane");
      }
    }
  }
  for (size_t v = 0; v < nv; ++v) r.onPlaneVertices += referenced[v] && sign[v] == 0 ? 1 : 0;
  r.cutEdges = newPositions.size() / 3;
  // Nothing strictly above: all below (including a solid flat within the tolerance band), and
  // the other way round.
  if (!anyAbove || !anyBelow) {
    Mesh whole = compactMesh(solid.positions, solid.triangles);
    const double volume = signedVolume(whole);
    if (!anyAbove) {
      r.below = std::move(whole);
      r.belowVolume = volume;
    } else {
      r.above = std::move(whole);
      r.aboveVolume = volume;
    }
    return r;
  }
  auto pos = [&](uint32_t v) { return split.vertex(v); };

  // Boundary of the above faces: half-edges whose twin face is below. They all lie in the plane
  // and form the cut loops, counter-clockwise around the cross-section seen from above.
  const MeshEdges se = buildEdges(split);
  const uint32_t halfedges = static_cast<uint32_t>(split.triangles.size());
  std::string why;
  const std::vector<uint32_t> twin = pairHalfedges(split, se, why);
  if (twin.empty()) return failed<ClipResult>(Status::Internal, "split mesh: " + why);
  std::vector<uint8_t> boundary(halfedges, 0);
  for (uint32_t h = 0; h < halfedges; ++h) {
    boundary[h] = side[h / 3] > 0 && side[twin[h] / 3] < 0 ? 1 : 0;
  }
  // Next loop edge after h (u -> v): walk the fan of above faces round v to its other boundary
  // edge. Pairing within a fan keeps loops that touch at a vertex from crossing there.
  const size_t maxSteps = split.faceCount() + 1;
  auto nextBoundary = [&](uint32_t h) -> uint32_t {
    uint32_t out = nextInFace(h);
    for (size_t step = 0; !boundary[out]; ++step) {
      if (step > maxSteps) return kNoIndex;
      out = nextInFace(twin[out]);
    }
    return out;
  };
  std::vector<std::vector<uint32_t>> loops;
  std::vector<uint8_t> visited(halfedges, 0);
  for (uint32_t h0 = 0; h0 < halfedges; ++h0) {
    if (!boundary[h0] || visited[h0]) continue;
    std::vector<uint32_t> loop;
    uint32_t h = h0;
    do {
      if (h == kNoIndex || visited[h] || loop.size() > halfedges) {
        return failed<ClipResult>(Status::Internal, "cut loop does not close");
      }
      visited[h] = 1;
      loop.push_back(split.triangles[h]);
      h = nextBoundary(h);
    } while (h != h0);
    loops.push_back(std::move(loop));
  }

  // Cap: the loops in the plane frame (e1, e2, n right-handed) about their centroid.
  const Eigen::Vector3d& n = pl.n;
  Eigen::Index axis = 0;
  n.cwiseAbs().minCoeff(&axis);
  const Eigen::Vector3d e1 = n.cross(Eigen::Vector3d::Unit(axis)).normalized();
  const Eigen::Vector3d e2 = n.cross(e1);
  std::vector<uint32_t> local(split.vertexCount(), kNoIndex);
  std::vector<uint32_t> global;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (std::vector<uint32_t>& loop : loops) {
    for (uint32_t& v : loop) {
      if (local[v] == kNoIndex) {
        local[v] = static_cast<uint32_t>(global.size());
        global.push_back(v);
        centroid += pos(v);
      }
      v = local[v];
    }
  }
  if (!global.empty()) centroid /= static_cast<double>(global.size());
  std::vector<Eigen::Vector2d> points(global.size());
  for (size_t i = 0; i < global.size(); ++i) {
    const Eigen::Vector3d q = pos(global[i]) - centroid;
    points[i] = {q.dot(e1), q.dot(e2)};
  }
  TriangulateOptions capOptions;
  capOptions.minArea = 0.5 * sliverArea2;
  // Edges in the plane between cap points whose two faces lie on one side: where the surface
  // touches the plane from one side along an edge inside the cross-section (a concave edge in
  // the plane). A cap triangle on that edge would give it four faces; without it, that piece
  // only touches itself there.
  for (size_t e = 0; e < se.edgeCount(); ++e) {
    const uint32_t a = static_cast<uint32_t>(se.keys[e] >> 32);
    const uint32_t b = static_cast<uint32_t>(se.keys[e] & 0xFFFFFFFFu);
    const uint32_t h = se.firstHalfedge[e];
    if (local[a] != kNoIndex && local[b] != kNoIndex && side[h / 3] == side[twin[h] / 3]) {
      capOptions.avoidEdges.push_back({local[a], local[b]});
    }
  }
  const PolygonTriangulation cap = triangulatePolygons(points, loops, capOptions);
  if (!cap.ok() || cap.skippedLoops > 0) {
    return failed<ClipResult>(Status::Internal, "cap triangulation failed: " + cap.message);
  }
  r.capLoops = loops.size();
  r.capHoles = cap.holeLoops + cap.orphanHoles;
  r.capArea = cap.area;
  r.forcedCapTriangles = cap.forcedTriangles;

  std::vector<uint32_t> below, above;
  below.reserve(split.triangles.size() + cap.triangles.size());
  above.reserve(split.triangles.size() + cap.triangles.size());
  for (size_t t = 0; t < side.size(); ++t) {
    std::vector<uint32_t>& dst = side[t] > 0 ? above : below;
    dst.insert(dst.end(), split.triangles.begin() + 3 * t, split.triangles.begin() + 3 * t + 3);
  }
  for (size_t t = 0; t < cap.triangles.size(); t += 3) {
    const uint32_t a = global[cap.triangles[t]], b = global[cap.triangles[t + 1]],
                   c = global[cap.triangles[t + 2]];
    below.insert(below.end(), {a, b, c});  // faces up: out of the piece below
    above.insert(above.end(), {a, c, b});
  }
  r.below = compactMesh(split.positions, below);
  r.above = compactMesh(split.positions, above);
  r.belowVolume = signedVolume(r.below);
  r.aboveVolume = signedVolume(r.above);
  return r;
}

}  // namespace

ClipResult clipByPlane(const Mesh& solid, const Plane& plane, double snapTolerance) {
  UnitPlane pl;
  Outcome o = checkPlane(plane, pl);
  if (o.ok()) o = checkTolerance(snapTolerance);
  MeshEdges edges;
  if (o.ok()) o = checkSolid(solid, edges);
  if (!o.ok()) return failed<ClipResult>(o.status, o.message);
  return clipChecked(solid, edges, pl, snapTolerance);
}

PartsResult clipSequence(const Mesh& solid, const std::vector<Plane>& planes, double snapTolerance,
                         const ProgressFn& progress) {
  for (size_t k = 0; k < planes.size(); ++k) {
    UnitPlane pl;
    const Outcome o = checkPlane(planes[k], pl);
    if (!o.ok())
      return failed<PartsResult>(o.status, "plane " + std::to_string(k) + ": " + o.message);
  }
  Outcome o = checkTolerance(snapTolerance);
  MeshEdges edges;
  if (o.ok()) o = checkSolid(solid, edges);
  if (!o.ok()) return failed<PartsResult>(o.status, o.message);

  PartsResult result;
  result.inputVolume = signedVolume(solid);
  Mesh remaining = compactMesh(solid.positions, solid.triangles);
  std::vector<ClipPart> above(planes.size());
  for (size_t k = 0; k < planes.size(); ++k) {
    if (!reportProgress(progress, "clip", double(k) / double(planes.size()))) {
      return failed<PartsResult>(Status::Cancelled, "cancelled");
    }
    above[k].planeIndex = static_cast<int>(k);
    if (remaining.empty()) continue;
    ClipResult c = clipByPlane(remaining, planes[k], snapTolerance);
    if (!c.ok()) {
      return failed<PartsResult>(c.status, "plane " + std::to_string(k) + ": " + c.message);
    }
    above[k].mesh = std::move(c.above);
    above[k].volume = c.aboveVolume;
    remaining = std::move(c.below);
    result.totalCapArea += c.capArea;
    result.forcedCapTriangles += c.forcedCapTriangles;
  }
  ClipPart platform;
  platform.mesh = std::move(remaining);
  platform.volume = signedVolume(platform.mesh);
  result.parts.push_back(std::move(platform));
  for (size_t k = planes.size(); k-- > 0;) result.parts.push_back(std::move(above[k]));
  for (ClipPart& part : result.parts) part.components = countSolids(part.mesh);
  reportProgress(progress, "clip", 1.0);
  return result;
}

}  // namespace omnislice
