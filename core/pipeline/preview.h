// SPDX-License-Identifier: MIT
// What viewers draw of a slice: the tool path as line segments (every method) and each method's
// own section (curved layer surfaces, voxels, the geodesic field and skeleton tree, the multidir
// parts and risky faces). Float32 and uint32 arrays as the page's three.js buffers take them; all
// positions in the part frame, mm. The float32 buffers are made in preview.cpp, the one place
// where the core's double-precision geometry becomes graphics data (with GLM, as WebGL and three.js
// lay it out); the program never reads them.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "motion/machine_path.h"
#include "program/read_program.h"
#include "toolpath/toolpath.h"

namespace omnislice {

// One line segment per move that deposits or travels.
struct ToolpathPreview {
  std::vector<float> positions;   // #S*6: x0 y0 z0 x1 y1 z1 per segment
  std::vector<uint8_t> features;  // #S: Feature code (toolpath.h), 0 = travel
  std::vector<uint32_t> layers;   // #S: layer index
  std::vector<float> machine;     // #S*6: machine values at each segment's end (machine kinds'
                                  // units: mm, deg; robot6 rad), for the machine animation
  std::vector<float> axes;        // #S*3: part-frame nozzle axis (unit) at each segment's end
  // #S*7: the platform transform at each segment's end (kinematics.h platformTransform: part
  // frame -> machine frame, robot6: robot base frame) as a unit quaternion x y z w and a
  // translation x y z (mm), the arguments of three.js Matrix4.compose(position, quaternion, 1).
  // Consecutive quaternions lie in one hemisphere (dot >= 0), so slerp between them takes the
  // short way. Empty when the machine kind is unknown.
  std::vector<float> poses;
  // Iso-planar fill (paper 003): NL curve of each segment, 1-based in print order (0 = the
  // segment is not on an NL curve: travel, join, planar base), so viewers can tell adjacent curves
  // (side steps) apart.
  std::vector<uint32_t> curves;   // #S
};

// Curved-layer methods (voxel, geodesic, surface): every layer's regions as one triangle soup.
struct LayerSurfacePreview {
  std::vector<float> positions;     // #V*3
  std::vector<uint32_t> triangles;  // #T*3 vertex indices
  std::vector<uint32_t> layers;     // #T layer index per triangle
};

// Voxel method (paper 001): centres of missed voxels and of support cells.
struct VoxelPreview {
  std::vector<float> missed;    // #M*3
  std::vector<float> support;   // #K*3
  float width = 0;              // voxel width, mm
};

// Geodesic method (paper 002).
struct GeodesicPreview {
  // The part's boundary surface (the tet mesh's) with the geodesic distance per vertex.
  std::vector<float> fieldPositions;      // #F*3
  std::vector<uint32_t> fieldTriangles;   // #FT*3
  std::vector<float> fieldValues;         // #F, mm
  // The skeleton tree: one point per node (its IGDS's centroid) with its layer, edges as node
  // index pairs (lower, upper), and the print sequence the program follows (node indices).
  std::vector<float> nodePositions;       // #N*3
  std::vector<uint32_t> nodeLayers;       // #N
  std::vector<uint32_t> treeEdges;        // #E*2
  std::vector<uint32_t> sequence;         // #N
  // Segments left out because no nozzle axis clears the part there (skipped_tool_path).
  std::vector<float> skippedSegments;     // #K*6: start and end per segment
  std::vector<uint32_t> skippedLayers;    // #K, the layer of each
};

// Multidir method (paper 000): every part's closed mesh in one soup with its print index per
// triangle, and a risky flag per triangle of the printed part (SliceOutput.partMesh): along +Z
// (before; faces on the platform band are not risky) and along the direction of the part the
// face's centroid falls in (after).
struct MultidirPreview {
  std::vector<float> partPositions;       // #PV*3
  std::vector<uint32_t> partTriangles;    // #PT*3
  std::vector<uint32_t> partIds;          // #PT print index
  std::vector<uint8_t> riskyBefore;       // #T, 1 = risky
  std::vector<uint8_t> riskyAfter;        // #T, 1 = risky
};

// What a method adds to the preview (empty sections for the others).
struct MethodPreview {
  LayerSurfacePreview surfaces;
  VoxelPreview voxel;
  GeodesicPreview geodesic;
  MultidirPreview multidir;
};

// Where the simulated program fails (verify): tips of unsupported and of colliding samples,
// spread evenly, at most a few thousand each.
struct VerifyPreview {
  std::vector<float> unsupported;  // #U*3
  std::vector<float> collisions;   // #C*3
};

struct SlicePreview {
  ToolpathPreview toolpath;
  MethodPreview method;
  VerifyPreview verify;
};

// The tool-path preview of a planned machine path: the part-frame tip path of every move that
// deposits or travels, with the machine values, nozzle axis and platform pose at each segment's
// end; curve tags from toolpath.
ToolpathPreview toolpathPreview(const MachinePath& path, const Toolpath& toolpath);

// The tool-path preview of a program read back (replay): one segment per move whose tip moves,
// feature codes from the feature markers (extruding moves without a known marker count as
// wall-inner, moves without filament as travel), the machine values and platform pose of the
// program's machine at each segment's end (axes and curves stay empty).
ToolpathPreview programPreview(const ParsedProgram& program);

// Float32 narrowing of part-frame geometry for the methods' preview sections: append a point (3
// values) or every value of a flat array.
void appendPoint(std::vector<float>& out, const Eigen::Vector3d& p);
void appendFloats(std::vector<float>& out, const std::vector<double>& values);

}  // namespace omnislice
