// The barrier and step bound of a patch (see contact.h). The collision mesh
// numbers its vertices [domain's fixed | scene's | domain's free], so that
// the fixed ones come first, as CollisionMesh wants, and the free ones are
// the variables in order.
#include "foldfill/contact.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "foldfill/error.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

// The domain's faces and the scene's in the collision mesh's numbering.
std::vector<Tri> collision_faces(const EmbedDomain& domain, const PatchScene& scene) {
  const int fixed = domain.fixed_count;
  const int scene_count = static_cast<int>(scene.positions.size());
  const int limit = fixed + scene_count;
  std::vector<Tri> faces;
  faces.reserve(domain.faces.size() + scene.faces.size());
  for (Tri f : domain.faces) {
    for (int& v : f) v = v < fixed ? v : v + scene_count;
    faces.push_back(f);
  }
  for (const Tri& f : scene.faces) {
    for (int v : f)
      if (v < 0 || v >= limit)
        throw InternalError("contact: a scene face has vertex " + std::to_string(v) + " of " +
                            std::to_string(limit));
    faces.push_back(f);
  }
  return faces;
}

std::vector<double> fixed_points(const EmbedDomain& domain, const PatchScene& scene) {
  std::vector<double> points;
  points.reserve(3 * (domain.fixed_positions.size() + scene.positions.size() +
                      static_cast<size_t>(domain.free_count())));
  for (const Vec3& p : domain.fixed_positions) points.insert(points.end(), p.begin(), p.end());
  for (const Vec3& p : scene.positions) points.insert(points.end(), p.begin(), p.end());
  points.resize(points.size() + 3 * static_cast<size_t>(domain.free_count()), 0.0);
  return points;
}

// A lower bound on triangle_obstacle_distance over the triangle abc. The
// signed distance to a sphere or a capsule is convex (a plane's is linear),
// so it lies above its tangent plane at the centroid, whose least value on
// the triangle is at a corner. Faces lying along the obstacle's surface, as
// draped cloth does, get a bound close to their distance.
double face_obstacle_lower_bound(const Obstacle& o, const Vec3& a, const Vec3& b, const Vec3& c) {
  const auto height = [&](const Vec3& p, const Vec3& direction, const Vec3& origin) {
    return (p[0] - origin[0]) * direction[0] + (p[1] - origin[1]) * direction[1] +
           (p[2] - origin[2]) * direction[2];
  };
  if (o.type == Obstacle::Type::Plane)
    return std::min({height(a, o.normal, o.center), height(b, o.normal, o.center),
                     height(c, o.normal, o.center)});
  Vec3 centre, d;
  for (int k = 0; k < 3; ++k) centre[k] = (a[k] + b[k] + c[k]) / 3;
  if (o.type == Obstacle::Type::Cylinder) {
    double t = height(centre, o.axis, o.center);
    t = std::clamp(t, -0.5 * o.height, 0.5 * o.height);
    for (int k = 0; k < 3; ++k) d[k] = centre[k] - (o.center[k] + t * o.axis[k]);
  } else {
    for (int k = 0; k < 3; ++k) d[k] = centre[k] - o.center[k];
  }
  const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  // On the axis (or not finite): the least the signed distance is anywhere.
  if (!(length > 0) || !std::isfinite(length)) return -o.radius;
  const Vec3 normal{d[0] / length, d[1] / length, d[2] / length};
  return length - o.radius +
         std::min(
             {height(a, normal, centre), height(b, normal, centre), height(c, normal, centre)});
}

void check_options(const ContactOptions& options) {
  const auto positive = [](double w) { return std::isfinite(w) && w > 0; };
  if (!positive(options.thickness) || !positive(options.stiffness) || !positive(options.skin))
    throw UsageError("contact: thickness, stiffness and skin must be positive");
  if (!(options.moved_drift >= 0 && options.moved_drift < 0.5) ||
      !(options.moved_share >= 0 && options.moved_share <= 1))
    throw UsageError("contact: moved_drift must be in [0, 0.5) and moved_share in [0, 1]");
}

}  // namespace

