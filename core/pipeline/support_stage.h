// SPDX-License-Identifier: MIT
// Supports as a pipeline step shared by the planar and multidir methods (internal to
// core/pipeline): settings -> generator options, the printed support volume, the report section.
#pragma once

#include "multidir/projected_supports.h"
#include "pipeline/report.h"
#include "pipeline/settings.h"
#include "toolpath/toolpath.h"

namespace omnislice::stage {

// support = projected, or auto with the multidir method (planar auto: overhangShare()).
bool supportsWanted(const Settings& settings);

// How much of a placed part's surface overhangs along +Z: the area of the faces risky by Eq. 1
// at alphaMaxDeg (multidir/risky_faces.h), faces whose every corner lies within platformBandMm of
// z = 0 left out (they rest on the platform), and its percentage of the whole surface.
struct OverhangShare {
  double overhangMm2 = 0, surfaceMm2 = 0, percent = 0;
};
OverhangShare overhangShare(const Mesh& part, double alphaMaxDeg, double platformBandMm);

// Generator options from the settings; methodAlphaDeg is the overhang angle when support.angle_deg
// is 0 (multidir: its alpha_max; planar: 45).
// Only faces within half the first layer of the platform rest on it: the overhangs J_G leaves out
// near the platform (multidir's 2 mm band) still get support.
SupportOptions supportOptionsFor(const Settings& settings, double methodAlphaDeg);

// Volume deposited by the Support moves: their filament times the filament's section, mm^3.
double printedSupportVolume(const Toolpath& path, double filamentDiameterMm);

// The report section of a support generation.
SupportReport supportReport(const SupportResult& supports, const SupportOptions& options, double regionVolumeMm3,
                            double printedVolumeMm3, double ms);

}  // namespace omnislice::stage
