// SPDX-License-Identifier: MIT
// Clipping a closed solid by planes (paper 000, Sec. III-B): one plane splits it into the closed
// solids below and above, the cut capped by triangulated planar polygons; a sequence of planes
// gives the remaining models M_k = M_{k-1} \ Gamma_k^+ (Eq. 5) and the parts in print order
// (Eq. 6).
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

// Plane {x : normal . x = offset}. Points with normal . x > offset are above (the open half-space
// Gamma^+), the rest below. normal should be unit; a non-unit normal is normalised together with
// the offset (the same half-spaces).
struct Plane {
  Eigen::Vector3d normal{0, 0, 1};
  double offset = 0;  // mm
};

struct ClipResult : Outcome {
  Mesh below;                     // closed solid on the side normal . x <= offset (empty if none)
  Mesh above;                     // closed solid on the side normal . x > offset (empty if none)
  double belowVolume = 0;         // mm^3, signed volume of below (>= 0 up to rounding)
  double aboveVolume = 0;         // mm^3
  double capArea = 0;             // mm^2, area of the cut (the cap of either side)
  size_t capLoops = 0;            // closed cross-section loops (outer contours + holes)
  size_t capHoles = 0;            // of those, holes (clockwise seen from above)
  size_t cutEdges = 0;            // input edges crossing the plane (one new vertex each)
  size_t onPlaneVertices = 0;     // input vertices taken as on the plane (incl. sliverSnaps)
  size_t sliverSnaps = 0;         // of those, vertices beyond snapTolerance (but within 1e-5 x the
                                  // bounding-box diagonal) taken as on the plane because cutting
                                  // next to them would leave faces of near-zero area
  size_t forcedCapTriangles = 0;  // cap triangles cut without a valid ear (numerically degenerate
                                  // cross-sections); 0 for a valid solid
};

// Split a closed solid by plane. The pieces: every input face wholly on one side goes to it; a
// face crossing the plane is split at new vertices on its crossing edges (one per edge, shared by
// both faces of the edge); a face lying in the plane goes to the side its outward normal leaves
// (facing up: below, facing down: above), so a plane through a flat face of the solid cuts
// nothing off there. The cut (cross-section) is capped on both sides by the same triangles, made
// only of the vertices of the cut loops, facing up on the below piece and down on the above
// piece; loops may nest (holes, islands in holes) and touch at vertices. Each piece is closed,
// consistently and outwardly oriented, welded, keeps only its referenced vertices (in increasing
// input order, new vertices after), and may hold several shells; belowVolume + aboveVolume equals
// the input's volume up to rounding. Vertices within snapTolerance (mm, >= 0) of the plane are
// treated as on it: no edge is cut there, so there are no slivers thinner than that. So is a vertex
// up to 1e-5 x the bounding-box diagonal away when a cut next to it would leave a face of twice
// area <= 4e-12 x the squared diagonal (what prepareMesh would drop as degenerate; counted in
// sliverSnaps). Above-piece vertices satisfy normal . x >= offset - snapTolerance, below-piece
// ones normal . x <= offset + snapTolerance (with 1e-5 x diagonal instead when sliverSnaps > 0).
// Vertices are never moved. A plane missing the solid leaves one piece empty and the other the
// whole solid (compacted). Degenerate positions that the exact result has too: pieces touching
// only at a vertex of the plane (a plane through a saddle vertex) come out as one mesh with that
// vertex shared (prepareMesh reports a non-manifold vertex; sliceMesh is unaffected;
// splitComponents separates them); where the surface touches the plane from one side inside the
// cross-section (a vertex, or a concave edge lying in the plane), that piece touches its own cap
// there (prepareMesh's self-intersection test counts the contact), the edge being kept out of the
// cap triangulation unless unavoidable (then an edge with four faces, still a valid input here).
// Cost: O(F) plus the cap triangulation (O(n log n) typical for n cut points); natively ~1.4 ms
// for the 10k-face Kitten, ~10 ms for the 46k-face Fertility.
// Preconditions: solid is closed, consistently and outwardly oriented, welded and not
// self-intersecting, i.e. the output of prepareMesh with solid.ok().
// Statuses: EmptyInput (no triangles), InvalidOption (non-finite or zero normal, non-finite offset,
// negative or non-finite snapTolerance, index out of range, plane offset overflowing against the
// coordinates), NonFiniteVertex, OpenMesh (boundary edges), NonManifoldInput (an edge run more
// often one way than the other, e.g. two faces running it the same way; solids touching along an
// edge, four faces on it, are accepted), DegenerateInput (a face repeating a vertex, or a clearly
// negative volume: inside out), Internal (an invariant failed).
ClipResult clipByPlane(const Mesh& solid, const Plane& plane, double snapTolerance = 1e-6);

struct ClipPart {
  Mesh mesh;              // closed solid; may be empty or hold several shells
  int planeIndex = -1;    // index into planes of the plane this part lies above (it is printed on
                          // that plane, normal as the printing direction); -1 for the platform part
  double volume = 0;      // mm^3, signed volume
  size_t components = 0;  // solids in mesh: shells of positive volume (a cavity is not counted)
};

struct PartsResult : Outcome {
  // Print order (Eq. 6), P = planes.size(): parts[0] is the last remaining model M_P (on the
  // platform), then the piece above planes[P-1], ..., last the piece above planes[0]; P + 1 parts.
  std::vector<ClipPart> parts;
  double inputVolume = 0;         // mm^3; the parts' volumes sum to it up to rounding
  double totalCapArea = 0;        // mm^2, sum of the cut areas of all planes
  size_t forcedCapTriangles = 0;  // summed over the planes (0 for valid input)
};

// Apply planes in order (planes[k] is the paper's gamma_{k+1}): M_0 = solid, the piece of M_k
// above planes[k] is cut off and M_{k+1} = M_k below planes[k] (Eq. 5), each step by
// clipByPlane(M_k, planes[k], snapTolerance). Once the remaining model is empty every later part
// is empty. Statuses: those of clipByPlane (the message names the plane, and a bad plane is
// reported before any clipping), Cancelled (progress stage "clip", fraction = planes done /
// planes).
PartsResult clipSequence(const Mesh& solid, const std::vector<Plane>& planes,
                         double snapTolerance = 1e-6, const ProgressFn& progress = {});

}  // namespace omnislice
