// SPDX-License-Identifier: MIT
#include "mesh/weld_vertices.h"

#include <cmath>
#include <cstring>

#include "mesh/index_table.h"

namespace omnislice {
namespace {

uint64_t bitsOf(double v) {
  if (v == 0) v = 0;  // -0.0 and +0.0 weld together
  uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

uint64_t hashPosition(const double* p) {
  return mixHash64(bitsOf(p[0]) ^ mixHash64(bitsOf(p[1]) ^ mixHash64(bitsOf(p[2]))));
}

bool finite3(const double* p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

WeldResult weldExact(const Mesh& mesh) {
  const size_t n = mesh.vertexCount();
  const double* pos = mesh.positions.data();
  WeldResult out;
  out.remap.resize(n);
  out.positions.reserve(mesh.positions.size());
  // The table stores the old index of each kept vertex; keepIndex maps it to the new index.
  std::vector<uint32_t> newIndexOfKept(n, 0);
  IndexTable table(n / 8);
  uint32_t next = 0;
  for (size_t i = 0; i < n; ++i) {
    const double* p = pos + 3 * i;
    const uint32_t id = static_cast<uint32_t>(i);
    uint32_t found = id;
    if (finite3(p)) {
      found = table.findOrInsert(hashPosition(p), id, [&](uint32_t other) {
        const double* q = pos + 3 * size_t(other);
        return q[0] == p[0] && q[1] == p[1] && q[2] == p[2];
      });
    }
    if (found == id) {
      newIndexOfKept[i] = next;
      out.remap[i] = next++;
      out.positions.insert(out.positions.end(), p, p + 3);
    } else {
      out.remap[i] = newIndexOfKept[found];
    }
  }
  out.merged = n - next;
  return out;
}

struct Cell {
  int64_t x, y, z;
  bool operator==(const Cell& o) const { return x == o.x && y == o.y && z == o.z; }
};

int64_t cellCoord(double v, double tolerance) {
  const double c = std::floor(v / tolerance);
  const double limit = 4.0e18;  // keep the cast defined for absurd coordinate / tolerance ratios
  if (c > limit) return int64_t(4000000000000000000LL);
  if (c < -limit) return -int64_t(4000000000000000000LL);
  return static_cast<int64_t>(c);
}

uint64_t hashCell(const Cell& c) {
  return mixHash64(uint64_t(c.x) ^ mixHash64(uint64_t(c.y) ^ mixHash64(uint64_t(c.z))));
}

WeldResult weldTolerance(const Mesh& mesh, double tolerance) {
  const size_t n = mesh.vertexCount();
  const double* pos = mesh.positions.data();
  const double tol2 = tolerance * tolerance;
  constexpr uint32_t kNone = 0xFFFFFFFFu;
  WeldResult out;
  out.remap.resize(n);
  out.positions.reserve(mesh.positions.size());
  std::vector<Cell> cells;           // per cell id
  std::vector<uint32_t> cellHead;    // per cell id: first kept vertex (new index)
  std::vector<uint32_t> nextInCell;  // per kept vertex (new index)
  IndexTable table(n / 8);
  uint32_t next = 0;
  for (size_t i = 0; i < n; ++i) {
    const double* p = pos + 3 * i;
    if (!finite3(p)) {
      out.remap[i] = next++;
      out.positions.insert(out.positions.end(), p, p + 3);
      nextInCell.push_back(kNone);
      continue;
    }
    const Cell c{cellCoord(p[0], tolerance), cellCoord(p[1], tolerance), cellCoord(p[2], tolerance)};
    uint32_t match = kNone;
    for (int dx = -1; dx <= 1 && match == kNone; ++dx) {
      for (int dy = -1; dy <= 1 && match == kNone; ++dy) {
        for (int dz = -1; dz <= 1 && match == kNone; ++dz) {
          const Cell nc{c.x + dx, c.y + dy, c.z + dz};
          const uint32_t cellId = table.find(hashCell(nc), [&](uint32_t id) { return cells[id] == nc; });
          if (cellId == IndexTable::kEmpty) continue;
          for (uint32_t v = cellHead[cellId]; v != kNone; v = nextInCell[v]) {
            const double* q = out.positions.data() + 3 * size_t(v);
            const double ex = q[0] - p[0], ey = q[1] - p[1], ez = q[2] - p[2];
            if (ex * ex + ey * ey + ez * ez <= tol2 && (match == kNone || v < match)) match = v;
          }
        }
      }
    }
    if (match != kNone) {
      out.remap[i] = match;
      continue;
    }
    const uint32_t newId = next++;
    out.remap[i] = newId;
    out.positions.insert(out.positions.end(), p, p + 3);
    const uint32_t candidate = static_cast<uint32_t>(cells.size());
    const uint32_t cellId =
        table.findOrInsert(hashCell(c), candidate, [&](uint32_t id) { return cells[id] == c; });
    if (cellId == candidate) {
      cells.push_back(c);
      cellHead.push_back(kNone);
    }
    nextInCell.push_back(cellHead[cellId]);
    cellHead[cellId] = newId;
  }
  out.merged = n - next;
  return out;
}

}  // namespace

WeldResult weldVertices(const Mesh& mesh, double tolerance) {
  WeldResult exact = weldExact(mesh);
  if (!(tolerance > 0) || !std::isfinite(tolerance)) return exact;
  // Exact copies first (one probe each), then the 27-cell search over the distinct positions
  // only: an STL soup has ~6 copies of each vertex.
  Mesh distinct;
  distinct.positions = std::move(exact.positions);
  WeldResult near = weldTolerance(distinct, tolerance);
  for (uint32_t& v : exact.remap) v = near.remap[v];
  near.remap = std::move(exact.remap);
  near.merged += exact.merged;
  return near;
}

}  // namespace omnislice
