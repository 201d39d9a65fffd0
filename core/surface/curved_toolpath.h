// SPDX-License-Identifier: MIT
// From curved layers and their surface paths to the part-frame Toolpath every writer consumes:
// printing orientation of paper 001 Section 5.2 (Eq. 3: from the closest point c_q on the layers
// printed before, t_q = q - c_q; the platform normal +Z on the first layer; the region's surface
// normal, flipped to agree, where no earlier layer is near), local bead height from the distance
// to the earlier layers (variable extrusion, paper 002 Eq. 12 / paper 001 Section 6.2.1), and
// travels between regions that retract and leave and approach along the nozzle axis.
// The low-pass filter and crest subdivision of Section 5.2 happen in core/motion (planMachineMotion).
#pragma once
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "surface/fermat_spiral.h"
#include "surface/surface_layers.h"
#include "toolpath/toolpath.h"

namespace omnislice {

struct CurvedToolpathOptions {
  double lineWidth = 0.45;          // bead width, mm
  double nominalHeight = 0.32;      // bead height where no earlier layer is measured, mm
  double minHeightFactor = 0.5;     // local height clamped to [min, max] x nominalHeight
  double maxHeightFactor = 1.75;
  double filamentDiameter = 1.75;   // mm
  double printSpeed = 30;           // mm/s
  double firstLayerSpeed = 20;      // mm/s (layer 0)
  double travelSpeed = 100;         // mm/s
  double retractLength = 0.8;       // mm of filament, 0 = off
  double retractMinTravel = 1.5;    // mm, shorter travels do not retract
  double travelClearance = 2.0;     // mm, leave/approach distance along the nozzle axis
  int earlierLayers = 3;            // layers below searched for c_q (Eq. 3)
};

struct CurvedToolpathResult : Outcome {
  Toolpath toolpath;                // Move.layer = layer index, Feature::Infill for part regions
                                    // (Feature::Support for support regions), axis per move
  size_t orientationFallbacks = 0;  // samples that used the surface normal instead of Eq. 3
  double orientationMs = 0;
};

// paths[l][r]: the paths of region r of layer l (same shape as layers). Progress stage "toolpath".
CurvedToolpathResult buildCurvedToolpath(const std::vector<CurvedLayer>& layers,
                                         const std::vector<std::vector<std::vector<SurfacePath>>>& paths,
                                         const CurvedToolpathOptions& options,
                                         const ProgressFn& progress = {});

}  // namespace omnislice
