// The collision mesh, the broad phase that finds its candidate pairs with box
// trees, and the barrier potential summed over the candidates.
#include "foldfill/collision.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "foldfill/error.h"

namespace foldfill {
namespace {

// A moving tree whose cost has grown past this factor of its cost when built
// is rebuilt: a rebuild costs about as much as a few searches.
constexpr double kRebuildFactor = 2;

// Pairs per thread below which a search is not worth spreading.
constexpr int kSmallestParallelSearch = 256;

const double* at(const double* array, int v) { return array + 3 * static_cast<ptrdiff_t>(v); }
Vec3 vec(const double* array, int v) {
  const double* p = at(array, v);
  return {p[0], p[1], p[2]};
}

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
    throw Error(ErrorKind::Internal, "collision mesh: fixed_count outside [0, vertex_count]");
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
        throw Error(ErrorKind::Internal,
                    "collision mesh: face " + std::to_string(f) + " out of range");
      }
      if (a != b) mesh.edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(mesh.edges.begin(), mesh.edges.end());
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
  std::vector<Box> boxes;
  for (int v = 0; v < fixed; ++v) boxes.push_back(point_box(v, positions, nullptr));
  static_points_.build(boxes);
  boxes.clear();
  for (int e : static_edges_) boxes.push_back(edge_box(mesh_.edges[e], positions, nullptr));
  static_edge_tree_.build(boxes);
  boxes.clear();
  for (int f : static_faces_) boxes.push_back(face_box(mesh_.faces[f], positions, nullptr));
  static_face_tree_.build(boxes);
  moving_boxes(positions, nullptr);
  update_trees();
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
  for (int k = 0; k < 3; ++k) {
    if (built_) {
      trees[k]->refit(*boxes[k]);
      if (!(trees[k]->cost() > kRebuildFactor * built_cost_[k])) continue;
    }
    trees[k]->build(*boxes[k]);
    built_cost_[k] = trees[k]->cost();
  }
  built_ = true;
}

// Five searches, spread over threads group by group: moving points against
// the static and the moving faces, moving faces against the static points,
// moving edges against the static and the moving edges. Each pair is found
// once, then all are sorted.
void CollisionBroadPhase::find(const double* positions, const double* displacements,
                               double distance, CollisionCandidates& candidates) {
  moving_boxes(positions, displacements);
  update_trees();
  const int threads = omp_get_max_threads();
  point_triangle_parts_.resize(threads);
  edge_edge_parts_.resize(threads);
  for (auto& part : point_triangle_parts_) part.clear();
  for (auto& part : edge_edge_parts_) part.clear();

  const int fixed = mesh_.fixed_count;
  const int point_groups = moving_points_.group_count();
  const int face_groups = moving_face_tree_.group_count();
  const int edge_groups = moving_edge_tree_.group_count();
  // Work items: [0, 2 P) points (static faces, then moving faces), then F
  // face groups, then [0, 2 E) edge groups (static edges, then moving edges).
  const int total = 2 * point_groups + face_groups + 2 * edge_groups;
  const bool parallel = mesh_.vertex_count - fixed >= kSmallestParallelSearch;
#pragma omp parallel if (parallel)
  {
    std::vector<IndexPair>& pt = point_triangle_parts_[omp_get_thread_num()];
    std::vector<IndexPair>& ee = edge_edge_parts_[omp_get_thread_num()];
    const auto& faces = mesh_.faces;
    const auto& edges = mesh_.edges;
#pragma omp for schedule(dynamic, 8)
    for (int item = 0; item < total; ++item) {
      int g = item;
      if (g < point_groups) {
        moving_points_.for_each_meeting_pair(g, static_face_tree_, distance, [&](int p, int f) {
          pt.push_back({fixed + p, static_faces_[f]});
        });
        continue;
      }
      g -= point_groups;
      if (g < point_groups) {
        moving_points_.for_each_meeting_pair(g, moving_face_tree_, distance, [&](int p, int f) {
          const int v = fixed + p, face = moving_faces_[f];
          if (!has_vertex(faces[face], v)) pt.push_back({v, face});
        });
        continue;
      }
      g -= point_groups;
      if (g < face_groups) {
        moving_face_tree_.for_each_meeting_pair(g, static_points_, distance, [&](int f, int v) {
          const int face = moving_faces_[f];
          if (!has_vertex(faces[face], v)) pt.push_back({v, face});
        });
        continue;
      }
      g -= face_groups;
      if (g < edge_groups) {
        moving_edge_tree_.for_each_meeting_pair(g, static_edge_tree_, distance, [&](int a, int b) {
          const int e = moving_edges_[a], h = static_edges_[b];
          if (!share_vertex(edges[e], edges[h])) ee.push_back({std::min(e, h), std::max(e, h)});
        });
        continue;
      }
      g -= edge_groups;
      moving_edge_tree_.for_each_meeting_pair(g, distance, [&](int a, int b) {
        const int e = moving_edges_[a], h = moving_edges_[b];
        if (!share_vertex(edges[e], edges[h])) ee.push_back({std::min(e, h), std::max(e, h)});
      });
    }
  }
  sort_index_pairs(point_triangle_parts_, mesh_.vertex_count, candidates.point_triangle,
                   sort_scratch_);
  sort_index_pairs(edge_edge_parts_, static_cast<int>(mesh_.edges.size()), candidates.edge_edge,
                   sort_scratch_);
}

double barrier_potential(const CollisionMesh& mesh, const double* positions,
                         const CollisionCandidates& candidates, double dhat, double weight,
                         double* gradient) {
  const double dhat_sq = dhat * dhat;
  double sum = 0;
  std::array<Vec3, 4> g;
  std::array<Vec3, 4>* want = gradient ? &g : nullptr;
  const auto accumulate = [&](double d2, const int(&v)[4]) {
    if (!(d2 < dhat_sq)) return;
    double derivative;
    sum += barrier_of_squared(d2, dhat, &derivative);
    if (!gradient) return;
    const double f = weight * derivative;
    for (int k = 0; k < 4; ++k) {
      double* out = gradient + 3 * static_cast<ptrdiff_t>(v[k]);
      for (int c = 0; c < 3; ++c) out[c] += f * g[k][c];
    }
  };
  for (const IndexPair& pair : candidates.point_triangle) {
    const Tri& f = mesh.faces[pair[1]];
    const int v[4] = {pair[0], f[0], f[1], f[2]};
    accumulate(point_triangle_distance_squared(vec(positions, v[0]), vec(positions, v[1]),
                                               vec(positions, v[2]), vec(positions, v[3]), want),
               v);
  }
  for (const IndexPair& pair : candidates.edge_edge) {
    const auto &e = mesh.edges[pair[0]], &h = mesh.edges[pair[1]];
    const int v[4] = {e[0], e[1], h[0], h[1]};
    accumulate(edge_edge_distance_squared(vec(positions, v[0]), vec(positions, v[1]),
                                          vec(positions, v[2]), vec(positions, v[3]), want),
               v);
  }
  return sum;
}

}  // namespace foldfill
