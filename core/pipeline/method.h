// SPDX-License-Identifier: MIT
// The one interface every slicing method implements, and the registry the pipeline runs them
// through. A method takes the placed part and the context (settings, machine, progress) and
// returns a part-frame tool path with its layers, timings, warnings, its report sections and its
// preview sections; the pipeline does the rest (read, validate, place before; motion, program,
// report after). One file per method: {planar,multidir,voxel,geodesic,surface}_method.cpp.
#pragma once
#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "machine/machine.h"
#include "mesh/mesh.h"
#include "pipeline/preview.h"
#include "pipeline/report.h"
#include "tet/tet_mesh.h"
#include "toolpath/toolpath.h"

namespace omnislice {

enum class Method {
  Planar,    // planar layers along one direction (with or without supports)
  Multidir,  // paper 000: planar clipping into parts printed along their own directions (3+2)
  Voxel,     // paper 001: curved layers of a voxel growing field
  Geodesic,  // paper 002: curved layers of the heat-method geodesic field on tets
  Surface,   // paper 003's experiments: an open surface printed as one layer on a planar base
  Auto,      // not a method: every method that applies to the machine runs, each program is
             // verified, and the best is delivered (pipeline.cpp; not in the registry)
};

// "planar", "multidir", "voxel", "geodesic", "surface", "auto".
const char* methodName(Method method);

// The method of a name as methodName() writes it; false for any other text.
bool parseMethod(const std::string& name, Method& method);

struct Settings;

// The part as a method receives it: read, validated and placed on the platform.
struct PlacedPart {
  Mesh mesh;                                            // part frame, min z = 0: a closed solid
                                                        // (the surface method: an open surface)
  Eigen::Matrix4d placement = Eigen::Matrix4d::Identity();  // input coordinates -> part frame
  std::optional<TetMesh> tets;                          // a .tet input's own tets, placed likewise
                                                        // (only for methods that use them)
};

struct MethodContext {
  const Settings& settings;
  const MachineProfile& machine;  // resolved: built-in or the user's, nozzle from the settings
  const ProgressFn& progress;
};

struct MethodResult : Outcome {
  Toolpath toolpath;          // part frame (of `part` when the method changed it)
  double layerHeight = 0;     // nominal bead height, mm: the program header's layer_height
  size_t slicedLayers = 0;    // layers the method made (the report's sliced_layers)
  size_t openChains = 0;      // planar sections left open (the report's open_chains)
  Eigen::Matrix4d turn = Eigen::Matrix4d::Identity();  // applied after the placement: the surface
                                                       // lifted onto its base, the part turned
                                                       // onto a 4dof machine's axis
  std::optional<Mesh> part;   // the part as printed when the method changed it (turned, or the
                              // solid under a surface); else the placed part
  double leftOutMm = 0;       // tool path the method planned but left out (no nozzle axis clears
                              // the part there), mm: a program with any is not sound
  // The lowest left-out point's height above the platform, mm (infinity when none is left out).
  double leftOutLowestMm = std::numeric_limits<double>::infinity();
  Timings timingsMs;          // the method's stages, in the order they ran
  std::vector<Warning> warnings;  // what the user should know about the delivered result
  MethodReport report;        // the method's sections of the report
  MethodPreview preview;      // the method's sections of the preview
};

using MethodRun = MethodResult (*)(const PlacedPart& part, const MethodContext& context);

// A method as the pipeline sees it before running it.
struct MethodEntry {
  Method method;
  bool needsSolid;               // a closed solid (false: the surface method's open surface)
  bool slicesAlongDirection;     // the part is turned so the `direction` setting points up
  bool usesInputTets;            // a .tet input's tets are read and placed for it
  bool boundsLayerCount;         // refused when the part needs more than 100,000 layers of the
                                 // layer height (the voxel method bounds its grid instead)
  std::vector<MachineKind> machines;  // the machine kinds it prints on
  const char* machineNeed;       // why, and what to choose: "tilts the nozzle along curved layers:
                                 // choose a machine with two rotary axes or a robot (table5, robot6)"
  MethodRun run;
};

// Every method, in the order of the Method enum.
const std::vector<MethodEntry>& methodRegistry();
const MethodEntry& methodEntry(Method method);

// The methods (each in its own file).
MethodResult runPlanarMethod(const PlacedPart& part, const MethodContext& context);
MethodResult runMultidirMethod(const PlacedPart& part, const MethodContext& context);
MethodResult runVoxelMethod(const PlacedPart& part, const MethodContext& context);
MethodResult runGeodesicMethod(const PlacedPart& part, const MethodContext& context);
MethodResult runSurfaceMethod(const PlacedPart& part, const MethodContext& context);

}  // namespace omnislice
