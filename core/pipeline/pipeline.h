// SPDX-License-Identifier: MIT
// The one pipeline every front end calls (CLI, wasm API, worker, page): mesh bytes -> read ->
// validate/repair -> place -> slice -> tool-paths -> program, plus info and verify.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "pipeline/settings.h"

namespace omnislice {

// Tool-path preview for viewers: one line segment per move that deposits or travels.
struct PreviewBuffers {
  std::vector<float> positions;   // #S*6: x0 y0 z0 x1 y1 z1 per segment, part frame, mm
  std::vector<uint8_t> features;  // #S: Feature code (toolpath.h), 0 = travel
  std::vector<uint32_t> layers;   // #S: layer index
  std::vector<float> machine;     // #S*6: machine values at each segment's end (machine kinds'
                                  // units: mm, deg; robot6 rad), for the machine animation
  std::vector<float> axes;        // #S*3: part-frame nozzle axis (unit) at each segment's end

  // Curved-layer methods (voxel, geodesic): every layer's regions merged into one triangle soup.
  std::vector<float> surfacePositions;    // #V*3, part frame, mm
  std::vector<uint32_t> surfaceTriangles; // #T*3 vertex indices
  std::vector<uint32_t> surfaceLayers;    // #T layer index per triangle
  // Voxel method: centres of missed voxels and of support cells, and the voxel width.
  std::vector<float> missedVoxels;        // #M*3, part frame, mm
  std::vector<float> supportVoxels;       // #K*3, part frame, mm
  float voxelWidth = 0;                   // mm, 0 for other methods
  // Iso-planar fill (paper 003): NL curve of each segment, 1-based in print order (0 = the
  // segment is not on an NL curve: travel, join, planar base), so viewers can tell adjacent curves
  // (side steps) apart.
  std::vector<uint32_t> curves;           // #S
  // Geodesic method (paper 002): the part's boundary surface (the tet mesh's) with the geodesic
  // distance per vertex (colour map), and the skeleton tree: one point per node (its IGDS's
  // centroid) with its layer, edges as node index pairs (lower, upper), and the print sequence
  // the program follows (node indices in print order).
  std::vector<float> fieldPositions;      // #F*3, part frame, mm
  std::vector<uint32_t> fieldTriangles;   // #FT*3
  std::vector<float> fieldValues;         // #F, mm
  std::vector<float> nodePositions;       // #N*3, part frame, mm
  std::vector<uint32_t> nodeLayers;       // #N
  std::vector<uint32_t> treeEdges;        // #E*2
  std::vector<uint32_t> sequence;         // #N
  // Segments of the tool path left out because no nozzle axis clears the part there (the
  // geodesic method's skipped_tool_path warning): start and end per segment.
  std::vector<float> skippedSegments;     // #K*6, part frame, mm
  std::vector<uint32_t> skippedLayers;    // #K, the layer of each
  // Multidir method (paper 000): every part's closed mesh (clipSequence) merged into one soup with
  // the part's print index per triangle, and a risky flag per triangle of the placed part
  // (SliceOutput.partMesh): along +Z (before; faces with centroid below the platform band are
  // not risky) and along the direction of the part its centroid falls in (after).
  std::vector<float> partPositions;       // #PV*3, part frame, mm
  std::vector<uint32_t> partTriangles;    // #PT*3
  std::vector<uint32_t> partIds;          // #PT print index
  std::vector<uint8_t> riskyBefore;       // #T of partMesh, 1 = risky
  std::vector<uint8_t> riskyAfter;        // #T of partMesh, 1 = risky
};

struct SliceOutput : Outcome {
  std::string program;       // program text (G-code, robot CSV or URScript)
  std::string programExtension = "gcode";  // "gcode" | "csv" | "script"
  std::string reportJson;    // method, machine, machine_kind, layers, path_mm, extrusion_mm,
                             // estimated_time_s, motion {...}, timings_ms {read, validate, place,
                             // slice, toolpath, motion, program}, mesh, machine_profile, ...
  std::string infoJson;      // meshInfoJson() of the prepared input
  PreviewBuffers preview;
  Mesh partMesh;             // the placed solid (part frame), for viewers
  int layers = 0;
  std::vector<Warning> warnings;  // also the report's "warnings" ([{code, message}])
};

// Slice mesh bytes with settings. Every failure is a Status with a message (never throws).
SliceOutput runSlice(const uint8_t* data, size_t size, const std::string& fileName,
                     const Settings& settings, const ProgressFn& progress = {});

struct InfoOutput : Outcome {
  std::string infoJson;      // `omnislice info` JSON
  Mesh partMesh;             // placed mesh
};

// Read, validate and place; status is an error only when the file cannot be read at all.
InfoOutput runInfo(const uint8_t* data, size_t size, const std::string& fileName,
                   const PlacementSettings& placement, const ProgressFn& progress = {});

struct VerifyOutput : Outcome {
  std::string verifyJson;    // verifyReportJson()
};

// Verify a program against the mesh it was made from (the header's placement is applied to the
// mesh bytes).
VerifyOutput runVerify(const std::string& programText, const uint8_t* meshData, size_t meshSize,
                       const std::string& meshName, const ProgressFn& progress = {});

}  // namespace omnislice
