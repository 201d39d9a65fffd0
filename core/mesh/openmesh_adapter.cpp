// SPDX-License-Identifier: MIT
#include "mesh/openmesh_adapter.h"

// GCC 12 flags OpenMesh's default-constructed VectorT in PropertyT::push_back (a header
// instantiated here) as maybe-uninitialized; the value is overwritten by add_vertex.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <vector>

namespace omnislice {
namespace {

struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

// Mutes omerr() for the lifetime of the guard (add_face reports "complex edge" there) and restores
// its previous state.
class MuteOpenMeshErrors {
 public:
  MuteOpenMeshErrors() : wasEnabled_(omerr().is_enabled()) { omerr().disable(); }
  ~MuteOpenMeshErrors() {
    if (wasEnabled_) omerr().enable();
  }

 private:
  bool wasEnabled_;
};

}  // namespace

HalfedgeBoundary countBoundaryLoops(const Mesh& mesh) {
  HalfedgeBoundary out;
  TriMesh om;
  om.reserve(mesh.vertexCount(), mesh.triangles.size() / 2 + 3, mesh.faceCount());
  std::vector<TriMesh::VertexHandle> handles;
  handles.reserve(mesh.vertexCount());
  for (size_t i = 0; i < mesh.vertexCount(); ++i) {
    const double* p = mesh.positions.data() + 3 * i;
    handles.push_back(om.add_vertex(TriMesh::Point(p[0], p[1], p[2])));
  }
  {
    MuteOpenMeshErrors mute;
    for (size_t f = 0; f < mesh.faceCount(); ++f) {
      const uint32_t* t = mesh.triangles.data() + 3 * f;
      // A repeated vertex would make OpenMesh create a self-loop edge and trip its assertions
      // (or corrupt its links without them): such faces never reach add_face.
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
        ++out.rejectedFaces;
        continue;
      }
      const TriMesh::FaceHandle fh = om.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
      if (!fh.is_valid()) ++out.rejectedFaces;
    }
  }
  std::vector<uint8_t> visited(om.n_halfedges(), 0);
  for (const TriMesh::HalfedgeHandle start : om.halfedges()) {
    if (!om.is_boundary(start) || visited[start.idx()]) continue;
    // An edge with no face on either side only arises from isolated vertices' edges; OpenMesh
    // never creates one through add_face, so every boundary half-edge lies on one loop.
    if (om.is_boundary(om.opposite_halfedge_handle(start))) {
      visited[start.idx()] = 1;
      continue;
    }
    ++out.boundaryLoops;
    TriMesh::HalfedgeHandle h = start;
    for (size_t steps = 0; steps < visited.size(); ++steps) {
      visited[h.idx()] = 1;
      ++out.boundaryHalfedges;
      h = om.next_halfedge_handle(h);
      if (h == start || !h.is_valid() || visited[h.idx()]) break;
    }
  }
  return out;
}

}  // namespace omnislice
