// SPDX-License-Identifier: MIT
// Iso-geodesic distance surfaces (paper 002 Section 2.2) and their Eq. 11 / Fig. 10 metrics.
#include "common/disjoint_sets.h"
#include "common/det_math.h"
#include "common/math_constants.h"
#include "common/stopwatch.h"
#include "geodesic/igds.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <unordered_map>

#include "geodesic/igds_remesh.h"
#include "geometry/aabb_tree.h"

namespace omnislice {

namespace {

// det(e1, e2, e3) times the gradient of the linear function that changes by d_j along edge e_j
// of a tet (Cramer's rule): d1 e2 x e3 + d2 e3 x e1 + d3 e1 x e2.
Eigen::Vector3d scaledGradient(const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
                               const Eigen::Vector3d& e3, double d1, double d2, double d3) {
  return d1 * e2.cross(e3) + d2 * e3.cross(e1) + d3 * e1.cross(e2);
}

IgdsResult fail(Status s, std::string message) { return failed<IgdsResult>(s, std::move(message)); }

// The interpolation faces of one iso-value, welded by tet edge.
struct RawIgds {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<double> slope;  // per triangle: |grad phi| in its tet (1 = layers one interval apart)
};

class IsoExtractor {
 public:
  IsoExtractor(const TetMesh& mesh, const std::vector<double>& phi) : mesh_(mesh), phi_(phi) {}

  void extract(const uint32_t* tets, size_t count, double c, RawIgds& out) {
    out.positions.clear();
    out.triangles.clear();
    out.slope.clear();
    weld_.clear();
    bool snapped = false;
    const uint64_t nv = mesh_.vertexCount();
    for (size_t q = 0; q < count; ++q) {
      const uint32_t* t = &mesh_.tets[4 * size_t(tets[q])];
      int below[4], above[4], nb = 0, na = 0;
      for (int k = 0; k < 4; ++k) {
        // A vertex exactly at the iso-value counts as above (header): no doubled point.
        if (phi_[t[k]] < c)
          below[nb++] = k;
        else
          above[na++] = k;
      }
      if (nb == 0 || na == 0) continue;
      auto point = [&](int kb, int ka) -> uint32_t {
        const uint32_t i = t[kb], j = t[ka];
        const double pi = phi_[i], pj = phi_[j];
        const bool onVertex = pj == c;
        const uint64_t key = onVertex ? uint64_t(j) * nv + j : uint64_t(std::min(i, j)) * nv + std::max(i, j);
        auto [it, inserted] = weld_.try_emplace(key, uint32_t(out.positions.size()));
        if (inserted) {
          const Eigen::Vector3d vi = mesh_.vertex(i), vj = mesh_.vertex(j);
          // Eq. 10: v = (|phi_i - phi| v_j + |phi_j - phi| v_i) / |phi_i - phi_j|.
          out.positions.push_back(onVertex ? vj
                                           : Eigen::Vector3d((std::abs(pi - c) * vj + std::abs(pj - c) * vi) /
                                                             std::abs(pi - pj)));
        }
        snapped = snapped || onVertex;
        return it->second;
      };
      // Orientation toward increasing phi, decided on the sign field (-1 below, +1 above) whose
      // iso-surface through the crossing edges' midpoints is never degenerate, even when points
      // sit on tet vertices.
      Eigen::Vector3d x[4];
      for (int k = 0; k < 4; ++k) x[k] = mesh_.vertex(t[k]);
      double s[4];
      for (int k = 0; k < 4; ++k) s[k] = phi_[t[k]] < c ? -1.0 : 1.0;
      const Eigen::Vector3d e1 = x[1] - x[0], e2 = x[2] - x[0], e3 = x[3] - x[0];
      const double det = e1.dot(e2.cross(e3));
      const Eigen::Vector3d g =
          scaledGradient(e1, e2, e3, s[1] - s[0], s[2] - s[0], s[3] - s[0]) * (det < 0 ? -1.0 : 1.0);
      const double slope = det != 0 ? scaledGradient(e1, e2, e3, phi_[t[1]] - phi_[t[0]],
                                                     phi_[t[2]] - phi_[t[0]], phi_[t[3]] - phi_[t[0]])
                                              .norm() / std::abs(det)
                                    : 0.0;
      auto emit = [&](std::array<int, 2> ea, std::array<int, 2> eb, std::array<int, 2> ec) {
        std::array<uint32_t, 3> tri{point(ea[0], ea[1]), point(eb[0], eb[1]), point(ec[0], ec[1])};
        const Eigen::Vector3d ma = 0.5 * (x[ea[0]] + x[ea[1]]), mb = 0.5 * (x[eb[0]] + x[eb[1]]),
                              mc = 0.5 * (x[ec[0]] + x[ec[1]]);
        if ((mb - ma).cross(mc - ma).dot(g) < 0) std::swap(tri[1], tri[2]);
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) return;  // snapped away
        out.triangles.push_back(tri);
        out.slope.push_back(slope);
      };
      if (nb == 1 || na == 1) {
        // Three points: the edges from the lone vertex.
        if (nb == 1) {
          emit({below[0], above[0]}, {below[0], above[1]}, {below[0], above[2]});
        } else {
          emit({below[0], above[0]}, {below[1], above[0]}, {below[2], above[0]});
        }
        continue;
      }
      // Four points in cyclic order ac, ad, bd, bc (a, b below; c, d above); split along the
      // shorter diagonal.
      const int a = below[0], b = below[1], cc = above[0], d = above[1];
      const std::array<int, 2> ac{a, cc}, ad{a, d}, bd{b, d}, bc{b, cc};
      auto pos = [&](std::array<int, 2> e) { return out.positions[point(e[0], e[1])]; };
      const double diag1 = (pos(ac) - pos(bd)).squaredNorm(), diag2 = (pos(ad) - pos(bc)).squaredNorm();
      if (diag1 <= diag2) {
        emit(ac, ad, bd);
        emit(ac, bd, bc);
      } else {
        emit(ac, ad, bc);
        emit(ad, bd, bc);
      }
    }
    if (snapped) cancelDuplicates(out);
  }

