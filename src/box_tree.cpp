// The box tree's build and refit (median splits, depth-first node order), and
// the sorted pair lists built on its searches.
#include "foldfill/box_tree.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "foldfill/error.h"

namespace foldfill {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// One empty box for all: low above high everywhere, so that it meets nothing
// and leaves the box of a node that holds it unchanged.
Box canonical(const Box& box) {
  if (!is_empty(box)) return box;
  return {{kInfinity, kInfinity, kInfinity}, {-kInfinity, -kInfinity, -kInfinity}};
}

void extend(Box& box, const Box& other) {
  for (int c = 0; c < 3; ++c) {
    box.low[c] = std::min(box.low[c], other.low[c]);
    box.high[c] = std::max(box.high[c], other.high[c]);
  }
}

}  // namespace

void BoxTree::build(const std::vector<Box>& boxes) {
  const int n = static_cast<int>(boxes.size());
  nodes_.clear();
  leaves_.clear();
  ids_.resize(n);
  boxes_.resize(n);
  if (n == 0) return;
  // Empty boxes get an infinite centre: they gather at the end of the order.
  std::vector<Vec3> centre(n);
  for (int i = 0; i < n; ++i) {
    ids_[i] = i;
    const Box& box = boxes[i];
    for (int c = 0; c < 3; ++c) {
      centre[i][c] = is_empty(box) ? kInfinity : 0.5 * box.low[c] + 0.5 * box.high[c];
    }
  }
  nodes_.reserve(2 * (n / (kLeafSize / 2) + 1));
  build_node(0, n, centre);
  for (int k = 0; k < n; ++k) boxes_[k] = canonical(boxes[ids_[k]]);
  refit_nodes();
}

// The node of ids_[begin, end): a leaf for a few boxes, else split at the
// median of the centres along the axis where they spread most (ties by box
// index, so that the split is unique). Returns its index.
int BoxTree::build_node(int begin, int end, const std::vector<Vec3>& centre) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kLeafSize) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    nodes_[index].end = index + 1;
    leaves_.push_back(index);
    return index;
  }
  double low[3] = {kInfinity, kInfinity, kInfinity}, high[3] = {-kInfinity, -kInfinity, -kInfinity};
  for (int k = begin; k < end; ++k) {
    const Vec3& c = centre[ids_[k]];
    if (!std::isfinite(c[0])) continue;
    for (int a = 0; a < 3; ++a) {
      low[a] = std::min(low[a], c[a]);
      high[a] = std::max(high[a], c[a]);
    }
  }
  int axis = 0;
  for (int a = 1; a < 3; ++a) {
    if (high[a] - low[a] > high[axis] - low[axis]) axis = a;
  }
  const int mid = begin + (end - begin) / 2;
  std::nth_element(ids_.begin() + begin, ids_.begin() + mid, ids_.begin() + end, [&](int i, int j) {
    const double ci = centre[i][axis], cj = centre[j][axis];
    return ci < cj || (ci == cj && i < j);
  });
  build_node(begin, mid, centre);
  const int right = build_node(mid, end, centre);
  nodes_[index].first = right;
  nodes_[index].end = static_cast<int>(nodes_.size());
  return index;
}

// Children follow their parent: one backward pass sets every node's box.
void BoxTree::refit_nodes() {
  for (int i = static_cast<int>(nodes_.size()) - 1; i >= 0; --i) {
    Node& node = nodes_[i];
    if (node.count > 0) {
      node.box = boxes_[node.first];
      for (int k = node.first + 1; k < node.first + node.count; ++k) extend(node.box, boxes_[k]);
    } else {
      node.box = nodes_[i + 1].box;
      extend(node.box, nodes_[node.first].box);
    }
  }
}

void BoxTree::refit(const std::vector<Box>& boxes) {
  if (boxes.size() != ids_.size()) {
    throw Error(ErrorKind::Internal, "box tree: refit with a different number of boxes");
  }
  for (size_t k = 0; k < ids_.size(); ++k) boxes_[k] = canonical(boxes[ids_[k]]);
  refit_nodes();
}

double BoxTree::cost() const {
  double sum = 0;
  for (const Node& node : nodes_) {
    if (node.count > 0 || is_empty(node.box)) continue;
    const double x = node.box.high[0] - node.box.low[0], y = node.box.high[1] - node.box.low[1],
                 z = node.box.high[2] - node.box.low[2];
    sum += 2 * (x * y + y * z + z * x);
  }
  return sum;
}

void sort_index_pairs(const std::vector<std::vector<IndexPair>>& parts, int first_count,
                      std::vector<IndexPair>& sorted, std::vector<int>& start) {
  start.assign(static_cast<size_t>(first_count) + 1, 0);
  size_t total = 0;
  for (const auto& part : parts) {
    total += part.size();
    for (const IndexPair& pair : part) ++start[pair[0] + 1];
  }
  for (int i = 0; i < first_count; ++i) start[i + 1] += start[i];
  sorted.resize(total);
  for (const auto& part : parts) {
    for (const IndexPair& pair : part) sorted[start[pair[0]]++] = pair;
  }
  // start[i] is now the end of first i's pairs, the start of first i + 1's.
  int begin = 0;
  for (int i = 0; i < first_count; ++i) {
    const int end = start[i];
    if (end - begin > 1) {
      // Few pairs per first: insertion sort by second.
      for (int k = begin + 1; k < end; ++k) {
        const IndexPair pair = sorted[k];
        int m = k;
        for (; m > begin && sorted[m - 1][1] > pair[1]; --m) sorted[m] = sorted[m - 1];
        sorted[m] = pair;
      }
    }
    begin = end;
  }
}

void sort_index_pairs(std::vector<IndexPair>& pairs, int first_count) {
  std::vector<std::vector<IndexPair>> parts(1);
  parts[0].swap(pairs);
  std::vector<int> start;
  sort_index_pairs(parts, first_count, pairs, start);
}

namespace {

// Pairs found group by group over threads, each thread into its own list,
// then sorted: the order the threads found them in does not matter.
template <typename Search>
std::vector<IndexPair> collect_sorted(int groups, int first_count, const Search& search) {
  std::vector<std::vector<IndexPair>> parts(omp_get_max_threads());
#pragma omp parallel
  {
    std::vector<IndexPair>& part = parts[omp_get_thread_num()];
#pragma omp for schedule(dynamic, 16)
    for (int g = 0; g < groups; ++g) search(g, part);
  }
  std::vector<IndexPair> sorted;
  std::vector<int> start;
  sort_index_pairs(parts, first_count, sorted, start);
  return sorted;
}

}  // namespace

std::vector<IndexPair> meeting_pairs(const BoxTree& a, const BoxTree& b, double margin) {
  return collect_sorted(a.group_count(), a.box_count(), [&](int g, std::vector<IndexPair>& out) {
    a.for_each_meeting_pair(g, b, margin, [&](int i, int j) { out.push_back({i, j}); });
  });
}

std::vector<IndexPair> meeting_pairs(const BoxTree& tree, double margin) {
  return collect_sorted(tree.group_count(), tree.box_count(),
                        [&](int g, std::vector<IndexPair>& out) {
                          tree.for_each_meeting_pair(g, margin, [&](int i, int j) {
                            out.push_back({std::min(i, j), std::max(i, j)});
                          });
                        });
}

}  // namespace foldfill
