// SPDX-License-Identifier: MIT
#include "cgal/mesh_distance_reference.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <exception>

namespace omnislice {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
}  // namespace

MeshDistanceReference meshDistanceReference(const Mesh& mesh,
                                            const std::vector<Eigen::Vector3d>& points) {
  MeshDistanceReference r;
  if (mesh.empty()) {
    r.status = Status::EmptyInput;
    r.message = "mesh has no triangles";
    return r;
  }
  try {
    SurfaceMesh sm;
    std::vector<SurfaceMesh::Vertex_index> v;
    v.reserve(mesh.vertexCount());
    for (size_t i = 0; i < mesh.vertexCount(); ++i) {
      const Eigen::Vector3d p = mesh.vertex(i);
      v.push_back(sm.add_vertex(Point(p.x(), p.y(), p.z())));
    }
    for (size_t f = 0; f < mesh.faceCount(); ++f) {
      const uint32_t a = mesh.triangles[3 * f], b = mesh.triangles[3 * f + 1],
                     c = mesh.triangles[3 * f + 2];
      if (a >= v.size() || b >= v.size() || c >= v.size() ||
          sm.add_face(v[a], v[b], v[c]) == SurfaceMesh::null_face()) {
        r.status = Status::NonManifoldInput;
        r.message = "face " + std::to_string(f) + " cannot be added to a surface mesh";
        return r;
      }
    }
    Tree tree(faces(sm).first, faces(sm).second, sm);
    tree.accelerate_distance_queries();
    CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel> side(tree);
    r.distances.reserve(points.size());
    r.inside.reserve(points.size());
    for (const Eigen::Vector3d& p : points) {
      const Point q(p.x(), p.y(), p.z());
      r.distances.push_back(std::sqrt(CGAL::to_double(tree.squared_distance(q))));
      r.inside.push_back(side(q) == CGAL::ON_BOUNDED_SIDE ? 1 : 0);
    }
  } catch (const std::exception& e) {
    r = MeshDistanceReference{};
    r.status = Status::Internal;
    r.message = std::string("CGAL failed: ") + e.what();
  }
  return r;
}

}  // namespace omnislice