 private:
  // Points snapped onto tet vertices can produce the same triangle twice (a tet face lying in the
  // iso-value with both tets below it): such pairs enclose nothing and are removed.
  static void cancelDuplicates(RawIgds& out) {
    std::vector<std::pair<std::array<uint32_t, 3>, uint32_t>> keys;
    keys.reserve(out.triangles.size());
    for (size_t f = 0; f < out.triangles.size(); ++f) {
      std::array<uint32_t, 3> k = out.triangles[f];
      std::sort(k.begin(), k.end());
      keys.push_back({k, uint32_t(f)});
    }
    std::sort(keys.begin(), keys.end());
    std::vector<uint8_t> drop(out.triangles.size(), 0);
    bool any = false;
    for (size_t i = 0; i < keys.size();) {
      size_t j = i;
      while (j < keys.size() && keys[j].first == keys[i].first) ++j;
      if (j - i >= 2)
        for (size_t k = i; k < j; ++k) drop[keys[k].second] = any = true;
      i = j;
    }
    if (!any) return;
    size_t w = 0;
    for (size_t f = 0; f < out.triangles.size(); ++f)
      if (!drop[f]) {
        out.slope[w] = out.slope[f];
        out.triangles[w++] = out.triangles[f];
      }
    out.triangles.resize(w);
    out.slope.resize(w);
  }

  const TetMesh& mesh_;
  const std::vector<double>& phi_;
  std::unordered_map<uint64_t, uint32_t> weld_;
};

// Connected IGDS: faces grown over edges shared by exactly two consistently oriented faces.
std::vector<std::vector<uint32_t>> components(const RawIgds& raw) {
  const size_t nf = raw.triangles.size();
  struct Key {
    uint32_t lo, hi, h;
    bool operator<(const Key& o) const {
      return lo != o.lo ? lo < o.lo : (hi != o.hi ? hi < o.hi : h < o.h);
    }
  };
  std::vector<Key> keys(3 * nf);
  for (size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = raw.triangles[f][k], b = raw.triangles[f][(k + 1) % 3];
      keys[3 * f + k] = {std::min(a, b), std::max(a, b), uint32_t(3 * f + k)};
    }
  std::sort(keys.begin(), keys.end());
  DisjointSets uf(nf);
  for (size_t i = 0; i < keys.size();) {
    size_t j = i;
    while (j < keys.size() && keys[j].lo == keys[i].lo && keys[j].hi == keys[i].hi) ++j;
    if (j - i == 2) uf.unite(keys[i].h / 3, keys[i + 1].h / 3);
    i = j;
  }
  std::vector<int32_t> index(nf, -1);
  std::vector<std::vector<uint32_t>> comps;
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t r = uf.find(uint32_t(f));
    if (index[r] < 0) {
      index[r] = int32_t(comps.size());
      comps.emplace_back();
    }
    comps[index[r]].push_back(uint32_t(f));
  }
  return comps;
}

