// SPDX-License-Identifier: MIT
#include "pipeline/support_stage.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "common/math_constants.h"
#include "multidir/risky_faces.h"

namespace omnislice::stage {

bool supportsWanted(const Settings& s) {
  return s.support.mode == SupportMode::Projected ||
         (s.support.mode == SupportMode::Auto && s.method == Method::Multidir);
}

OverhangShare overhangShare(const Mesh& part, double alphaMaxDeg, double platformBandMm) {
  OverhangShare s;
  const double sinAlpha = sinAlphaMax(alphaMaxDeg);
  for (size_t f = 0; f < part.faceCount(); ++f) {
    const Eigen::Vector3d a = part.vertex(part.triangles[3 * f]), b = part.vertex(part.triangles[3 * f + 1]),
                          c = part.vertex(part.triangles[3 * f + 2]);
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double area = 0.5 * n.norm();
    s.surfaceMm2 += area;
    if (!(area > 0)) continue;
    if (std::max({a.z(), b.z(), c.z()}) <= platformBandMm) continue;  // on the platform
    if (riskyAlong(n.normalized(), Eigen::Vector3d::UnitZ(), sinAlpha)) s.overhangMm2 += area;
  }
  s.percent = s.surfaceMm2 > 0 ? 100 * s.overhangMm2 / s.surfaceMm2 : 0;
  return s;
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

SupportReport supportReport(const SupportResult& r, const SupportOptions& o, double regionVolumeMm3,
                            double printedVolumeMm3, double ms) {
  SupportReport s;
  s.samplingMm = o.samplingMm;
  s.angleDeg = o.alphaMaxDeg;
  s.minDiameterMm = o.minDiameterMm;
  s.roofMm = o.roofMm;
  s.mergeAngleDeg = o.mergeAngleDeg;
  s.samples = r.samples;
  s.pointOverhangs = r.pointOverhangs;
  s.patchSamples = r.patchSamples;
  s.landedOnModel = r.landedOnModel;
  s.landedOnPlatform = r.landedOnPlatform;
  s.blocked = r.blocked;
  s.merges = r.merges;
  s.struts = r.struts.size();
  s.roofs = r.roofs.size();
  s.riskyAreaMm2 = r.riskyAreaMm2;
  s.strutVolumeMm3 = r.strutVolumeMm3;
  s.roofVolumeMm3 = r.roofVolumeMm3;
  s.regionVolumeMm3 = regionVolumeMm3;
  s.printedVolumeMm3 = printedVolumeMm3;
  s.ms = ms;
  return s;
}

}  // namespace omnislice::stage
