// A bounding volume hierarchy over axis-aligned boxes: the one broad phase of
// foldfill (boxes in, index pairs out), for collision candidates and any
// other search for nearby primitives.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

// A closed axis-aligned box (the mesh's Box3). A box with a non-finite
// coordinate or with low above high anywhere is empty: it meets nothing.
using Box = Box3;

// Whether `box` is empty (above).
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
  // One expression without branches: in the trees' searches the outcome is
  // unpredictable, and six short-circuited comparisons mispredict often.
  return (a.low[0] - margin <= b.high[0]) & (b.low[0] - margin <= a.high[0]) &
         (a.low[1] - margin <= b.high[1]) & (b.low[1] - margin <= a.high[1]) &
         (a.low[2] - margin <= b.high[2]) & (b.low[2] - margin <= a.high[2]);
}

using IndexPair = std::array<int, 2>;

// For lists of the pairs of points (or of primitives over them) nearer than
// some reach at `anchor` (a "Verlet list"): the most any two of them can
// have come closer since, where the points are 3 doubles each, those of
// [first, end) moved to `points` and the others stayed (their displacement,
// 0, is in the set). With `move` (3 doubles per point, read in [first,
// end)), along the step from `points` by `move` as well: a difference of
// displacements is convex along it, so its ends are enough. A pair comes
// closer by at most the difference of its corners' displacements, and those
// differ by at most the set's diameter: bounded by twice its largest
// displacement and by twice its radius about the centre of its box,
// whichever is less (about one largest displacement where the points move
// in one direction, instead of two). +infinity where a displacement is not
// finite.
double closing_bound(const double* points, const double* anchor, size_t first, size_t end,
                     const double* move = nullptr);

// A binary tree of boxes, split at the median of the longest axis of the
// box centres, with up to kLeafSize boxes per leaf. Built once for a set of
// boxes, it can be refitted to new boxes of the same primitives in linear
// time: pairs found stay exact, only the search slows down when the
// primitives move far from where they were at the build (cost() tells how
// much). The build depends only on the boxes (ties broken by index), never
// on the thread count.
//
// Pair searches descend two trees (or one tree and itself) together, so that
// a pair of far-apart subtrees is dismissed at once. They call visit(i, j)
// with box indices, in an order that is fixed for given trees but not
// sorted: callers that need an order sort what they keep (sort_index_pairs).
class BoxTree {
 public:
  static constexpr int kLeafSize = 8;
  static_assert(kLeafSize <= 32, "a leaf's meeting boxes are the bits of one unsigned");

  BoxTree() = default;
  explicit BoxTree(const std::vector<Box>& boxes) { build(boxes); }

  void build(const std::vector<Box>& boxes);
  // The tree of `boxes` in the order `order` (a permutation of their
  // indices), each node halving its range of it, with no sorting: linear
  // time. Its searches are as fast as the order is spatially coherent, as
  // the leaf order of a tree of nearby primitives is (the faces' for their
  // corners and edges).
  void build_in_order(const std::vector<Box>& boxes, const std::vector<int>& order);
  // The box indices in the order of the leaves.
  const std::vector<int>& leaf_order() const { return ids_; }
  // New boxes for the same indices as the last build (same count; throws
  // InternalError otherwise).
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

  // Calls visit(i, j) for every box i of this tree and box j of `other` that
  // meet within `margin`.
  template <typename Visit>
  void for_each_meeting_pair(const BoxTree& other, double margin, Visit&& visit) const;
  // Calls visit(i, j) for every pair of this tree's own boxes that meet
  // within `margin`, each pair once (i != j, either way round).
  template <typename Visit>
  void for_each_meeting_pair(double margin, Visit&& visit) const;

  // The same searches split into independent parts for threads: the parts
  // of split_search (about `count` of them, fewer for small trees) visit
  // every pair of the whole search once between them.
  struct SearchPart {
    int a = 0, b = 0;  // node indices; a == b: the pairs within one subtree
  };
  std::vector<SearchPart> split_search(const BoxTree& other, double margin, int count) const;
  std::vector<SearchPart> split_search(double margin, int count) const;
  template <typename Visit>
  void for_each_meeting_pair(const SearchPart& part, const BoxTree& other, double margin,
                             Visit&& visit) const;
  template <typename Visit>
  void for_each_meeting_pair(const SearchPart& part, double margin, Visit&& visit) const;

