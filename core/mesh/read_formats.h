// SPDX-License-Identifier: MIT
// Per-format mesh readers behind readMesh() (read_mesh.h). Each parses a whole in-memory file of
// its format and returns the raw mesh, or ParseError / TruncatedFile / EmptyInput /
// UnsupportedFormat with a message. None throws except std::bad_alloc, caught by readMesh().
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mesh/read_mesh.h"

namespace omnislice {

// Appends x, y, z (cheaper than a range insert of three values in the hot loops).
inline void pushXyz(std::vector<double>& v, const double* xyz) {
  v.push_back(xyz[0]);
  v.push_back(xyz[1]);
  v.push_back(xyz[2]);
}

// True when the bytes look like an ASCII STL: "solid" first, text only, a "facet" or "endsolid"
// keyword early on. A binary STL whose header starts with "solid" fails the text test.
bool looksLikeAsciiStl(const uint8_t* data, size_t size);

// True when size == 84 + 50 * (triangle count in bytes 80..83).
bool binaryStlSizeMatches(const uint8_t* data, size_t size);

// STL, binary or ASCII (decided from size and content, not from the first word). Binary gives 3
// vertices per face; a declared count larger than the data is TruncatedFile, smaller a warning.
ReadMeshResult readStl(const uint8_t* data, size_t size);

// Wavefront OBJ: v and f records (all index forms, negative indices), polygons fan-triangulated.
ReadMeshResult readObj(const uint8_t* data, size_t size);

// OFF / COFF / NOFF (ASCII): counts line, '#' comments, polygons fan-triangulated.
ReadMeshResult readOff(const uint8_t* data, size_t size);

// PLY ascii / binary_little_endian / binary_big_endian: vertex x,y,z and face vertex_indices.
ReadMeshResult readPly(const uint8_t* data, size_t size);

// 3MF: zip container, model part found via _rels/.rels; meshes, components, build transforms,
// units scaled to millimetres.
ReadMeshResult read3mf(const uint8_t* data, size_t size);

}  // namespace omnislice
