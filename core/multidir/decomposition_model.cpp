// SPDX-License-Identifier: MIT
// The model of the multidir plane search (decomposition_model.h): option and mesh checks, faces
// and the platform footprint, the occupancy grid (non-zero winding of vertical rays through cell
// centres, kept where connected to the platform layer) with its coarse volume samples, the
// Criterion II flood fill, cell sets kept by planes, and the exact J_G of a plane sequence.
#include "multidir/decomposition_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace omnislice::decomposition_detail {

// ---- options and mesh -----------------------------------------------------------------------

Outcome checkCommonOptions(const MultidirOptions& o) {
  auto bad = [](const std::string& what) { return failed<Outcome>(Status::InvalidOption, what); };
  if (!(o.alphaMaxDeg > 0 && o.alphaMaxDeg < 90)) return bad("alphaMaxDeg must be in (0, 90)");
  if (!(o.w >= 1) || !std::isfinite(o.w)) return bad("w must be a finite number >= 1");
  if (!(o.platformMarginMm >= 0) || !std::isfinite(o.platformMarginMm)) {
    return bad("platformMarginMm must be finite and >= 0");
  }
  if (!(o.platformRadiusMm >= 0) || !std::isfinite(o.platformRadiusMm)) {
    return bad("platformRadiusMm must be finite and >= 0");
  }
  if (!(o.platformBandMm >= 0) || !std::isfinite(o.platformBandMm)) {
    return bad("platformBandMm must be finite and >= 0");
  }
  if (o.gridResolution < 8 || o.gridResolution > 1000) return bad("gridResolution must be in [8, 1000]");
  if (!(o.floatingToleranceCells >= 0) || !std::isfinite(o.floatingToleranceCells)) {
    return bad("floatingToleranceCells must be finite and >= 0");
  }
  return {};
}

Outcome checkMesh(const Mesh& mesh) {
  if (mesh.triangles.empty()) return failed<Outcome>(Status::EmptyInput, "mesh has no triangles");
  if (mesh.positions.size() % 3 != 0 || mesh.triangles.size() % 3 != 0) {
    return failed<Outcome>(Status::ParseError, "mesh arrays are not multiples of 3");
  }
  const size_t nv = mesh.vertexCount();
  for (uint32_t i : mesh.triangles) {
    if (i >= nv) return failed<Outcome>(Status::ParseError, "triangle index out of range");
  }
  double lo = std::numeric_limits<double>::infinity(), extent = 0;
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const double x = mesh.positions[i];
    if (!std::isfinite(x)) return failed<Outcome>(Status::NonFiniteVertex, "non-finite vertex coordinate");
    extent = std::max(extent, std::abs(x));
    if (i % 3 == 2) lo = std::min(lo, x);
  }
  if (lo < -1e-9 * (1 + extent)) {
    return failed<Outcome>(Status::InvalidOption, "mesh lies below the platform z = 0 (place it first)");
  }
  return {};
}

// ---- the model: faces, occupancy grid, platform ------------------------------------------------

