// SPDX-License-Identifier: MIT
// Curved layers as every curved-layer method hands them on (voxel field of paper 001, geodesic
// field of paper 002): per layer, connected regions as part-frame triangle meshes, in print order.
#pragma once
#include <cstdint>
#include <vector>

#include "mesh/mesh.h"

namespace omnislice {

// One connected region of one curved layer, a triangle mesh in the part frame.
struct LayerRegion {
  Mesh mesh;
  std::vector<uint8_t> boundaryVertex;  // per vertex: 1 on the trimmed boundary (on the part's
                                        // or the supports' surface), else 0
  double area = 0;                      // mm^2
  bool support = false;                 // the region lies in support cells
};

struct CurvedLayer {
  double isoValue = 0;                  // g_i
  std::vector<LayerRegion> regions;
};

// Layer-thickness statistics of Fig. 15: points sampled on every layer i > first, distance to
// the previous layer's surface.
struct ThicknessStats {
  size_t samples = 0;
  double mean = 0, stddev = 0;
  double maxDeviation = 0;         // max |distance - mean|, mm
  double histogramMin = 0;         // mm, left edge of the first bin
  double histogramBin = 0;         // mm, bin width
  std::vector<uint32_t> histogram; // counts of distance - mean per bin
};

// Thickness statistics between consecutive layers: points sampled every sampleSpacing mm over
// each layer's regions (layer i > 0), distance to the nearest point of layer i - 1.
// Sampling is deterministic and area-uniform (about one point per sampleSpacing^2, R2 sequence;
// the spacing grows so that at most about 2 million points are taken). Histogram bins are
// 0.05 * mean wide (wider when more than 400 would be needed), centred on multiples of the width
// so zero deviation sits mid-bin. Fewer than two layers or sampleSpacing <= 0: empty stats.
ThicknessStats layerThicknessStats(const std::vector<CurvedLayer>& layers, double sampleSpacing);

}  // namespace omnislice
