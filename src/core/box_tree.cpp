// The box tree's build and refit (median splits, depth-first node order), and
// the sorted pair lists built on its searches.
#include "foldfill/box_tree.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
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

// The boxes being placed: their centres as floats, axis by axis (infinite
// for an empty box, so that empty boxes gather at the end of the order), and
// the sort keys of a node's boxes along its split axis: the centre's bits in
// an order-preserving form above the box index, so that one integer
// comparison orders by centre and breaks ties by index. Floats are enough:
// the split only shapes the tree, never which pairs a search finds.
struct BoxTree::Placement {
  std::vector<float> centre[3];
  std::vector<uint64_t> keys, scratch;
};

namespace {

// The bits of `f` as an unsigned integer in the same order as the floats.
uint32_t ordered_bits(float f) {
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  return bits & 0x80000000u ? ~bits : bits | 0x80000000u;
}

// Puts the key that sorted order would put at `nth` there, the smaller ones
// before it and the larger after, like std::nth_element on distinct keys
// (quickselect, median-of-three pivots), with a partition without branches
// on the keys: a tree's centres come in no useful order and a branch per
// key would mispredict half the time. `scratch` holds at least as many.
void select_nth(uint64_t* keys, int nth, int count, uint64_t* scratch) {
  int begin = 0, end = count, rounds = 0;
  while (end - begin > 16) {
    if (++rounds > 64) {  // a pathological order: std::nth_element's guarantee
      std::nth_element(keys + begin, keys + nth, keys + end);
      return;
    }
    const uint64_t a = keys[begin], b = keys[begin + (end - begin) / 2], c = keys[end - 1];
    const uint64_t pivot = std::max(std::min(a, b), std::min(std::max(a, b), c));
    int low = 0, high = end - begin - 1;
    for (int k = begin; k < end; ++k) {
      const uint64_t key = keys[k];
      const int below = key < pivot;
      // Both free ends receive the key; the one it does not belong to stays
      // free and is written again later.
      scratch[low] = key;
      scratch[high] = key;
      low += below;
      high -= 1 - below;
    }
    std::copy(scratch, scratch + (end - begin), keys + begin);
    const int split = begin + low;  // keys[split] is the pivot's or above
    if (nth < split) {
      end = split;
    } else {
      begin = split;
    }
  }
  std::sort(keys + begin, keys + end);
}

}  // namespace

void BoxTree::build(const std::vector<Box>& boxes) {
  const int n = static_cast<int>(boxes.size());
  nodes_.clear();
  ids_.resize(n);
  boxes_.resize(n);
  if (n == 0) return;
  Placement placement;
  for (int c = 0; c < 3; ++c) placement.centre[c].resize(n);
  placement.keys.resize(n);
  placement.scratch.resize(n);
  for (int i = 0; i < n; ++i) {
    const Box& box = boxes[i];
    const bool empty = is_empty(box);
    for (int c = 0; c < 3; ++c)
      placement.centre[c][i] = empty ? std::numeric_limits<float>::infinity()
                                     : static_cast<float>(0.5 * box.low[c] + 0.5 * box.high[c]);
    ids_[i] = i;
  }
  nodes_.reserve(2 * (n / (kLeafSize / 2) + 1));
  build_node(&placement, 0, n);
  for (int k = 0; k < n; ++k) boxes_[k] = canonical(boxes[ids_[k]]);
  refit_nodes();
}

