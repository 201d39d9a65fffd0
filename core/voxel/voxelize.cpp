// SPDX-License-Identifier: MIT
// Conservative voxelisation (paper 001 Section 4.1). Cells live on the world lattice of pitch w
// (cell (i, j, k) of the lattice spans w [i, i+1] x [j, j+1] x [k, k+1]), so z = 0 is a cell
// boundary and faces of a model lying on multiples of w are cell boundaries too.
//
// Which cells are Solid: a cell is Solid when the interior of its cube meets the interior of the
// solid H. That is the tightest set whose union covers H, and it is what "the closed cube meets
// the solid" means once cells that only touch H along a face, an edge or a corner (they hold no
// material) are left out. By connectedness of the open cube it is exactly: the centre is inside H,
// or some surface triangle meets the open cube. The second test is the separating-axis test with
// the 13 axes of a triangle/box pair, where touching projections count as separated (exact for a
// closed triangle against an open box: the facets of their Minkowski difference have those
// normals). Consequence, asserted in the tests: an axis-aligned box [0, a w]^3 gives exactly a^3
// cells, the same box moved by half a cell (a + 1)^3.
#include "voxel/voxelize.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "geometry/aabb_tree.h"

namespace omnislice {

namespace {

using Eigen::Vector3d;

// Triangle (vertices relative to the box centre, in cell units) against the open box
// (-h, h)^3. True when they share a point.
bool triangleMeetsOpenBox(const Vector3d& v0, const Vector3d& v1, const Vector3d& v2, double h) {
  // Box face normals.
  for (int a = 0; a < 3; ++a) {
    const double lo = std::min({v0[a], v1[a], v2[a]});
    const double hi = std::max({v0[a], v1[a], v2[a]});
    if (lo >= h || hi <= -h) return false;
  }
  auto separated = [&](const Vector3d& axis) {
    const double r = h * (std::abs(axis.x()) + std::abs(axis.y()) + std::abs(axis.z()));
    if (r == 0) return false;  // degenerate axis: says nothing
    const double p0 = axis.dot(v0), p1 = axis.dot(v1), p2 = axis.dot(v2);
    return std::min({p0, p1, p2}) >= r || std::max({p0, p1, p2}) <= -r;
  };
  const Vector3d e0 = v1 - v0, e1 = v2 - v1, e2 = v0 - v2;
  // Triangle normal.
  if (separated(e0.cross(e1))) return false;
  // Edge x box-axis cross products.
  const Vector3d edges[3] = {e0, e1, e2};
  for (const Vector3d& e : edges) {
    if (separated(Vector3d(0, -e.z(), e.y()))) return false;  // X x e
    if (separated(Vector3d(e.z(), 0, -e.x()))) return false;  // Y x e
    if (separated(Vector3d(-e.y(), e.x(), 0))) return false;  // Z x e
  }
  return true;
}

VoxelizeResult fail(Status s, std::string message) { return failed<VoxelizeResult>(s, std::move(message)); }

std::string cellsMessage(double cells, size_t maxCells, double width) {
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "voxel grid of %.0f cells at width %g mm exceeds maxCells = %zu (use a larger width)",
                cells, width, maxCells);
  return buf;
}

}  // namespace

