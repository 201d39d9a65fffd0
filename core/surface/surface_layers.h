// SPDX-License-Identifier: MIT
// Curved layers as every curved-layer method hands them on (voxel field of paper 001, geodesic
// field of paper 002): per layer, connected regions as part-frame triangle meshes, in print order.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <functional>
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
  bool partial = false;                 // a partial layer: laid only where the full layers around
                                        // it lie too far apart (bounded thickness); its regions'
                                        // cut edges are inside the part
};

// Every region of the layer as one mesh (vertices of region 0 first).
Mesh layerMesh(const CurvedLayer& layer);

// Keeps the part of each region where value(vertex position) > 0, the triangles crossing zero cut
// along the linear crossing on their edges (a crossing within a tenth of an edge's length of an end
// snaps to that end, so the cut leaves no slivers); the cut vertices are boundary vertices. The
// pieces are split into connected regions (triangles sharing a vertex), regions under minArea
// dropped; each keeps its parent's support flag.
void clipLayerRegions(CurvedLayer& layer, const std::function<double(const Eigen::Vector3d&)>& value,
                      double minArea);

// One layer's thickness samples (ThicknessStats::layers).
struct LayerThickness {
  size_t samples = 0;
  double mean = 0, min = 0, max = 0;  // mm; 0 without samples
  bool full = true;                   // not a partial layer
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
  std::vector<LayerThickness> layers;  // per layer (layer 0: no samples)
  // Sample-weighted mean over the full (not partial) layers: the nominal layer height.
  double fullMean() const;
};

// Thickness statistics between consecutive layers: points sampled every sampleSpacing mm over
// each layer's regions (layer i > 0), distance to the nearest point of the layers below it back
// to the last full layer (layer i - 1 when there are no partial layers) or of the platform z = 0.
// Sampling is deterministic and area-uniform (about one point per sampleSpacing^2, R2 sequence;
// the spacing grows so that at most about 2 million points are taken). Histogram bins are
// 0.05 * mean wide (wider when more than 400 would be needed), centred on multiples of the width
// so zero deviation sits mid-bin. Fewer than two layers or sampleSpacing <= 0: empty stats.
ThicknessStats layerThicknessStats(const std::vector<CurvedLayer>& layers, double sampleSpacing);

}  // namespace omnislice
