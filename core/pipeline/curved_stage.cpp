// SPDX-License-Identifier: MIT
#include "pipeline/curved_stage.h"

namespace omnislice::stage {

CurvedToolpathOptions curvedToolpathOptions(const Settings& settings, const MachineProfile& machine,
                                            double nominalHeight, double maxTiltDegrees) {
  CurvedToolpathOptions o;
  o.nominalHeight = nominalHeight;
  o.filamentDiameter = settings.filamentDiameter;
  o.printSpeed = settings.printSpeed;
  o.firstLayerSpeed = settings.firstLayerSpeed;
  o.travelSpeed = settings.travelSpeed;
  o.retractLength = settings.retractLength;
  o.retractMinTravel = settings.retractMinTravel;
  o.retractSpeed = settings.retractSpeed;
  o.maxTiltDegrees = maxTiltDegrees;
  o.coneHalfAngleDegrees = machine.nozzle.coneHalfAngleDegrees;
  o.coneLength = machine.nozzle.coneLength;
  o.collisionClearance = nominalHeight;
  return o;
}

int printedLayerCount(const std::vector<std::vector<std::vector<SurfacePath>>>& paths) {
  int printed = 0;
  for (const auto& layer : paths) {
    bool any = false;
    for (const auto& region : layer) any = any || !region.empty();
    printed += any ? 1 : 0;
  }
  return printed;
}

void appendLayerSurfaces(const std::vector<CurvedLayer>& layers, PreviewBuffers& p) {
  for (size_t l = 0; l < layers.size(); ++l) {
    for (const LayerRegion& region : layers[l].regions) {
      const uint32_t base = static_cast<uint32_t>(p.surfacePositions.size() / 3);
      for (double v : region.mesh.positions) p.surfacePositions.push_back(static_cast<float>(v));
      for (uint32_t i : region.mesh.triangles) p.surfaceTriangles.push_back(base + i);
      p.surfaceLayers.insert(p.surfaceLayers.end(), region.mesh.faceCount(), static_cast<uint32_t>(l));
    }
  }
}

}  // namespace omnislice::stage