PatchContact::PatchContact(const EmbedDomain& domain, const PatchScene& scene,
                           const ContactOptions& options, std::vector<Obstacle> obstacles)
    : options_(options),
      obstacles_(std::move(obstacles)),
      fixed_count_(domain.fixed_count + static_cast<int>(scene.positions.size())),
      first_patch_face_(domain.strip_face_count),
      end_patch_face_(static_cast<int>(domain.faces.size())) {
  check_options(options);
  for (const Obstacle& o : obstacles_)
    if (o.type == Obstacle::Type::Mesh)
      throw InternalError("contact: a mesh obstacle belongs in the scene");
  const std::vector<Tri> faces = collision_faces(domain, scene);
  points_ = fixed_points(domain, scene);
  const int vertex_count = fixed_count_ + domain.free_count();
  broad_phase_ =
      CollisionBroadPhase(make_collision_mesh(faces, vertex_count, fixed_count_), points_.data());
  displacement_.assign(points_.size(), 0.0);
  for (int f = first_patch_face_; f < end_patch_face_; ++f) {
    const Tri& t = faces[f];
    if (std::max({t[0], t[1], t[2]}) >= fixed_count_) continue;
    Box box;
    for (int c = 0; c < 3; ++c) {
      box.low[c] = std::min({points_[3 * t[0] + c], points_[3 * t[1] + c], points_[3 * t[2] + c]});
      box.high[c] = std::max({points_[3 * t[0] + c], points_[3 * t[1] + c], points_[3 * t[2] + c]});
    }
    for (int g : broad_phase_.static_faces_meeting(box)) {
      // A pair of two such faces once.
      const bool fixed_patch_face = g >= first_patch_face_ && g < end_patch_face_;
      if (g != f && !(fixed_patch_face && g < f)) fixed_patch_pairs_.push_back({f, g});
    }
  }
}

const double* PatchContact::place(const Eigen::VectorXd& x) const {
  const size_t offset = 3 * static_cast<size_t>(fixed_count_);
  if (static_cast<size_t>(x.size()) + offset != points_.size())
    throw InternalError("contact: " + std::to_string(x.size()) + " variables for a patch of " +
                        std::to_string((points_.size() - offset) / 3) + " free vertices");
  std::copy(x.data(), x.data() + x.size(), points_.begin() + static_cast<std::ptrdiff_t>(offset));
  return points_.data();
}

// The candidates within thickness + skin of the anchor, their distances
// there, and the anchor: the points where they were last searched, vertex by
// vertex. Every pair that is not among them is at least thickness + skin
// apart at the anchor, so that while the free vertices' displacements from
// it spread over less than `closer`, a pair closer than thickness + skin -
// closer is among them, with an anchor distance below its distance + closer
// (gather). A refresh moves the anchor to the current points. Where only a
// few vertices have moved far from it (ContactOptions::moved_drift and
// moved_share), only those move: a pair none of whose corners moved keeps
// its anchor distance, and the pairs with a moved corner are searched again
// (find_within_touching). The others' displacements stay below moved_drift
// times the skin, so that the refreshed candidates last almost as long as
// fresh ones, for a search over a part of the patch.
void PatchContact::refresh_candidates(Scope scope, const double* step) const {
  const double reach = options_.thickness + options_.skin;
  ++candidate_searches_;
  if (scope == Scope::Everything && has_candidates_ && candidates_scope_ == Scope::Everything &&
      refresh_moved_vertices(step)) {
    refresh_obstacle_candidates(reach);
    ++partial_candidate_searches_;
    return;
  }
  // The search keeps only the pairs closer than the reach (before sorting
  // them: most pairs of meeting boxes are farther), then their distances.
  if (scope == Scope::Everything) {
    broad_phase_.find_within(points_.data(), reach, candidates_);
  } else {
    candidates_.point_triangle.clear();
    candidates_.edge_edge.clear();
  }
  candidates_scope_ = scope;
  anchor_ = points_;
  point_triangle_distance_.clear();
  for (const IndexPair& pair : candidates_.point_triangle)
    point_triangle_distance_.push_back(anchor_distance_pt(pair));
  edge_edge_distance_.clear();
  for (const IndexPair& pair : candidates_.edge_edge)
    edge_edge_distance_.push_back(anchor_distance_ee(pair));
  refresh_obstacle_candidates(reach);
  has_candidates_ = true;
}

