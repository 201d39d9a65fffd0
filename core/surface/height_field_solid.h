// SPDX-License-Identifier: MIT
// The solid under an open surface: how `--method surface` turns a surface to print (paper 003's
// saddle and bicycle seat) into something a slicer and `omnislice verify` understand. The surface
// layer is printed on a support base (the paper pre-fabricated it; Omnislice prints it with planar
// layers first): the base is the solid between the platform z = 0 and the surface moved down by
// the layer thickness along its normals; the part verified is the solid between z = 0 and the
// surface itself.
#pragma once
#include "common/status.h"
#include "mesh/mesh.h"

namespace omnislice {

struct HeightFieldSolid : Outcome {
  Mesh solid;            // closed, outward-oriented: top = the (offset) surface, vertical side
                         // walls along every boundary loop down to z = 0, bottom = the top's
                         // triangles projected to z = 0 (reversed)
  Mesh top;              // the (offset) top surface, oriented up
  double minTopZ = 0;    // lowest top vertex, mm (the caller lifts the surface so that it is at
                         // least the base thickness)
};

// Checks and builds. The surface must be an open, edge-manifold, consistently oriented triangle
// mesh that is a height field over the platform: its triangles, oriented so the majority faces +Z,
// all face up (normal z > minNormalZ) and its boundary loops project to simple, disjoint polygons.
// offset >= 0: top vertices are moved by -offset along their (area-weighted) normals first (the
// check is repeated on the moved surface). Every top vertex must lie above z = 0 (after the
// offset). Statuses (human messages name the fault): EmptyInput, NonFiniteVertex, OpenMesh is NOT
// used (open is required); NonManifoldInput (edge shared by > 2 triangles, inconsistent
// orientation), DegenerateInput (closed surface: no boundary; the surface folds over itself seen
// from above; a vertex at or below z = 0), InvalidOption (offset < 0 or not finite).
HeightFieldSolid heightFieldSolid(const Mesh& surface, double offset = 0, double minNormalZ = 0.02);

}  // namespace omnislice
