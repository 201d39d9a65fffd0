// SPDX-License-Identifier: MIT
// The print sequence of the IGDS (paper 002 Section 3.1): the layer-priority (LPT), depth-priority
// (DPT) and greedy (A3, Algorithm 3) traversals of the skeleton tree under Criteria 1 (lower-nodes
// first) and 2 (no node after one of its potential collision surfaces).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/status.h"
#include "geodesic/collision_surfaces.h"
#include "geodesic/skeleton_tree.h"

namespace omnislice {

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
                                   // from pairwise different nodes (print_sequence.cpp)
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
// then air moves (print_sequence.cpp, Relaxation), so it never collides on more nodes than LPT or
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
