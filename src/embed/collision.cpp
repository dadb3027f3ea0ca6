// The collision mesh, the broad phase that finds its candidate pairs with box
// trees, and the barrier potential summed over the candidates.
#include "foldfill/collision.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "foldfill/error.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

// A moving tree whose cost has grown past this factor of its cost when built
// is rebuilt: a rebuild costs about as much as a few searches.
constexpr double kRebuildFactor = 2;

// Free vertices below which a search is not worth spreading over threads.
// Below this many free vertices a search runs on one thread: the threads of
// a parallel region would mostly wait for each other (and spin, with
// libgomp's default wait policy).
constexpr int kSmallestParallelSearch = 5000;
// Parts of each search per thread: enough for an even share of the work.
constexpr int kPartsPerThread = 32;

const double* at(const double* array, int v) { return array + 3 * static_cast<ptrdiff_t>(v); }

// The box of vertices `v` at `x`, and at x + dx too when `dx` is non-null.
template <int N>
Box box_of(const int (&v)[N], const double* x, const double* dx) {
  Box box;
  const double* p = at(x, v[0]);
  for (int c = 0; c < 3; ++c) box.low[c] = box.high[c] = p[c];
  const auto add = [&](const double* q) {
    for (int c = 0; c < 3; ++c) {
      box.low[c] = std::min(box.low[c], q[c]);
      box.high[c] = std::max(box.high[c], q[c]);
    }
  };
  for (int k = 1; k < N; ++k) add(at(x, v[k]));
  if (dx) {
    for (int k = 0; k < N; ++k) {
      const double *p0 = at(x, v[k]), *d = at(dx, v[k]);
      const double q[3] = {p0[0] + d[0], p0[1] + d[1], p0[2] + d[2]};
      add(q);
    }
  }
  return box;
}

Box point_box(int v, const double* x, const double* dx) {
  const int corners[1] = {v};
  return box_of(corners, x, dx);
}
Box edge_box(const std::array<int, 2>& e, const double* x, const double* dx) {
  const int corners[2] = {e[0], e[1]};
  return box_of(corners, x, dx);
}
Box face_box(const Tri& f, const double* x, const double* dx) {
  const int corners[3] = {f[0], f[1], f[2]};
  return box_of(corners, x, dx);
}

bool has_vertex(const Tri& f, int v) { return f[0] == v || f[1] == v || f[2] == v; }
bool share_vertex(const std::array<int, 2>& e, const std::array<int, 2>& g) {
  return e[0] == g[0] || e[0] == g[1] || e[1] == g[0] || e[1] == g[1];
}

}  // namespace

