// SPDX-License-Identifier: MIT
// Repair of a mesh that does not bound a solid (holes, non-manifold edges and vertices, debris)
// into a closed manifold one: the `repair = auto` step of prepareMesh (mesh/prepare_mesh.h).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

struct SolidRepairOptions {
  bool zipTJunctions = true;  // step (0) below
  // Loops of more points are capped by a fan from their centroid instead of the dihedral-angle
  // triangulation (its cost grows with n^2-n^3).
  size_t maxTriangulatedLoop = 400;
  // Holes of at most this many rim points in a smooth surface (no crease into the hole, rim not
  // flat) are refined and faired to continue the surface (mesh/fair_patch.h); others stay flat.
  bool fair = true;
  size_t maxFairedLoop = 200;
  // An edge-connected piece whose hole caps would make more than this share of its area, and
  // whose closed volume is flat (36 pi V^2 / A^3, 1 for a ball, below sheetQuotient: a cap copies
  // the sheet) is a sheet (an open surface), not a solid with holes: its holes are left open and
  // the solid refused. Measured: a wavy sheet 0.0004, the Costa surface 0.00004, a hemisphere
  // bowl 0.59, the Kitten with 40 % of its surface cut away 0.32.
  double maxCapAreaShare = 0.4;
  double sheetQuotient = 0.02;
  // Debris, dropped: a piece that had holes, is a sheet or has less than debrisVolumeShare of the
  // largest piece's volume, and whose box diagonal is below debrisSizeShare of the model's. Pieces
  // that were closed stay, however small (they are the model's: an ogre's teeth).
  double debrisVolumeShare = 1e-4;
  double debrisSizeShare = 0.05;
  // A sheet of less than this share of the largest piece's area (an island left between holes).
  double debrisAreaShare = 0.02;
  // Faces hanging into holes (two boundary edges) are dropped, again until none is left, unless
  // that takes more than this share of the faces (a ribbon one face wide would vanish).
  double maxPrunedShare = 0.5;
};

struct SolidRepairStats {
  size_t tJunctionsZipped = 0;    // boundary vertices on another boundary edge: that face split there
  size_t edgesUnpaired = 0;       // edges of more than two faces split into pairs of faces
  size_t facesLeftOver = 0;       // faces left unpaired at an edge of an odd number of faces, dropped
  size_t verticesSplit = 0;       // vertex copies made so every vertex is one fan
  size_t facesPruned = 0;         // faces hanging into holes by one edge, dropped
  size_t holesFilled = 0;         // boundary loops closed (triangulated or capped)
  size_t holesFaired = 0;         // of those, refined and faired to the surface around
  size_t holesCapped = 0;         // of those, loops too long to triangulate: a fan from the centroid
  size_t holesLeft = 0;           // loops of sheets, left open
  size_t sheets = 0;              // pieces judged sheets (see maxCapAreaShare)
  double largestHoleMm = 0;       // largest box diagonal of a filled loop
  double filledAreaMm2 = 0;       // area of the triangles added
  size_t filledFaces = 0;
  size_t sheetsDropped = 0;       // sheets dropped beside solid pieces of more area
  size_t sheetFacesDropped = 0;
  double sheetAreaDroppedMm2 = 0;
  size_t debrisPieces = 0;        // pieces dropped as debris
  size_t debrisFaces = 0;
  double rebuiltPitchMm = 0;      // prepareMesh rebuilt the surface on a grid of this pitch instead
                                  // (mesh/rebuild_solid.h); the other counts are then 0
};

struct SolidRepairResult : Outcome {
  Mesh mesh;
  size_t firstFilledFace = 0;         // faces of mesh from this one on close holes (stats.filledFaces)
  SolidRepairStats stats;
  std::vector<std::string> repairs;   // one line per kind of repair done, with counts and sizes
};

// Repair `mesh` (welded, without degenerate or duplicate faces: prepareMesh's first repairs) toward
// a closed manifold. Steps: (0) T-junctions: a boundary vertex within 1e-6 of the diagonal of
// another boundary edge, strictly inside it, splits that edge's face by a fan from its opposite
// corner (cracks between faces tessellated apart close exactly); (1) at an edge of more than two faces, the faces are sorted by angle
// about the edge and paired with a neighbour running the edge the other way so that each pair
// encloses material; then every vertex is split into one copy per fan of faces linked through
// manifold or paired edges (non-manifold edges and vertices gone); (2) faces are oriented
// consistently per piece, and faces hanging into a hole by one edge dropped; (3) each boundary
// loop is triangulated (cgal/hole_triangulation.h) or, when longer than maxTriangulatedLoop or
// when the triangulation would reuse an edge of the mesh, capped by a fan from its centroid, unless
// its piece is a sheet; (4) small pieces that had holes (tiny in volume, or sheets) and islands
// of surface left between holes are dropped, and so are sheets beside solid pieces of more area
// than theirs (a mesh of sheets only, or mostly, stays open and is refused). Only Cancelled is an error: what cannot be
// repaired stays, for prepareMesh to refuse. Progress stage "repair".
SolidRepairResult repairSolid(const Mesh& mesh, const SolidRepairOptions& options = {},
                              const ProgressFn& progress = {});

}  // namespace omnislice
