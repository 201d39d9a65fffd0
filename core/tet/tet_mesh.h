// SPDX-License-Identifier: MIT
// Tetrahedral meshes for the geodesic method (paper 002): the exchange struct, the `.tet` reader
// of ../shared/models (`N vertices`, `M tets`, N lines of coordinates, M lines `4 i j k l`),
// validation, the boundary surface and quality statistics.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

// positions: #V*3 (mm); tets: #T*4 vertex indices, positively oriented (signed volume > 0:
// (b - a) . ((c - a) x (d - a)) > 0).
struct TetMesh {
  std::vector<double> positions;
  std::vector<uint32_t> tets;

  size_t vertexCount() const { return positions.size() / 3; }
  size_t tetCount() const { return tets.size() / 4; }
  Eigen::Vector3d vertex(size_t i) const {
    return {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]};
  }
};

struct TetMeshResult : Outcome {
  TetMesh mesh;
  size_t flipped = 0;  // tets whose orientation was reversed to make the volume positive
  std::vector<std::string> warnings;
};

// Parse `.tet` text. Tolerates blank lines, '#' comments, CRLF, extra whitespace; the counts'
// words ("vertices", "tets"/"tetrahedra") are optional but the two counts come first. Statuses:
// EmptyInput, ParseError (bad line, wrong arity: the message names the line), TruncatedFile
// (fewer lines than declared), NonFiniteVertex, DegenerateInput (index out of range, a tet with
// a repeated vertex or zero volume, no tets). Negative tets are flipped (counted). Indices are
// 0-based; each tet line must hold exactly `4 i j k l` and each vertex line exactly `x y z`.
// "Zero volume" is |6 V| <= 1e-12 * (longest edge)^3 (roundoff-flat); slivers are kept.
// Warnings: vertices used by no tet, flipped tets, lines after the declared tets.
TetMeshResult readTetMesh(const uint8_t* data, size_t size);

// Checks a mesh built in memory the same way (sizes, indices, finite, no repeated vertex, nonzero
// volume) and flips negative tets (counted).
TetMeshResult validateTetMesh(TetMesh mesh);

// Boundary surface: the faces used by exactly one tet, outward-oriented, on the tet mesh's
// vertex indices (unused vertices kept, so indices match the TetMesh). Faces shared by three or
// more tets are not boundary. Expects positively oriented tets (validateTetMesh); returns no
// triangles when an index is out of range.
Mesh tetBoundary(const TetMesh& mesh);

// The same faces with the tet each belongs to (in tetBoundary's order).
struct TetBoundaryFace {
  uint32_t tet = 0;
  std::array<uint32_t, 3> v{};  // outward-oriented
};
std::vector<TetBoundaryFace> tetBoundaryFaces(const TetMesh& mesh);

struct TetQuality {
  double volume = 0;                 // mm^3, sum of signed tet volumes
  double meanEdge = 0;               // mm, over distinct edges (paper: t = h^2, h the mean edge length)
  double minDihedralDegrees = 0, maxDihedralDegrees = 0;  // over the 6 angles of every tet
  double minRadiusRatio = 0;         // 3 r_in / r_out, 1 for the regular tet
  size_t nonManifoldFaces = 0;       // faces shared by more than two tets
};

// Statistics of a mesh (all zero for an empty mesh or out-of-range indices). Linear time.
TetQuality tetQuality(const TetMesh& mesh);

}  // namespace omnislice