 private:
  // Nodes in depth-first order: an internal node's left child follows it.
  struct Node {
    Box box;
    int first = 0;  // internal: right child; leaf: first box position
    int count = 0;  // boxes of a leaf, 0 for an internal node
  };
  struct Placement;
  void build_node(Placement* placement, int begin, int end);
  void refit_nodes();
  // Whether the pair search of nodes i (here) and j (of `other`) goes on in
  // i's children rather than j's.
  bool descend_first(const BoxTree& other, int i, int j) const;
  template <typename Visit>
  void cross(const BoxTree& other, int i, int j, double margin, Visit& visit) const;
  template <typename Visit>
  void within(int i, double margin, Visit& visit) const;

  std::vector<Node> nodes_;
  std::vector<int> ids_;    // box indices by position (grouped by leaf)
  std::vector<Box> boxes_;  // boxes by position, empty ones made canonical
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
void BoxTree::for_each_meeting(const Box& query, double margin, Visit&& visit) const {
  if (nodes_.empty() || is_empty(query)) return;
  int stack[64];  // depth-first: at most one pending right child per level
  int top = 0, node = 0;
  while (true) {
    const Node& n = nodes_[node];
    if (boxes_meet(n.box, query, margin)) {
      if (n.count == 0) {
        stack[top++] = n.first;
        ++node;
        continue;
      }
      for (int k = n.first; k < n.first + n.count; ++k) {
        if (boxes_meet(boxes_[k], query, margin)) visit(ids_[k]);
      }
    }
    if (top == 0) return;
    node = stack[--top];
  }
}

inline bool BoxTree::descend_first(const BoxTree& other, int i, int j) const {
  const Node &a = nodes_[i], &b = other.nodes_[j];
  if (a.count > 0 || b.count > 0) return b.count > 0;
  const auto size = [](const Box& box) {
    return box.high[0] - box.low[0] + box.high[1] - box.low[1] + box.high[2] - box.low[2];
  };
  return size(a.box) >= size(b.box);
}

// Two leaves: each box of i against j's box first, then against j's boxes.
// Otherwise the larger node (or the internal one) is split.
template <typename Visit>
void BoxTree::cross(const BoxTree& other, int i, int j, double margin, Visit& visit) const {
  const Node &a = nodes_[i], &b = other.nodes_[j];
  if (!boxes_meet(a.box, b.box, margin)) return;
  if (a.count > 0 && b.count > 0) {
    for (int k = a.first; k < a.first + a.count; ++k) {
      const Box& box = boxes_[k];
      if (!boxes_meet(box, b.box, margin)) continue;
      // The leaf's meeting boxes as bits, then visited in order: the tests
      // run without a branch per box.
      unsigned meets = 0;
      for (int m = 0; m < b.count; ++m)
        meets |= unsigned(boxes_meet(box, other.boxes_[b.first + m], margin)) << m;
      while (meets) {
        const int m = __builtin_ctz(meets);
        meets &= meets - 1;
        visit(ids_[k], other.ids_[b.first + m]);
      }
    }
  } else if (descend_first(other, i, j)) {
    cross(other, i + 1, j, margin, visit);
    cross(other, a.first, j, margin, visit);
  } else {
    cross(other, i, j + 1, margin, visit);
    cross(other, i, b.first, margin, visit);
  }
}

template <typename Visit>
void BoxTree::within(int i, double margin, Visit& visit) const {
  const Node& n = nodes_[i];
  if (n.count > 0) {
    for (int k = n.first; k < n.first + n.count; ++k) {
      for (int m = k + 1; m < n.first + n.count; ++m) {
        if (boxes_meet(boxes_[k], boxes_[m], margin)) visit(ids_[k], ids_[m]);
      }
    }
    return;
  }
  within(i + 1, margin, visit);
  within(n.first, margin, visit);
  cross(*this, i + 1, n.first, margin, visit);
}

template <typename Visit>
void BoxTree::for_each_meeting_pair(const BoxTree& other, double margin, Visit&& visit) const {
  if (!nodes_.empty() && !other.nodes_.empty()) cross(other, 0, 0, margin, visit);
}

template <typename Visit>
void BoxTree::for_each_meeting_pair(double margin, Visit&& visit) const {
  if (!nodes_.empty()) within(0, margin, visit);
}

template <typename Visit>
void BoxTree::for_each_meeting_pair(const SearchPart& part, const BoxTree& other, double margin,
                                    Visit&& visit) const {
  cross(other, part.a, part.b, margin, visit);
}

template <typename Visit>
void BoxTree::for_each_meeting_pair(const SearchPart& part, double margin, Visit&& visit) const {
  if (part.a == part.b) {
    within(part.a, margin, visit);
  } else {
    cross(*this, part.a, part.b, margin, visit);
  }
}

}  // namespace foldfill
