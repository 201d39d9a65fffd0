// SPDX-License-Identifier: MIT
// Print order of the IGDS (paper 002 Section 3.1): the skeleton tree (Algorithm 1, adjacency by
// steepest paths on the part's boundary surface, Fig. 12), the nozzle's collision model (its
// bounding cone swept over each IGDS, Fig. 15; potential collision surfaces, Algorithm 2) and the
// three traversals: layer priority (LPT), depth priority (DPT) and the greedy traversal of
// Algorithm 3 (A3) under Criteria 1 and 2.
//
// Omnislice's graph is a DAG, not only a tree: on parts of genus > 0 a node may have two
// lower-nodes (branches merging); Criterion 1 then waits for all of them, so no manual cut is
// needed (the paper's future work).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/progress.h"
#include "common/status.h"
#include "mesh/mesh.h"
#include "surface/surface_layers.h"

namespace omnislice {

struct SkeletonNode {
  uint32_t layer = 0, region = 0;  // index into layers[layer].regions
  double isoValue = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // area-weighted, mm
  double area = 0;                                     // mm^2
  std::vector<uint32_t> lower, upper;  // node indices (lower: layer - 1, upper: layer + 1)
};

struct SkeletonTree : Outcome {
  std::vector<SkeletonNode> nodes;  // sorted by (layer, region)
  size_t edges = 0;
  size_t fallbackLinks = 0;  // links made by nearest boundary where no steepest path decided
  bool isTree = true;        // every node has at most one lower-node
  double ms = 0;
};

struct SkeletonOptions {
  int pathsPerNode = 8;  // steepest paths traced per IGDS, from boundary points spread along its
                         // boundary (the paper traces one from a random edge)
};

// layers: as extractIgds returns them (empty layers allowed); boundary: the part's boundary
// surface (tetBoundary) with field = the geodesic distance per boundary-mesh vertex. Node a on
// layer i and b on layer i + 1 are adjacent when a steepest ascending path on the boundary
// surface, started at a's boundary, crosses phi_{i+1} on b's boundary, or a steepest descending
// path from b's boundary crosses phi_i on a's boundary (Fig. 12). A node of layer i + 1 left
// without a lower-node (paths stalled) is linked to the layer-i node nearest to its boundary
// (counted in fallbackLinks); nodes of the first non-empty layer have none, nor have nodes whose
// previous layer is empty. Paths start at the boundary-surface edges crossing phi_i whose crossing
// point lies within 0.75 mean edge length of the node's IGDS boundary (pathsPerNode of them, spread
// by farthest-point picks); a path's end on phi_{i+1} names the node whose boundary passes within
// that tolerance.
// Statuses: InvalidOption (field size differs from the boundary's vertex count, a non-finite
// field value, iso-values not increasing, a malformed boundary or region mesh, pathsPerNode < 1),
// EmptyInput (no region or no boundary triangle).
SkeletonTree buildSkeletonTree(const std::vector<CurvedLayer>& layers, const Mesh& boundary,
                               const std::vector<double>& field,
                               const SkeletonOptions& options = {});

// The nozzle as its bounding cone (Fig. 15a): apex at the tip, axis along the IGDS normal,
// half-angle angleDegrees (the paper's nozzle angle), length length; points within clearance
// along the axis above the tip are ignored (the bead being laid).
struct CollisionConeOptions {
  double angleDegrees = 45;   // (0, 90)
  double length = 25;         // mm, > 0
  double clearance = 0.3;     // mm, >= 0
  double sampleSpacing = 1.0; // mm, > 0: points tested on each IGDS (vertices, open-boundary
                              // samples, and a grid on triangles longer than 2 sampleSpacing;
                              // at most 64 samples per edge, 16 per triangle side)
};

struct CollisionModel : Outcome {
  // pcs[i]: the potential collision surfaces of node i (Algorithm 2): the other nodes with a test
  // point inside the envelope volume of the cone swept over node i, closed as in Fig. 15: the
  // ring-like ruled surface of the cones along the IGDS's boundary on the sides, the IGDS itself
  // below, the cone length on top. Tested as the union of the IGDS's normal offset up to the cone
  // length (faces, creases, vertex fans) and the cones along its open boundary (axis: the
  // boundary vertices' normals); on a flat IGDS this is exactly the union of the cones placed at
  // all its points. Sorted ascending.
  std::vector<std::vector<uint32_t>> pcs;
  size_t pairsTested = 0;   // node pairs whose bounding volumes met (others skipped)
  size_t foldedFaces = 0;   // IGDS faces whose normal opposes the sum of their corners' vertex
                            // normals (flipped by remeshing): no nozzle direction, left out
  double ms = 0;
};

// The exact inside rule and the culling (hierarchies with spheres, normal cones and slabs, dual
// traversal, early exit) are stated in print_order.cpp; tests compare it with a brute force.
// Options: angle in (0, 90), length > 0, clearance in [0, length), sampleSpacing > 0.
// Measured native (CPU time; cone length 25 mm): 300 curved IGDS of 1,024 vertices on three
// leaning branches 0.6 s at 15 deg, 1.0 s at 45 deg, 1.8-2.0 s at 75 deg (about half of all pairs
// collide there); 136 marching-tets IGDS of the test tree 60-180 ms; 1,896 IGDS of
// compas_branches_16 (56k tets) 0.4 s at 15 deg, 0.65 s at 45 deg.
// Statuses: InvalidOption (options out of range, tree not built from these layers, malformed
// region mesh), Cancelled (progress stage "collision").
CollisionModel potentialCollisionSurfaces(const std::vector<CurvedLayer>& layers,
                                          const SkeletonTree& tree,
                                          const CollisionConeOptions& options = {},
                                          const ProgressFn& progress = {});

enum class TraversalKind { LPT, DPT, A3 };
const char* traversalName(TraversalKind kind);                 // "LPT", "DPT", "A3"
bool parseTraversal(const std::string& text, TraversalKind& kind);  // case-insensitive

struct PrintSequence : Outcome {
  TraversalKind kind = TraversalKind::A3;
  std::vector<uint32_t> order;  // every node once; Criterion 1 always holds
  // A transition a -> b where b is not an upper-node of a is a retraction, and its air move is
  // the distance between the two nodes' centroids (the nozzle leaves a and crosses to b).
  size_t retractions = 0;
  double airMoveMm = 0;
  // Collision-free: no node is printed after one of its potential collision surfaces.
  bool collisionFree = true;
  size_t collidingNodes = 0;     // nodes printed after one of their PCS
  size_t unavoidableNodes = 0;   // nodes whose PCS holds one of their own ancestors (through
                                 // lower-nodes): Criterion 1 makes them collide in every order
  size_t collidingLowerBound = 0;  // no order has fewer colliding nodes: the larger of the
                                   // strongly connected components of "lower-node before node"
                                   // and "u before every node of pcs[u]" that hold a PCS link,
                                   // and a greedy packing of such cycles whose PCS links come
                                   // from pairwise different nodes (print_order.cpp)
  size_t criterion2Relaxed = 0;  // A3 only: where no candidate met Criterion 2, the steps that
                                 // broke it (then the candidates blocking the fewest nodes, an
                                 // upper-node of the current one first, else the nearest), or
                                 // with exemptions chosen beforehand, the nodes whose
                                 // avoidable PCS entries the order breaks
  double ms = 0;
};

// LPT: layer by layer, within a layer nearest centroid first from the current node. DPT: from the
// current node to an upper-node (nearest first) while Criterion 1 allows, else the nearest node
// Criterion 1 allows. A3 (Algorithm 3): candidates meet Criteria 1 and 2; an upper-node of the
// current node first (nearest), else the nearest candidate; starting with the candidate nearest
// to the first layer's lowest centroid. Criterion 2 leaves out the unavoidable PCS entries (a
// node's own ancestors, printed before it whatever the order): they would block their ancestors
// for nothing. So with criterion2Relaxed == 0, A3's colliding nodes are exactly the unavoidable
// ones. Where no candidate meets Criterion 2, A3 breaks it for the candidates blocking the fewest
// nodes, counted three ways (all unprinted blockers; only those whose collision is not yet
// decided; or letting a decided node stop blocking the rest of its PCS); a fourth way exempts
// beforehand a set of nodes from blocking: the smallest found of a greedy feedback set and the
// colliding nodes of the best order so far, of LPT and of DPT, each pruned of exemptions whose
// links close no cycle. A3 keeps the order with the fewest colliding nodes, then retractions,
// then air moves (print_order.cpp, Relaxation), so it never collides on more nodes than LPT or
// DPT. LPT and DPT also start at that lowest centroid; ties in distance go to the lower node
// index. Linear in the PCS entries plus O(k^2) nearest-candidate scans (k nodes); where
// Criterion 2 must break, the exemptions add one search over the lowest PCS entries per
// candidate exemption (branches_16 at 40 deg, 1,593 nodes: 50 ms; the bound's packing 10 ms).
// Statuses: InvalidOption (tree or collision model carries an error, pcs size differs from the
// node count, links not symmetric or not between consecutive layers, indices out of range),
// EmptyInput (no node).
PrintSequence printSequence(const SkeletonTree& tree, const CollisionModel& collisions,
                            TraversalKind kind);

}  // namespace omnislice
