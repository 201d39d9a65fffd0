// SPDX-License-Identifier: MIT
// Mesh readers: STL (binary and ASCII; a binary file may start with "solid"), OBJ (polygons are
// fan-triangulated, negative indices), OFF, PLY (ascii, binary little and big endian), 3MF (zip
// container, stored or deflated entries, inflated in the core so CLI, wasm and page share it),
// TET (tetrahedral mesh, read as its boundary surface: the solid it fills).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

struct ReadMeshResult : Outcome {
  Mesh mesh;                          // raw: STL gives 3 vertices per face; nothing merged or fixed
  std::string format;                 // "stl-binary", "stl-ascii", "obj", "off", "ply-ascii",
                                      // "ply-binary-le", "ply-binary-be", "3mf", "tet"
  std::vector<std::string> warnings;  // non-fatal oddities (e.g. "STL header count 12 != 10 read")
};

// Parse a mesh from memory. nameHint is the file name (its extension picks the format when
// present; otherwise the content is sniffed). Statuses: EmptyInput (no bytes / no faces),
// UnsupportedFormat, ParseError (malformed text, bad index), TruncatedFile (declared content
// missing). Never throws; non-finite coordinates are read as they are (validation reports them).
ReadMeshResult readMesh(const uint8_t* data, size_t size, const std::string& nameHint);

// Read a file from disk (IoError when it cannot be opened), then readMesh().
ReadMeshResult readMeshFile(const std::string& path);

}  // namespace omnislice
