// SPDX-License-Identifier: MIT
// Sound or not (issue 25): the program the pipeline made, simulated as `omnislice verify` does
// (PROGRAM-FORMAT.md "What verification measures"), judged by fixed criteria, and, when it is not
// sound, the statement a user gets before anything is written: what fails, where, and what would
// print the model (supports, another method, another machine, another placement).
#pragma once
#include <limits>
#include <string>

#include "common/progress.h"
#include "common/status.h"
#include "machine/machine.h"
#include "mesh/mesh.h"
#include "pipeline/method.h"
#include "pipeline/preview.h"
#include "pipeline/report.h"
#include "pipeline/settings.h"

namespace omnislice {

// The criteria a sound program meets (the Goal of issue 25).
struct SoundnessCriteria {
  double minInside = 0.99;     // share of samples within w/2 of the solid
  double minCoverage = 0.97;   // share of interior grid points inside a bead (solid fills only)
  double minSupported = 0.99;  // share of surface samples with earlier material within 1.5 h
  // Share of the part's surface with a bead within w + h (+ half a sample spacing): every part of
  // the model is printed. Sound programs of the nine shared models at 40 mm reach 0.998-1.0; the
  // geodesic branches at 20 mm, whose tets do not connect the thin branches, 0.315 (3 layers of
  // 38, judged sound before: coverage finds no interior point in a part that thin).
  double minReached = 0.99;
  // No collision, no limit violated, no tool path left out: zero, not a share.
};

// The mode a slice runs in: auto is refuse for the multi-axis methods and off for planar.
VerifyMode effectiveVerifyMode(const Settings& settings);

struct SoundnessCheck : Outcome {
  VerifySection section;  // the report's "verify"
  VerifyPreview preview;  // where it fails, for viewers
  std::vector<float> unsupportedTips;  // #U*3: every unsupported surface sample (up to 200,000,
                                       // spread evenly beyond), for curved supports
};

// Simulate `program` (the text the pipeline wrote) against `part` (the printed solid in the part
// frame; for the surface method the solid under the surface) and judge it. The statement is filled
// when it is not sound. Progress stage "verify". Statuses: those of readProgram and
// verifyProgram (Internal when the pipeline's own program does not parse), Cancelled.
SoundnessCheck checkProgram(const std::string& program, const Mesh& part, const Settings& settings,
                            const MachineProfile& machine, const MethodResult& result, VerifyMode mode,
                            const SoundnessCriteria& criteria = {}, const ProgressFn& progress = {});

// A change of one setting the pipeline may try by itself when a program is unsound.
struct SettingRemedy {
  std::string key, value;  // as setSetting takes them
  std::string why;         // what it addresses ("collisions": another layer field)
};

// The remedies for this check's failures, in the order to try them (empty when none applies, or
// when another failure besides theirs would leave the program unsound anyway):
// - voxel or geodesic, colliding samples or tool path left out (beads supported, the fill
//   sound), with motion.axis_freedom_deg set above 15: the axes leaning at most 15 deg from
//   their ideal (geodesic, table5, 40 mm: the shared coin 1 mm left out at 25, sound at the
//   default 15);
// - voxel, colliding samples: the layer field smoothed half as much (voxel.smooth; where the
//   field's creases fall moves with the smoothing: 40 mm, table5, at 20 / 10 / 40 passes the
//   Kitten 14 / 0 / 13 colliding samples, the topopt part 28 / 35 / 2, the Yoga 144 / 35 / 462;
//   every sound program a second smoothing gave on the shared models came from half: the Kitten
//   at 20 and 40 mm, the Bunnyhead at 20 mm; none of three unsound held-out models); then, from
//   the default growth (pg-sp-gcfa), voxel.strategy sp-gcfa (at 40 mm it made the Yoga and the
//   topopt part sound on table5 and robot6 and the kitten (ply) on robot6; fertility 467 -> 53);
// - geodesic, supported below the bound: thinner layers where the field is slow at the surface
//   (geodesic.max_thickness_ratio 0.55, then 0.45; the Yoga on robot6 at 40 mm 0.9895 -> 0.995
//   for 18 % more layers);
// - multidir with supports on, beads over air: multidir.alpha_max_deg 40 (the shared topopt at
//   20 mm, 0.987 -> 0.994 for 4 % more time);
// - geodesic leaving tool path out next to the bed (leftOutLowestMm, the lowest left-out point's
//   height above the platform, within 5 intervals) and failing nothing else: the heat source
//   within one interval of the platform (geodesic.base_band_mm; the Kitten at 100 mm sound).
std::vector<SettingRemedy> automaticRemedies(const VerifySection& check, const Settings& settings,
                                             double leftOutLowestMm = std::numeric_limits<double>::infinity());

// The "remedied" warning: the program of the user's settings failed (first.failures) and the
// delivered one was made with the last of `tried`.
std::string remediedMessage(const VerifySection& first, const std::vector<AttemptSection>& tried);

// The attempts into the check of the delivered program; when it is not sound, its statement names
// them before its last sentence: "Made again with geodesic.max_thickness_ratio=0.55 (still: 1.1 %
// of the surface ...); geodesic.max_thickness_ratio=0.45 (still: ...)."
void noteAttempts(VerifySection& check, const std::vector<AttemptSection>& tried);

}  // namespace omnislice