VoxelizeResult voxelizeSolid(const Mesh& mesh, const VoxelizeOptions& options,
                             const ProgressFn& progress) {
  const double w = options.width;
  if (!std::isfinite(w) || w <= 0) return fail(Status::InvalidOption, "voxel width must be a finite value > 0 mm");
  if (options.margin < 2) return fail(Status::InvalidOption, "voxel margin must be >= 2 cells");
  if (options.margin > 1000) return fail(Status::InvalidOption, "voxel margin must be <= 1000 cells");
  if (!std::isfinite(options.platformRadius) || options.platformRadius < 0) {
    return fail(Status::InvalidOption, "platform radius must be a finite value >= 0 mm");
  }
  if (mesh.empty() || mesh.vertexCount() == 0) return fail(Status::EmptyInput, "mesh has no triangles");
  if (mesh.positions.size() % 3 != 0 || mesh.triangles.size() % 3 != 0) {
    return fail(Status::ParseError, "mesh arrays are not a multiple of 3");
  }
  for (double c : mesh.positions) {
    if (!std::isfinite(c)) return fail(Status::NonFiniteVertex, "mesh has a non-finite vertex coordinate");
  }
  const size_t nv = mesh.vertexCount();
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity());
  Vector3d hi = -lo;
  for (uint32_t idx : mesh.triangles) {
    if (idx >= nv) return fail(Status::ParseError, "triangle index out of range");
    const Vector3d p = mesh.vertex(idx);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = (hi - lo).norm();
  if (lo.z() < -1e-9 * (1 + extent)) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "mesh must be placed on the platform (min z = %g mm < 0)", lo.z());
    return fail(Status::InvalidOption, buf);
  }
  // Lattice indices must fit an int with room for margins and the platform disc.
  const double reach = std::max(lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff()) + options.platformRadius;
  if (reach / w > 5e8) return fail(Status::InvalidOption, "voxel width too small for the model's coordinates");

  const int m = options.margin;
  // Touched lattice cells: open interval (i, i+1) meets [lo, hi] (in cell units).
  auto firstCell = [&](double v) { return static_cast<int>(std::floor(v / w)); };
  auto lastCell = [&](double v, int first) {
    return std::max(first, static_cast<int>(std::ceil(v / w)) - 1);
  };
  const int iLo = firstCell(lo.x()), iHi = lastCell(hi.x(), iLo);
  const int jLo = firstCell(lo.y()), jHi = lastCell(hi.y(), jLo);
  const int kHi = std::max(0, lastCell(hi.z(), firstCell(std::max(0.0, lo.z()))));
  // Part grid (lattice k >= 0 only): compact, no margin.
  const int px = iHi - iLo + 1, py = jHi - jLo + 1, pz = kHi + 1;
  {
    const double estimate = double(px + 2 * m) * double(py + 2 * m) * double(pz + 2 * m + 1);
    if (estimate > double(options.maxCells)) return fail(Status::InvalidOption, cellsMessage(estimate, options.maxCells, w));
  }
  std::vector<uint8_t> part(size_t(px) * size_t(py) * size_t(pz), 0);
  auto pidx = [&](int i, int j, int k) { return size_t(i) + size_t(px) * (size_t(j) + size_t(py) * size_t(k)); };
  const char* stage = "voxelize";
  if (!reportProgress(progress, stage, 0)) return fail(Status::Cancelled, "cancelled");

  const AabbTree tree(mesh);
  const uint8_t solid = static_cast<uint8_t>(VoxelState::Solid);

  // 1. Cell centres inside H: one column query per (i, j) gives every centre of the column.
  std::vector<ColumnCrossing> crossings;
  const size_t columns = size_t(px) * size_t(py);
  for (int j = 0; j < py; ++j) {
    for (int i = 0; i < px; ++i) {
      const size_t col = size_t(i) + size_t(px) * size_t(j);
      if ((col & 255) == 0 && !reportProgress(progress, stage, 0.5 * double(col) / double(columns))) {
        return fail(Status::Cancelled, "cancelled");
      }
      const double x = w * (iLo + i + 0.5), y = w * (jLo + j + 0.5);
      tree.columnCrossings(x, y, crossings);
      if (crossings.empty()) continue;
      std::sort(crossings.begin(), crossings.end(),
                [](const ColumnCrossing& a, const ColumnCrossing& b) { return a.z < b.z; });
      size_t c = 0;
      int winding = 0;
      for (int k = 0; k < pz; ++k) {
        const double z = w * (k + 0.5);
        while (c < crossings.size() && crossings[c].z < z) winding += crossings[c++].sign;
        if (winding != 0) part[pidx(i, j, k)] = solid;
      }
    }
  }

  // 2. Cells whose open cube a surface triangle meets: rasterise each triangle over the cells of
  // its bounding box near its plane.
  const size_t nf = mesh.faceCount();
  const Vector3d shift(iLo, jLo, 0);
  for (size_t f = 0; f < nf; ++f) {
    if ((f & 1023) == 0 && !reportProgress(progress, stage, 0.5 + 0.5 * double(f) / double(nf))) {
      return fail(Status::Cancelled, "cancelled");
    }
    // Cell units relative to the part grid's corner.
    const Vector3d a = mesh.vertex(mesh.triangles[3 * f]) / w - shift;
    const Vector3d b = mesh.vertex(mesh.triangles[3 * f + 1]) / w - shift;
    const Vector3d c = mesh.vertex(mesh.triangles[3 * f + 2]) / w - shift;
    const Vector3d tlo = a.cwiseMin(b).cwiseMin(c), thi = a.cwiseMax(b).cwiseMax(c);
    int r0[3], r1[3];
    const int n[3] = {px, py, pz};
    bool emptyRange = false;
    for (int d = 0; d < 3; ++d) {
      r0[d] = std::max(0, static_cast<int>(std::floor(tlo[d])));
      r1[d] = std::min(n[d] - 1, static_cast<int>(std::ceil(thi[d])) - 1);
      if (r1[d] < r0[d]) emptyRange = true;
    }
    if (emptyRange) continue;
    auto test = [&](int i, int j, int k) {
      uint8_t& s = part[pidx(i, j, k)];
      if (s == solid) return;
      const Vector3d centre(i + 0.5, j + 0.5, k + 0.5);
      if (triangleMeetsOpenBox(a - centre, b - centre, c - centre, 0.5)) s = solid;
    };
    const Vector3d nrm = (b - a).cross(c - a);
    int d = 0;
    if (std::abs(nrm.y()) > std::abs(nrm[d])) d = 1;
    if (std::abs(nrm.z()) > std::abs(nrm[d])) d = 2;
    if (nrm[d] == 0) {  // degenerate (zero-area) triangle: every cell of its bounding box
      for (int k = r0[2]; k <= r1[2]; ++k)
        for (int j = r0[1]; j <= r1[1]; ++j)
          for (int i = r0[0]; i <= r1[0]; ++i) test(i, j, k);
      continue;
    }
    // Walk the cells along the two other axes; along the dominant axis d only the cells the
    // triangle's plane crosses over that square (at most ~3, as |n_d| is the largest component),
    // widened by one cell against rounding. The exact test decides.
    const int ax = (d + 1) % 3, ay = (d + 2) % 3;
    const double gx = -nrm[ax] / nrm[d], gy = -nrm[ay] / nrm[d];  // plane: x_d = a_d + gx dx + gy dy
    int cell[3];
    for (int u = r0[ax]; u <= r1[ax]; ++u) {
      for (int v = r0[ay]; v <= r1[ay]; ++v) {
        const double dx0 = u - a[ax], dx1 = u + 1 - a[ax], dy0 = v - a[ay], dy1 = v + 1 - a[ay];
        const double z00 = gx * dx0 + gy * dy0, z01 = gx * dx0 + gy * dy1, z10 = gx * dx1 + gy * dy0,
                     z11 = gx * dx1 + gy * dy1;
        const double zlo = std::max(tlo[d], a[d] + std::min({z00, z01, z10, z11}));
        const double zhi = std::min(thi[d], a[d] + std::max({z00, z01, z10, z11}));
        const int k0 = std::max(r0[d], static_cast<int>(std::floor(zlo)) - 1);
        const int k1 = std::min(r1[d], static_cast<int>(std::ceil(zhi)));
        cell[ax] = u;
        cell[ay] = v;
        for (int k = k0; k <= k1; ++k) {
          cell[d] = k;
          test(cell[0], cell[1], cell[2]);
        }
      }
    }
  }

  // 3. Footprint: the lowest part layer holding Solid cells; its centre (mean of cell centres).
  int kFoot = -1;
  for (int k = 0; k < pz && kFoot < 0; ++k) {
    for (size_t q = 0; q < columns; ++q) {
      if (part[q + columns * size_t(k)] == solid) {
        kFoot = k;
        break;
      }
    }
  }
  if (kFoot < 0) return fail(Status::DegenerateInput, "the mesh encloses no volume at this voxel width");
  double cx = 0, cy = 0;
  size_t footCells = 0;
  for (int j = 0; j < py; ++j) {
    for (int i = 0; i < px; ++i) {
      if (part[pidx(i, j, kFoot)] != solid) continue;
      cx += w * (iLo + i + 0.5);
      cy += w * (jLo + j + 0.5);
      ++footCells;
    }
  }
  cx /= double(footCells);
  cy /= double(footCells);
  const double R = options.platformRadius;
  int gi0 = iLo, gi1 = iHi, gj0 = jLo, gj1 = jHi;
  if (R > 0) {
    gi0 = std::min(gi0, static_cast<int>(std::floor((cx - R) / w)));
    gi1 = std::max(gi1, static_cast<int>(std::floor((cx + R) / w)));
    gj0 = std::min(gj0, static_cast<int>(std::floor((cy - R) / w)));
    gj1 = std::max(gj1, static_cast<int>(std::floor((cy + R) / w)));
  }

  // 4. Final grid: lattice cells [gi0 - m, gi1 + m] x [gj0 - m, gj1 + m] x [-1 - m, kHi + m];
  // the platform layer is lattice k = -1 (z in [-w, 0]), grid k = m.
  const double total = double(gi1 - gi0 + 1 + 2 * m) * double(gj1 - gj0 + 1 + 2 * m) * double(pz + 1 + 2 * m);
  if (total > double(options.maxCells)) return fail(Status::InvalidOption, cellsMessage(total, options.maxCells, w));
  VoxelizeResult result;
  VoxelGrid& g = result.grid;
  g.width = w;
  g.dims = Eigen::Vector3i(gi1 - gi0 + 1 + 2 * m, gj1 - gj0 + 1 + 2 * m, pz + 1 + 2 * m);
  g.platformK = m;
  g.origin = Vector3d(w * (gi0 - m), w * (gj0 - m), -w * (m + 1));
  g.state.assign(size_t(g.dims.x()) * size_t(g.dims.y()) * size_t(g.dims.z()), 0);
  const int di = iLo - (gi0 - m), dj = jLo - (gj0 - m), dk = m + 1;
  for (int k = 0; k < pz; ++k) {
    for (int j = 0; j < py; ++j) {
      for (int i = 0; i < px; ++i) {
        if (part[pidx(i, j, k)] != solid) continue;
        g.state[g.index(i + di, j + dj, k + dk)] = solid;
        ++result.solidCount;
      }
    }
  }
  const uint8_t platform = static_cast<uint8_t>(VoxelState::Platform);
  for (int j = 0; j < py; ++j) {
    for (int i = 0; i < px; ++i) {
      if (part[pidx(i, j, kFoot)] == solid) g.state[g.index(i + di, j + dj, m)] = platform;
    }
  }
  if (R > 0) {
    for (int j = 0; j < g.dims.y(); ++j) {
      for (int i = 0; i < g.dims.x(); ++i) {
        const Vector3d c = g.center(i, j, m);
        if ((c.x() - cx) * (c.x() - cx) + (c.y() - cy) * (c.y() - cy) <= R * R) g.state[g.index(i, j, m)] = platform;
      }
    }
  }
  for (int j = 0; j < g.dims.y(); ++j) {
    for (int i = 0; i < g.dims.x(); ++i) result.platformCount += g.state[g.index(i, j, m)] == platform;
  }
  if (!reportProgress(progress, stage, 1)) return fail(Status::Cancelled, "cancelled");
  return result;
}

size_t addSupportColumns(VoxelGrid& grid, const std::vector<uint8_t>& missed) {
  if (missed.size() != grid.cellCount() || grid.cellCount() == 0) return 0;
  const uint8_t empty = static_cast<uint8_t>(VoxelState::Empty);
  const uint8_t support = static_cast<uint8_t>(VoxelState::Support);
  const uint8_t platform = static_cast<uint8_t>(VoxelState::Platform);
  size_t added = 0;
  for (size_t q = 0; q < missed.size(); ++q) {
    if (!missed[q]) continue;
    const Eigen::Vector3i c = grid.cell(q);
    if (c.z() <= grid.platformK) continue;  // a platform (or below) cell needs no support
    for (int k = c.z() - 1; k >= grid.platformK; --k) {
      uint8_t& s = grid.state[grid.index(c.x(), c.y(), k)];
      if (s != empty) break;  // reached Solid, Support or Platform
      if (k == grid.platformK) {
        s = platform;
        break;
      }
      s = support;
      ++added;
    }
  }
  return added;
}

}  // namespace omnislice