double PatchContact::anchor_distance_pt(const IndexPair& pair) const {
  const double* p = anchor_.data();
  const Tri& f = mesh().faces[pair[1]];
  return std::sqrt(point_triangle_distance_squared(point_at(p, pair[0]), point_at(p, f[0]),
                                                   point_at(p, f[1]), point_at(p, f[2])));
}

double PatchContact::anchor_distance_ee(const IndexPair& pair) const {
  const double* p = anchor_.data();
  const auto& a = mesh().edges[pair[0]];
  const auto& b = mesh().edges[pair[1]];
  return std::sqrt(edge_edge_distance_squared(point_at(p, a[0]), point_at(p, a[1]),
                                              point_at(p, b[0]), point_at(p, b[1])));
}

void PatchContact::refresh_obstacle_candidates(double reach) const {
  const CollisionMesh& m = mesh();
  const double* p = anchor_.data();
  obstacle_candidates_.clear();
  for (int f = first_patch_face_; f < end_patch_face_; ++f) {
    const Tri& t = m.faces[f];
    for (int o = 0; o < static_cast<int>(obstacles_.size()); ++o)
      if (!(face_obstacle_lower_bound(obstacles_[o], point_at(p, t[0]), point_at(p, t[1]),
                                      point_at(p, t[2])) >= reach))
        obstacle_candidates_.push_back({f, o});
  }
}

// The partial refresh (see refresh_candidates), where few enough vertices
// moved; false, with nothing changed, otherwise. With `step`, the current
// points end that step, whose start the candidates must cover as well: a
// vertex moved where it is far from the anchor at either.
bool PatchContact::refresh_moved_vertices(const double* step) const {
  const double limit = options_.moved_drift * options_.skin;
  const int vertex_count = static_cast<int>(points_.size() / 3);
  moved_.assign(vertex_count, 0);
  int moved_count = 0;
  for (int v = fixed_count_; v < vertex_count; ++v) {
    const double* p = &points_[3 * static_cast<size_t>(v)];
    const double* a = &anchor_[3 * static_cast<size_t>(v)];
    const double dx = p[0] - a[0], dy = p[1] - a[1], dz = p[2] - a[2];
    bool far = !(dx * dx + dy * dy + dz * dz < limit * limit);
    if (step && !far) {
      const double* m = step + 3 * static_cast<size_t>(v);
      const double sx = dx - m[0], sy = dy - m[1], sz = dz - m[2];
      far = !(sx * sx + sy * sy + sz * sz < limit * limit);
    }
    if (far) {
      moved_[v] = 1;
      ++moved_count;
    }
  }
  if (moved_count > options_.moved_share * (vertex_count - fixed_count_)) return false;
  for (int v = fixed_count_; v < vertex_count; ++v)
    if (moved_[v])
      std::copy_n(points_.begin() + 3 * static_cast<std::ptrdiff_t>(v), 3,
                  anchor_.begin() + 3 * static_cast<std::ptrdiff_t>(v));
  const double reach = options_.thickness + options_.skin;
  broad_phase_.find_within_touching(anchor_.data(), reach, moved_, touched_);
  const CollisionMesh& m = mesh();
  // The kept pairs (no moved corner) and the searched ones (a moved corner)
  // are apart: merged in order.
  const auto merge = [&](std::vector<IndexPair>& pairs, std::vector<double>& distances,
                         const std::vector<IndexPair>& fresh, const auto& untouched,
                         const auto& distance) {
    merged_pairs_.clear();
    merged_distances_.clear();
    size_t k = 0;
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (!untouched(pairs[i])) continue;
      for (; k < fresh.size() && fresh[k] < pairs[i]; ++k) {
        merged_pairs_.push_back(fresh[k]);
        merged_distances_.push_back(distance(fresh[k]));
      }
      merged_pairs_.push_back(pairs[i]);
      merged_distances_.push_back(distances[i]);
    }
    for (; k < fresh.size(); ++k) {
      merged_pairs_.push_back(fresh[k]);
      merged_distances_.push_back(distance(fresh[k]));
    }
    pairs.swap(merged_pairs_);
    distances.swap(merged_distances_);
  };
  merge(
      candidates_.point_triangle, point_triangle_distance_, touched_.point_triangle,
      [&](const IndexPair& pair) {
        const Tri& f = m.faces[pair[1]];
        return !(moved_[pair[0]] || moved_[f[0]] || moved_[f[1]] || moved_[f[2]]);
      },
      [&](const IndexPair& pair) { return anchor_distance_pt(pair); });
  merge(
      candidates_.edge_edge, edge_edge_distance_, touched_.edge_edge,
      [&](const IndexPair& pair) {
        const auto &a = m.edges[pair[0]], &b = m.edges[pair[1]];
        return !(moved_[a[0]] || moved_[a[1]] || moved_[b[0]] || moved_[b[1]]);
      },
      [&](const IndexPair& pair) { return anchor_distance_ee(pair); });
  return true;
}

