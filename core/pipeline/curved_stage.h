// SPDX-License-Identifier: MIT
// What the curved-layer methods (voxel, surface, geodesic) share between their layers and the
// pipeline's result: the tool-path options taken from the settings and the machine, the printed
// layer count and the preview's layer surfaces. Internal to core/pipeline.
#pragma once
#include <vector>

#include "pipeline/pipeline.h"
#include "pipeline/settings.h"
#include "machine/machine.h"
#include "surface/curved_toolpath.h"

namespace omnislice::stage {

// Speeds, retraction and filament from the settings; the nozzle cone from the machine; the tilt
// limit maxTiltDegrees; bead height nominalHeight, also the gouging check's clearance (the
// program header's layer_height, verify's h).
CurvedToolpathOptions curvedToolpathOptions(const Settings& settings, const MachineProfile& machine,
                                            double nominalHeight, double maxTiltDegrees);

// Layers with at least one path.
int printedLayerCount(const std::vector<std::vector<std::vector<SurfacePath>>>& paths);

// Every region's surface into preview.surfacePositions / surfaceTriangles / surfaceLayers.
void appendLayerSurfaces(const std::vector<CurvedLayer>& layers, PreviewBuffers& preview);

}  // namespace omnislice::stage