CollisionMesh make_collision_mesh(const std::vector<Tri>& faces, int vertex_count,
                                  int fixed_count) {
  if (fixed_count < 0 || fixed_count > vertex_count) {
    throw InternalError("collision mesh: fixed_count outside [0, vertex_count]");
  }
  CollisionMesh mesh;
  mesh.faces = faces;
  mesh.vertex_count = vertex_count;
  mesh.fixed_count = fixed_count;
  mesh.edges.reserve(3 * faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = faces[f][k], b = faces[f][(k + 1) % 3];
      if (a < 0 || a >= vertex_count) {
        throw InternalError("collision mesh: face " + std::to_string(f) + " out of range");
      }
      if (a != b) mesh.edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  sort_index_pairs(mesh.edges, vertex_count);
  mesh.edges.erase(std::unique(mesh.edges.begin(), mesh.edges.end()), mesh.edges.end());
  return mesh;
}

CollisionBroadPhase::CollisionBroadPhase(const CollisionMesh& mesh, const double* positions)
    : mesh_(mesh) {
  const int fixed = mesh_.fixed_count;
  for (int e = 0; e < static_cast<int>(mesh_.edges.size()); ++e) {
    const auto& edge = mesh_.edges[e];
    (std::max(edge[0], edge[1]) < fixed ? static_edges_ : moving_edges_).push_back(e);
  }
  for (int f = 0; f < static_cast<int>(mesh_.faces.size()); ++f) {
    const Tri& face = mesh_.faces[f];
    (std::max({face[0], face[1], face[2]}) < fixed ? static_faces_ : moving_faces_).push_back(f);
  }
  std::vector<Box> points, edges, faces;
  for (int v = 0; v < fixed; ++v) points.push_back(point_box(v, positions, nullptr));
  for (int e : static_edges_) edges.push_back(edge_box(mesh_.edges[e], positions, nullptr));
  for (int f : static_faces_) faces.push_back(face_box(mesh_.faces[f], positions, nullptr));
  // The static faces' tree is built; the static points' and edges' follow
  // its leaf order (static_order), in linear time. The moving trees are
  // built at the first search, where the free vertices are placed.
  static_face_tree_.build(faces);
  std::vector<int> point_order, edge_order;
  static_order(point_order, edge_order);
  static_points_.build_in_order(points, point_order);
  static_edge_tree_.build_in_order(edges, edge_order);
}

// The fixed vertices in the order the static faces' leaves first reach
// them (those of no static face last, ascending), and the static edges by
// the first of their corners in that order (ties ascending): orders as
// coherent as the faces' tree.
void CollisionBroadPhase::static_order(std::vector<int>& points, std::vector<int>& edges) const {
  const int fixed = mesh_.fixed_count;
  std::vector<int> rank(fixed, -1);
  points.clear();
  points.reserve(fixed);
  for (int k : static_face_tree_.leaf_order())
    for (int v : mesh_.faces[static_faces_[k]])
      if (rank[v] < 0) {
        rank[v] = static_cast<int>(points.size());
        points.push_back(v);
      }
  for (int v = 0; v < fixed; ++v)
    if (rank[v] < 0) {
      rank[v] = static_cast<int>(points.size());
      points.push_back(v);
    }
  // A counting sort of the static edges by their first corner's rank.
  std::vector<int> start(fixed + 1, 0);
  const int count = static_cast<int>(static_edges_.size());
  const auto key = [&](int k) {
    const auto& e = mesh_.edges[static_edges_[k]];
    return std::min(rank[e[0]], rank[e[1]]);
  };
  for (int k = 0; k < count; ++k) ++start[key(k) + 1];
  for (int r = 0; r < fixed; ++r) start[r + 1] += start[r];
  edges.assign(count, 0);
  for (int k = 0; k < count; ++k) edges[start[key(k)]++] = k;
}

void CollisionBroadPhase::moving_boxes(const double* positions, const double* displacements) {
  const int fixed = mesh_.fixed_count, n = mesh_.vertex_count;
  point_boxes_.resize(n - fixed);
  edge_boxes_.resize(moving_edges_.size());
  face_boxes_.resize(moving_faces_.size());
  // Fixed vertices keep their place whatever `displacements` says.
  const auto swept = [&](const auto& corners) -> Box {
    if (!displacements) return box_of(corners, positions, nullptr);
    Box box = box_of(corners, positions, displacements);
    bool any_fixed = false;
    for (int v : corners) any_fixed |= v < fixed;
    if (!any_fixed) return box;
    // Rare: a primitive with fixed corners; only its free corners sweep.
    box = box_of(corners, positions, nullptr);
    for (int v : corners) {
      if (v < fixed) continue;
      const double *p = at(positions, v), *d = at(displacements, v);
      for (int c = 0; c < 3; ++c) {
        box.low[c] = std::min(box.low[c], p[c] + d[c]);
        box.high[c] = std::max(box.high[c], p[c] + d[c]);
      }
    }
    return box;
  };
  for (int v = fixed; v < n; ++v) {
    const int corners[1] = {v};
    point_boxes_[v - fixed] = swept(corners);
  }
  for (size_t k = 0; k < moving_edges_.size(); ++k) {
    const auto& e = mesh_.edges[moving_edges_[k]];
    const int corners[2] = {e[0], e[1]};
    edge_boxes_[k] = swept(corners);
  }
  for (size_t k = 0; k < moving_faces_.size(); ++k) {
    const Tri& f = mesh_.faces[moving_faces_[k]];
    const int corners[3] = {f[0], f[1], f[2]};
    face_boxes_[k] = swept(corners);
  }
}

void CollisionBroadPhase::update_trees() {
  BoxTree* trees[3] = {&moving_points_, &moving_edge_tree_, &moving_face_tree_};
  const std::vector<Box>* boxes[3] = {&point_boxes_, &edge_boxes_, &face_boxes_};
  bool rebuild[3];
  for (int k = 0; k < 3; ++k) {
    rebuild[k] = !moving_built_;
    if (rebuild[k]) continue;
    trees[k]->refit(*boxes[k]);
    rebuild[k] = trees[k]->cost() > kRebuildFactor * built_cost_[k];
  }
  moving_built_ = true;
#pragma omp parallel for schedule(dynamic, 1) if (rebuild[0] + rebuild[1] + rebuild[2] > 1)
  for (int k = 0; k < 3; ++k) {
    if (!rebuild[k]) continue;
    trees[k]->build(*boxes[k]);
    built_cost_[k] = trees[k]->cost();
  }
}

// Five searches, each split into parts spread over threads: moving points
// against the static and the moving faces, moving faces against the static
// points, moving edges against the static and the moving edges. Each pair is
// found once, kept when `keep_pt(vertex, face)` / `keep_ee(edge, edge)` say
// so, then all are sorted.
template <typename KeepPointTriangle, typename KeepEdgeEdge>
void CollisionBroadPhase::search(const double* positions, const double* displacements,
                                 double distance, const KeepPointTriangle& keep_pt,
                                 const KeepEdgeEdge& keep_ee, CollisionCandidates& candidates) {
  moving_boxes(positions, displacements);
  update_trees();
  const int threads = omp_get_max_threads();
  point_triangle_parts_.resize(threads);
  edge_edge_parts_.resize(threads);
  for (auto& part : point_triangle_parts_) part.clear();
  for (auto& part : edge_edge_parts_) part.clear();

  const int count = kPartsPerThread * threads;
  parts_[0] = moving_points_.split_search(static_face_tree_, distance, count);
  parts_[1] = moving_points_.split_search(moving_face_tree_, distance, count);
  parts_[2] = moving_face_tree_.split_search(static_points_, distance, count);
  parts_[3] = moving_edge_tree_.split_search(static_edge_tree_, distance, count);
  parts_[4] = moving_edge_tree_.split_search(distance, count);
  work_.clear();
  for (int search = 0; search < 5; ++search) {
    for (int k = 0; k < static_cast<int>(parts_[search].size()); ++k) work_.push_back({search, k});
  }
  const int fixed = mesh_.fixed_count;
  const int total = static_cast<int>(work_.size());
  const bool parallel = mesh_.vertex_count - fixed >= kSmallestParallelSearch;
#pragma omp parallel if (parallel)
  {
    std::vector<IndexPair>& pt = point_triangle_parts_[omp_get_thread_num()];
    std::vector<IndexPair>& ee = edge_edge_parts_[omp_get_thread_num()];
    const auto& faces = mesh_.faces;
    const auto& edges = mesh_.edges;
    const auto point_face = [&](int v, int face) {
      if (!has_vertex(faces[face], v) && keep_pt(v, face)) pt.push_back({v, face});
    };
    const auto edge_pair = [&](int e, int h) {
      if (!share_vertex(edges[e], edges[h]) && keep_ee(e, h)) {
        ee.push_back({std::min(e, h), std::max(e, h)});
      }
    };
#pragma omp for schedule(dynamic, 1)
    for (int item = 0; item < total; ++item) {
      const BoxTree::SearchPart& part = parts_[work_[item][0]][work_[item][1]];
      switch (work_[item][0]) {
        case 0:
          moving_points_.for_each_meeting_pair(
              part, static_face_tree_, distance,
              [&](int p, int f) { point_face(fixed + p, static_faces_[f]); });
          break;
        case 1:
          moving_points_.for_each_meeting_pair(
              part, moving_face_tree_, distance,
              [&](int p, int f) { point_face(fixed + p, moving_faces_[f]); });
          break;
        case 2:
          moving_face_tree_.for_each_meeting_pair(
              part, static_points_, distance,
              [&](int f, int v) { point_face(v, moving_faces_[f]); });
          break;
        case 3:
          moving_edge_tree_.for_each_meeting_pair(
              part, static_edge_tree_, distance,
              [&](int a, int b) { edge_pair(moving_edges_[a], static_edges_[b]); });
          break;
        default:
          moving_edge_tree_.for_each_meeting_pair(
              part, distance, [&](int a, int b) { edge_pair(moving_edges_[a], moving_edges_[b]); });
      }
    }
  }
  sort_index_pairs(point_triangle_parts_, mesh_.vertex_count, candidates.point_triangle,
                   sort_scratch_);
  sort_index_pairs(edge_edge_parts_, static_cast<int>(mesh_.edges.size()), candidates.edge_edge,
                   sort_scratch_);
}

void CollisionBroadPhase::find(const double* positions, const double* displacements,
                               double distance, CollisionCandidates& candidates) {
  const auto all = [](int, int) { return true; };
  search(positions, displacements, distance, all, all, candidates);
}

namespace {

// Whether a point-triangle or an edge-edge pair of `mesh` is closer than
// `distance` at `positions`. Most pairs whose boxes meet are farther, and
// cheaply shown to be (point_triangle_farther, edge_edge_farther).
struct NearTest {
  const CollisionMesh& mesh;
  const double* positions;
  double distance_sq;

  bool point_triangle(int v, int face) const {
    const Tri& f = mesh.faces[face];
    const Vec3 p = point_at(positions, v), a = point_at(positions, f[0]),
               b = point_at(positions, f[1]), c = point_at(positions, f[2]);
    return !point_triangle_farther(p, a, b, c, distance_sq) &&
           point_triangle_distance_squared(p, a, b, c) < distance_sq;
  }
  bool edge_edge(int e, int h) const {
    const auto &ea = mesh.edges[e], &eb = mesh.edges[h];
    const Vec3 a0 = point_at(positions, ea[0]), a1 = point_at(positions, ea[1]),
               b0 = point_at(positions, eb[0]), b1 = point_at(positions, eb[1]);
    return !edge_edge_farther(a0, a1, b0, b1, distance_sq) &&
           edge_edge_distance_squared(a0, a1, b0, b1) < distance_sq;
  }
};

}  // namespace

void CollisionBroadPhase::find_within(const double* positions, double distance,
                                      CollisionCandidates& candidates) {
  const NearTest near{mesh_, positions, distance * distance};
  const auto near_pt = [&](int v, int face) { return near.point_triangle(v, face); };
  const auto near_ee = [&](int e, int h) { return near.edge_edge(e, h); };
  search(positions, nullptr, distance, near_pt, near_ee, candidates);
}

// A tree of the moving primitives with a moved corner, searched against the
// trees of everything: moved points against all faces, faces with a moved
// corner against the static points and the points that did not move (the
// pairs with a moved point were found by the first), edges with a moved
// corner against all edges (a pair of two such edges once). On one thread:
// the moved primitives are a minority, else a whole search is cheaper.
void CollisionBroadPhase::find_within_touching(const double* positions, double distance,
                                               const std::vector<char>& moved,
                                               CollisionCandidates& candidates) {
  if (static_cast<int>(moved.size()) != mesh_.vertex_count)
    throw InternalError("broad phase: one moved flag per vertex expected");
  moving_boxes(positions, nullptr);
  update_trees();
  const int fixed = mesh_.fixed_count;
  const auto& faces = mesh_.faces;
  const auto& edges = mesh_.edges;
  const auto is_moved = [&](int v) { return v >= fixed && moved[v]; };
  touched_points_.clear();
  for (int v = fixed; v < mesh_.vertex_count; ++v)
    if (moved[v]) touched_points_.push_back(v - fixed);
  touched_edges_.clear();
  edge_touched_.assign(moving_edges_.size(), 0);
  for (size_t k = 0; k < moving_edges_.size(); ++k) {
    const auto& e = edges[moving_edges_[k]];
    if (is_moved(e[0]) || is_moved(e[1])) {
      touched_edges_.push_back(static_cast<int>(k));
      edge_touched_[k] = 1;
    }
  }
  touched_faces_.clear();
  for (size_t k = 0; k < moving_faces_.size(); ++k) {
    const Tri& f = faces[moving_faces_[k]];
    if (is_moved(f[0]) || is_moved(f[1]) || is_moved(f[2]))
      touched_faces_.push_back(static_cast<int>(k));
  }
  const NearTest near{mesh_, positions, distance * distance};
  std::vector<IndexPair>& pt = candidates.point_triangle;
  std::vector<IndexPair>& ee = candidates.edge_edge;
  pt.clear();
  ee.clear();
  const auto point_face = [&](int v, int face) {
    if (!has_vertex(faces[face], v) && near.point_triangle(v, face)) pt.push_back({v, face});
  };
  const auto build = [&](const std::vector<int>& touched, const std::vector<Box>& boxes) {
    touched_boxes_.clear();
    for (int k : touched) touched_boxes_.push_back(boxes[k]);
    touched_tree_.build(touched_boxes_);
  };
  build(touched_points_, point_boxes_);
  touched_tree_.for_each_meeting_pair(static_face_tree_, distance, [&](int p, int f) {
    point_face(fixed + touched_points_[p], static_faces_[f]);
  });
  touched_tree_.for_each_meeting_pair(moving_face_tree_, distance, [&](int p, int f) {
    point_face(fixed + touched_points_[p], moving_faces_[f]);
  });
  build(touched_faces_, face_boxes_);
  touched_tree_.for_each_meeting_pair(static_points_, distance, [&](int f, int v) {
    point_face(v, moving_faces_[touched_faces_[f]]);
  });
  touched_tree_.for_each_meeting_pair(moving_points_, distance, [&](int f, int p) {
    if (!moved[fixed + p]) point_face(fixed + p, moving_faces_[touched_faces_[f]]);
  });
  build(touched_edges_, edge_boxes_);
  const auto edge_pair = [&](int e, int h) {
    if (!share_vertex(edges[e], edges[h]) && near.edge_edge(e, h))
      ee.push_back({std::min(e, h), std::max(e, h)});
  };
  touched_tree_.for_each_meeting_pair(static_edge_tree_, distance, [&](int a, int b) {
    edge_pair(moving_edges_[touched_edges_[a]], static_edges_[b]);
  });
  touched_tree_.for_each_meeting_pair(moving_edge_tree_, distance, [&](int a, int b) {
    const int e = moving_edges_[touched_edges_[a]], h = moving_edges_[b];
    if (!edge_touched_[b] || e < h) edge_pair(e, h);
  });
  sort_index_pairs(pt, mesh_.vertex_count);
  sort_index_pairs(ee, static_cast<int>(edges.size()));
}

void CollisionBroadPhase::meeting_faces(const double* positions, std::vector<IndexPair>& pairs) {
  moving_boxes(positions, nullptr);
  update_trees();
  pairs.clear();
  moving_face_tree_.for_each_meeting_pair(static_face_tree_, 0.0, [&](int a, int b) {
    pairs.push_back({moving_faces_[a], static_faces_[b]});
  });
  moving_face_tree_.for_each_meeting_pair(0.0, [&](int a, int b) {
    pairs.push_back({std::min(moving_faces_[a], moving_faces_[b]),
                     std::max(moving_faces_[a], moving_faces_[b])});
  });
  sort_index_pairs(pairs, static_cast<int>(mesh_.faces.size()));
}

std::vector<int> CollisionBroadPhase::static_faces_meeting(const Box& box) const {
  std::vector<int> faces;
  static_face_tree_.for_each_meeting(box, 0.0, [&](int f) { faces.push_back(static_faces_[f]); });
  std::sort(faces.begin(), faces.end());
  return faces;
}

namespace {

// Candidate pairs per block of the barrier sum: blocks of a fixed size, summed
// in order, make the sum independent of the thread count.
constexpr long kBarrierBlock = 16384;

// The corners of the k-th candidate pair (point-triangle pairs first) and
// their squared distance, with its gradient when `gradient` is non-null.
double pair_distance(const CollisionMesh& mesh, const double* x,
                     const CollisionCandidates& candidates, long k, int (&v)[4],
                     std::array<Vec3, 4>* gradient) {
  const long pt_count = static_cast<long>(candidates.point_triangle.size());
  if (k < pt_count) {
    const IndexPair& pair = candidates.point_triangle[k];
    const Tri& f = mesh.faces[pair[1]];
    v[0] = pair[0];
    v[1] = f[0];
    v[2] = f[1];
    v[3] = f[2];
    return point_triangle_distance_squared(point_at(x, v[0]), point_at(x, v[1]), point_at(x, v[2]),
                                           point_at(x, v[3]), gradient);
  }
  const IndexPair& pair = candidates.edge_edge[k - pt_count];
  const auto &e = mesh.edges[pair[0]], &h = mesh.edges[pair[1]];
  v[0] = e[0];
  v[1] = e[1];
  v[2] = h[0];
  v[3] = h[1];
  return edge_edge_distance_squared(point_at(x, v[0]), point_at(x, v[1]), point_at(x, v[2]),
                                    point_at(x, v[3]), gradient);
}

// A pair within dhat: its corners and its barrier gradient.
struct ActivePair {
  int vertex[4];
  std::array<Vec3, 4> gradient;
};

}  // namespace

// Blocks in parallel, each with its partial sum and its pairs within dhat;
// then the partial sums and the gradients added in block order.
double barrier_potential(const CollisionMesh& mesh, const double* positions,
                         const CollisionCandidates& candidates, double dhat, double weight,
                         double* gradient) {
  const double dhat_sq = dhat * dhat;
  const long total = static_cast<long>(candidates.size());
  const long blocks = (total + kBarrierBlock - 1) / kBarrierBlock;
  std::vector<double> partial(blocks, 0.0);
  std::vector<std::vector<ActivePair>> active(gradient ? blocks : 0);
#pragma omp parallel for schedule(dynamic, 1) if (blocks > 1)
  for (long b = 0; b < blocks; ++b) {
    double sum = 0;
    std::array<Vec3, 4> g;
    int v[4];
    for (long k = b * kBarrierBlock; k < std::min(total, (b + 1) * kBarrierBlock); ++k) {
      const double d2 = pair_distance(mesh, positions, candidates, k, v, gradient ? &g : nullptr);
      if (!(d2 < dhat_sq)) continue;
      double derivative;
      sum += barrier_of_squared(d2, dhat, &derivative);
      if (!gradient) continue;
      ActivePair pair;
      for (int i = 0; i < 4; ++i) {
        pair.vertex[i] = v[i];
        for (int c = 0; c < 3; ++c) pair.gradient[i][c] = weight * derivative * g[i][c];
      }
      active[b].push_back(pair);
    }
    partial[b] = sum;
  }
  double sum = 0;
  for (long b = 0; b < blocks; ++b) {
    sum += partial[b];
    if (!gradient) continue;
    for (const ActivePair& pair : active[b]) {
      for (int i = 0; i < 4; ++i) {
        double* out = gradient + 3 * static_cast<ptrdiff_t>(pair.vertex[i]);
        for (int c = 0; c < 3; ++c) out[c] += pair.gradient[i][c];
      }
    }
  }
  return sum;
}

void keep_candidates_within(const CollisionMesh& mesh, const double* positions, double distance,
                            CollisionCandidates& candidates) {
  const long total = static_cast<long>(candidates.size());
  const long pt_count = static_cast<long>(candidates.point_triangle.size());
  const double distance_sq = distance * distance;
  std::vector<char> keep(total);
#pragma omp parallel for schedule(static) if (total > 32768)
  for (long k = 0; k < total; ++k) {
    int v[4];
    keep[k] = pair_distance(mesh, positions, candidates, k, v, nullptr) < distance_sq;
  }
  long kept = 0;
  for (long k = 0; k < pt_count; ++k) {
    if (keep[k]) candidates.point_triangle[kept++] = candidates.point_triangle[k];
  }
  candidates.point_triangle.resize(kept);
  kept = 0;
  for (long k = pt_count; k < total; ++k) {
    if (keep[k]) candidates.edge_edge[kept++] = candidates.edge_edge[k - pt_count];
  }
  candidates.edge_edge.resize(kept);
}

}  // namespace foldfill