namespace {

Outcome buildFaces(const Mesh& mesh, const MultidirOptions& o, Model& m) {
  const size_t nv = mesh.vertexCount(), nf = mesh.faceCount();
  m.vert.resize(nv);
  m.lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  m.hi = -m.lo;
  for (size_t i = 0; i < nv; ++i) {
    m.vert[i] = mesh.vertex(i);
    m.lo = m.lo.cwiseMin(m.vert[i]);
    m.hi = m.hi.cwiseMax(m.vert[i]);
  }
  m.sinAlpha = sinAlphaMax(o.alphaMaxDeg);
  m.tri.resize(nf);
  m.area.resize(nf);
  m.normal.resize(nf);
  m.platRisk.assign(nf, 0);
  const Vec3 up(0, 0, 1);
  for (size_t f = 0; f < nf; ++f) {
    m.tri[f] = {mesh.triangles[3 * f], mesh.triangles[3 * f + 1], mesh.triangles[3 * f + 2]};
    m.corner.push_back({m.vert[m.tri[f][0]], m.vert[m.tri[f][1]], m.vert[m.tri[f][2]]});
    const Vec3 &a = m.vert[m.tri[f][0]], &b = m.vert[m.tri[f][1]], &c = m.vert[m.tri[f][2]];
    const Vec3 cr = (b - a).cross(c - a);
    const double len = cr.norm();
    m.area[f] = 0.5 * len;
    m.normal[f] = len > 0 ? Vec3(cr / len) : Vec3::Zero();
    m.volume += a.dot(b.cross(c)) / 6.0;
    const double cz = (a.z() + b.z() + c.z()) / 3.0;
    if (m.riskyAlong(f, up) && !(cz < o.platformBandMm)) m.platRisk[f] = m.area[f];
    m.jgBefore += m.platRisk[f];
    m.surfaceArea += m.area[f];
  }
  // Platform footprint: vertices within the band (at least the lowest ones).
  const double band = std::max(o.platformBandMm, 1e-9 * (1 + m.hi.cwiseAbs().maxCoeff()));
  for (const Vec3& v : m.vert) {
    if (v.z() - m.lo.z() <= band) m.footprint.emplace_back(v.x(), v.y());
  }
  m.margin = o.platformMarginMm;
  m.radius = o.platformRadiusMm;
  return {};
}

struct Crossing {
  uint32_t column;
  double z;
  int sign;  // +1 entering the solid going up (down-facing triangle), -1 leaving
};

Outcome buildGrid(const MultidirOptions& o, Model& m) {
  const Vec3 ext = m.hi - m.lo;
  const double longest = ext.maxCoeff();
  if (!(longest > 0)) return failed<Outcome>(Status::DegenerateInput, "the mesh has zero extent");
  m.h = longest / o.gridResolution;
  const double h = m.h;
  m.origin = Vec3(m.lo.x() - h, m.lo.y() - h, -h);
  m.nx = static_cast<int>(std::ceil(ext.x() / h)) + 3;
  m.ny = static_cast<int>(std::ceil(ext.y() / h)) + 3;
  m.nz = static_cast<int>(std::ceil(m.hi.z() / h)) + 3;
  const size_t nGrid = static_cast<size_t>(m.nx) * m.ny * m.nz;
  std::vector<Crossing> cross;
  for (const auto& t : m.tri) {
    Eigen::Vector2d a(m.vert[t[0]].x(), m.vert[t[0]].y()), b(m.vert[t[1]].x(), m.vert[t[1]].y()),
        c(m.vert[t[2]].x(), m.vert[t[2]].y());
    double za = m.vert[t[0]].z(), zb = m.vert[t[1]].z(), zc = m.vert[t[2]].z();
    auto cross2 = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
    double area2 = cross2(b - a, c - a);
    if (area2 == 0) continue;
    int sign = -1;  // counter-clockwise seen from above: an upward face, the ray leaves
    if (area2 < 0) {
      std::swap(b, c);
      std::swap(zb, zc);
      area2 = -area2;
      sign = 1;
    }
    // Tie rule for centres exactly on an edge: each edge u->v of a counter-clockwise triangle owns
    // its points when it runs downward (or leftward when horizontal); the twin edge v->u of the
    // neighbour then does not, so a column through a shared edge is counted once.
    auto owns = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
      return v.y() < u.y() || (v.y() == u.y() && v.x() < u.x());
    };
    const bool ownAB = owns(a, b), ownBC = owns(b, c), ownCA = owns(c, a);
    const double minx = std::min({a.x(), b.x(), c.x()}), maxx = std::max({a.x(), b.x(), c.x()});
    const double miny = std::min({a.y(), b.y(), c.y()}), maxy = std::max({a.y(), b.y(), c.y()});
    const int i0 = std::max(0, static_cast<int>(std::ceil((minx - m.origin.x()) / h - 0.5)));
    const int i1 = std::min(m.nx - 1, static_cast<int>(std::floor((maxx - m.origin.x()) / h - 0.5)));
    const int j0 = std::max(0, static_cast<int>(std::ceil((miny - m.origin.y()) / h - 0.5)));
    const int j1 = std::min(m.ny - 1, static_cast<int>(std::floor((maxy - m.origin.y()) / h - 0.5)));
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const Eigen::Vector2d p(m.origin.x() + (i + 0.5) * h, m.origin.y() + (j + 0.5) * h);
        const double e0 = cross2(b - a, p - a), e1 = cross2(c - b, p - b), e2 = cross2(a - c, p - c);
        if (e0 < 0 || e1 < 0 || e2 < 0) continue;
        if ((e0 == 0 && !ownAB) || (e1 == 0 && !ownBC) || (e2 == 0 && !ownCA)) continue;
        const double z = (e1 * za + e2 * zb + e0 * zc) / area2;
        cross.push_back({static_cast<uint32_t>(i + m.nx * j), z, sign});
      }
    }
  }
  std::sort(cross.begin(), cross.end(), [](const Crossing& x, const Crossing& y) {
    return x.column != y.column ? x.column < y.column : x.z < y.z;
  });
  std::vector<uint8_t> solid(nGrid, 0);
  const size_t layer = static_cast<size_t>(m.nx) * m.ny;
  for (size_t s = 0; s < cross.size();) {
    size_t e = s;
    while (e < cross.size() && cross[e].column == cross[s].column) ++e;
    int winding = 0;
    const Crossing* run = cross.data() + s;
    for (size_t q = 1; q < e - s; ++q) {
      winding += run[q - 1].sign;
      if (winding == 0) continue;
      const double z0 = run[q - 1].z, z1 = run[q].z;
      int k0 = static_cast<int>(std::ceil((z0 - m.origin.z()) / h - 0.5));
      int k1 = static_cast<int>(std::floor((z1 - m.origin.z()) / h - 0.5));
      k0 = std::max(k0, 1);
      k1 = std::min(k1, m.nz - 2);
      for (int k = k0; k <= k1; ++k) {
        const double zc = m.origin.z() + (k + 0.5) * h;
        if (zc > z0 && zc < z1) solid[run[0].column + layer * k] = 1;
      }
    }
    s = e;
  }
  // Keep the cells connected to the platform layer (k = 1, or the lowest solid layer).
  int baseLayer = -1;
  for (int k = 1; k < m.nz && baseLayer < 0; ++k) {
    for (size_t c = 0; c < layer; ++c) {
      if (solid[c + layer * k]) {
        baseLayer = k;
        break;
      }
    }
  }
  if (baseLayer < 0) return failed<Outcome>(Status::DegenerateInput, "no occupancy-grid cell lies inside the solid");
  std::vector<uint32_t> queue;
  std::vector<uint8_t> reached(nGrid, 0);
  for (size_t c = 0; c < layer; ++c) {
    const size_t g = c + layer * baseLayer;
    if (solid[g]) {
      reached[g] = 1;
      queue.push_back(static_cast<uint32_t>(g));
    }
  }
  const long steps[6] = {1, -1, m.nx, -m.nx, static_cast<long>(layer), -static_cast<long>(layer)};
  for (size_t q = 0; q < queue.size(); ++q) {
    for (long st : steps) {
      const size_t g = static_cast<size_t>(static_cast<long>(queue[q]) + st);
      if (solid[g] && !reached[g]) {
        reached[g] = 1;
        queue.push_back(static_cast<uint32_t>(g));
      }
    }
  }
  m.cellOf.assign(nGrid, -1);
  size_t solidCount = 0;
  for (size_t g = 0; g < nGrid; ++g) {
    solidCount += solid[g];
    if (!reached[g]) continue;
    m.cellOf[g] = static_cast<int32_t>(m.gridOf.size());
    m.gridOf.push_back(static_cast<uint32_t>(g));
    const size_t i = g % m.nx, j = (g / m.nx) % m.ny, k = g / layer;
    m.centre.emplace_back(m.origin.x() + (i + 0.5) * h, m.origin.y() + (j + 0.5) * h,
                          m.origin.z() + (k + 0.5) * h);
    if (static_cast<int>(k) == baseLayer) m.baseCells.push_back(static_cast<uint32_t>(m.gridOf.size() - 1));
  }
  m.cells = m.gridOf.size();
  m.orphans = solidCount - m.cells;
  m.isBase.assign(m.cells, 0);
  for (uint32_t c : m.baseCells) m.isBase[c] = 1;
  m.nbr.resize(6 * m.cells);
  for (size_t c = 0; c < m.cells; ++c) {
    for (int q = 0; q < 6; ++q) {
      const int32_t nb = m.cellOf[static_cast<size_t>(static_cast<long>(m.gridOf[c]) + steps[q])];
      m.nbr[6 * c + q] = nb < 0 ? kNoCell : static_cast<uint32_t>(nb);
    }
  }
  // ~1500 samples: the prefilter only has to be right to ~20% of V/w (the fine grid decides).
  const int bf = std::max(1, static_cast<int>(std::lround(std::cbrt(m.cells / 1500.0))));
  const size_t bx = static_cast<size_t>(m.nx / bf + 1), by = static_cast<size_t>(m.ny / bf + 1);
  const size_t bz = static_cast<size_t>(m.nz / bf + 1);
  std::vector<int32_t> blockOf(bx * by * bz, -1);
  for (size_t c = 0; c < m.cells; ++c) {
    const size_t g = m.gridOf[c];
    const size_t i = g % m.nx, j = (g / m.nx) % m.ny, k = g / layer;
    const size_t b = i / bf + bx * (j / bf + by * (k / bf));
    if (blockOf[b] < 0) {
      blockOf[b] = static_cast<int32_t>(m.samplePos.size());
      m.samplePos.push_back(Vec3::Zero());
      m.sampleWeight.push_back(0);
    }
    m.samplePos[blockOf[b]] += m.centre[c];
    m.sampleWeight[blockOf[b]] += 1;
  }
  for (size_t q = 0; q < m.samplePos.size(); ++q) m.samplePos[q] /= m.sampleWeight[q];
  return {};
}

}  // namespace

