// SPDX-License-Identifier: MIT
// Print order of the IGDS (paper 002 Section 3.1), in three steps, each with its own header:
// - skeleton_tree.h: the skeleton tree (Algorithm 1, adjacency by steepest paths on the part's
//   boundary surface, Fig. 12);
// - collision_surfaces.h: the nozzle's collision model (its bounding cone swept over each IGDS,
//   Fig. 15; potential collision surfaces, Algorithm 2);
// - print_sequence.h: the three traversals: layer priority (LPT), depth priority (DPT) and the
//   greedy traversal of Algorithm 3 (A3) under Criteria 1 and 2.
#pragma once

#include "geodesic/collision_surfaces.h"
#include "geodesic/print_sequence.h"
#include "geodesic/skeleton_tree.h"