// The node of boxes [begin, end) of ids_: a leaf for a few boxes, else its
// two halves; with `placement`, first ordered so that they split at the
// median of the centres along the axis where they spread most (ties by box
// index, so that the split is unique), without it in the order they are.
void BoxTree::build_node(Placement* placement, int begin, int end) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kLeafSize) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return;
  }
  const int mid = begin + (end - begin) / 2;
  if (placement) {
    float low[3], high[3];
    for (int a = 0; a < 3; ++a) {
      low[a] = std::numeric_limits<float>::infinity();
      high[a] = -std::numeric_limits<float>::infinity();
    }
    for (int k = begin; k < end; ++k) {
      const int id = ids_[k];
      if (!std::isfinite(placement->centre[0][id])) continue;
      for (int a = 0; a < 3; ++a) {
        low[a] = std::min(low[a], placement->centre[a][id]);
        high[a] = std::max(high[a], placement->centre[a][id]);
      }
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a) {
      if (high[a] - low[a] > high[axis] - low[axis]) axis = a;
    }
    const float* centre = placement->centre[axis].data();
    uint64_t* keys = placement->keys.data();
    for (int k = begin; k < end; ++k)
      keys[k] = uint64_t{ordered_bits(centre[ids_[k]])} << 32 | static_cast<uint32_t>(ids_[k]);
    select_nth(keys + begin, mid - begin, end - begin, placement->scratch.data());
    for (int k = begin; k < end; ++k) ids_[k] = static_cast<int>(keys[k] & 0xffffffffu);
  }
  build_node(placement, begin, mid);
  nodes_[index].first = static_cast<int>(nodes_.size());
  build_node(placement, mid, end);
}