// The interpolated region as it is (remesh = false).
void plainRegion(const RemeshInput& in, LayerRegion& region) {
  Mesh& m = region.mesh;
  for (const Eigen::Vector3d& p : in.positions) m.positions.insert(m.positions.end(), {p.x(), p.y(), p.z()});
  std::vector<std::array<uint32_t, 3>> keys;
  for (const auto& t : in.triangles) {
    m.triangles.insert(m.triangles.end(), t.begin(), t.end());
    for (int k = 0; k < 3; ++k) keys.push_back({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3]), 0});
    const Eigen::Vector3d a = in.positions[t[0]], b = in.positions[t[1]], c = in.positions[t[2]];
    region.area += 0.5 * (b - a).cross(c - a).norm();
  }
  std::sort(keys.begin(), keys.end());
  region.boundaryVertex.assign(in.positions.size(), 0);
  for (size_t i = 0; i < keys.size();) {
    size_t j = i;
    while (j < keys.size() && keys[j][0] == keys[i][0] && keys[j][1] == keys[i][1]) ++j;
    if (j - i == 1) region.boundaryVertex[keys[i][0]] = region.boundaryVertex[keys[i][1]] = 1;
    i = j;
  }
}

// Ears folded against the layer: a triangle whose apex belongs to it alone (so both edges at the
// apex are open boundary), turned more than 45 degrees from the triangle across its base, with the
// apex within a quarter of the base from the base's line. Remeshing leaves a few where the boundary
// runs along a flat wall of the part (the shared coin, fit 80 at 0.6 mm: 97 ears, 18 of them
// flat and lying in the wall): their normal, across the layer, tilted the collision envelope of
// the boundary vertex by 90 degrees into the layers printed before (11 nodes of the coin read as
// colliding in every order, at any nozzle angle). Each is dropped with its apex: the boundary then
// runs along the base, within a quarter of its length. Returns the number dropped.
size_t dropFoldedEars(LayerRegion& region) {
  Mesh& m = region.mesh;
  const size_t nv = m.vertexCount();
  std::vector<uint8_t> dropFace(m.faceCount(), 0), dropVertex(nv, 0);
  auto faceNormal = [&](size_t f) {
    const Eigen::Vector3d a = m.vertex(m.triangles[3 * f]);
    return Eigen::Vector3d((m.vertex(m.triangles[3 * f + 1]) - a).cross(m.vertex(m.triangles[3 * f + 2]) - a));
  };
  {
    // Most regions have no vertex in a single triangle: no edge sorting for them.
    std::vector<uint32_t> valence(nv, 0);
    for (uint32_t v : m.triangles) ++valence[v];
    if (std::find(valence.begin(), valence.end(), 1u) == valence.end()) return 0;
  }
  size_t dropped = 0;
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<uint32_t> valence(nv, 0);
    std::vector<std::pair<uint64_t, uint32_t>> edgeFace;  // (edge key, face) of the kept faces
    for (size_t f = 0; f < m.faceCount(); ++f) {
      if (dropFace[f]) continue;
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = m.triangles[3 * f + k], b = m.triangles[3 * f + (k + 1) % 3];
        ++valence[a];
        edgeFace.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), uint32_t(f)});
      }
    }
    std::sort(edgeFace.begin(), edgeFace.end());
    for (size_t f = 0; f < m.faceCount(); ++f) {
      if (dropFace[f]) continue;
      for (int k = 0; k < 3; ++k) {
        const uint32_t c = m.triangles[3 * f + k], a = m.triangles[3 * f + (k + 1) % 3],
                       b = m.triangles[3 * f + (k + 2) % 3];
        if (valence[c] != 1) continue;
        const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
        uint32_t other = UINT32_MAX;
        for (auto it = std::lower_bound(edgeFace.begin(), edgeFace.end(), std::make_pair(key, uint32_t(0)));
             it != edgeFace.end() && it->first == key; ++it)
          if (it->second != f) other = it->second;
        if (other == UINT32_MAX) continue;  // the base is open too: an isolated triangle, kept
        const Eigen::Vector3d A = m.vertex(a), B = m.vertex(b), C = m.vertex(c);
        const double base = (B - A).norm();
        if (!(base > 0)) continue;
        const double height = (C - A).cross(B - A).norm() / base;
        const Eigen::Vector3d nf = faceNormal(f), ng = faceNormal(other);
        const double nn = nf.norm() * ng.norm();
        const bool folded = !(nn > 0) || nf.dot(ng) < std::sqrt(0.5) * nn;  // over 45 degrees
        if (!folded || height > 0.25 * base) continue;
        dropFace[f] = 1;
        dropVertex[c] = 1;
        region.area -= 0.5 * nf.norm();
        ++dropped;
        changed = true;
        break;
      }
    }
  }
  if (dropped == 0) return 0;
  std::vector<uint32_t> remap(nv, UINT32_MAX);
  Mesh kept;
  std::vector<uint8_t> boundary;
  for (size_t v = 0; v < nv; ++v) {
    if (dropVertex[v]) continue;
    remap[v] = uint32_t(kept.vertexCount());
    kept.positions.insert(kept.positions.end(), m.positions.begin() + 3 * v, m.positions.begin() + 3 * v + 3);
    boundary.push_back(v < region.boundaryVertex.size() ? region.boundaryVertex[v] : 0);
  }
  for (size_t f = 0; f < m.faceCount(); ++f) {
    if (dropFace[f]) continue;
    for (int k = 0; k < 3; ++k) kept.triangles.push_back(remap[m.triangles[3 * f + k]]);
  }
  m = std::move(kept);
  region.boundaryVertex = std::move(boundary);
  region.area = std::max(region.area, 0.0);
  return dropped;
}

}  // namespace

