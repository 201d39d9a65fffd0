// SPDX-License-Identifier: MIT
#include "cgal/shell_union.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <vector>

#include <Eigen/Geometry>

#include "common/disjoint_sets.h"
#include "mesh/mesh_topology.h"

namespace omnislice {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

// A union made so far: its surface, volume, the members' summed area and the shells in it.
struct Part {
  SurfaceMesh mesh;
  double volume = 0;
  double area = 0;
  std::vector<uint32_t> members;
};

struct Shell {
  std::vector<uint32_t> faces;
  Eigen::Vector3d min = Eigen::Vector3d::Constant(INFINITY);
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-INFINITY);
  double volume = 0;
  double area = 0;
};

bool boxesOverlap(const Shell& a, const Shell& b) {
  return (a.min.array() <= b.max.array()).all() && (b.min.array() <= a.max.array()).all();
}

SurfaceMesh toSurfaceMesh(const Mesh& mesh, const std::vector<uint32_t>& faces) {
  SurfaceMesh out;
  std::vector<int64_t> local(mesh.vertexCount(), -1);
  std::vector<SurfaceMesh::Vertex_index> handles;
  for (uint32_t f : faces) {
    SurfaceMesh::Vertex_index v[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t g = mesh.triangles[3 * f + k];
      if (local[g] < 0) {
        local[g] = int64_t(handles.size());
        handles.push_back(out.add_vertex(Point(mesh.positions[3 * g], mesh.positions[3 * g + 1],
                                               mesh.positions[3 * g + 2])));
      }
      v[k] = handles[size_t(local[g])];
    }
    out.add_face(v[0], v[1], v[2]);
  }
  return out;
}

// Appends a surface mesh's triangles (faces of more than three corners are fanned) to out.
void appendSurfaceMesh(const SurfaceMesh& sm, Mesh& out) {
  std::vector<uint32_t> index(sm.number_of_vertices() + sm.number_of_removed_vertices(), 0);
  for (SurfaceMesh::Vertex_index v : sm.vertices()) {
    index[size_t(v)] = uint32_t(out.vertexCount());
    const Point& p = sm.point(v);
    out.positions.insert(out.positions.end(), {p.x(), p.y(), p.z()});
  }
  for (SurfaceMesh::Face_index f : sm.faces()) {
    std::vector<uint32_t> corners;
    for (SurfaceMesh::Vertex_index v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      corners.push_back(index[size_t(v)]);
    }
    for (size_t k = 1; k + 1 < corners.size(); ++k) {
      out.triangles.insert(out.triangles.end(), {corners[0], corners[k], corners[k + 1]});
    }
  }
}

double surfaceArea(const SurfaceMesh& sm) {
  double area = 0;
  for (SurfaceMesh::Face_index f : sm.faces()) area += PMP::face_area(f, sm);
  return area;
}

// Rounded crossing points can leave triangles flat or almost (areas below what prepareMesh
// keeps: 1e-12 x the squared diagonal): flip or collapse them away, so that dropping them later
// does not open the surface. Only those triangles are touched.
void removeSlivers(SurfaceMesh& sm) {
  try {
    PMP::remove_degenerate_faces(sm);
    const CGAL::Bbox_3 box = PMP::bbox(sm);
    const double diag2 = CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                         CGAL::square(box.zmax() - box.zmin());
    for (int round = 0; round < 3; ++round) {
      std::vector<SurfaceMesh::Face_index> slivers;
      for (SurfaceMesh::Face_index f : sm.faces()) {
        if (PMP::face_area(f, sm) <= 1e-11 * diag2) slivers.push_back(f);
      }
      if (slivers.empty()) break;
      // Caps: an angle above 160 deg; needles: longest edge over 4 x the shortest; edges shorter
      // than 1e-4 x the diagonal may collapse.
      PMP::experimental::remove_almost_degenerate_faces(slivers, sm, std::cos(160 * CGAL_PI / 180), 4,
                                                       1e-4 * std::sqrt(diag2));
    }
    sm.collect_garbage();
  } catch (const std::exception&) {
  }
}

}  // namespace

