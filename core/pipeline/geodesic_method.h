// SPDX-License-Identifier: MIT
// The geodesic method of paper 002 as one pipeline step: placed solid (or a given tet mesh) ->
// tet mesh (core/tet/tet_mesher) -> heat-method geodesic distance from the platform
// (core/geodesic/heat_geodesic) -> iso-geodesic distance surfaces with metrics
// (core/geodesic/igds) -> skeleton tree, potential collision surfaces and the LPT / DPT / A3
// sequences (core/geodesic/print_order) -> filling paths on every IGDS (Section 3.2: iso-contours
// of the boundary geodesic distance connected into Fermat spirals, core/surface/fermat_spiral; or
// iso-planar paths with fill = isoplanar) -> part-frame Toolpath in the chosen sequence, nozzle
// axis along the IGDS normal, extrusion from the local layer thickness (Eq. 12). Internal to
// core/pipeline.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "pipeline/pipeline.h"
#include "pipeline/settings.h"
#include "machine/machine.h"
#include "tet/tet_mesh.h"
#include "toolpath/toolpath.h"

namespace omnislice {

struct GeodesicMethodOutput : Outcome {
  Toolpath toolpath;
  std::string reportJson;     // the report's "geodesic" object
  std::string isoplanarJson;  // fill = isoplanar: the report's "isoplanar" object
  double layerHeight = 0;     // the geodesic interval d, mm
  int layers = 0;             // IGDS layers with at least one path
  std::vector<std::pair<std::string, double>> timingsMs;  // tetmesh, field, igds, order, paths,
                                                          // toolpath (pipeline stage names)
  PreviewBuffers preview;     // surface (IGDS), field, skeleton and skipped-segment fields only
  std::vector<Warning> warnings;  // e.g. skipped_tool_path
};

// part: the placed, validated solid (min z = 0). tets: the placed tet mesh when the input was a
// `.tet` file (its boundary is `part`), else nullptr (the solid is meshed). machine: the resolved
// profile (its tilt range bounds the nozzle axes, its nozzle cone is the default collision cone).
// Progress stages "tetmesh", "field", "igds", "order", "paths", "toolpath".
GeodesicMethodOutput runGeodesicMethod(const Mesh& part, const TetMesh* tets, const Settings& settings,
                                       const MachineProfile& machine, const ProgressFn& progress);

}  // namespace omnislice
