// SPDX-License-Identifier: MIT
#include "voxel/layer_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "voxel/growth_field.h"

namespace omnislice {

namespace {

// Indices of the grown cells (G >= 1) in growth order (counting sort by G).
std::vector<uint32_t> growthOrder(const std::vector<int32_t>& g) {
  int32_t maxG = 0;
  for (int32_t v : g) maxG = std::max(maxG, v);
  std::vector<uint32_t> start(static_cast<size_t>(maxG) + 2, 0);
  for (int32_t v : g) {
    if (v >= 1) ++start[static_cast<size_t>(v) + 1];
  }
  for (size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  std::vector<uint32_t> order(start.back());
  for (size_t i = 0; i < g.size(); ++i) {
    if (g[i] >= 1) order[start[static_cast<size_t>(g[i])]++] = static_cast<uint32_t>(i);
  }
  return order;
}

}  // namespace

// The layer field: G counts growth steps (time), and a step of the field-governed growth may add
// only a thin sliver of voxels, so iso-values of G bunch up where the front waited and spread where
// it ran. The generation 1 + max over the voxel's AM-stable neighbours added at earlier steps
// counts fronts instead: one unit per face- or edge-neighbour step (paper 001 Section 6.2.1: "the
// field value is increased by one in both cases", 1.25 w per unit). For neighbouring voxels it
// orders exactly as G does (a voxel added later than its neighbour has a larger generation), so
// the layers keep the growth's order locally; every voxel has a neighbour one generation below.
std::vector<int32_t> generationField(const VoxelGrid& grid, const std::vector<int32_t>& g) {
  const std::vector<uint32_t> order = growthOrder(g);
  std::vector<int32_t> gen(g.size());
  for (size_t i = 0; i < g.size(); ++i) gen[i] = g[i] >= 1 ? 0 : g[i];
  const auto& offsets = amStableOffsets();
  for (uint32_t idx : order) {
    const Eigen::Vector3i c = grid.cell(idx);
    int32_t best = 0;
    for (const Eigen::Vector3i& o : offsets) {
      const Eigen::Vector3i n = c + o;
      if (!grid.inRange(n.x(), n.y(), n.z())) continue;
      const size_t ni = grid.index(n.x(), n.y(), n.z());
      if (g[ni] >= 1 && g[ni] < g[idx]) best = std::max(best, gen[ni]);
    }
    gen[idx] = best + 1;
  }
  return gen;
}

// The growth distance: the length of the shortest path from the platform through AM-stable
// neighbour steps that each go to a voxel added at a later growth step (a shortest path in the
// growth's DAG, in voxel widths x `scale`, rounded), raised where needed to stay above every
// neighbour grown earlier. Where the field-governed growth made a region wait, G jumps between the
// early and the late voxels and its iso-surfaces bunch up there; this distance does not jump, so
// layers keep their thickness (30 mm Bunny, 0.64 mm voxels: thickness std 0.32 mm with G, 0.15 mm
// with this; verify coverage 0.914 -> 0.990, supported 0.797 -> 0.920, collisions 162 -> 344).
std::vector<int32_t> growthDistanceField(const VoxelGrid& grid, const std::vector<int32_t>& g,
                                         double scale, double orderMargin) {
  const std::vector<uint32_t> order = growthOrder(g);
  std::vector<double> d(g.size(), 0.0);
  const auto& offsets = amStableOffsets();
  for (uint32_t idx : order) {
    if (g[idx] == 1) {
      d[idx] = 0.5;  // a first-layer voxel's centre is half a voxel above the platform
      continue;
    }
    const Eigen::Vector3i c = grid.cell(idx);
    double best = std::numeric_limits<double>::infinity();
    // A voxel resting on the platform is half a voxel above it whenever the growth reached it, not
    // a step beyond the neighbours grown before it (kept though it did not lift the 20 mm box's
    // rim, whose first-layer tips stay at 0.22 mm against 0.34 in the middle: the rim's columns
    // are grown later all the way up).
    if (c.z() > 0 && grid.state[grid.index(c.x(), c.y(), c.z() - 1)] == static_cast<uint8_t>(VoxelState::Platform))
      best = 0.5;
    for (const Eigen::Vector3i& o : offsets) {
      const Eigen::Vector3i n = c + o;
      if (!grid.inRange(n.x(), n.y(), n.z())) continue;
      const size_t ni = grid.index(n.x(), n.y(), n.z());
      if (g[ni] >= 1 && g[ni] < g[idx]) best = std::min(best, d[ni] + o.cast<double>().norm());
    }
    // Keep the growth order with every earlier neighbour: at least orderMargin voxels above each
    // (0.1: on a 30 mm Bunny, 0.1 / 0.25 / 0.5 gave supported 0.92 / 0.90 / 0.88, collisions
    // 344 / 960 / 141, thickness std 0.15 / 0.16 / 0.29 mm).
    double above = 0;
    for (const Eigen::Vector3i& o : offsets) {
      const Eigen::Vector3i n = c + o;
      if (!grid.inRange(n.x(), n.y(), n.z())) continue;
      const size_t ni = grid.index(n.x(), n.y(), n.z());
      if (g[ni] >= 1 && g[ni] < g[idx]) above = std::max(above, d[ni] + orderMargin);
    }
    d[idx] = std::max(std::isfinite(best) ? best : 0.5, above);
  }
  std::vector<int32_t> out(g.size());
  for (size_t i = 0; i < g.size(); ++i) {
    out[i] = g[i] >= 1 ? std::max<int32_t>(1, static_cast<int32_t>(std::lround(d[i] * scale))) : g[i];
  }
  return out;
}

// The base: voxels at most this many cells above the platform keep the field's rise across a top
// face too (4 cells: about four first layers). Higher tops stay free boundaries: with the linear
// rule at every top face, collisions rose on most shared models (40 mm, table5: fertility 518 ->
// 2,375, kitten-ply 89 -> 1,254, bunnyhead 0 -> 153), and at every face (sides too) more so.
constexpr int kBaseCells = 4;

// Jacobi smoothing of a layer field over valued face neighbours (iterations), returned scaled by
// `scale` and rounded (the extractor takes integers): the voxel staircase of G becomes gentler
// iso-surfaces. Values <= 0 (platform, empty, missed) are kept and not averaged in; across the
// platform (and the top of the base) the field continues linearly.
std::vector<int32_t> smoothedField(const VoxelGrid& grid, const std::vector<int32_t>& g,
                                   int iterations, int32_t scale) {
  std::vector<double> a(g.size()), b;
  for (size_t i = 0; i < g.size(); ++i) a[i] = g[i];
  const Eigen::Vector3i faces[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int it = 0; it < iterations; ++it) {
    b = a;
    for (size_t idx = 0; idx < g.size(); ++idx) {
      if (g[idx] <= 0) continue;
      const Eigen::Vector3i c = grid.cell(idx);
      double sum = a[idx];
      int n = 1;
      for (const Eigen::Vector3i& o : faces) {
        const Eigen::Vector3i q = c + o;
        if (!grid.inRange(q.x(), q.y(), q.z())) continue;
        const size_t qi = grid.index(q.x(), q.y(), q.z());
        if (g[qi] <= 0) {
          // Across the platform, and across the top of the base (a thin plate on the bed), the
          // field continues linearly: the missing cell counts as 2 a - the value on the other
          // side (a where that has no value either), so the passes keep how the field rises from
          // the bed. Left out (a free boundary, as at the part's sides and higher tops) the
          // passes lifted the bottom cells towards the values above them, and flattened a plate
          // of two voxels to one value: the lowest layers ran down to the bed (a 20 mm box: tips
          // 0.02-0.08 mm over it, beads 0.32 mm) or vanished from the plate (the branches' base).
          const bool platform = grid.state[qi] == static_cast<uint8_t>(VoxelState::Platform);
          if (!platform && !(o.z() > 0 && c.z() - grid.platformK <= kBaseCells)) continue;
          const Eigen::Vector3i r = c - o;
          double ghost = a[idx];
          if (grid.inRange(r.x(), r.y(), r.z())) {
            const size_t ri = grid.index(r.x(), r.y(), r.z());
            if (g[ri] > 0) ghost = 2 * a[idx] - a[ri];
          }
          sum += ghost;
          ++n;
          continue;
        }
        sum += a[qi];
        ++n;
      }
      b[idx] = sum / n;
    }
    a.swap(b);
  }
  std::vector<int32_t> out(g.size());
  for (size_t i = 0; i < g.size(); ++i) {
    out[i] = g[i] <= 0 ? g[i] : std::max<int32_t>(1, static_cast<int32_t>(std::lround(a[i] * scale)));
  }
  return out;
}

// Millimetres per field unit as the layers will measure it: the thickness of iso-surfaces spaced
// one unit apart, averaged over their area, is 1 / |grad G| weighted by area, and by the coarea
// formula that average over all level sets is V / integral |grad G| dV, i.e. w over the mean
// gradient (in units per cell) over the valued voxels (central differences over valued face
// neighbours, one-sided at the border). The growth advances G by one per front step, but how far a
// step reaches depends on the strategy (the field-governed growth takes thinner steps), so curved
// layers of a given thickness need the iso step measured, not assumed (Eq. 2 assumes the paper's
// 1.25 w per unit, Section 6.2.1).
double millimetresPerFieldUnit(const VoxelGrid& grid, const std::vector<int32_t>& g) {
  auto valued = [&](int i, int j, int k, double& v) {
    if (!grid.inRange(i, j, k)) return false;
    const int32_t x = g[grid.index(i, j, k)];
    if (x <= 0) return false;
    v = x;
    return true;
  };
  double sum = 0;
  size_t count = 0;
  for (size_t idx = 0; idx < grid.cellCount(); ++idx) {
    if (g[idx] <= 0) continue;
    const Eigen::Vector3i c = grid.cell(idx);
    double grad2 = 0;
    for (int a = 0; a < 3; ++a) {
      Eigen::Vector3i lo = c, hi = c;
      lo[a] -= 1;
      hi[a] += 1;
      double vl = 0, vh = 0;
      const bool hasL = valued(lo.x(), lo.y(), lo.z(), vl), hasH = valued(hi.x(), hi.y(), hi.z(), vh);
      double d = 0;
      if (hasL && hasH) d = 0.5 * (vh - vl);
      else if (hasL) d = g[idx] - vl;
      else if (hasH) d = vh - g[idx];
      grad2 += d * d;
    }
    sum += std::sqrt(grad2);
    ++count;
  }
  // A field without any gradient (one voxel layer, e.g. a plate thinner than a voxel): 0, and the
  // caller extracts a single layer.
  if (count == 0 || sum <= 0) return 0;
  return grid.width * static_cast<double>(count) / sum;
}

const char* layerFieldName(LayerField field) {
  switch (field) {
    case LayerField::Distance: return "distance";
    case LayerField::Steps: return "steps";
    case LayerField::Generations: return "generations";
  }
  return "distance";
}

std::vector<int32_t> layerFieldOf(const VoxelGrid& grid, const std::vector<int32_t>& g, LayerField field,
                                  int smoothIterations) {
  std::vector<int32_t> f = field == LayerField::Generations ? generationField(grid, g)
                           : field == LayerField::Distance  ? growthDistanceField(grid, g, 16, 0.1)
                                                            : g;
  if (smoothIterations > 0) f = smoothedField(grid, f, smoothIterations, 16);
  return f;
}

}  // namespace omnislice
