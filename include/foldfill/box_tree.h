// A bounding volume hierarchy over axis-aligned boxes: the one broad phase of
// foldfill (boxes in, index pairs out), for collision candidates and any
// other search for nearby primitives.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

// A closed axis-aligned box. A box with a non-finite coordinate or with low
// above high anywhere is empty: it meets nothing.
struct Box {
  Vec3 low, high;
};

inline bool is_empty(const Box& box) {
  for (int c = 0; c < 3; ++c) {
    if (!(std::isfinite(box.low[c]) && std::isfinite(box.high[c]) && box.low[c] <= box.high[c])) {
      return true;
    }
  }
  return false;
}

// Whether the non-empty boxes `a` and `b` are at most `margin` (>= 0) apart
// along every axis (touching boxes meet for margin 0). Boxes of two
// primitives within distance `margin` of each other always meet.
inline bool boxes_meet(const Box& a, const Box& b, double margin) {
  return a.low[0] - margin <= b.high[0] && b.low[0] - margin <= a.high[0] &&
         a.low[1] - margin <= b.high[1] && b.low[1] - margin <= a.high[1] &&
         a.low[2] - margin <= b.high[2] && b.low[2] - margin <= a.high[2];
}

using IndexPair = std::array<int, 2>;

// A binary tree of boxes, split at the median of the longest axis of the
// box centres, with up to kLeafSize boxes per leaf (a "group" below). Built
// once for a set of boxes, it can be refitted to new boxes of the same
// primitives in linear time: pairs found stay exact, only the search slows
// down when the primitives move far from where they were at the build
// (cost() tells how much). The build depends only on the boxes (ties broken
// by index), never on the thread count.
//
// Searches call visit(i, j) with box indices, in an order that is fixed for a
// given tree but not sorted: callers that need an order sort what they keep
// (sort_index_pairs).
class BoxTree {
 public:
  static constexpr int kLeafSize = 4;

  BoxTree() = default;
  explicit BoxTree(const std::vector<Box>& boxes) { build(boxes); }

  void build(const std::vector<Box>& boxes);
  // New boxes for the same indices as the last build (same count).
  void refit(const std::vector<Box>& boxes);

  int box_count() const { return static_cast<int>(ids_.size()); }
  // Sum of the surface areas of the internal nodes: the expected cost of a
  // search grows with it (compare it after a refit with its value after a
  // build to decide whether to rebuild). 0 for a tree of one leaf.
  double cost() const;

  // Calls visit(j) for every box j that meets `query` within `margin` (none
  // for an empty query).
  template <typename Visit>
  void for_each_meeting(const Box& query, double margin, Visit&& visit) const;

  // The boxes are grouped by leaf: groups [0, group_count()) partition them.
  // Searching group by group spreads a pair search over threads.
  int group_count() const { return static_cast<int>(leaves_.size()); }

  // Calls visit(i, j) for every box i of `group` and box j of `other` that
  // meet within `margin`.
  template <typename Visit>
  void for_each_meeting_pair(int group, const BoxTree& other, double margin, Visit&& visit) const;
  // Calls visit(i, j) for every pair of this tree's own boxes that meet
  // within `margin` and of which i is in `group`, each pair once over all
  // groups (i != j, in no particular order).
  template <typename Visit>
  void for_each_meeting_pair(int group, double margin, Visit&& visit) const;

 private:
  // Nodes in depth-first order: an internal node's left child follows it.
  struct Node {
    Box box;
    int first = 0;  // internal: right child; leaf: first box position
    int count = 0;  // boxes of a leaf, 0 for an internal node
    int end = 0;    // one past the last node of its subtree
  };
  int build_node(int begin, int end, const std::vector<Vec3>& centre);
  void refit_nodes();
  // Calls visit(k) for the position k of every box that meets `query` within
  // `margin` in the nodes of index >= `from`.
  template <typename Visit>
  void search(const Box& query, double margin, int from, Visit&& visit) const;

  std::vector<Node> nodes_;
  std::vector<int> leaves_;  // node index of each group
  std::vector<int> ids_;     // box indices by position (grouped by leaf)
  std::vector<Box> boxes_;   // boxes by position, empty ones made canonical
};

// Sorts pairs by (first, second), given every first index is in [0,
// first_count): a counting sort by first, then each first's few pairs by
// second. Linear in pairs + first_count, and a deterministic order whatever
// order the pairs were found in.
void sort_index_pairs(std::vector<IndexPair>& pairs, int first_count);
// The same for the pairs of all `parts` together (pairs found by several
// threads), into `sorted`, with `start` as scratch: both keep their capacity
// from call to call.
void sort_index_pairs(const std::vector<std::vector<IndexPair>>& parts, int first_count,
                      std::vector<IndexPair>& sorted, std::vector<int>& start);

// Every pair (i, j) of a box i of `a` and a box j of `b` that meet within
// `margin`, sorted. In parallel; the result does not depend on the thread count.
std::vector<IndexPair> meeting_pairs(const BoxTree& a, const BoxTree& b, double margin);
// Every pair (i, j), i < j, of boxes of `tree` that meet within `margin`, sorted.
std::vector<IndexPair> meeting_pairs(const BoxTree& tree, double margin);

// Implementation of the templates.

template <typename Visit>
void BoxTree::search(const Box& query, double margin, int from, Visit&& visit) const {
  if (nodes_.empty()) return;
  int stack[64];  // depth-first: at most one pending right child per level
  int top = 0, node = 0;
  while (true) {
    const Node& n = nodes_[node];
    // A subtree ending before `from` holds no node of index >= from.
    if (n.end > from && boxes_meet(n.box, query, margin)) {
      if (n.count == 0) {
        stack[top++] = n.first;
        ++node;
        continue;
      }
      for (int k = n.first; k < n.first + n.count; ++k) {
        if (boxes_meet(boxes_[k], query, margin)) visit(k);
      }
    }
    if (top == 0) return;
    node = stack[--top];
  }
}

template <typename Visit>
void BoxTree::for_each_meeting(const Box& query, double margin, Visit&& visit) const {
  if (is_empty(query)) return;
  search(query, margin, 0, [&](int k) { visit(ids_[k]); });
}

// One search for a whole leaf, then its few boxes against each box found: the
// boxes of a leaf are close to each other, so that their search is nearly
// the same.
template <typename Visit>
void BoxTree::for_each_meeting_pair(int group, const BoxTree& other, double margin,
                                    Visit&& visit) const {
  const Node& leaf = nodes_[leaves_[group]];
  const int begin = leaf.first, end = leaf.first + leaf.count;
  other.search(leaf.box, margin, 0, [&](int m) {
    const Box& b = other.boxes_[m];
    for (int k = begin; k < end; ++k) {
      if (boxes_meet(boxes_[k], b, margin)) visit(ids_[k], other.ids_[m]);
    }
  });
}

// Box positions grow with the node index of their leaf, so that a pair of
// positions k < m is searched from the leaf of k only: from that leaf on.
template <typename Visit>
void BoxTree::for_each_meeting_pair(int group, double margin, Visit&& visit) const {
  const int node = leaves_[group];
  const Node& leaf = nodes_[node];
  const int begin = leaf.first, end = leaf.first + leaf.count;
  search(leaf.box, margin, node, [&](int m) {
    const Box& b = boxes_[m];
    for (int k = begin; k < end && k < m; ++k) {
      if (boxes_meet(boxes_[k], b, margin)) visit(ids_[k], ids_[m]);
    }
  });
}

}  // namespace foldfill
