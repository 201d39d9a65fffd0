// SPDX-License-Identifier: MIT
// prepareMesh: validation, safe repair and the MeshInfo report. The steps live in their own
// files (weld_vertices, mesh_topology, orient_mesh, openmesh_adapter, cgal/self_intersections,
// repair_mesh);
// this file orders them, reports progress and words the findings.
#include "mesh/prepare_mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>

#include "cgal/self_intersections.h"
#include "cgal/shell_union.h"
#include "mesh/rebuild_solid.h"
#include "common/plural.h"
#include "mesh/mesh_topology.h"
#include "mesh/openmesh_adapter.h"
#include "mesh/orient_mesh.h"
#include "mesh/repair_mesh.h"
#include "mesh/weld_vertices.h"

namespace omnislice {
namespace {

constexpr const char* kStage = "validate";

// Zero-area threshold relative to the squared bounding-box diagonal: far below any printable
// feature, far above the rounding noise of a cross product of collinear edges.
constexpr double kDegenerateAreaRatio = 1e-12;

// repairSolid filled or dropped more than this share of the surface: check it against the rebuild.
constexpr double kLargeRepairShare = 0.02;
// ... and take the rebuild when their volumes differ by more than this share (a rebuilt box on a
// 160-cell grid is within 0.04 % of its volume).
constexpr double kRebuildVolumeGap = 0.05;

std::string shortNumber(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

bool finite3(const double* p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

PrepareMeshResult fail(Status status, std::string message) {
  PrepareMeshResult r;
  r.status = status;
  r.message = std::move(message);
  r.solid.status = status;
  r.solid.message = r.message;
  return r;
}

PrepareMeshResult cancelled() { return fail(Status::Cancelled, "validation cancelled"); }

double twiceArea(const Mesh& m, const uint32_t* t) {
  const Eigen::Vector3d a = m.vertex(t[0]);
  return (m.vertex(t[1]) - a).cross(m.vertex(t[2]) - a).norm();
}

// Bounds of the vertices referenced by faces.
BoundingBox referencedBox(const Mesh& m) {
  BoundingBox box;
  if (m.triangles.empty()) return box;
  box.min = Eigen::Vector3d::Constant(INFINITY);
  box.max = -box.min;
  for (uint32_t v : m.triangles) {
    const Eigen::Vector3d p = m.vertex(v);
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  return box;
}

struct FaceFilter {
  std::vector<uint32_t> triangles;
  size_t repeated = 0;    // faces with a repeated vertex index
  size_t zeroArea = 0;    // faces with distinct indices but (numerically) zero area
};

// Keep the faces that are not degenerate.
FaceFilter dropDegenerateFaces(const Mesh& m, double areaEps2) {
  FaceFilter out;
  out.triangles.reserve(m.triangles.size());
  for (size_t f = 0; f < m.faceCount(); ++f) {
    const uint32_t* t = m.triangles.data() + 3 * f;
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      ++out.repeated;
    } else if (twiceArea(m, t) <= areaEps2) {
      ++out.zeroArea;
    } else {
      out.triangles.insert(out.triangles.end(), t, t + 3);
    }
  }
  return out;
}

// Faces on the same three vertices as an earlier face. Such faces share all their edges, so only
// the other faces on each face's first edge are compared (no hash over all faces).
// Faces on the same three vertices as an earlier face. With bothOfOpposite, a face running the
// other way round from the earlier one drops that one too (an internal wall where two shells
// touch face to face; its count goes to internalPairs).
std::vector<uint32_t> duplicateFaces(const Mesh& m, const MeshEdges& edges, bool bothOfOpposite,
                                     size_t& internalPairs) {
  std::vector<uint32_t> out;
  std::vector<uint8_t> taken(bothOfOpposite ? m.faceCount() : 0, 0);
  auto sortedFace = [&](uint32_t f) {
    std::array<uint32_t, 3> s = {m.triangles[3 * f], m.triangles[3 * f + 1], m.triangles[3 * f + 2]};
    std::sort(s.begin(), s.end());
    return s;
  };
  // The same cyclic order (same orientation) of the three vertices.
  auto sameWay = [&](uint32_t f, uint32_t g) {
    const uint32_t* a = m.triangles.data() + 3 * f;
    const uint32_t* b = m.triangles.data() + 3 * g;
    for (int k = 0; k < 3; ++k) {
      if (a[0] == b[k] && a[1] == b[(k + 1) % 3]) return true;
    }
    return false;
  };
  for (uint32_t f = 0; f < m.faceCount(); ++f) {
    const uint32_t edge = edges.edgeOfHalfedge[3 * f];
    if (edges.faceCount[edge] < 2) continue;
    const auto mine = sortedFace(f);
    for (uint32_t h = edges.firstHalfedge[edge]; h != kNoIndex && h / 3 < f; h = edges.nextHalfedge[h]) {
      const uint32_t g = h / 3;
      if (sortedFace(g) != mine) continue;
      if (bothOfOpposite && !taken[g] && !sameWay(f, g)) {
        taken[g] = 1;
        out.push_back(g);
        ++internalPairs;
      }
      out.push_back(f);
      break;
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// The first face of `after` from which on every face is one of before's faces from `first` on
// (same three positions: the second validation only drops and turns faces, never reorders);
// after.faceCount() when the filled faces are not the trailing ones.
size_t trailingFilledFaces(const Mesh& before, size_t first, const Mesh& after) {
  using Key = std::array<double, 9>;
  auto key = [](const Mesh& m, size_t f) {
    std::array<std::array<double, 3>, 3> p;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = m.triangles[3 * f + k];
      p[k] = {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
    }
    std::sort(p.begin(), p.end());
    Key out;
    for (int k = 0; k < 9; ++k) out[k] = p[k / 3][k % 3];
    return out;
  };
  std::vector<Key> filled;
  for (size_t f = first; f < before.faceCount(); ++f) filled.push_back(key(before, f));
  std::sort(filled.begin(), filled.end());
  size_t start = after.faceCount();
  while (start > 0 && std::binary_search(filled.begin(), filled.end(), key(after, start - 1))) --start;
  for (size_t f = 0; f < start; ++f) {
    if (std::binary_search(filled.begin(), filled.end(), key(after, f))) return after.faceCount();
  }
  return start;
}

std::string shellsLeftWarning(size_t shells) {
  return "shells: " + plural(shells, "overlapping shell was", "overlapping shells were") +
         " not united with the others (it intersects itself, or the group is too large); slicing "
         "uses the union of the sections";
}

// Drop vertices no face references; keeps the order of the others.
size_t compactVertices(Mesh& m) {
  constexpr uint32_t kUnused = 0xFFFFFFFFu;
  std::vector<uint32_t> remap(m.vertexCount(), kUnused);
  for (uint32_t v : m.triangles) remap[v] = 0;
  std::vector<double> positions;
  positions.reserve(m.positions.size());
  uint32_t next = 0;
  for (size_t i = 0; i < remap.size(); ++i) {
    if (remap[i] == kUnused) continue;
    remap[i] = next++;
    positions.insert(positions.end(), m.positions.begin() + 3 * i, m.positions.begin() + 3 * i + 3);
  }
  const size_t dropped = m.vertexCount() - next;
  for (uint32_t& v : m.triangles) v = remap[v];
  m.positions = std::move(positions);
  return dropped;
}

}  // namespace

PrepareMeshResult prepareMesh(const Mesh& raw, const PrepareOptions& options, const ProgressFn& progress) {
  if (!reportProgress(progress, kStage, 0)) return cancelled();
  if (raw.triangles.empty()) return fail(Status::EmptyInput, "the mesh has no faces");
  if (raw.triangles.size() % 3 != 0) {
    return fail(Status::ParseError, "triangle index count " + std::to_string(raw.triangles.size()) +
                                        " is not a multiple of 3");
  }
  if (raw.positions.size() % 3 != 0) {
    return fail(Status::ParseError, "position count " + std::to_string(raw.positions.size()) +
                                        " is not a multiple of 3");
  }
  if (raw.vertexCount() >= kNoIndex || raw.faceCount() >= kNoIndex / 3) {
    return fail(Status::InvalidOption, "the mesh is too large for 32-bit indices");
  }
  if (!(options.mergeTolerance >= 0) || !std::isfinite(options.mergeTolerance)) {
    return fail(Status::InvalidOption, "merge tolerance must be a finite value >= 0 mm");
  }
  const size_t nv = raw.vertexCount();
  size_t nonFinite = 0;
  {
    std::vector<uint8_t> checked(nv, 0);
    for (size_t i = 0; i < raw.triangles.size(); ++i) {
      const uint32_t v = raw.triangles[i];
      if (v >= nv) {
        return fail(Status::ParseError, "face " + std::to_string(i / 3) + " references vertex " +
                                            std::to_string(v) + " but the mesh has " +
                                            std::to_string(nv) + " vertices");
      }
      if (checked[v]) continue;
      checked[v] = 1;
      if (!finite3(raw.positions.data() + 3 * size_t(v))) ++nonFinite;
    }
  }
  if (nonFinite > 0) {
    PrepareMeshResult r = fail(Status::NonFiniteVertex,
                               plural(nonFinite, "vertex has", "vertices have") +
                                   " a NaN or infinite coordinate");
    r.info.nonFiniteVertices = nonFinite;
    return r;
  }
  if (!reportProgress(progress, kStage, 0.05)) return cancelled();

  PrepareMeshResult result;
  MeshInfo& info = result.info;
  Mesh mesh;
  FaceFilter filtered;
  {
    // Weld (repair), drop degenerate faces, drop unreferenced vertices.
    Mesh welded;
    if (options.repair && options.weld) {
      WeldResult weld = weldVertices(raw, options.mergeTolerance);
      welded.positions = std::move(weld.positions);
      welded.triangles.resize(raw.triangles.size());
      for (size_t i = 0; i < raw.triangles.size(); ++i) welded.triangles[i] = weld.remap[raw.triangles[i]];
      if (weld.merged > 0) {
        info.repairs.push_back("merged " + plural(weld.merged, "duplicate vertex", "duplicate vertices") +
                               (options.mergeTolerance > 0
                                    ? " (within " + shortNumber(options.mergeTolerance) + " mm)"
                                    : ""));
      }
    } else {
      welded = raw;
    }
    if (!reportProgress(progress, kStage, 0.15)) return cancelled();
    const BoundingBox box = referencedBox(welded);
    const double diag2 = (box.max - box.min).squaredNorm();
    filtered = dropDegenerateFaces(welded, 2 * kDegenerateAreaRatio * diag2);
    if (filtered.triangles.empty()) {
      return fail(Status::DegenerateInput,
                  "all " + plural(welded.faceCount(), "face is", "faces are") +
                      " degenerate (repeated vertices or zero area)");
    }
    if (options.repair) {
      mesh.positions = std::move(welded.positions);
      mesh.triangles = std::move(filtered.triangles);
      const size_t degenerate = filtered.repeated + filtered.zeroArea;
      if (degenerate > 0) {
        info.repairs.push_back("dropped " + plural(degenerate, "degenerate face", "degenerate faces") +
                               " (" + std::to_string(filtered.repeated) + " with repeated vertices, " +
                               std::to_string(filtered.zeroArea) + " with zero area)");
      }
      const size_t unused = compactVertices(mesh);
      if (unused > 0) {
        info.repairs.push_back("dropped " + plural(unused, "unreferenced vertex", "unreferenced vertices"));
      }
    } else {
      mesh = std::move(welded);
      const size_t degenerate = filtered.repeated + filtered.zeroArea;
      if (degenerate > 0) {
        info.warnings.push_back("degenerate: " + plural(degenerate, "face has", "faces have") +
                                " repeated vertices or zero area (repair off)");
      }
    }
  }
  if (!reportProgress(progress, kStage, 0.25)) return cancelled();

  // Topology.
  MeshEdges edges = buildEdges(mesh);
  if (options.repair) {
    size_t internalPairs = 0;
    const std::vector<uint32_t> duplicates =
        duplicateFaces(mesh, edges, options.closeSolid, internalPairs);
    if (!duplicates.empty()) {
      // Rare: drop them and rebuild the edges. The first copy keeps every vertex referenced.
      std::vector<uint8_t> drop(mesh.faceCount(), 0);
      for (uint32_t f : duplicates) drop[f] = 1;
      size_t kept = 0;
      for (size_t f = 0; f < mesh.faceCount(); ++f) {
        if (drop[f]) continue;
        for (int k = 0; k < 3; ++k) mesh.triangles[3 * kept + k] = mesh.triangles[3 * f + k];
        ++kept;
      }
      mesh.triangles.resize(3 * kept);
      edges = buildEdges(mesh);
      if (duplicates.size() > 2 * internalPairs) {
        info.repairs.push_back("dropped " + plural(duplicates.size() - 2 * internalPairs,
                                                   "duplicate face", "duplicate faces"));
      }
      if (internalPairs > 0) {
        info.repairs.push_back("dropped " + plural(internalPairs, "pair", "pairs") +
                               " of opposite faces where shells touched face to face");
      }
    }
  }
  if (!reportProgress(progress, kStage, 0.35)) return cancelled();
  const TopologyCounts topo = countTopology(mesh, edges);
  if (!reportProgress(progress, kStage, 0.45)) return cancelled();
  OrientOptions orientOptions;
  orientOptions.outward = options.repair;  // flips are computed either way, applied on repair
  const OrientResult orient = orientMesh(mesh, edges, orientOptions);
  if (options.repair) {
    for (size_t f = 0; f < mesh.faceCount(); ++f) {
      if (orient.flip[f]) std::swap(mesh.triangles[3 * f + 1], mesh.triangles[3 * f + 2]);
    }
    if (orient.reorientedFaces > 0) {
      info.repairs.push_back("reoriented " + plural(orient.reorientedFaces, "face", "faces") +
                             " to agree with their neighbours");
    }
    if (orient.outwardComponents > 0) {
      info.repairs.push_back("flipped " + plural(orient.outwardComponents, "closed shell", "closed shells") +
                             " (" + plural(orient.outwardFaces, "face", "faces") +
                             ") so that normals point out of the solid");
    }
  }
  if (!reportProgress(progress, kStage, 0.5)) return cancelled();

  info.vertices = mesh.vertexCount();
  info.faces = mesh.faceCount();
  info.shells = topo.shells;
  info.boundaryEdges = topo.boundaryEdges;
  info.nonManifoldEdges = topo.nonManifoldEdges;
  info.nonManifoldVertices = topo.nonManifoldVertices;
  info.closed = topo.boundaryEdges == 0;
  info.manifold = topo.nonManifoldEdges == 0 && topo.nonManifoldVertices == 0;
  const size_t misoriented = options.repair ? orient.misorientedEdges : topo.misorientedEdges;
  info.oriented = misoriented == 0;
  info.bbox = referencedBox(mesh);
  {
    const Eigen::Vector3d centre = 0.5 * (info.bbox.min + info.bbox.max);
    double volume = 0, area = 0;
    for (size_t f = 0; f < mesh.faceCount(); ++f) {
      const uint32_t* t = mesh.triangles.data() + 3 * f;
      const Eigen::Vector3d a = mesh.vertex(t[0]) - centre;
      const Eigen::Vector3d b = mesh.vertex(t[1]) - centre;
      const Eigen::Vector3d c = mesh.vertex(t[2]) - centre;
      volume += a.dot(b.cross(c));
      area += (b - a).cross(c - a).norm();
    }
    info.volumeMm3 = volume / 6;
    info.areaMm2 = area / 2;
  }
  if (!reportProgress(progress, kStage, 0.55)) return cancelled();

  // Holes, counted on OpenMesh's half-edge structure.
  size_t rejected = 0;
  if (!info.closed) {
    const HalfedgeBoundary hb = countBoundaryLoops(mesh);
    info.boundaryLoops = hb.boundaryLoops;
    rejected = hb.rejectedFaces;
  }
  if (!reportProgress(progress, kStage, 0.6)) return cancelled();

  // Findings that cannot be repaired safely.
  std::string openMessage, manifoldMessage;
  if (!info.closed) {
    openMessage = plural(info.boundaryEdges, "boundary edge", "boundary edges") + " in " +
                  plural(info.boundaryLoops, "hole", "holes") + "; the solid is not closed";
    info.errors.push_back(std::string("open_mesh: ") + openMessage);
  }
  if (topo.nonManifoldEdges > 0) {
    const std::string m = plural(topo.nonManifoldEdges, "edge", "edges") + " shared by more than two faces";
    info.errors.push_back("non_manifold: " + m);
    if (manifoldMessage.empty()) manifoldMessage = m;
  }
  if (topo.nonManifoldVertices > 0) {
    const std::string m = plural(topo.nonManifoldVertices, "vertex", "vertices") +
                          " where separate sheets of faces touch at a point";
    info.errors.push_back("non_manifold: " + m);
    if (manifoldMessage.empty()) manifoldMessage = m;
  }
  if (!info.oriented) {
    std::string m;
    if (orient.nonOrientableComponents > 0) {
      m = plural(orient.nonOrientableComponents, "component is", "components are") +
          " not orientable (Moebius-like); " +
          plural(misoriented, "edge joins", "edges join") + " faces of opposite orientation";
    } else {
      m = plural(misoriented, "edge joins", "edges join") +
          " faces of opposite orientation (repair off)";
    }
    info.errors.push_back("inconsistent_orientation: " + m);
    if (manifoldMessage.empty()) manifoldMessage = m;
  }
  if (rejected > 0) {
    info.warnings.push_back("half_edge: " + plural(rejected, "face was", "faces were") +
                            " rejected by the half-edge structure (non-manifold or misoriented); "
                            "boundary_loops counts the accepted faces");
  }
  if (!options.repair && info.closed && info.oriented && info.volumeMm3 < 0) {
    info.warnings.push_back("inside_out: the signed volume is negative (repair off)");
  }
  if (options.repair && orient.nestedSameOrientation > 0) {
    info.warnings.push_back("nested_shells: " +
                            plural(orient.nestedSameOrientation, "closed shell lies", "closed shells lie") +
                            " inside another with the same orientation; slicing fills it (union)");
  }
  if (orient.nestingUnchecked > 0) {
    info.warnings.push_back("nesting: " + plural(orient.nestingUnchecked, "shell was", "shells were") +
                            " not tested for lying inside another (too costly); treated as outermost");
  }
  if (!info.closed) {
    result.solid.status = Status::OpenMesh;
    result.solid.message = openMessage;
  } else if (!manifoldMessage.empty()) {
    result.solid.status = Status::NonManifoldInput;
    result.solid.message = manifoldMessage;
  }

  // repair = auto for a solid: close holes, split non-manifold spots, drop debris, then validate
  // the result again (its own report replaces this one; the repairs of both passes are kept).
  if (options.closeSolid && options.repair && !result.solid.ok()) {
    SolidRepairResult fixed = repairSolid(mesh, options.solidRepair, progress);
    if (!fixed.ok()) return cancelled();
    PrepareOptions again = options;
    again.closeSolid = false;
    again.weld = false;  // the split vertices share positions with their originals
    again.selfIntersectionsOfSolidsOnly = true;  // an unrepaired result is rebuilt or refused
    // The second pass reports only cancellation: "validate" already ran once.
    const ProgressFn quiet = [&progress](const char*, double) { return reportProgress(progress, kStage, 1); };
    PrepareMeshResult second = prepareMesh(fixed.mesh, again, quiet);
    if (!second.ok()) return second;

    // The last resort: a surface rebuilt from inside/outside samples of the faces as read (so
    // that walls present twice still cancel), validated and repaired once more (the net's
    // non-manifold spots are split); its result when that is a solid.
    RebuildResult rebuilt;
    // why(volume of the rebuilt solid): the reason written in the repairs line.
    auto rebuiltSolid = [&](const std::function<std::string(double)>& why) -> std::optional<PrepareMeshResult> {
      rebuilt = rebuildSolid(raw, {}, progress, 1.0, 1.0);
      if (!rebuilt.ok() || !rebuilt.accepted) return std::nullopt;
      PrepareOptions last = options;
      last.rebuild = false;
      last.uniteShells = false;
      PrepareMeshResult third = prepareMesh(rebuilt.mesh, last, quiet);
      if (!third.ok() || !third.solid.ok()) return std::nullopt;
      std::vector<std::string> repairs = info.repairs;
      repairs.push_back("rebuilt the surface from inside/outside samples on a " + shortNumber(rebuilt.pitchMm) +
                        " mm grid: " + why(third.info.volumeMm3));
      repairs.insert(repairs.end(), third.info.repairs.begin(), third.info.repairs.end());
      third.info.repairs = std::move(repairs);
      third.info.warnings.push_back("rebuilt: the surface was rebuilt on a " + shortNumber(rebuilt.pitchMm) +
                                    " mm grid; edges and details finer than that are rounded");
      third.info.solidRepaired = true;
      third.info.solidRepair = SolidRepairStats{};
      third.info.solidRepair.rebuiltPitchMm = rebuilt.pitchMm;
      third.info.firstFilledFace = 0;  // every face is new
      return third;
    };

    if (second.solid.ok()) {
      // A repair that filled or dropped much of the surface may have changed the shape (faces
      // tessellated apart with T-junctions between them read as holes and loose sheets): when
      // the rebuilt surface encloses a clearly different volume, the rebuild is what the file
      // meant.
      const double area = std::max(second.info.areaMm2, 1e-300);
      if (options.rebuild && (fixed.stats.filledAreaMm2 > kLargeRepairShare * area ||
                              fixed.stats.sheetAreaDroppedMm2 > kLargeRepairShare * area)) {
        const double v = second.info.volumeMm3;
        std::optional<PrepareMeshResult> other = rebuiltSolid([&](double rebuiltVolume) {
          return "closed face by face it would enclose " + shortNumber(v) + " mm3, its faces enclose " +
                 shortNumber(rebuiltVolume) + " mm3 (by " + (rebuilt.winding ? "winding" : "parity") +
                 " along rays)";
        });
        if (rebuilt.status == Status::Cancelled) return cancelled();
        if (other && std::abs(other->info.volumeMm3 - v) > kRebuildVolumeGap * other->info.volumeMm3) {
          return *other;
        }
      }
      std::vector<std::string> repairs = std::move(info.repairs);
      repairs.insert(repairs.end(), fixed.repairs.begin(), fixed.repairs.end());
      repairs.insert(repairs.end(), second.info.repairs.begin(), second.info.repairs.end());
      second.info.repairs = std::move(repairs);
      second.info.solidRepair = fixed.stats;
      second.info.solidRepaired = true;
      second.info.firstFilledFace = trailingFilledFaces(fixed.mesh, fixed.firstFilledFace, second.mesh);
      return second;
    }
    // Not repairable face by face: rebuild it, when the samples bound a solid.
    std::string rebuildVerdict;
    if (options.rebuild) {
      std::optional<PrepareMeshResult> other = rebuiltSolid(
          [&](double) { return "it could not be closed face by face (" + second.solid.message + ")"; });
      if (rebuilt.status == Status::Cancelled) return cancelled();
      if (other) return *other;
      if (rebuilt.ok() && !rebuilt.accepted && rebuilt.insideSamples > 0) {
        const RebuildOptions limits;
        auto percent = [](size_t part, size_t whole) {
          return shortNumber(std::round(1000.0 * double(part) / double(std::max<size_t>(whole, 1))) / 10) + " %";
        };
        std::string why;
        if (rebuilt.touchesBorder) {
          why = "rays through it leave the model on one side only";
        } else if (double(rebuilt.disagreeing) > limits.maxDisagreement * double(rebuilt.insideSamples)) {
          why = percent(rebuilt.disagreeing, rebuilt.touchedSamples) +
                " of the points inside by some ray direction are outside by another";
        } else {
          why = percent(rebuilt.inventedVertices, rebuilt.netVertices) +
                " of the rebuilt surface would close openings where the file has no faces";
        }
        rebuildVerdict = "; nor can it be rebuilt from inside/outside samples: " + why +
                         " (open sheets, or faces inside the part)";
      }
    }
    // Not repairable: this pass's mesh and findings stand, with the reason.
    info.solidRepair = fixed.stats;
    info.solidRepaired = true;
    info.firstFilledFace = mesh.faceCount();
    if (fixed.stats.sheets > 0) {
      result.solid.status = Status::OpenMesh;
      result.solid.message =
          "the surface is open and cannot bound a solid: closing its " +
          plural(fixed.stats.holesLeft, "hole", "holes") + " would make up more than " +
          std::to_string(int(std::lround(100 * options.solidRepair.maxCapAreaShare))) +
          " % of its area and enclose almost no volume (a sheet, not a solid with holes)" + rebuildVerdict +
          "; print an open height field with method surface, or close it in a modelling tool";
      info.errors.insert(info.errors.begin(), "open_mesh: " + result.solid.message);
    } else {
      info.warnings.push_back("repair: could not make a closed solid of it: " + second.solid.message + rebuildVerdict);
    }
  }

  // Self-intersections: a warning, the slicer unions sections with the non-zero rule.
  if (options.checkSelfIntersections && (result.solid.ok() || !options.selfIntersectionsOfSolidsOnly)) {
    if (options.selfIntersectionMaxFaces > 0 && info.faces > options.selfIntersectionMaxFaces) {
      info.warnings.push_back("self_intersections not checked above " +
                              std::to_string(options.selfIntersectionMaxFaces) + " faces (" +
                              std::to_string(info.faces) + " here)");
    } else {
      SelfIntersectionOptions so;
      so.cap = options.selfIntersectionCap;
      so.collectPairs = false;
      const SelfIntersectionResult si = findSelfIntersections(mesh, so, progress, 0.6, 1.0);
      if (si.status == Status::Cancelled) return cancelled();
      if (!si.ok()) {
        info.warnings.push_back("self_intersections not checked: " + si.message);
      } else {
        info.selfIntersections = si.count;
        info.selfIntersectionsCapped = si.capped;
        if (si.count > 0) {
          info.warnings.push_back("self_intersecting: " + std::string(si.capped ? "at least " : "") +
                                  plural(si.count, "face pair intersects", "face pairs intersect") +
                                  "; slicing uses the union");
        }
      }
    }
  }

  // Overlapping or nested closed shells of a solid: replace them by their union and validate
  // that again (its report replaces this one, with this pass's repairs first).
  if (options.uniteShells && options.repair && result.solid.ok() && info.shells > 1 &&
      (info.selfIntersections > 0 || orient.nestedSameOrientation > 0)) {
    ShellUnionResult united = uniteOverlappingShells(mesh, {}, progress, 1.0, 1.0);
    if (united.status == Status::Cancelled) return cancelled();
    if (united.ok() && united.groups > 0) {
      // Corefinement with inexact constructions rounds the points where surfaces cross: two can
      // fall on one position (welding collapses the triangle between them) and a sliver can lose
      // its area (dropped as degenerate, leaving a tiny hole), and a vertex where the united
      // surfaces touch at a point is split by CGAL into two at one position. The solid repair
      // mends those (it fills the slivers' holes flat and splits the point again).
      PrepareOptions again = options;
      again.closeSolid = true;
      again.uniteShells = false;
      const ProgressFn quiet = [&progress](const char*, double) { return reportProgress(progress, kStage, 1); };
      PrepareMeshResult third = prepareMesh(united.mesh, again, quiet);
      if (!third.ok()) return third;
      if (third.solid.ok()) {
        std::vector<std::string> repairs = std::move(info.repairs);
        repairs.push_back("united " + std::to_string(united.shellsUnited) +
                          " overlapping or nested shells: the surface of their union replaces them (" +
                          shortNumber(united.removedAreaMm2) + " mm2 of surface inside the part removed)");
        repairs.insert(repairs.end(), third.info.repairs.begin(), third.info.repairs.end());
        third.info.repairs = std::move(repairs);
        third.info.shellsUnited = united.shellsUnited;
        third.info.shellUnions = united.groups;
        third.info.unitedInnerAreaMm2 = united.removedAreaMm2;
        if (united.shellsLeft > 0) third.info.warnings.push_back(shellsLeftWarning(united.shellsLeft));
        return third;
      }
      info.warnings.push_back("shells: the union of the overlapping shells is not a closed solid (" +
                              third.solid.message + "); slicing uses the union");
    } else if (united.ok() && united.shellsLeft > 0) {
      info.warnings.push_back(shellsLeftWarning(united.shellsLeft));
    }
  }
  if (!reportProgress(progress, kStage, 1)) return cancelled();
  result.mesh = std::move(mesh);
  return result;
}

std::string meshInfoJson(const MeshInfo& info) {
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  auto point = [&](const Eigen::Vector3d& p) {
    return nlohmann::json::array({number(p.x()), number(p.y()), number(p.z())});
  };
  nlohmann::json j;
  j["vertices"] = info.vertices;
  j["faces"] = info.faces;
  j["shells"] = info.shells;
  j["closed"] = info.closed;
  j["manifold"] = info.manifold;
  j["oriented"] = info.oriented;
  j["volume_mm3"] = number(info.volumeMm3);
  j["area_mm2"] = number(info.areaMm2);
  j["bbox"] = {{"min", point(info.bbox.min)}, {"max", point(info.bbox.max)}};
  j["boundary_edges"] = info.boundaryEdges;
  j["boundary_loops"] = info.boundaryLoops;
  j["non_manifold_edges"] = info.nonManifoldEdges;
  j["non_manifold_vertices"] = info.nonManifoldVertices;
  if (info.solidRepaired) {
    const SolidRepairStats& r = info.solidRepair;
    j["repair"] = {{"t_junctions", r.tJunctionsZipped},
                   {"holes_filled", r.holesFilled},
                   {"holes_faired", r.holesFaired},
                   {"holes_capped", r.holesCapped},
                   {"holes_left", r.holesLeft},
                   {"largest_hole_mm", number(r.largestHoleMm)},
                   {"filled_area_mm2", number(r.filledAreaMm2)},
                   {"filled_faces", r.filledFaces},
                   {"first_filled_face", info.firstFilledFace},
                   {"edges_split", r.edgesUnpaired},
                   {"vertices_split", r.verticesSplit},
                   {"sheets", r.sheets},
                   {"sheets_dropped", r.sheetsDropped},
                   {"debris_pieces", r.debrisPieces},
                   {"debris_faces", r.debrisFaces},
                   {"rebuilt_mm", number(r.rebuiltPitchMm)}};
  }
  if (info.shellsUnited > 0) {
    j["shells_united"] = {{"shells", info.shellsUnited},
                          {"unions", info.shellUnions},
                          {"inner_area_mm2", number(info.unitedInnerAreaMm2)}};
  }
  j["self_intersections"] = info.selfIntersections;
  j["self_intersections_capped"] = info.selfIntersectionsCapped;
  j["non_finite_vertices"] = info.nonFiniteVertices;
  j["repairs"] = info.repairs;
  j["errors"] = info.errors;
  j["warnings"] = info.warnings;
  return j.dump();
}

}  // namespace omnislice