// The candidates whose anchor distance is at most `distance` into active_.
void PatchContact::select_candidates(double distance) const {
  active_.point_triangle.clear();
  active_.edge_edge.clear();
  for (size_t k = 0; k < candidates_.point_triangle.size(); ++k)
    if (point_triangle_distance_[k] <= distance)
      active_.point_triangle.push_back(candidates_.point_triangle[k]);
  for (size_t k = 0; k < candidates_.edge_edge.size(); ++k)
    if (edge_edge_distance_[k] <= distance) active_.edge_edge.push_back(candidates_.edge_edge[k]);
}

// A pair that is not among the candidates was at least thickness + skin
// apart at the anchor, and has come closer since by at most closing_bound
// (box_tree.h) of the free vertices' displacements from it, at the current
// points or anywhere along the step `move`.
bool PatchContact::gather(double distance, const double* move) const {
  if (!has_candidates_) return false;
  const double closer = closing_bound(points_.data(), anchor_.data(),
                                      static_cast<size_t>(fixed_count_), points_.size() / 3, move);
  if (!(distance + closer < options_.thickness + options_.skin)) return false;
  select_candidates(distance + closer);
  return true;
}

bool PatchContact::gather(Scope scope, double distance, const double* move) const {
  // Candidates of the obstacles alone do not serve the whole contact.
  if (scope == Scope::Everything && candidates_scope_ == Scope::ObstaclesOnly) return false;
  if (!gather(distance, move)) return false;
  if (scope == Scope::ObstaclesOnly) {
    active_.point_triangle.clear();
    active_.edge_edge.clear();
  }
  return true;
}

double PatchContact::evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
                              Scope scope) const {
  if (scope == Scope::ObstaclesOnly && obstacles_.empty()) return 0;
  place(x);
  // Refreshed candidates hold at the current points (a whole search at no
  // drift, a partial one below half the skin) unless those are not finite:
  // the barrier is then +infinity.
  if (!gather(scope, options_.thickness, nullptr)) {
    refresh_candidates(scope);
    if (!gather(scope, options_.thickness, nullptr)) return std::numeric_limits<double>::infinity();
  }
  // gradient_ is all zeros between calls: a call zeroes what it wrote, the
  // free vertices' part and the fixed corners of the active pairs, instead
  // of the whole array (the scene's vertices, often ten times the patch's).
  double* full_gradient = nullptr;
  if (gradient) {
    gradient_.resize(points_.size(), 0.0);
    full_gradient = gradient_.data();
  }
  double value = barrier_potential(mesh(), points_.data(), active_, options_.thickness,
                                   options_.stiffness, full_gradient);
  if (std::isfinite(value)) value += obstacle_barrier(full_gradient);
  if (!gradient) return value;
  const bool finite = std::isfinite(value);
  double* free_gradient = gradient_.data() + 3 * static_cast<size_t>(fixed_count_);
  for (Eigen::Index k = 0; k < gradient->size(); ++k) {
    if (finite) (*gradient)[k] += free_gradient[k];
    free_gradient[k] = 0;
  }
  const CollisionMesh& m = mesh();
  const auto clear_fixed = [&](int v) {
    if (v < fixed_count_)
      std::fill_n(gradient_.begin() + 3 * static_cast<std::ptrdiff_t>(v), 3, 0.0);
  };
  for (const IndexPair& pair : active_.point_triangle) {
    clear_fixed(pair[0]);
    for (int v : m.faces[pair[1]]) clear_fixed(v);
  }
  for (const IndexPair& pair : active_.edge_edge)
    for (int e : pair)
      for (int v : m.edges[e]) clear_fixed(v);
  return value;
}

