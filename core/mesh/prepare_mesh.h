// SPDX-License-Identifier: MIT
// Validation and safe repair of a raw mesh (its placement on the platform: mesh/place_mesh.h).
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "mesh/repair_mesh.h"

namespace omnislice {

// What validation found and what it did. Counts are after repair.
struct MeshInfo {
  size_t vertices = 0;
  size_t faces = 0;
  size_t shells = 0;                 // edge-connected components
  bool closed = false;               // no boundary edge
  bool manifold = false;             // every edge has <= 2 faces and every vertex link is one fan
  bool oriented = false;             // consistently oriented (after repair)
  size_t boundaryEdges = 0;
  size_t boundaryLoops = 0;          // holes (counted on the half-edge mesh)
  size_t nonManifoldEdges = 0;
  size_t nonManifoldVertices = 0;
  size_t selfIntersections = 0;      // intersecting face pairs found (capped, see selfIntersectionsCapped)
  bool selfIntersectionsCapped = false;
  size_t nonFiniteVertices = 0;
  double volumeMm3 = 0;              // signed volume (closed meshes), > 0 after outward repair
  double areaMm2 = 0;
  BoundingBox bbox;
  std::vector<std::string> repairs;  // e.g. "merged 1240 duplicate vertices", "dropped 3 degenerate faces"
  bool solidRepaired = false;        // PrepareOptions::closeSolid ran repairSolid (solidRepair set)
  SolidRepairStats solidRepair;
  size_t firstFilledFace = 0;        // solidRepaired: the faces from this one on close holes (the
                                     // mesh's last faces; = faces when they cannot be told apart)
  size_t shellsUnited = 0;           // uniteShells: overlapping closed shells replaced by their union
  size_t shellUnions = 0;            // ... the unions they became
  double unitedInnerAreaMm2 = 0;     // ... surface of theirs that lay inside another, removed
  std::vector<std::string> errors;   // each "code: message", e.g. "open_mesh: 147 boundary edges ..."
  std::vector<std::string> warnings; // e.g. "self_intersecting: 12 face pairs intersect (sliced as union)"
};

struct PrepareOptions {
  bool repair = true;               // apply safe repairs (merge, drop degenerate, orient, outward)
  bool checkSelfIntersections = true;  // CGAL box-intersection test (costly on huge meshes)
  size_t selfIntersectionCap = 1000;   // stop counting after this many pairs (0 = no cap)
  bool selfIntersectionsOfSolidsOnly = false;  // skip the test when the mesh is not a solid (the
                                               // repair's second pass: it is rebuilt or refused)
  size_t selfIntersectionMaxFaces = 500000;  // skip the test above this many faces, with a
                                             // warning (0 = no limit): it costs ~0.9 s per 1M
                                             // faces natively, the rest of validation ~0.25 s
  double mergeTolerance = 0;        // 0 = merge bit-identical positions only; > 0 in mm
  bool weld = true;                 // with repair: merge vertices (mergeTolerance) first
  // The `repair = auto` setting for a method that slices a solid: when the mesh does not bound
  // one, repairSolid() (mesh/repair_mesh.h) closes its holes, splits its non-manifold edges and
  // vertices and drops debris, and the result is validated again. Also drops both faces of a
  // pair on the same vertices running opposite ways (an internal wall) instead of one.
  bool closeSolid = false;
  SolidRepairOptions solidRepair;
  // With repair, for a method that slices a solid (set with closeSolid): closed outward shells
  // that intersect or lie inside one another are replaced by the surface of their union
  // (cgal/shell_union.h), so that no face lies inside the solid. Only when the self-intersection
  // test found intersecting faces or a shell was found nested in one of the same orientation.
  bool uniteShells = false;
  // With closeSolid: when repairSolid cannot close the mesh, rebuild its surface from
  // inside/outside samples of the faces as given (mesh/rebuild_solid.h) where those bound a solid.
  bool rebuild = true;
};

struct PrepareMeshResult : Outcome {
  Mesh mesh;        // repaired mesh (welded, no degenerate faces, oriented, outward)
  MeshInfo info;
  // For slicing a solid: Ok when the repaired mesh is a closed manifold; otherwise the first
  // unrepairable error: EmptyInput, NonFiniteVertex, DegenerateInput, OpenMesh, NonManifoldInput.
  Outcome solid;
};

// Validate and (optionally) repair. status is an error only when there is nothing to work with
// (EmptyInput, NonFiniteVertex, DegenerateInput, Cancelled; ParseError for an index out of range
// or a size not a multiple of 3; InvalidOption for a negative or non-finite mergeTolerance);
// topological problems of the solid are reported in info.errors and result.solid so `info` can
// still describe the mesh.
// Repairs, in order: weld, drop degenerate faces (repeated index, or area <= 1e-12 x squared bbox
// diagonal), drop unreferenced vertices, drop faces on the same three vertices as an earlier one,
// orient each edge-connected sheet consistently, flip closed shells outward (nested shells flip
// with their outermost container, so a cavity facing inward stays a cavity). Manifold and orientation
// counts use two-face edges only; "oriented" means no two-face edge has both faces running it the
// same way. Self-intersections are a warning (the slicer unions with the non-zero rule) and are
// not checked above options.selfIntersectionMaxFaces. Progress stage: "validate".
// Cost (native, 1M-face STL soup): ~0.3 s without the self-intersection test, which adds ~0.9 s.
PrepareMeshResult prepareMesh(const Mesh& raw, const PrepareOptions& options,
                              const ProgressFn& progress = {});

// MeshInfo as the JSON object `omnislice info` prints (keys: vertices, faces, shells, closed,
// manifold, oriented, volume_mm3, area_mm2, bbox {min,max}, boundary_edges, boundary_loops,
// non_manifold_edges, non_manifold_vertices, self_intersections, self_intersections_capped,
// non_finite_vertices, repairs, errors, warnings; with solidRepaired also repair {holes_filled,
// holes_capped, holes_left, largest_hole_mm, filled_area_mm2, filled_faces, first_filled_face, edges_split,
// vertices_split, sheets, debris_pieces, debris_faces, rebuilt_mm (grid pitch of a rebuilt
// surface, 0 when not rebuilt)}; with shellsUnited also shells_united
// {shells, unions, inner_area_mm2}). Non-finite numbers are written as null.
std::string meshInfoJson(const MeshInfo& info);
}  // namespace omnislice