ShellUnionResult uniteOverlappingShells(const Mesh& mesh, const ShellUnionOptions& options,
                                        const ProgressFn& progress, double from, double to) {
  ShellUnionResult r;
  auto report = [&](double t) { return reportProgress(progress, "validate", from + (to - from) * t); };
  auto cancelled = [&r]() {
    r.status = Status::Cancelled;
    r.message = "cancelled";
    r.mesh = {};
    return r;
  };
  r.mesh = mesh;
  const size_t faceCount = mesh.faceCount();
  if (faceCount == 0) return r;

  // Shells: the edge-connected components (a solid has no vertex where separate fans touch).
  const FaceComponents components = edgeComponents(mesh, buildEdges(mesh));
  const std::vector<uint32_t>& shellOfFace = components.label;
  std::vector<Shell> shells(components.count);
  const Eigen::Vector3d centre = mesh.vertex(mesh.triangles[0]);
  for (size_t f = 0; f < faceCount; ++f) {
    Shell& s = shells[shellOfFace[f]];
    s.faces.push_back(uint32_t(f));
    const Eigen::Vector3d a = mesh.vertex(mesh.triangles[3 * f]);
    const Eigen::Vector3d b = mesh.vertex(mesh.triangles[3 * f + 1]);
    const Eigen::Vector3d c = mesh.vertex(mesh.triangles[3 * f + 2]);
    s.min = s.min.cwiseMin(a).cwiseMin(b).cwiseMin(c);
    s.max = s.max.cwiseMax(a).cwiseMax(b).cwiseMax(c);
    s.volume += (a - centre).dot((b - centre).cross(c - centre)) / 6;
    s.area += 0.5 * (b - a).cross(c - a).norm();
  }
  std::vector<uint32_t> outward;
  for (uint32_t i = 0; i < shells.size(); ++i) {
    if (shells[i].volume > 0 && shells[i].faces.size() >= 4) outward.push_back(i);
  }
  r.shellsIn = outward.size();
  if (outward.size() < 2) return r;

  // Pairs with overlapping boxes (a sweep along x), tested on the surfaces and bounded sides.
  std::sort(outward.begin(), outward.end(),
            [&](uint32_t a, uint32_t b) { return shells[a].min.x() < shells[b].min.x(); });
  std::vector<std::unique_ptr<SurfaceMesh>> surfaces(shells.size());
  auto surface = [&](uint32_t i) -> SurfaceMesh& {
    if (!surfaces[i]) surfaces[i] = std::make_unique<SurfaceMesh>(toSurfaceMesh(mesh, shells[i].faces));
    return *surfaces[i];
  };
  DisjointSets groups(shells.size());
  try {
    for (size_t i = 0; i < outward.size(); ++i) {
      if (!report(0.3 * double(i) / double(outward.size()))) return cancelled();
      const Shell& a = shells[outward[i]];
      for (size_t j = i + 1; j < outward.size() && shells[outward[j]].min.x() <= a.max.x(); ++j) {
        if (!boxesOverlap(a, shells[outward[j]])) continue;
        if (groups.find(outward[i]) == groups.find(outward[j])) continue;
        if (PMP::do_intersect(surface(outward[i]), surface(outward[j]),
                              CGAL::parameters::do_overlap_test_of_bounded_sides(true),
                              CGAL::parameters::do_overlap_test_of_bounded_sides(true))) {
          groups.unite(outward[i], outward[j]);
        }
      }
    }
  } catch (const std::exception&) {
    r.status = Status::Internal;
    r.message = "the overlap test of the shells failed";
    r.mesh = mesh;
    return r;
  }

  std::vector<std::vector<uint32_t>> members(shells.size());
  for (uint32_t i : outward) members[groups.find(i)].push_back(i);
  std::vector<uint8_t> united(shells.size(), 0);
  Mesh out;
  size_t unionsDone = 0, unionsTotal = 0;  // corefinements, for progress
  for (const auto& m : members) unionsTotal += m.size() > 1 ? m.size() - 1 : 0;
  for (auto& m : members) {
    if (m.size() < 2) continue;
    std::sort(m.begin(), m.end());
    size_t faces = 0;
    for (uint32_t i : m) faces += shells[i].faces.size();
    if (faces > options.maxFaces) {
      r.shellsLeft += m.size();
      continue;
    }
    // Members that intersect themselves cannot enter a corefinement: they stay as they are.
    std::vector<Part> parts;
    for (uint32_t i : m) {
      bool selfIntersecting = true;
      try {
        selfIntersecting = PMP::does_self_intersect(surface(i));
      } catch (const std::exception&) {
      }
      if (selfIntersecting) {
        ++r.shellsLeft;
      } else {
        parts.push_back({surface(i), shells[i].volume, shells[i].area, {i}});
      }
    }
    // Unions of unions of about equal size, level by level (folding every member into the largest
    // would corefine the whole body once per member: 40 shells of an ogre, 4 s against 1 s). A
    // pair CGAL cannot unite (or whose volume is not between the larger part's and the sum)
    // keeps the larger part; the smaller one's shells stay as they were.
    while (parts.size() > 1) {
      std::sort(parts.begin(), parts.end(), [](const Part& a, const Part& b) {
        return a.mesh.number_of_faces() < b.mesh.number_of_faces();
      });
      std::vector<Part> next;
      for (size_t k = 0; k + 1 < parts.size(); k += 2) {
        Part& a = parts[k];
        Part& b = parts[k + 1];
        SurfaceMesh result;
        bool ok = false;
        try {
          ok = PMP::corefine_and_compute_union(a.mesh, b.mesh, result) && CGAL::is_closed(result) &&
               CGAL::is_triangle_mesh(result);
        } catch (const std::exception&) {
          ok = false;
        }
        const double volume = ok ? PMP::volume(result) : 0;
        const double slack = 1e-6 * (a.volume + b.volume) + 1e-9;
        if (ok && volume >= std::max(a.volume, b.volume) - slack && volume <= a.volume + b.volume + slack) {
          Part joined{std::move(result), volume, a.area + b.area, std::move(a.members)};
          joined.members.insert(joined.members.end(), b.members.begin(), b.members.end());
          next.push_back(std::move(joined));
        } else {
          Part& larger = a.volume >= b.volume ? a : b;
          r.shellsLeft += (a.volume >= b.volume ? b : a).members.size();
          next.push_back(std::move(larger));
        }
        ++unionsDone;
        if (!report(0.3 + 0.7 * std::min(1.0, double(unionsDone) / double(std::max<size_t>(unionsTotal, 1))))) {
          return cancelled();
        }
      }
      if (parts.size() % 2 == 1) next.push_back(std::move(parts.back()));
      parts = std::move(next);
    }
    if (parts.empty()) continue;
    SurfaceMesh& acc = parts[0].mesh;
    const std::vector<uint32_t>& joined = parts[0].members;
    const double accArea = parts[0].area;
    if (joined.size() < 2) continue;
    removeSlivers(acc);
    for (uint32_t i : joined) united[i] = 1;
    ++r.groups;
    r.shellsUnited += joined.size();
    r.removedAreaMm2 += std::max(0.0, accArea - surfaceArea(acc));
    appendSurfaceMesh(acc, out);
  }
  if (r.groups == 0) return r;

  // The other shells, faces in input order, vertices renumbered.
  std::vector<int64_t> vertexIndex(mesh.vertexCount(), -1);
  for (size_t f = 0; f < faceCount; ++f) {
    if (united[shellOfFace[f]]) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.triangles[3 * f + k];
      if (vertexIndex[v] < 0) {
        vertexIndex[v] = int64_t(out.vertexCount());
        out.positions.insert(out.positions.end(),
                             {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]});
      }
      out.triangles.push_back(uint32_t(vertexIndex[v]));
    }
  }
  if (!report(1)) return cancelled();
  r.mesh = std::move(out);
  return r;
}

}  // namespace omnislice