void BoxTree::build_in_order(const std::vector<Box>& boxes, const std::vector<int>& order) {
  const int n = static_cast<int>(boxes.size());
  if (static_cast<int>(order.size()) != n)
    throw InternalError("box tree: an order of another number of boxes");
  std::vector<char> seen(n, 0);
  for (int id : order) {
    if (id < 0 || id >= n || seen[id])
      throw InternalError("box tree: an order that is not a permutation");
    seen[id] = 1;
  }
  nodes_.clear();
  ids_ = order;
  boxes_.resize(n);
  if (n == 0) return;
  for (int k = 0; k < n; ++k) boxes_[k] = canonical(boxes[ids_[k]]);
  nodes_.reserve(2 * (n / (kLeafSize / 2) + 1));
  build_node(nullptr, 0, n);
  refit_nodes();
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
    throw InternalError("box tree: refit with a different number of boxes");
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

std::vector<BoxTree::SearchPart> BoxTree::split_search(const BoxTree& other, double margin,
                                                       int count) const {
  std::vector<SearchPart> parts, next;
  if (nodes_.empty() || other.nodes_.empty()) return parts;
  parts.push_back({0, 0});
  // Split every part one level down until there are enough.
  while (static_cast<int>(parts.size()) < count) {
    next.clear();
    bool split = false;
    for (const SearchPart& part : parts) {
      const Node &a = nodes_[part.a], &b = other.nodes_[part.b];
      if (!boxes_meet(a.box, b.box, margin)) continue;
      if (a.count > 0 && b.count > 0) {
        next.push_back(part);
      } else if (descend_first(other, part.a, part.b)) {
        next.push_back({part.a + 1, part.b});
        next.push_back({a.first, part.b});
        split = true;
      } else {
        next.push_back({part.a, part.b + 1});
        next.push_back({part.a, b.first});
        split = true;
      }
    }
    parts.swap(next);
    if (!split) break;
  }
  return parts;
}

std::vector<BoxTree::SearchPart> BoxTree::split_search(double margin, int count) const {
  std::vector<SearchPart> parts, next;
  if (nodes_.empty()) return parts;
  parts.push_back({0, 0});
  while (static_cast<int>(parts.size()) < count) {
    next.clear();
    bool split = false;
    for (const SearchPart& part : parts) {
      const Node &a = nodes_[part.a], &b = nodes_[part.b];
      if (part.a == part.b) {
        if (a.count > 0) {
          next.push_back(part);
        } else {
          next.push_back({part.a + 1, part.a + 1});
          next.push_back({a.first, a.first});
          next.push_back({part.a + 1, a.first});
          split = true;
        }
      } else if (!boxes_meet(a.box, b.box, margin)) {
        continue;
      } else if (a.count > 0 && b.count > 0) {
        next.push_back(part);
      } else if (descend_first(*this, part.a, part.b)) {
        next.push_back({part.a + 1, part.b});
        next.push_back({a.first, part.b});
        split = true;
      } else {
        next.push_back({part.a, part.b + 1});
        next.push_back({part.a, b.first});
        split = true;
      }
    }
    parts.swap(next);
    if (!split) break;
  }
  return parts;
}

namespace {

// Parts of a search per thread: enough for an even share of the work.
constexpr int kPartsPerThread = 32;

// Pairs found part by part over threads, each thread into its own list, then
// sorted: the order the threads found them in does not matter.
template <typename Search>
std::vector<IndexPair> collect_sorted(int parts, int first_count, const Search& search) {
  std::vector<std::vector<IndexPair>> found(omp_get_max_threads());
#pragma omp parallel
  {
    std::vector<IndexPair>& part = found[omp_get_thread_num()];
#pragma omp for schedule(dynamic, 1)
    for (int p = 0; p < parts; ++p) search(p, part);
  }
  std::vector<IndexPair> sorted;
  std::vector<int> start;
  sort_index_pairs(found, first_count, sorted, start);
  return sorted;
}

}  // namespace

std::vector<IndexPair> meeting_pairs(const BoxTree& a, const BoxTree& b, double margin) {
  const auto parts = a.split_search(b, margin, kPartsPerThread * omp_get_max_threads());
  return collect_sorted(
      static_cast<int>(parts.size()), a.box_count(), [&](int p, std::vector<IndexPair>& out) {
        a.for_each_meeting_pair(parts[p], b, margin, [&](int i, int j) { out.push_back({i, j}); });
      });
}

std::vector<IndexPair> meeting_pairs(const BoxTree& tree, double margin) {
  const auto parts = tree.split_search(margin, kPartsPerThread * omp_get_max_threads());
  return collect_sorted(static_cast<int>(parts.size()), tree.box_count(),
                        [&](int p, std::vector<IndexPair>& out) {
                          tree.for_each_meeting_pair(parts[p], margin, [&](int i, int j) {
                            out.push_back({std::min(i, j), std::max(i, j)});
                          });
                        });
}

double closing_bound(const double* points, const double* anchor, size_t first, size_t end,
                     const double* move) {
  // Calls visit(dx, dy, dz) for each moved point's displacement, and with
  // `move` for its displacement at the step's end too.
  const auto for_each_displacement = [&](const auto& visit) {
    for (size_t k = 3 * first; k < 3 * end; k += 3) {
      const double dx = points[k] - anchor[k], dy = points[k + 1] - anchor[k + 1],
                   dz = points[k + 2] - anchor[k + 2];
      visit(dx, dy, dz);
      if (move) visit(dx + move[k], dy + move[k + 1], dz + move[k + 2]);
    }
  };
  double drift = 0;
  double low[3] = {0, 0, 0}, high[3] = {0, 0, 0};
  bool finite = true;
  for_each_displacement([&](double x, double y, double z) {
    finite &= std::isfinite(x) && std::isfinite(y) && std::isfinite(z);
    drift = std::max(drift, x * x + y * y + z * z);
    low[0] = std::min(low[0], x), high[0] = std::max(high[0], x);
    low[1] = std::min(low[1], y), high[1] = std::max(high[1], y);
    low[2] = std::min(low[2], z), high[2] = std::max(high[2], z);
  });
  if (!finite) return std::numeric_limits<double>::infinity();
  const double centre[3] = {0.5 * (low[0] + high[0]), 0.5 * (low[1] + high[1]),
                            0.5 * (low[2] + high[2])};
  double radius = centre[0] * centre[0] + centre[1] * centre[1] + centre[2] * centre[2];
  for_each_displacement([&](double x, double y, double z) {
    x -= centre[0], y -= centre[1], z -= centre[2];
    radius = std::max(radius, x * x + y * y + z * z);
  });
  return 2 * std::sqrt(std::min(drift, radius));
}

}  // namespace foldfill