double PatchContact::step_bound(const Eigen::VectorXd& x, const Eigen::VectorXd& dx,
                                Scope scope) const {
  if (scope == Scope::ObstaclesOnly && obstacles_.empty()) return 1;
  place(x);
  const size_t offset = 3 * static_cast<size_t>(fixed_count_);
  std::copy(dx.data(), dx.data() + dx.size(),
            displacement_.begin() + static_cast<std::ptrdiff_t>(offset));
  // The pairs that may meet during the step: the candidates' (gather), or,
  // for a step too long for them even when fresh, those of the swept boxes
  // (none with the obstacles alone).
  bool covered = gather(scope, 0.0, displacement_.data());
  if (!covered) {
    // Fresh candidates around the step's end: every point of the step is
    // within its move of there, and the next step starts there (most steps
    // are taken whole), so that they last for it as well.
    for (size_t k = offset; k < points_.size(); ++k) points_[k] += displacement_[k];
    refresh_candidates(scope, displacement_.data());
    place(x);
    covered = gather(scope, 0.0, displacement_.data());
    if (!covered && scope == Scope::Everything)
      broad_phase_.find(points_.data(), displacement_.data(), 0.0, active_);
  }
  const double bound = scope == Scope::Everything
                           ? collision_step_bound(mesh(), points_.data(), displacement_.data(),
                                                  active_, options_.ccd)
                           : 1.0;
  return obstacle_step_bound(bound, covered);
}

double PatchContact::obstacle_barrier(double* gradient) const {
  if (obstacles_.empty()) return 0;
  const CollisionMesh& m = mesh();
  const double* p = points_.data();
  double sum = 0;
  std::array<Vec3, 3> g;
  for (const auto& [f, obstacle] : obstacle_candidates_) {
    const Tri& t = m.faces[f];
    const Obstacle& o = obstacles_[obstacle];
    const Vec3 a = point_at(p, t[0]), b = point_at(p, t[1]), c = point_at(p, t[2]);
    if (face_obstacle_lower_bound(o, a, b, c) >= options_.thickness) continue;
    const double d = triangle_obstacle_distance(o, a, b, c, gradient ? &g : nullptr);
    if (!(d < options_.thickness)) continue;
    double derivative = 0;
    const double value = barrier(d, options_.thickness, gradient ? &derivative : nullptr);
    if (!std::isfinite(value)) return value;
    sum += options_.stiffness * value;
    if (!gradient) continue;
    for (int k = 0; k < 3; ++k) {
      if (t[k] < fixed_count_) continue;
      for (int c2 = 0; c2 < 3; ++c2)
        gradient[3 * t[k] + c2] += options_.stiffness * derivative * g[k][c2];
    }
  }
  return sum;
}