Outcome buildModel(const Mesh& mesh, const MultidirOptions& o, Model& m) {
  Outcome r = checkMesh(mesh);
  if (!r.ok()) return r;
  r = buildFaces(mesh, o, m);
  if (!r.ok()) return r;
  return buildGrid(o, m);
}

// ---- cell sets and Criterion II --------------------------------------------------------------

// Counts the cells of S n {n . x <= d} reachable from the platform layer through face neighbours.
size_t reachableBelow(const Model& m, const Bits& s, const Vec3& n, double d, FloodScratch& fs) {
  if (fs.stamp.size() != m.cells) fs.stamp.assign(m.cells, 0);
  if (++fs.gen == 0) {
    std::fill(fs.stamp.begin(), fs.stamp.end(), 0);
    fs.gen = 1;
  }
  fs.queue.clear();
  for (uint32_t c : m.baseCells) {
    if (testBit(s, c) && n.dot(m.centre[c]) <= d) {
      fs.stamp[c] = fs.gen;
      fs.queue.push_back(c);
    }
  }
  for (size_t q = 0; q < fs.queue.size(); ++q) {
    const uint32_t* nb = &m.nbr[6 * static_cast<size_t>(fs.queue[q])];
    for (int e = 0; e < 6; ++e) {
      const uint32_t c = nb[e];
      if (c == kNoCell || fs.stamp[c] == fs.gen || !testBit(s, c)) continue;
      if (n.dot(m.centre[c]) > d) continue;
      fs.stamp[c] = fs.gen;
      fs.queue.push_back(c);
    }
  }
  return fs.queue.size();
}

