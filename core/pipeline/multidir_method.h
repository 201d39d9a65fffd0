// SPDX-License-Identifier: MIT
// The multi-directional (3+2-axis) method of paper 000 as one pipeline step: placed solid ->
// clipping planes by the search of Section IV (core/multidir/decomposition) -> closed parts in
// print order (Eq. 5-6, core/mesh/clip_mesh) -> each part sliced with planar layers along its own
// direction and planned by the foundation slicer (core/slice) -> one part-frame Toolpath, Move.part
// = the part's print index; the motion planner turns the machine between parts only after a
// retract and a safe move. Internal to core/pipeline.
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "pipeline/pipeline.h"
#include "pipeline/settings.h"
#include "machine/machine.h"
#include "toolpath/toolpath.h"

namespace omnislice {

struct MultidirMethodOutput : Outcome {
  Toolpath toolpath;
  std::string reportJson;   // the report's "multidir" object
  int layers = 0;           // layers over all parts
  Eigen::Matrix4d turn = Eigen::Matrix4d::Identity();  // 4dof axis search: the part turned about
                                                       // Z so the chosen axis lies on the
                                                       // machine's (applied to part and placement)
  Mesh part;                // the part as printed (turned when turn is not the identity)
  std::vector<std::pair<std::string, double>> timingsMs;  // decompose, clip, slice, toolpath
  PreviewBuffers preview;   // partPositions, partTriangles, partIds, riskyBefore, riskyAfter only
                            // (risky flags per triangle of part)
};

// part: the placed, validated solid (min z = 0). machine: rotary4 (4dof about its A axis, X),
// table5 or robot6 (5dof within the tilt range); cartesian3 is refused. Progress stages
// "decompose", "clip", "slice", "toolpath".
MultidirMethodOutput runMultidirMethod(const Mesh& part, const Settings& settings,
                                       const MachineProfile& machine, const ProgressFn& progress);

}  // namespace omnislice
