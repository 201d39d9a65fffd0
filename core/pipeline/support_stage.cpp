// SPDX-License-Identifier: MIT
#include "pipeline/support_stage.h"

#include <nlohmann/json.hpp>

#include "common/math_constants.h"
#include "pipeline/stage_support.h"

namespace omnislice::stage {

bool supportsWanted(const Settings& s) {
  return s.support.mode == "projected" || (s.support.mode == "auto" && s.method == "multidir");
}

SupportOptions supportOptionsFor(const Settings& s, double methodAlphaDeg) {
  SupportOptions o;
  o.samplingMm = s.support.samplingMm > 0 ? s.support.samplingMm : 2.5 * s.nozzleDiameter + 1;
  o.alphaMaxDeg = s.support.angleDeg > 0 ? s.support.angleDeg : methodAlphaDeg;
  o.platformBandMm = 0.5 * s.effectiveFirstLayerHeight();
  o.lambda = s.support.lambda;
  o.minDiameterMm = s.support.minDiameterMm > 0 ? s.support.minDiameterMm : 2 * s.effectiveLineWidth();
  o.roofMm = s.support.roofLayers * s.layerHeight;
  o.mergeAngleDeg = s.support.mergeAngleDeg;
  return o;
}

double printedSupportVolume(const Toolpath& path, double filamentDiameterMm) {
  double filament = 0;
  for (const Move& m : path.moves) {
    if (m.kind == MoveKind::Support && m.filament > 0) filament += m.filament;
  }
  return filament * kPi * 0.25 * filamentDiameterMm * filamentDiameterMm;
}

std::string supportReportJson(const SupportResult& r, const SupportOptions& o, double regionVolumeMm3,
                              double printedVolumeMm3, double ms) {
  nlohmann::ordered_json j = {{"generated", true},
                              {"sampling_mm", finite(o.samplingMm)},
                              {"angle_deg", finite(o.alphaMaxDeg)},
                              {"min_diameter_mm", finite(o.minDiameterMm)},
                              {"roof_mm", finite(o.roofMm)},
                              {"merge_angle_deg", finite(o.mergeAngleDeg)},
                              {"samples", r.samples},
                              {"point_overhangs", r.pointOverhangs},
                              {"patch_samples", r.patchSamples},
                              {"landed_on_model", r.landedOnModel},
                              {"landed_on_platform", r.landedOnPlatform},
                              {"blocked", r.blocked},
                              {"merges", r.merges},
                              {"struts", r.struts.size()},
                              {"roofs", r.roofs.size()},
                              {"risky_area_mm2", finite(r.riskyAreaMm2)},
                              {"strut_volume_mm3", finite(r.strutVolumeMm3)},
                              {"roof_volume_mm3", finite(r.roofVolumeMm3)},
                              {"region_volume_mm3", finite(regionVolumeMm3)},
                              {"printed_volume_mm3", finite(printedVolumeMm3)},
                              {"ms", finite(ms)}};
  return j.dump();
}

}  // namespace omnislice::stage