double PatchContact::obstacle_step_bound(double t_max, bool candidates_cover) const {
  if (obstacles_.empty()) return t_max;
  const CollisionMesh& m = mesh();
  const double* p = points_.data();
  const double* d = displacement_.data();
  CcdOptions ccd = options_.ccd;
  const auto bound_face = [&](int f, const Obstacle& o) {
    const Tri& t = m.faces[f];
    const Vec3 a = point_at(p, t[0]), b = point_at(p, t[1]), c = point_at(p, t[2]);
    const Vec3 da = point_at(d, t[0]), db = point_at(d, t[1]), dc = point_at(d, t[2]);
    const double move = std::sqrt(std::max({da[0] * da[0] + da[1] * da[1] + da[2] * da[2],
                                            db[0] * db[0] + db[1] * db[1] + db[2] * db[2],
                                            dc[0] * dc[0] + dc[1] * dc[1] + dc[2] * dc[2]}));
    // A face that cannot reach the obstacle within t_max: its distance
    // falls by at most its largest corner's move.
    if (face_obstacle_lower_bound(o, a, b, c) > move * t_max) return;
    ccd.t_max = t_max;
    t_max = triangle_obstacle_ccd(o, a, b, c, da, db, dc, ccd);
  };
  if (candidates_cover) {
    for (const auto& [f, o] : obstacle_candidates_) {
      if (!(t_max > 0)) break;
      bound_face(f, obstacles_[o]);
    }
    return t_max;
  }
  for (int f = first_patch_face_; f < end_patch_face_ && t_max > 0; ++f)
    for (const Obstacle& o : obstacles_) bound_face(f, o);
  return t_max;
}

std::vector<IndexPair> PatchContact::patch_face_pairs(const Eigen::VectorXd& x) const {
  std::vector<IndexPair> pairs;
  broad_phase_.meeting_faces(place(x), pairs);
  if (fixed_patch_pairs_.empty()) return pairs;
  pairs.insert(pairs.end(), fixed_patch_pairs_.begin(), fixed_patch_pairs_.end());
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

double PatchContact::min_distance(const Eigen::VectorXd& x, double limit) const {
  const double* p = place(x);
  // The candidates hold every pair nearer than `limit` where gather holds
  // for it (as after an evaluation at x); a search otherwise, which leaves
  // the candidates as they are.
  CollisionCandidates found;
  const bool gathered = candidates_scope_ == Scope::Everything && gather(limit, nullptr);
  if (!gathered) broad_phase_.find(p, nullptr, limit, found);
  const CollisionCandidates& near = gathered ? active_ : found;
  const CollisionMesh& m = mesh();
  double smallest = limit * limit;
  for (const IndexPair& pair : near.point_triangle) {
    const Tri& f = m.faces[pair[1]];
    const Vec3 q = point_at(p, pair[0]), a = point_at(p, f[0]), b = point_at(p, f[1]),
               c = point_at(p, f[2]);
    if (!point_triangle_farther(q, a, b, c, smallest))
      smallest = std::min(smallest, point_triangle_distance_squared(q, a, b, c));
  }
  for (const IndexPair& pair : near.edge_edge) {
    const auto& e = m.edges[pair[0]];
    const auto& h = m.edges[pair[1]];
    const Vec3 a0 = point_at(p, e[0]), a1 = point_at(p, e[1]), b0 = point_at(p, h[0]),
               b1 = point_at(p, h[1]);
    if (!edge_edge_farther(a0, a1, b0, b1, smallest))
      smallest = std::min(smallest, edge_edge_distance_squared(a0, a1, b0, b1));
  }
  double nearest = std::sqrt(smallest);
  for (int f = first_patch_face_; f < end_patch_face_; ++f) {
    const Tri& t = m.faces[f];
    for (const Obstacle& o : obstacles_)
      nearest = std::min(
          nearest, std::max(0.0, triangle_obstacle_distance(o, point_at(p, t[0]), point_at(p, t[1]),
                                                            point_at(p, t[2]))));
  }
  return nearest;
}

std::vector<Vec3> PatchContact::positions(const Eigen::VectorXd& x) const {
  const double* p = place(x);
  std::vector<Vec3> result(points_.size() / 3);
  for (size_t v = 0; v < result.size(); ++v) result[v] = point_at(p, static_cast<long>(v));
  return result;
}

double PatchObjective::step_bound(const Eigen::VectorXd& x, const Eigen::VectorXd& dx) const {
  return contact_ ? contact_->step_bound(x, dx, scope_) : 1.0;
}

double PatchObjective::value(const Eigen::VectorXd& x, Eigen::VectorXd* gradient) const {
  const double fabric = energy_.evaluate(x, gradient).total;
  if (!contact_) return fabric;
  const double barrier = contact_->evaluate(x, gradient, scope_);
  return std::isfinite(barrier) ? fabric + barrier : std::numeric_limits<double>::infinity();
}

}  // namespace foldfill
