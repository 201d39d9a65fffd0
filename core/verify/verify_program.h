// SPDX-License-Identifier: MIT
// Verification by simulation: the measures of ../shared/PROGRAM-FORMAT.md ("What verification
// measures"), computed on a parsed program against the part's solid in the part frame.
#pragma once
#include <string>
#include <vector>

#include "common/memory_budget.h"
#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "program/read_program.h"

namespace omnislice {

struct VerifyOptions {
  double sampleSpacing = 0.5;    // mm along extruding path
  double gridSpacing = 0;        // mm for coverage, 0 = min(nozzle diameter, layer height)
  size_t maxGridPoints = 200000000;  // refuse coverage grids larger than this (InvalidOption)
  size_t maxSamples = 50000000;      // refuse programs with more path samples (InvalidOption)
  double memoryBudgetMb = kDefaultMemoryBudgetMb;  // samples and grid estimated larger: OutOfMemory
                                                   // (common/memory_budget.h; <= 0: no budget)
  size_t keepPoints = 0;             // > 0: keep up to this many positions of the unsupported
                                     // and of the colliding samples (spread evenly over them), for
                                     // viewers to draw where a program fails
  size_t keepUnsupported = 0;        // > 0: keep up to this many unsupported positions instead
                                     // of keepPoints (curved supports need all of them)
};

// Where a collision happened: the sample (tip position and nozzle axis), the earlier material
// point inside its cone, the program line of the move the sample lies on (1-based, 0 = unknown).
struct CollisionExample {
  double tip[3] = {0, 0, 0}, axis[3] = {0, 0, 1}, earlier[3] = {0, 0, 0};
  int layer = -1;
  int line = 0;
};

// A surface sample that nothing earlier supports (tip position, layer, program line).
struct UnsupportedExample {
  double tip[3] = {0, 0, 0};
  int layer = -1;
  int line = 0;
  double overhangDeg = 0;  // the nearest face's angle from the nozzle axis: 0 = a wall along
                           // it, 90 = facing straight against it (down), < 0 facing up
};

struct VerifyReport : Outcome {
  double inside = 0;            // share of the part's samples (support excluded: it lies outside
                                // the part by design) within w/2 of the solid
  double coverage = 0;          // share of interior grid points inside some bead
  double surfaceReached = 0;    // share of the part's surface area with a bead sample within
  double surfaceReach = 0;      // this distance (w + h + half the sample spacing), mm
  double supported = 0;         // share of the part's surface samples supported (by anything
                                // earlier, support included; support's own samples are not judged)
  size_t supportSamples = 0;    // samples on support features
  size_t surfaceSamples = 0;    // the part's surface samples (judged for supported)
  size_t unsupportedSamples = 0;  // of those, not supported
  std::vector<UnsupportedExample> unsupportedExamples;  // up to 10, spread over all of them
  double supportedAll = 0;      // same over all samples
  size_t collisions = 0;        // samples with an earlier sample inside the nozzle cone
  std::vector<CollisionExample> collisionExamples;  // the first few (at most 10), in print order
  std::vector<float> unsupportedPoints;  // options.keepPoints: #U*3 tips of unsupported samples
  std::vector<float> collisionPoints;    // options.keepPoints: #C*3 tips of colliding samples
  size_t limitViolations = 0;   // moves with an axis outside the declared limits
  double extrusionMm = 0;       // filament deposited
  double pathMm = 0;            // extruding path length
  size_t samples = 0;
  size_t gridPoints = 0;        // interior grid points considered for coverage
  int layers = 0;
};

// mesh: the part's solid already in the part frame (apply program.placement to the input mesh).
VerifyReport verifyProgram(const ParsedProgram& program, const Mesh& partMesh,
                           const VerifyOptions& options = {}, const ProgressFn& progress = {});

// JSON object with keys inside, coverage, surface_reached, surface_reach_mm, supported, supported_all, collisions, limits,
// extrusion_mm, path_mm, samples, grid_points, layers, collision_examples [{tip, axis, earlier,
// layer, line}].
std::string verifyReportJson(const VerifyReport& report);

}  // namespace omnislice