constexpr double kMinRemeshArea = 10;  // x L^2
constexpr double kMaxDeviation = 0.5;   // x interval
constexpr double kMinEdge = 0.25;       // x targetEdge, smallest remeshing length

IgdsResult extractIgds(const TetMesh& mesh, const std::vector<double>& distance,
                       const IgdsOptions& options, const ProgressFn& progress) {
  const size_t nv = mesh.vertexCount(), nt = mesh.tetCount();
  if (nt == 0 || mesh.tets.size() % 4 != 0) return fail(Status::EmptyInput, "the tet mesh has no tets");
  if (mesh.positions.size() != 3 * nv)
    return fail(Status::InvalidOption, "positions are not 3 per vertex");
  if (distance.size() != nv)
    return fail(Status::InvalidOption, "distance has " + std::to_string(distance.size()) +
                                           " values for " + std::to_string(nv) + " vertices");
  if (!(options.interval > 0) || !std::isfinite(options.interval))
    return fail(Status::InvalidOption, "interval must be a finite positive length (mm)");
  if (!(options.minRegionArea >= 0) || !std::isfinite(options.minRegionArea) ||
      !(options.targetEdge >= 0) || !std::isfinite(options.targetEdge) ||
      options.remeshIterations < 0 || options.smoothIterations < 0)
    return fail(Status::InvalidOption, "negative or non-finite IGDS option");
  for (uint32_t v : mesh.tets)
    if (v >= nv) return fail(Status::DegenerateInput, "tet vertex index out of range");
  for (double x : mesh.positions)
    if (!std::isfinite(x)) return fail(Status::NonFiniteVertex, "non-finite tet vertex coordinate");
  double maxPhi = -std::numeric_limits<double>::infinity();
  for (double x : distance) {
    if (!std::isfinite(x)) return fail(Status::NonFiniteVertex, "non-finite geodesic distance");
    maxPhi = std::max(maxPhi, x);
  }
  const double d = options.interval;
  // The iso-values: i d for i = 1, 2, ... while i d < max phi, or the given ones below max phi.
  std::vector<double> iso;
  if (options.isoValues.empty()) {
    const double ratio = maxPhi / d;
    if (ratio > double(options.maxLayers) + 1)
      return fail(Status::InvalidOption, "interval gives more than " + std::to_string(options.maxLayers) +
                                             " iso-values");
    size_t layerCount = ratio >= 1 ? size_t(std::floor(ratio)) : 0;
    while (layerCount > 0 && double(layerCount) * d >= maxPhi) --layerCount;
    iso.resize(layerCount);
    for (size_t i = 0; i < layerCount; ++i) iso[i] = double(i + 1) * d;
  } else {
    for (size_t i = 0; i < options.isoValues.size(); ++i) {
      const double c = options.isoValues[i];
      if (!std::isfinite(c) || !(c > 0) || (i > 0 && !(c > options.isoValues[i - 1])))
        return fail(Status::InvalidOption, "iso-values must be finite, positive and increasing");
      if (c < maxPhi) iso.push_back(c);
    }
  }
  const size_t layerCount = iso.size();
  if (layerCount > options.maxLayers)
    return fail(Status::InvalidOption, "interval gives more than " + std::to_string(options.maxLayers) +
                                           " iso-values");
  if (layerCount == 0) return fail(Status::EmptyInput, "max distance below one interval: no IGDS");

  IgdsResult result;
  // Tets per iso-value (CSR, layer i from 1 at iso[i - 1]): tet k crosses phi_i when
  // min < phi_i <= max.
  std::vector<uint32_t> start(layerCount + 2, 0), list;
  std::vector<std::pair<uint32_t, uint32_t>> range(nt);
  for (size_t k = 0; k < nt; ++k) {
    double lo = distance[mesh.tets[4 * k]], hi = lo;
    for (int c = 1; c < 4; ++c) {
      lo = std::min(lo, distance[mesh.tets[4 * k + c]]);
      hi = std::max(hi, distance[mesh.tets[4 * k + c]]);
    }
    const size_t first = size_t(std::upper_bound(iso.begin(), iso.end(), lo) - iso.begin()) + 1;
    const size_t last = size_t(std::upper_bound(iso.begin(), iso.end(), hi) - iso.begin());
    if (first > last) {
      range[k] = {1, 0};
      continue;
    }
    range[k] = {uint32_t(first), uint32_t(last)};
    for (uint32_t i = range[k].first; i <= range[k].second; ++i) ++start[i + 1];
  }
  for (size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  list.resize(start.back());
  {
    std::vector<uint32_t> fill(start.begin(), start.end());
    for (size_t k = 0; k < nt; ++k)
      for (uint32_t i = range[k].first; i <= range[k].second; ++i) list[fill[i]++] = uint32_t(k);
  }
  double targetEdge = options.targetEdge;
  if (targetEdge <= 0) targetEdge = tetQuality(mesh).meanEdge;
  if (!(targetEdge > 0)) targetEdge = d;

  IsoExtractor extractor(mesh, distance);
  RawIgds raw;
  RemeshParams params;
  params.targetEdge = targetEdge;
  params.remeshIterations = options.remeshIterations;
  params.smoothIterations = options.smoothIterations;
  params.maxDeviation = kMaxDeviation * d;
  result.layers.resize(layerCount);
  result.regionTargetEdge.resize(layerCount);
  for (size_t i = 1; i <= layerCount; ++i) {
    const double fraction = double(i - 1) / double(layerCount);
    if (!reportProgress(progress, "igds", fraction)) return fail(Status::Cancelled, "cancelled");
    const double c = iso[i - 1];
    // Half the nearer neighbouring iso-value's distance (d / 2 for uniform layers).
    const double below = i == 1 ? c : c - iso[i - 2];
    const double above = i == layerCount ? below : iso[i] - c;
    params.maxDeviation = kMaxDeviation * (options.isoValues.empty() ? d : std::min(below, above));
    CurvedLayer& layer = result.layers[i - 1];
    layer.isoValue = c;
    const double ta = nowMs();
    extractor.extract(list.data() + start[i], start[i + 1] - start[i], c, raw);
    result.interpolatedTriangles += raw.triangles.size();
    const std::vector<std::vector<uint32_t>> comps = components(raw);
    result.interpolationMs += nowMs() - ta;
    std::vector<int32_t> map(raw.positions.size(), -1);
    for (const std::vector<uint32_t>& comp : comps) {
      double area = 0;
      for (uint32_t f : comp) {
        const auto& tr = raw.triangles[f];
        area += 0.5 * (raw.positions[tr[1]] - raw.positions[tr[0]])
                          .cross(raw.positions[tr[2]] - raw.positions[tr[0]])
                          .norm();
      }
      if (area < options.minRegionArea || area <= 0) continue;
      RemeshInput in;
      std::vector<uint32_t> used;
      for (uint32_t f : comp) {
        in.slope.push_back(raw.slope[f]);
        std::array<uint32_t, 3> tri;
        for (int k = 0; k < 3; ++k) {
          const uint32_t v = raw.triangles[f][k];
          if (map[v] < 0) {
            map[v] = int32_t(in.positions.size());
            in.positions.push_back(raw.positions[v]);
            used.push_back(v);
          }
          tri[k] = uint32_t(map[v]);
        }
        in.triangles.push_back(tri);
      }
      for (uint32_t v : used) map[v] = -1;
      LayerRegion region;
      // Remeshing at L = targetEdge, except: a region smaller than 10 L^2 (caps near a maximum
      // of the field, slivers) uses L' = sqrt(area / 10), and when the remeshed chords lie
      // farther than half an interval from the interpolated IGDS (strongly curved regions: such
      // chords were measured to cross the next IGDS) the region is remeshed once more at half the
      // length (likewise when two of its triangles intersect); if that fails too, or the length
      // would fall below L / 4, it stays as interpolated
      // (the interpolation never crosses its neighbours). Where the field is steeper than 1 the
      // neighbours are nearer than an interval, and the half is of that distance (each chord
      // against its nearest interpolated triangle's slope): the shared bracket's layers 8/9 over
      // its uneven base crossed otherwise (|grad phi| up to 2.2).
      double usedEdge = 0;
      if (options.remesh) {
        double L = std::min(params.targetEdge, std::sqrt(area / kMinRemeshArea));
        for (int attempt = 0; attempt < 2 && L >= kMinEdge * params.targetEdge; ++attempt, L *= 0.5) {
          RemeshParams local = params;
          local.targetEdge = L;
          LayerRegion trial;
          const RemeshStats st = remeshIgdsRegion(in, local, trial, progress, fraction);
          if (st.cancelled) return fail(Status::Cancelled, "cancelled");
          result.remeshMs += st.remeshMs;
          result.smoothMs += st.smoothMs;
          if (!st.deviates && !st.selfIntersecting) {
            region = std::move(trial);
            usedEdge = L;
            break;
          }
        }
      }
      if (usedEdge == 0) {
        plainRegion(in, region);
        if (options.remesh) ++result.keptInterpolated;
      }
      if (options.remesh) result.droppedEars += dropFoldedEars(region);  // plain: as interpolated
      result.triangleCount += region.mesh.faceCount();
      result.regionTargetEdge[i - 1].push_back(usedEdge);
      layer.regions.push_back(std::move(region));
      ++result.regionCount;
    }
  }
  if (result.regionCount == 0) return fail(Status::EmptyInput, "no IGDS region left");
  reportProgress(progress, "igds", 1.0);
  return result;
}

namespace {

struct BoundarySegment {
  Eigen::Vector3d a, b, normal, conormal;  // unit normal / outward conormal of the face
};

std::vector<BoundarySegment> boundarySegments(const CurvedLayer& layer) {
  std::vector<BoundarySegment> out;
  for (const LayerRegion& r : layer.regions) {
    const Mesh& m = r.mesh;
    const size_t nf = m.faceCount(), nv = m.vertexCount();
    std::vector<std::array<uint32_t, 3>> keys;  // lo, hi, half-edge
    keys.reserve(3 * nf);
    for (size_t f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = m.triangles[3 * f + k], b = m.triangles[3 * f + (k + 1) % 3];
        keys.push_back({std::min(a, b), std::max(a, b), uint32_t(3 * f + k)});
      }
    std::sort(keys.begin(), keys.end());
    for (size_t i = 0; i < keys.size();) {
      size_t j = i;
      while (j < keys.size() && keys[j][0] == keys[i][0] && keys[j][1] == keys[i][1]) ++j;
      if (j - i == 1) {
        const uint32_t h = keys[i][2], f = h / 3, k = h % 3;
        const uint32_t ia = m.triangles[3 * f + k], ib = m.triangles[3 * f + (k + 1) % 3],
                       ic = m.triangles[3 * f + (k + 2) % 3];
        if (ia < nv && ib < nv && ic < nv) {
          BoundarySegment s;
          s.a = m.vertex(ia);
          s.b = m.vertex(ib);
          Eigen::Vector3d n = (s.b - s.a).cross(m.vertex(ic) - s.a);
          if (n.norm() > 0) {
            s.normal = n.normalized();
            // The face lies left of a -> b seen from the normal: outward is (b - a) x n.
            s.conormal = (s.b - s.a).cross(s.normal).normalized();
            out.push_back(s);
          }
        }
      }
      i = j;
    }
  }
  return out;
}

}  // namespace

IgdsMetrics igdsMetrics(const std::vector<CurvedLayer>& layers, double interval,
                        double sampleSpacing) {
  IgdsMetrics metrics;
  if (!(interval > 0) || !std::isfinite(interval)) return metrics;
  const bool sampleThickness = sampleSpacing > 0 && std::isfinite(sampleSpacing);
  constexpr double kA1 = 0.7548776662466927, kA2 = 0.5698402909980532;  // R2 sequence
  uint64_t counter = 0;
  double weightedAlpha = 0, overhangLength = 0;
  std::vector<BoundarySegment> previous;
  for (size_t li = 0; li < layers.size(); ++li) {
    const CurvedLayer& layer = layers[li];
    IgdsLayerMetrics lm;
    lm.isoValue = layer.isoValue;
    std::vector<BoundarySegment> segs = boundarySegments(layer);
    // P' on the previous layer's boundary curves (segments as degenerate triangles), or the
    // platform below P for the first layer (and after a layer without boundary).
    // The previous layer's surfaces (for the split test below and the thickness samples).
    std::unique_ptr<AabbTree> prevSurface;
    if (li > 0 && !layers[li - 1].regions.empty()) {
      Mesh surface;
      for (const LayerRegion& r : layers[li - 1].regions) {
        const uint32_t base = uint32_t(surface.vertexCount());
        surface.positions.insert(surface.positions.end(), r.mesh.positions.begin(), r.mesh.positions.end());
        for (uint32_t v : r.mesh.triangles) surface.triangles.push_back(base + v);
      }
      prevSurface = std::make_unique<AabbTree>(surface);
    }
    std::unique_ptr<AabbTree> prevTree;
    if (li > 0 && !previous.empty()) {
      Mesh m;
      for (const BoundarySegment& s : previous) {
        const uint32_t base = uint32_t(m.vertexCount());
        m.positions.insert(m.positions.end(), {s.a.x(), s.a.y(), s.a.z(), s.b.x(), s.b.y(), s.b.z()});
        m.triangles.insert(m.triangles.end(), {base, base + 1, base + 1});
      }
      prevTree = std::make_unique<AabbTree>(m);
    }
    double layerAlpha = 0;
    for (const BoundarySegment& s : segs) {
      const double w = (s.b - s.a).norm();
      const Eigen::Vector3d P = 0.5 * (s.a + s.b);
      lm.boundaryLengthMm += w;
      Eigen::Vector3d Pp(P.x(), P.y(), 0);
      if (prevTree) Pp = prevTree->closest(P).point;
      const Eigen::Vector3d v = P - Pp;
      const double vn = v.norm();
      // P lies over the previous IGDS, not beyond its boundary: the nearest point of the previous
      // surface is inside it, nearer than any boundary point. This happens where a layer splits
      // (a saddle of the field: the new boundary between two branches is printed on the previous
      // layer's interior, while the nearest boundary point is across a branch). Not an overhang.
      if (prevTree && prevSurface && (P - prevSurface->closest(P).point).norm() < vn * (1 - 1e-9) - 1e-12)
        continue;
      // Outward of P' (Fig. 8): a positive component along the outward conormal. The small
      // tolerance keeps vertical walls (component zero up to roundoff) at alpha = 0.
      if (vn <= 0 || v.dot(s.conormal) <= 1e-6 * vn) continue;
      const double alpha =
          det::atan2(v.cross(s.normal).norm(), v.dot(s.normal)) * 180.0 / kPi;
      if (!(alpha > 0)) continue;
      lm.overhangLengthMm += w;
      layerAlpha += alpha * w;
      lm.overhangMaxDegrees = std::max(lm.overhangMaxDegrees, alpha);
    }
    if (lm.overhangLengthMm > 0) lm.overhangAverageDegrees = layerAlpha / lm.overhangLengthMm;
    if (lm.boundaryLengthMm > 0) lm.overhangRatio = lm.overhangLengthMm / lm.boundaryLengthMm;
    weightedAlpha += layerAlpha;
    overhangLength += lm.overhangLengthMm;
    metrics.overhangMaxLayerDegrees = std::max(metrics.overhangMaxLayerDegrees, lm.overhangAverageDegrees);

    // Thickness: distance from samples of this layer to the previous layer's surfaces (the
    // platform z = 0 for the first layer; none after an empty layer).
    if (sampleThickness && (li == 0 || !layers[li - 1].regions.empty())) {
      // The layer's step in phi (d itself for uniform layers, whatever the rounding of i d).
      const double step = li == 0 ? layer.isoValue : layer.isoValue - layers[li - 1].isoValue;
      const double ref = std::abs(step - interval) <= 1e-9 * interval || !(step > 0) ? interval : step;
      double sum = 0, sumDev = 0;
      lm.thicknessMinMm = std::numeric_limits<double>::infinity();
      double carry = 0.5;
      const double perArea = 1.0 / (sampleSpacing * sampleSpacing);
      for (const LayerRegion& r : layer.regions) {
        const Mesh& m = r.mesh;
        for (size_t f = 0; f < m.faceCount(); ++f) {
          const Eigen::Vector3d a = m.vertex(m.triangles[3 * f]), b = m.vertex(m.triangles[3 * f + 1]),
                                c = m.vertex(m.triangles[3 * f + 2]);
          carry += 0.5 * (b - a).cross(c - a).norm() * perArea;
          const double count = std::floor(carry);
          carry -= count;
          for (double s = 0; s < count; ++s) {
            ++counter;
            const double u = std::fmod(0.5 + kA1 * double(counter), 1.0);
            const double v = std::fmod(0.5 + kA2 * double(counter), 1.0);
            const double rr = std::sqrt(u);
            const Eigen::Vector3d p = (1 - rr) * a + rr * (1 - v) * b + rr * v * c;
            const double t = prevSurface ? prevSurface->closest(p).distance : std::abs(p.z());
            if (!std::isfinite(t)) continue;
            ++lm.thicknessSamples;
            sum += t;
            sumDev += std::abs(t - ref);
            lm.thicknessMinMm = std::min(lm.thicknessMinMm, t);
            lm.thicknessMaxMm = std::max(lm.thicknessMaxMm, t);
            lm.thicknessMaxDeviationPercent =
                std::max(lm.thicknessMaxDeviationPercent, std::abs(t - ref) / ref * 100);
          }
        }
      }
      if (lm.thicknessSamples > 0) {
        lm.thicknessMeanMm = sum / double(lm.thicknessSamples);
        lm.thicknessMeanDeviationPercent = sumDev / double(lm.thicknessSamples) / ref * 100;
      } else {
        lm.thicknessMinMm = 0;
      }
      metrics.thicknessMaxDeviationPercent =
          std::max(metrics.thicknessMaxDeviationPercent, lm.thicknessMaxDeviationPercent);
    }
    metrics.layers.push_back(lm);
    previous = std::move(segs);
  }
  if (overhangLength > 0) metrics.overhangAverageDegrees = weightedAlpha / overhangLength;
  return metrics;
}

std::vector<double> surfaceLimitedIsoValues(const TetMesh& mesh, const std::vector<double>& distance,
                                            double interval, double maxRatio, double quantile) {
  std::vector<double> iso;
  const size_t nv = mesh.vertexCount();
  if (!(interval > 0) || !std::isfinite(interval) || !(maxRatio > 0) || !std::isfinite(maxRatio) ||
      distance.size() != nv || mesh.positions.size() != 3 * nv || mesh.tets.size() % 4 != 0)
    return iso;
  quantile = std::clamp(std::isfinite(quantile) ? quantile : 0.0, 0.0, 1.0);
  double maxPhi = 0;
  for (double x : distance) {
    if (!std::isfinite(x)) return iso;
    maxPhi = std::max(maxPhi, x);
  }
  if (maxPhi / interval > 1e7) return iso;
  // Per boundary face: its phi range (the IGDS boundary curves cross it there), |grad phi| in its
  // tet (the linear field's gradient) and its area.
  struct Sample {
    double lo, hi, slope, area;
  };
  std::vector<Sample> samples;
  for (const TetBoundaryFace& f : tetBoundaryFaces(mesh)) {
    const uint32_t* v = &mesh.tets[4 * f.tet];
    const Eigen::Vector3d p0 = mesh.vertex(v[0]);
    const Eigen::Vector3d e1 = mesh.vertex(v[1]) - p0, e2 = mesh.vertex(v[2]) - p0,
                          e3 = mesh.vertex(v[3]) - p0;
    const double det = e1.dot(e2.cross(e3));
    const Eigen::Vector3d a = mesh.vertex(f.v[0]);
    const Eigen::Vector3d n2 = (mesh.vertex(f.v[1]) - a).cross(mesh.vertex(f.v[2]) - a);
    const double area = 0.5 * n2.norm();
    if (!(std::abs(det) > 0) || !(area > 0)) continue;
    // |grad phi| of the tet's linear field (Cramer's rule).
    const double slope = (scaledGradient(e1, e2, e3, distance[v[1]] - distance[v[0]],
                                         distance[v[2]] - distance[v[0]], distance[v[3]] - distance[v[0]]) /
                          det)
                             .norm();
    double lo = distance[f.v[0]], hi = lo;
    for (int c = 1; c < 3; ++c) {
      lo = std::min(lo, distance[f.v[c]]);
      hi = std::max(hi, distance[f.v[c]]);
    }
    samples.push_back({lo, hi, slope, area});
  }
  // Buckets of one interval: a band (c, c + s], s <= d, meets at most two.
  const size_t buckets = size_t(std::floor(maxPhi / interval)) + 2;
  std::vector<std::vector<uint32_t>> bucket(buckets);
  for (size_t k = 0; k < samples.size(); ++k) {
    const size_t b0 = size_t(std::max(0.0, std::floor(samples[k].lo / interval)));
    const size_t b1 = std::min(buckets - 1, size_t(std::max(0.0, std::floor(samples[k].hi / interval))));
    for (size_t b = b0; b <= b1; ++b) bucket[b].push_back(uint32_t(k));
  }
  std::vector<uint32_t> stamp(samples.size(), 0);
  uint32_t round = 0;
  std::vector<std::pair<double, double>> band;  // (slope, area)
  auto stepFrom = [&](double c, double s) {
    band.clear();
    ++round;
    const size_t b0 = size_t(std::floor(c / interval));
    for (size_t b = b0; b <= b0 + 1 && b < buckets; ++b) {
      for (uint32_t k : bucket[b]) {
        if (stamp[k] == round) continue;
        stamp[k] = round;
        if (samples[k].hi > c && samples[k].lo <= c + s) band.push_back({samples[k].slope, samples[k].area});
      }
    }
    if (band.empty()) return interval;
    std::sort(band.begin(), band.end());
    double total = 0;
    for (const auto& x : band) total += x.second;
    double acc = 0, q = band.back().first;
    for (const auto& x : band) {
      acc += x.second;
      if (acc >= quantile * total) {
        q = x.first;
        break;
      }
    }
    return interval * std::min(1.0, std::max(0.5, maxRatio * q));
  };
  for (double c = 0;;) {
    double s = interval;
    // The first layer lies on the platform, which carries it wherever the field is slow: a
    // whole interval, as in the paper (a shorter one laid its beads closer to the bed than half
    // their height where the field dips at the surface).
    if (c > 0) {
      for (int refine = 0; refine < 3; ++refine) s = stepFrom(c, s);
    }
    c += s;
    if (!(c < maxPhi)) break;
    iso.push_back(c);
  }
  return iso;
}

}  // namespace omnislice
