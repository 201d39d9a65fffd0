// SPDX-License-Identifier: MIT
// Supports as the last resort for the curved-layer methods (issue 25 item 5): what the simulation
// finds printed over air gets a support fin under it, printed with the nozzle vertical.
//
// Construction. Each unsupported surface sample of a program's check (verify: no earlier material
// within 1.5 h) is matched to the tool-path move it lies on; along a bead the matched samples form
// stretches (consecutive samples at most 0.6 mm apart on one run of extruding moves). Only samples
// at an underside get a column: on the vertical line through the sample the part's surface must
// face down within 1.5 h under it (samples over part material, a layer too thick, get none). A
// column is a stack of copies at the heights j h (support layers shared by all columns), from
// the highest within [h/2, 3h/2) under the sample down to the lowest at least h/2 over what the
// column stands on: the platform, or the part's surface, which must then be printed before the
// column's lowest copy. A stretch's copies on one support layer form a horizontal polyline (a
// fin's layer); a lone sample gets a dash of one line width along its bead.
//
// Order. A copy is printed (highest copies decided first): before the path holding its sample,
// before the copy above it, before any tool-path material enters the vertical nozzle's cone at it,
// and no later than any copy in that cone; its pieces go after the retraction that ends the path
// before that place (with the filament pushed back for them and pulled again), lowest support
// layer first. A column is dropped when a path printed after one of its copies would hold that
// copy in its own nozzle cone (a region the tool path prints later beside the fin). The cone is
// verify's (the machine's half-angle and length), widened by 0.35 mm for the distance between
// verify's samples and these.
//
// The program with the fins is checked again like any other (pipeline.cpp), which judges the fins
// by the same measures.
#pragma once
#include <cstddef>
#include <vector>

#include "common/progress.h"
#include "mesh/mesh.h"
#include "toolpath/toolpath.h"

namespace omnislice {

struct CurvedSupportOptions {
  double layerHeightMm = 0.2;       // h: the fins' bead height and the copies' spacing
  double lineWidthMm = 0.4;         // the fins' bead width
  double filamentDiameterMm = 1.75;
  double speedMmS = 30;             // support beads
  double travelSpeedMmS = 150;
  double retractMm = 0;             // filament pushed back before the fins when the path before
  double retractSpeedMmS = 35;      // them retracted (and pulled again after them)
  double matchMm = 0.05;            // a sample lies on a move when within this distance of it
                                    // (verify's samples lie on the program's moves, which follow
                                    // the tool path's within the chord tolerance)
  double coneHalfAngleDeg = 40;     // the machine's nozzle cone (verify's collision test)
  double coneLengthMm = 25;
  size_t maxCopies = 1000000;       // more support beads (column heights) than this: no fins
                                    // (about 100 bytes and 15 us natively each)
};

struct CurvedSupportResult {
  bool cancelled = false;      // progress returned false (toolpath then empty)
  size_t copies = 0;           // column heights the samples at an underside would need; above
                               // maxCopies nothing is built (columns 0)
  Toolpath toolpath;           // the input with the fins inserted
  size_t samples = 0;          // unsupported samples given
  size_t matched = 0;          // of those, found on an extruding move
  size_t columns = 0;          // samples that got a column (fin points)
  size_t onPlatform = 0;       // of the columns, standing on the platform
  size_t notUnderside = 0;     // samples with part material (not air) within 1.5 h below
  size_t blocked = 0;          // samples at an underside without a column, for one of:
  size_t landsLater = 0;       //   landing on part printed after their lowest copy
  size_t inLaterCones = 0;     //   a copy in the cone of a path printed after it
                               //   (the rest: no room for a copy under them)
  size_t fins = 0;             // stretches that got a fin
  size_t beads = 0;            // support beads (one per copy piece)
  double pathMm = 0;           // support path length
  double filamentMm = 0;       // support filament
};

// The fins for `unsupported` (#U*3 part-frame tips, verify's unsupported samples of the program
// made from `path`) under the part `part` (closed, part frame). Deterministic. Cost: the tool path
// sampled every 0.5 mm into two cell hierarchies, then one descent per copy for each cone test.
// Progress stage "supports" while the copies are placed.
CurvedSupportResult addCurvedSupports(const Toolpath& path, const Mesh& part, const std::vector<float>& unsupported,
                                      const CurvedSupportOptions& options, const ProgressFn& progress = {});

}  // namespace omnislice
