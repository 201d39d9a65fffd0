// SPDX-License-Identifier: MIT
// The print sequence of the IGDS (print_sequence.h, paper 002 Algorithm 3): Criteria 1 and 2 as
// a precedence graph, its strongly connected components and feedback exemptions, the LPT / DPT /
// A3 walks with their relaxations of Criterion 2, and the lower bound on colliding nodes.
#include "geodesic/print_sequence.h"

#include <Eigen/Core>
#include <algorithm>
#include <cctype>
#include <deque>
#include <limits>
#include <string>
#include <utility>

#include "common/stopwatch.h"

namespace omnislice {

const char* traversalName(TraversalKind kind) {
  switch (kind) {
    case TraversalKind::LPT: return "LPT";
    case TraversalKind::DPT: return "DPT";
    case TraversalKind::A3: return "A3";
  }
  return "A3";
}

bool parseTraversal(const std::string& text, TraversalKind& kind) {
  std::string t;
  for (char c : text) t += char(std::toupper(static_cast<unsigned char>(c)));
  if (t == "LPT") kind = TraversalKind::LPT;
  else if (t == "DPT") kind = TraversalKind::DPT;
  else if (t == "A3") kind = TraversalKind::A3;
  else return false;
  return true;
}

namespace {

// Strongly connected components (iterative Tarjan) of a graph on n nodes whose successors of v
// are given by successor(v, k, w): true and the k-th successor in w, false past the last one.
// comp[v] gets its component; returns the number of components.
template <class Successor>
uint32_t strongComponents(size_t n, const Successor& successor, std::vector<uint32_t>& comp) {
  constexpr uint32_t kUnseen = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> index(n, kUnseen), low(n, 0), stack;
  comp.assign(n, kUnseen);
  std::vector<uint8_t> onStack(n, 0);
  std::vector<std::pair<uint32_t, size_t>> call;  // (node, next successor)
  uint32_t next = 0, comps = 0;
  for (uint32_t root = 0; root < n; ++root) {
    if (index[root] != kUnseen) continue;
    call.push_back({root, 0});
    index[root] = low[root] = next++;
    stack.push_back(root);
    onStack[root] = 1;
    while (!call.empty()) {
      auto& [v, k] = call.back();
      uint32_t w = 0;
      if (successor(v, k, w)) {
        ++k;
        if (index[w] == kUnseen) {
          index[w] = low[w] = next++;
          stack.push_back(w);
          onStack[w] = 1;
          call.push_back({w, 0});
        } else if (onStack[w]) {
          low[v] = std::min(low[v], index[w]);
        }
        continue;
      }
      if (low[v] == index[v]) {
        uint32_t x;
        do {
          x = stack.back();
          stack.pop_back();
          onStack[x] = 0;
          comp[x] = comps;
        } while (x != v);
        ++comps;
      }
      const uint32_t done = v;
      call.pop_back();
      if (!call.empty()) low[call.back().first] = std::min(low[call.back().first], low[done]);
    }
  }
  return comps;
}

// The precedence graph: lower-node -> node (Criterion 1) and u -> x for x in links[u] unless u
// is exempt (Criterion 2). Its strongly connected components in comp; returns which of them hold
// a link u -> x of a non-exempt u (a cycle of constraints: every order breaks one such link).
std::vector<uint8_t> cyclicComponents(const SkeletonTree& tree,
                                      const std::vector<std::vector<uint32_t>>& links,
                                      const std::vector<uint8_t>& exempt,
                                      std::vector<uint32_t>& comp) {
  const size_t n = tree.nodes.size();
  auto successor = [&](uint32_t v, size_t k, uint32_t& w) {
    const auto& up = tree.nodes[v].upper;
    if (k < up.size()) {
      w = up[k];
      return true;
    }
    k -= up.size();
    if (exempt[v] || k >= links[v].size()) return false;
    w = links[v][k];
    return true;
  };
  const uint32_t comps = strongComponents(n, successor, comp);
  std::vector<uint8_t> cyclic(comps, 0);
  for (uint32_t u = 0; u < n; ++u)
    if (!exempt[u])
      for (uint32_t x : links[u])
        if (comp[x] == comp[u]) cyclic[comp[u]] = 1;
  return cyclic;
}

// A component holding a PCS link u -> x is a cycle of constraints, so every order breaks one of
// its PCS links and makes one of its nodes collide; components are disjoint, so their count
// bounds the colliding nodes from below.
size_t cyclesWithPcsLink(const SkeletonTree& tree, const CollisionModel& collisions) {
  std::vector<uint32_t> comp;
  const std::vector<uint8_t> none(tree.nodes.size(), 0);
  size_t count = 0;
  for (uint8_t c : cyclicComponents(tree, collisions.pcs, none, comp)) count += c;
  return count;
}

// Gives back, in the order given, every exemption whose links close no cycle (no target of
// u's links reaches u; the graph without u's links is acyclic already).
void giveBack(const SkeletonTree& tree, const std::vector<std::vector<uint32_t>>& links,
              const std::vector<uint32_t>& order, std::vector<uint8_t>& exempt) {
  const size_t n = tree.nodes.size();
  std::vector<uint32_t> seen(n, 0), stack;
  uint32_t stamp = 0;
  for (uint32_t u : order) {
    if (!exempt[u] || links[u].empty()) continue;
    ++stamp;
    stack.assign(links[u].begin(), links[u].end());
    for (uint32_t x : stack) seen[x] = stamp;
    bool cycle = false;
    while (!stack.empty() && !cycle) {
      const uint32_t v = stack.back();
      stack.pop_back();
      auto visit = [&](uint32_t w) {
        if (w == u) cycle = true;
        if (seen[w] == stamp) return;
        seen[w] = stamp;
        stack.push_back(w);
      };
      for (uint32_t w : tree.nodes[v].upper) visit(w);
      if (!exempt[v])
        for (uint32_t w : links[v]) visit(w);
    }
    if (!cycle) exempt[u] = 0;
  }
}

// Nodes allowed to collide so that the precedence graph without their Criterion-2 links is
// acyclic (a feedback set over PCS sources), greedily: from the nodes that collide in any order
// (stuck), while a component holds a cycle, exempt in each such component the node with the most
// links inside it (ties: lower index); then give back every exemption (latest first) whose links
// close no cycle. Every order consistent with the rest makes at most the exempt nodes collide.
std::vector<uint8_t> feedbackExemptions(const SkeletonTree& tree,
                                        const std::vector<std::vector<uint32_t>>& links,
                                        const std::vector<uint8_t>& stuck) {
  const size_t n = tree.nodes.size();
  std::vector<uint8_t> exempt = stuck;
  std::vector<uint32_t> comp, added;
  for (;;) {
    const std::vector<uint8_t> cyclic = cyclicComponents(tree, links, exempt, comp);
    std::vector<uint32_t> bestNode(cyclic.size(), 0), bestLinks(cyclic.size(), 0);
    for (uint32_t u = 0; u < n; ++u) {
      if (exempt[u] || !cyclic[comp[u]]) continue;
      uint32_t inside = 0;
      for (uint32_t x : links[u]) inside += comp[x] == comp[u];
      if (inside > bestLinks[comp[u]]) {
        bestLinks[comp[u]] = inside;
        bestNode[comp[u]] = u;
      }
    }
    const size_t before = added.size();
    for (size_t c = 0; c < cyclic.size(); ++c)
      if (cyclic[c] && bestLinks[c] > 0) {
        exempt[bestNode[c]] = 1;
        added.push_back(bestNode[c]);
      }
    if (added.size() == before) break;
  }
  giveBack(tree, links, std::vector<uint32_t>(added.rbegin(), added.rend()), exempt);
  return exempt;
}

// A lower bound on the colliding nodes of any order: cycles of the precedence graph whose PCS
// links come from pairwise different nodes (each cycle makes one of its link sources collide).
// The stuck nodes are one-link cycles; the others are packed greedily, by 0-1 breadth-first
// search (a lower-node link costs 0, a PCS link 1) for the cycle through each node u with the
// fewest other sources, accepting cycles of at most 1, 2 and then 4 other sources, over links of
// sources not used yet. links holds the lowest PCS entries (the cycles are the same).
size_t packedCycles(const SkeletonTree& tree, const std::vector<std::vector<uint32_t>>& links,
                    const std::vector<uint8_t>& stuck) {
  const size_t n = tree.nodes.size();
  constexpr uint32_t kFar = std::numeric_limits<uint32_t>::max();
  std::vector<uint8_t> used = stuck;
  size_t count = 0;
  for (uint8_t s : stuck) count += s;
  std::vector<uint32_t> cost(n, kFar), from(n, kFar), touched;
  std::deque<uint32_t> queue;
  std::vector<uint32_t> comp;
  const std::vector<uint8_t> cyclic = cyclicComponents(tree, links, stuck, comp);
  for (const uint32_t limit : {1u, 2u, 4u}) {
    for (uint32_t u = 0; u < n; ++u) {
      if (used[u] || !cyclic[comp[u]]) continue;
      for (uint32_t v : touched) cost[v] = kFar;
      touched.clear();
      queue.clear();
      for (uint32_t x : links[u])
        if (cost[x] != 0) {
          cost[x] = 0;
          from[x] = u;
          touched.push_back(x);
          queue.push_back(x);
        }
      while (!queue.empty() && cost[u] == kFar) {
        const uint32_t v = queue.front();
        queue.pop_front();
        if (cost[v] > limit) break;
        auto relax = [&](uint32_t w, uint32_t c, bool front) {
          if (c >= cost[w]) return;
          if (cost[w] == kFar) touched.push_back(w);
          cost[w] = c;
          from[w] = v;
          front ? queue.push_front(w) : queue.push_back(w);
        };
        for (uint32_t w : tree.nodes[v].upper) relax(w, cost[v], true);
        if (v != u && !used[v])
          for (uint32_t w : links[v]) relax(w, cost[v] + 1, false);
      }
      if (cost[u] > limit) continue;
      // Walk back from u to one of its own link targets, marking the sources of PCS links.
      used[u] = 1;
      for (uint32_t w = u; cost[w] != 0 || from[w] != u;) {
        const uint32_t v = from[w];
        if (cost[v] != cost[w]) used[v] = 1;  // v -> w was a PCS link
        w = v;
      }
      ++count;
    }
  }
  return count;
}

PrintSequence sequenceFailure(TraversalKind kind, Status s, std::string msg) {
  PrintSequence r;
  r.kind = kind;
  r.status = s;
  r.message = std::move(msg);
  r.collisionFree = false;
  return r;
}

// InvalidOption (or EmptyInput) for a tree or collision model printSequence cannot use.
Outcome checkSequenceInput(const SkeletonTree& tree, const CollisionModel& collisions) {
  auto fail = [](Status s, std::string msg) { return failed<Outcome>(s, std::move(msg)); };
  const size_t n = tree.nodes.size();
  if (!tree.ok()) return fail(Status::InvalidOption, "sequence: the skeleton tree carries an error");
  if (n == 0) return fail(Status::EmptyInput, "sequence: empty skeleton tree");
  if (!collisions.ok())
    return fail(Status::InvalidOption, "sequence: the collision model carries an error");
  if (collisions.pcs.size() != n)
    return fail(Status::InvalidOption, "sequence: collision model has " +
                                           std::to_string(collisions.pcs.size()) +
                                           " entries for " + std::to_string(n) + " nodes");
  for (size_t i = 0; i < n; ++i) {
    const SkeletonNode& nd = tree.nodes[i];
    if (i && (nd.layer < tree.nodes[i - 1].layer ||
              (nd.layer == tree.nodes[i - 1].layer && nd.region <= tree.nodes[i - 1].region)))
      return fail(Status::InvalidOption, "sequence: nodes not sorted by (layer, region)");
    for (uint32_t l : nd.lower)
      if (l >= n || tree.nodes[l].layer + 1 != nd.layer ||
          !std::binary_search(tree.nodes[l].upper.begin(), tree.nodes[l].upper.end(), uint32_t(i)))
        return fail(Status::InvalidOption, "sequence: node " + std::to_string(i) +
                                               " has an inconsistent lower-node link");
    for (uint32_t u : nd.upper)
      if (u >= n || !std::binary_search(tree.nodes[u].lower.begin(), tree.nodes[u].lower.end(),
                                        uint32_t(i)))
        return fail(Status::InvalidOption, "sequence: node " + std::to_string(i) +
                                               " has an inconsistent upper-node link");
    for (uint32_t j : collisions.pcs[i])
      if (j >= n || j == i)
        return fail(Status::InvalidOption, "sequence: collision model index out of range");
  }
  return {};
}

// Ancestors (through lower-nodes) of every node as bitsets of `words` 64-bit words, node i's at
// [i * words, (i + 1) * words); nodes in (layer, region) order so lower-nodes come first.
std::vector<uint64_t> ancestorSets(const SkeletonTree& tree, size_t words) {
  const size_t n = tree.nodes.size();
  std::vector<uint64_t> anc(n * words, 0);
  for (size_t i = 0; i < n; ++i)
    for (uint32_t l : tree.nodes[i].lower) {
      anc[i * words + l / 64] |= uint64_t(1) << (l % 64);
      for (size_t w = 0; w < words; ++w) anc[i * words + w] |= anc[size_t(l) * words + w];
    }
  return anc;
}

// Criteria 1 and 2 as the walks use them, and where every order starts.
struct Constraints {
  Constraints(const SkeletonTree& t, const CollisionModel& m) : tree(t), collisions(m) {}
  const SkeletonTree& tree;
  const CollisionModel& collisions;
  std::vector<uint32_t> lowerLeft0;  // per node: its lower-nodes (Criterion 1)
  std::vector<uint32_t> blockers0;   // per node x: the u with x in avoidable[u] (Criterion 2)
  // Criterion 2: x may be printed only once every u with x in pcs[u] is printed, except where x
  // is an ancestor of u (that collision happens in every order).
  std::vector<std::vector<uint32_t>> avoidable, blockedBy;
  std::vector<uint8_t> stuck;  // pcs[u] holds an ancestor of u: u collides in every order
  size_t unavoidable = 0;      // stuck nodes
  // Only the lowest entries of each PCS matter for cycles and collisions: x in pcs[u] above
  // another entry y (y an ancestor of x) is printed after y anyway.
  std::vector<std::vector<uint32_t>> lowestLinks;
  uint32_t lowest = 0;  // the first layer's lowest centroid: every walk starts there
};

Constraints constraintsOf(const SkeletonTree& tree, const CollisionModel& collisions) {
  const size_t n = tree.nodes.size();
  Constraints c(tree, collisions);
  c.lowerLeft0.resize(n);
  c.blockers0.assign(n, 0);
  for (size_t i = 0; i < n; ++i) c.lowerLeft0[i] = uint32_t(tree.nodes[i].lower.size());
  const size_t words = (n + 63) / 64;
  const std::vector<uint64_t> anc = ancestorSets(tree, words);
  auto isAncestor = [&](uint32_t x, size_t of) {
    return (anc[of * words + x / 64] >> (x % 64)) & 1;
  };
  c.avoidable.resize(n);
  c.blockedBy.resize(n);
  c.stuck.assign(n, 0);
  for (size_t u = 0; u < n; ++u) {
    for (uint32_t x : collisions.pcs[u]) {
      if (isAncestor(x, u)) {
        c.stuck[u] = 1;
        continue;
      }
      c.avoidable[u].push_back(x);
      c.blockedBy[x].push_back(uint32_t(u));
      ++c.blockers0[x];
    }
    c.unavoidable += c.stuck[u];
  }
  // Start: the first layer's lowest centroid (first non-empty layer = nodes[0].layer).
  for (uint32_t i = 0; i < n && tree.nodes[i].layer == tree.nodes[0].layer; ++i)
    if (tree.nodes[i].centroid.z() < tree.nodes[c.lowest].centroid.z()) c.lowest = i;
  c.lowestLinks.resize(n);
  std::vector<uint64_t> mask(words, 0);
  for (size_t u = 0; u < n; ++u) {
    for (uint32_t x : c.avoidable[u]) mask[x / 64] |= uint64_t(1) << (x % 64);
    for (uint32_t x : c.avoidable[u]) {
      bool above = false;
      for (size_t w = 0; w < words && !above; ++w) above = (anc[x * words + w] & mask[w]) != 0;
      if (!above) c.lowestLinks[u].push_back(x);
    }
    for (uint32_t x : c.avoidable[u]) mask[x / 64] = 0;
  }
  return c;
}

bool isUpperNode(const SkeletonTree& tree, uint32_t a, uint32_t b) {
  const auto& up = tree.nodes[a].upper;
  return std::binary_search(up.begin(), up.end(), b);
}

// Per node: does the order print one of its (lowest) avoidable PCS entries before it?
std::vector<uint8_t> breaksLinks(const Constraints& c, const std::vector<uint32_t>& order) {
  const size_t n = c.tree.nodes.size();
  std::vector<size_t> pos(n);
  for (size_t i = 0; i < n; ++i) pos[order[i]] = i;
  std::vector<uint8_t> breaks(n, 0);
  for (uint32_t u = 0; u < n; ++u)
    for (uint32_t x : c.lowestLinks[u]) breaks[u] = breaks[u] || pos[x] < pos[u];
  return breaks;
}

// Where A3 must break Criterion 2 (no candidate meets it), four policies (Relaxation); A3
// keeps the order with the fewest colliding nodes, then retractions, then air moves.
enum class Relaxation {
  Blockers,   // the candidates with the fewest unprinted blockers
  Undecided,  // ... the fewest blockers whose collision is not yet decided
  Release,    // a node whose collision is decided (a node of its PCS printed first) stops
              // blocking the rest of its PCS: that would only shift collisions onto others
  Exempt,     // as Release, and a feedback set of nodes (feedbackExemptions), chosen before
              // the walk so that the remaining constraints are acyclic, never blocks
};

// The next node of a walk among the Criterion-1 candidates `avail`, after node cur (-1 at the
// start; distances from `from`), nearest first (ties: lower index). LPT: in the lowest layer
// available. DPT: an upper-node of cur, else any. A3: meeting Criterion 2 (meetsC2), an
// upper-node of cur first; where none meets it, the candidates of least cost (counted in
// criterion2Relaxed), an upper-node of cur first.
template <class MeetsC2, class Cost>
int64_t pickNext(const SkeletonTree& tree, TraversalKind kind, const std::vector<uint32_t>& avail, int64_t cur,
                 const Eigen::Vector3d& from, const MeetsC2& c2, const Cost& cost, size_t& criterion2Relaxed) {
  auto nearestOf = [&](auto&& pred) {
    int64_t best = -1;
    double bestD = std::numeric_limits<double>::infinity();
    for (uint32_t c : avail) {
      if (!pred(c)) continue;
      const double d = (tree.nodes[c].centroid - from).norm();
      if (d < bestD || (d == bestD && c < best)) {
        bestD = d;
        best = c;
      }
    }
    return best;
  };
  auto isUpper = [&](uint32_t a, uint32_t b) { return isUpperNode(tree, a, b); };
  int64_t pick = -1;
  switch (kind) {
    case TraversalKind::LPT: {
      uint32_t minLayer = std::numeric_limits<uint32_t>::max();
      for (uint32_t c : avail) minLayer = std::min(minLayer, tree.nodes[c].layer);
      pick = nearestOf([&](uint32_t c) { return tree.nodes[c].layer == minLayer; });
      break;
    }
    case TraversalKind::DPT:
      if (cur >= 0) pick = nearestOf([&](uint32_t c) { return isUpper(uint32_t(cur), c); });
      if (pick < 0) pick = nearestOf([](uint32_t) { return true; });
      break;
    case TraversalKind::A3:
      if (cur >= 0)
        pick = nearestOf([&](uint32_t c) { return c2(c) && isUpper(uint32_t(cur), c); });
      if (pick < 0) pick = nearestOf([&](uint32_t c) { return c2(c); });
      if (pick < 0) {
        // No candidate meets Criterion 2 (cycles of potential collisions, e.g. where two
        // fronts close a loop): among the candidates that would break it for the fewest
        // nodes, an upper-node of the current node first, else the nearest.
        uint32_t fewest = std::numeric_limits<uint32_t>::max();
        for (uint32_t c : avail) fewest = std::min(fewest, cost(c));
        if (cur >= 0)
          pick = nearestOf([&](uint32_t c) { return cost(c) == fewest && isUpper(uint32_t(cur), c); });
        if (pick < 0) pick = nearestOf([&](uint32_t c) { return cost(c) == fewest; });
        ++criterion2Relaxed;
      }
      break;
  }
  return pick;
}

// The colliding nodes of a complete order (node u printed after some x in pcs[u]); with the
// Exempt policy, criterion2Relaxed also counts the nodes whose avoidable entries it breaks.
void scoreOrder(const Constraints& c, Relaxation policy, PrintSequence& seq) {
  const size_t n = c.tree.nodes.size();
  std::vector<size_t> pos(n);
  for (size_t i = 0; i < n; ++i) pos[seq.order[i]] = i;
  if (policy == Relaxation::Exempt)  // the nodes whose avoidable entries the order breaks
    for (uint8_t b : breaksLinks(c, seq.order)) seq.criterion2Relaxed += b;
  for (size_t u = 0; u < n; ++u)
    for (uint32_t x : c.collisions.pcs[u])
      if (pos[x] < pos[u]) {
        ++seq.collidingNodes;
        break;
      }
  seq.collisionFree = seq.collidingNodes == 0;
}

// One walk of traversal `kind` under `policy` (exempt: the nodes that never block, used by the
// Exempt policy only) into seq. False when no node meets Criterion 1 (cyclic links).
bool walk(const Constraints& c, TraversalKind kind, Relaxation policy, const std::vector<uint8_t>& exempt,
          PrintSequence& seq) {
  const SkeletonTree& tree = c.tree;
  const size_t n = tree.nodes.size();
  seq.kind = kind;
  std::vector<uint32_t> lowerLeft = c.lowerLeft0, blockersLeft = c.blockers0;
  std::vector<uint8_t> printed(n, 0), released(n, 0), decided(n, 0);
  auto release = [&](uint32_t u) {
    if (released[u]) return;
    released[u] = 1;
    for (uint32_t x : c.avoidable[u]) --blockersLeft[x];
  };
  if (policy == Relaxation::Exempt) {
    for (uint32_t u = 0; u < n; ++u)
      if (exempt[u]) release(u);
  }
  auto c2 = [&](uint32_t x) { return blockersLeft[x] == 0; };
  auto cost = [&](uint32_t x) {
    if (policy != Relaxation::Undecided) return blockersLeft[x];
    uint32_t k = 0;
    for (uint32_t u : c.blockedBy[x]) k += !printed[u] && !decided[u];
    return k;
  };
  std::vector<uint32_t> avail;  // Criterion-1 candidates
  for (uint32_t i = 0; i < n; ++i)
    if (lowerLeft[i] == 0) avail.push_back(i);
  int64_t cur = -1;
  while (seq.order.size() < n) {
    if (avail.empty()) return false;
    const Eigen::Vector3d from = cur >= 0 ? tree.nodes[cur].centroid : tree.nodes[c.lowest].centroid;
    const int64_t pick = pickNext(tree, kind, avail, cur, from, c2, cost, seq.criterion2Relaxed);
    const uint32_t p = uint32_t(pick);
    if (cur >= 0 && !isUpperNode(tree, uint32_t(cur), p)) {
      ++seq.retractions;
      seq.airMoveMm += (tree.nodes[uint32_t(cur)].centroid - tree.nodes[p].centroid).norm();
    }
    seq.order.push_back(p);
    printed[p] = 1;
    avail.erase(std::find(avail.begin(), avail.end(), p));
    release(p);
    for (uint32_t u : c.blockedBy[p]) {
      if (printed[u]) continue;
      decided[u] = 1;  // p printed before u: u collides whatever comes next
      if (policy == Relaxation::Release || policy == Relaxation::Exempt) release(u);
    }
    for (uint32_t u : tree.nodes[p].upper)
      if (--lowerLeft[u] == 0) avail.push_back(u);
    cur = p;
  }
  scoreOrder(c, policy, seq);
  return true;
}

bool better(const PrintSequence& a, const PrintSequence& b) {
  return a.collidingNodes < b.collidingNodes ||
         (a.collidingNodes == b.collidingNodes &&
          (a.retractions < b.retractions ||
           (a.retractions == b.retractions && a.airMoveMm < b.airMoveMm)));
}

// The exemptions of the Exempt policy: the smallest of the greedy feedback set and the colliding
// nodes of the best order so far, of LPT's and of DPT's, each with every exemption given back
// (latest printed first) whose links close no cycle. So A3 never collides on more nodes than LPT
// or DPT. False when a walk finds cyclic links.
bool chooseExemptions(const Constraints& c, const PrintSequence& best, std::vector<uint8_t>& exempt) {
  const SkeletonTree& tree = c.tree;
  const size_t n = tree.nodes.size();
  auto count = [&](const std::vector<uint8_t>& e) {
    size_t k = 0;
    for (size_t u = 0; u < n; ++u) k += e[u] && !c.stuck[u];
    return k;
  };
  exempt = feedbackExemptions(tree, c.lowestLinks, c.stuck);
  std::vector<PrintSequence> seeds(3);
  seeds[0] = best;
  if (!walk(c, TraversalKind::LPT, Relaxation::Blockers, exempt, seeds[1]) ||
      !walk(c, TraversalKind::DPT, Relaxation::Blockers, exempt, seeds[2]))
    return false;
  for (const PrintSequence& seed : seeds) {
    std::vector<uint8_t> seeded = breaksLinks(c, seed.order);
    for (uint32_t u = 0; u < n; ++u) seeded[u] = seeded[u] || c.stuck[u];
    std::vector<uint32_t> latestFirst;
    for (auto it = seed.order.rbegin(); it != seed.order.rend(); ++it)
      if (!c.stuck[*it]) latestFirst.push_back(*it);
    giveBack(tree, c.lowestLinks, latestFirst, seeded);
    if (count(seeded) < count(exempt)) exempt.swap(seeded);
  }
  return true;
}

// A3 where its first walk broke Criterion 2: the walks under the other policies (Undecided,
// Release, then Exempt with chooseExemptions) replace `out` when better. False when a walk
// finds cyclic links.
bool relaxCriterion2(const Constraints& c, TraversalKind kind, PrintSequence& out) {
  const std::vector<uint8_t> none;
  for (const Relaxation policy : {Relaxation::Undecided, Relaxation::Release}) {
    PrintSequence seq;
    if (!walk(c, kind, policy, none, seq)) return false;
    if (better(seq, out)) out = std::move(seq);
  }
  std::vector<uint8_t> exempt;
  if (!chooseExemptions(c, out, exempt)) return false;
  PrintSequence seq;
  if (!walk(c, kind, Relaxation::Exempt, exempt, seq)) return false;
  if (better(seq, out)) out = std::move(seq);
  return true;
}

}  // namespace

PrintSequence printSequence(const SkeletonTree& tree, const CollisionModel& collisions,
                            TraversalKind kind) {
  const auto t0 = Clock::now();
  const Outcome input = checkSequenceInput(tree, collisions);
  if (!input.ok()) return sequenceFailure(kind, input.status, input.message);
  const Constraints c = constraintsOf(tree, collisions);
  PrintSequence out;
  out.kind = kind;
  const char* cyclicLinks = "sequence: no node meets Criterion 1 (cyclic links)";
  if (!walk(c, kind, Relaxation::Blockers, {}, out)) return sequenceFailure(kind, Status::Internal, cyclicLinks);
  if (kind == TraversalKind::A3 && out.criterion2Relaxed > 0 && !relaxCriterion2(c, kind, out)) {
    return sequenceFailure(kind, Status::Internal, cyclicLinks);
  }
  out.unavoidableNodes = c.unavoidable;
  out.collidingLowerBound =
      std::max(cyclesWithPcsLink(tree, collisions), packedCycles(tree, c.lowestLinks, c.stuck));
  out.ms = msSince(t0);
  return out;
}

}  // namespace omnislice