// The occupancy cells kept by planes [0, k).
Bits cellsKept(const Model& m, const std::vector<Vec3>& ns, const std::vector<double>& ds, size_t k,
               size_t& count) {
  Bits s((m.cells + 63) / 64, 0);
  count = 0;
  for (size_t c = 0; c < m.cells; ++c) {
    bool keep = true;
    for (size_t i = 0; i < k && keep; ++i) keep = ns[i].dot(m.centre[c]) <= ds[i];
    if (keep) {
      setBit(s, c);
      ++count;
    }
  }
  return s;
}

// The cells of s whose centres lie on or below the plane {x : n.x = d}, and how many.
Bits cellsBelow(const Model& m, const Bits& s, const Vec3& n, double d, size_t& count) {
  Bits below(s.size(), 0);
  count = 0;
  forEachBit(s, [&](size_t c) {
    if (n.dot(m.centre[c]) <= d) {
      setBit(below, c);
      ++count;
    }
  });
  return below;
}


// ---- exact J_G of a plane sequence ------------------------------------------------------------

// partRisk[k] for the part above plane k, partRisk.back() for the platform part.
std::vector<double> exactRisk(const Model& m, const std::vector<Vec3>& ns, const std::vector<double>& ds) {
  const size_t np = ns.size();
  std::vector<double> risk(np + 1, 0);
  for (size_t f = 0; f < m.tri.size(); ++f) {
    if (!(m.area[f] > 0)) continue;
    Poly poly = {m.vert[m.tri[f][0]], m.vert[m.tri[f][1]], m.vert[m.tri[f][2]]};
    for (size_t k = 0; k < np && !poly.empty(); ++k) {
      double tmin = std::numeric_limits<double>::infinity(), tmax = -tmin;
      for (const Vec3& p : poly) {
        const double t = ns[k].dot(p);
        tmin = std::min(tmin, t);
        tmax = std::max(tmax, t);
      }
      if (tmax <= ds[k] && tmin < ds[k]) continue;  // wholly below
      const bool risky = m.riskyAlong(f, ns[k]);
      if (tmin >= ds[k]) {  // wholly above (a face lying in the plane counts as above)
        if (risky) risk[k] += polyArea(poly, m.normal[f]);
        poly.clear();
        break;
      }
      if (risky) risk[k] += polyArea(clipPoly(poly, ns[k], ds[k], true), m.normal[f]);
      poly = clipPoly(poly, ns[k], ds[k], false);
    }
    if (!poly.empty() && m.platRisk[f] > 0) risk[np] += polyArea(poly, m.normal[f]);
  }
  return risk;
}

}  // namespace omnislice::decomposition_detail
