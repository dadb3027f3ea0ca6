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

void check_options(const ContactOptions& options) {
  const auto positive = [](double w) { return std::isfinite(w) && w > 0; };
  if (!positive(options.thickness) || !positive(options.stiffness) || !positive(options.skin))
    throw UsageError("contact: thickness, stiffness and skin must be positive");
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
}

const double* PatchContact::place(const Eigen::VectorXd& x) const {
  const size_t offset = 3 * static_cast<size_t>(fixed_count_);
  if (static_cast<size_t>(x.size()) + offset != points_.size())
    throw InternalError("contact: " + std::to_string(x.size()) + " variables for a patch of " +
                        std::to_string((points_.size() - offset) / 3) + " free vertices");
  std::copy(x.data(), x.data() + x.size(), points_.begin() + static_cast<std::ptrdiff_t>(offset));
  return points_.data();
}

// The candidates within thickness + skin of the current points, their
// distances there, and those points as the anchor they are valid around:
// while no free vertex has moved more than `drift` from it, a pair closer
// than thickness + skin - 2 drift is among them, with an anchor distance
// below its distance + 2 drift.
void PatchContact::refresh_candidates() const {
  const double reach = options_.thickness + options_.skin;
  broad_phase_.find(points_.data(), nullptr, reach, candidates_);
  const CollisionMesh& m = mesh();
  const double* p = points_.data();
  const auto point = [&](int v) { return Vec3{p[3 * v], p[3 * v + 1], p[3 * v + 2]}; };
  // Only the pairs closer than the reach are kept, with their distances.
  size_t kept = 0;
  point_triangle_distance_.clear();
  for (const IndexPair& pair : candidates_.point_triangle) {
    const Tri& f = m.faces[pair[1]];
    const double d = std::sqrt(
        point_triangle_distance_squared(point(pair[0]), point(f[0]), point(f[1]), point(f[2])));
    if (!(d < reach)) continue;
    candidates_.point_triangle[kept++] = pair;
    point_triangle_distance_.push_back(d);
  }
  candidates_.point_triangle.resize(kept);
  kept = 0;
  edge_edge_distance_.clear();
  for (const IndexPair& pair : candidates_.edge_edge) {
    const auto& a = m.edges[pair[0]];
    const auto& b = m.edges[pair[1]];
    const double d =
        std::sqrt(edge_edge_distance_squared(point(a[0]), point(a[1]), point(b[0]), point(b[1])));
    if (!(d < reach)) continue;
    candidates_.edge_edge[kept++] = pair;
    edge_edge_distance_.push_back(d);
  }
  candidates_.edge_edge.resize(kept);
  anchor_ = points_;
  has_candidates_ = true;
  ++candidate_searches_;
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
// apart at the anchor, and can since have come closer by at most twice the
// largest distance of a free vertex from its anchor position: at the current
// points, or anywhere along the step `move` (at its start or its end, the
// distance to a point being convex along a segment).
bool PatchContact::gather(double distance, const double* move) const {
  if (!has_candidates_) return false;
  double drift = 0;
  for (size_t k = 3 * static_cast<size_t>(fixed_count_); k < points_.size(); k += 3) {
    const double dx = points_[k] - anchor_[k], dy = points_[k + 1] - anchor_[k + 1],
                 dz = points_[k + 2] - anchor_[k + 2];
    drift = std::max(drift, dx * dx + dy * dy + dz * dz);
    if (!move) continue;
    const double ex = dx + move[k], ey = dy + move[k + 1], ez = dz + move[k + 2];
    drift = std::max(drift, ex * ex + ey * ey + ez * ez);
  }
  const double closer = 2 * std::sqrt(drift);
  if (!(distance + closer < options_.thickness + options_.skin)) return false;
  select_candidates(distance + closer);
  return true;
}

double PatchContact::evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* gradient) const {
  place(x);
  if (!gather(options_.thickness, nullptr)) {
    refresh_candidates();
    gather(options_.thickness, nullptr);
  }
  double* full_gradient = nullptr;
  if (gradient) {
    gradient_.assign(points_.size(), 0.0);
    full_gradient = gradient_.data();
  }
  double value = barrier_potential(mesh(), points_.data(), active_, options_.thickness,
                                   options_.stiffness, full_gradient);
  if (std::isfinite(value)) value += obstacle_barrier(full_gradient);
  if (gradient && std::isfinite(value)) {
    const size_t offset = 3 * static_cast<size_t>(fixed_count_);
    for (Eigen::Index k = 0; k < gradient->size(); ++k)
      (*gradient)[k] += gradient_[offset + static_cast<size_t>(k)];
  }
  return value;
}

double PatchContact::step_bound(const Eigen::VectorXd& x, const Eigen::VectorXd& dx) const {
  place(x);
  const size_t offset = 3 * static_cast<size_t>(fixed_count_);
  std::copy(dx.data(), dx.data() + dx.size(),
            displacement_.begin() + static_cast<std::ptrdiff_t>(offset));
  // The pairs that may meet during the step: the candidates' (gather), or,
  // for a step too long for them even when fresh, those of the swept boxes.
  if (!gather(0.0, displacement_.data())) {
    // Fresh candidates around the step's end: every point of the step is
    // within its move of there, and the next step starts there (most steps
    // are taken whole), so that they last for it as well.
    for (size_t k = offset; k < points_.size(); ++k) points_[k] += displacement_[k];
    refresh_candidates();
    place(x);
    if (!gather(0.0, displacement_.data()))
      broad_phase_.find(points_.data(), displacement_.data(), 0.0, active_);
  }
  const double bound =
      collision_step_bound(mesh(), points_.data(), displacement_.data(), active_, options_.ccd);
  return obstacle_step_bound(bound);
}

namespace {

// A lower bound on triangle_obstacle_distance for a face whose corners all
// lie within `radius` of `centre`: the centre's own distance less the radius
// (the distance to a sphere, a capsule or a plane is 1-Lipschitz).
double lower_bound(const Obstacle& o, const Vec3& centre, double radius) {
  Vec3 d;
  switch (o.type) {
    case Obstacle::Type::Plane: {
      double s = 0;
      for (int c = 0; c < 3; ++c) s += (centre[c] - o.center[c]) * o.normal[c];
      return s - radius;
    }
    case Obstacle::Type::Cylinder: {
      double t = 0;
      for (int c = 0; c < 3; ++c) t += (centre[c] - o.center[c]) * o.axis[c];
      t = std::clamp(t, -0.5 * o.height, 0.5 * o.height);
      for (int c = 0; c < 3; ++c) d[c] = centre[c] - (o.center[c] + t * o.axis[c]);
      break;
    }
    default:
      for (int c = 0; c < 3; ++c) d[c] = centre[c] - o.center[c];
  }
  return std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - o.radius - radius;
}

// The centroid of a triangle and the largest distance from it to a corner.
double bounding_ball(const Vec3& a, const Vec3& b, const Vec3& c, Vec3& centre) {
  for (int k = 0; k < 3; ++k) centre[k] = (a[k] + b[k] + c[k]) / 3;
  const auto squared = [&](const Vec3& p) {
    const double x = p[0] - centre[0], y = p[1] - centre[1], z = p[2] - centre[2];
    return x * x + y * y + z * z;
  };
  return std::sqrt(std::max({squared(a), squared(b), squared(c)}));
}

}  // namespace

double PatchContact::obstacle_barrier(double* gradient) const {
  if (obstacles_.empty()) return 0;
  const CollisionMesh& m = mesh();
  const double* p = points_.data();
  const auto point = [&](int v) { return Vec3{p[3 * v], p[3 * v + 1], p[3 * v + 2]}; };
  double sum = 0;
  std::array<Vec3, 3> g;
  for (int f = first_patch_face_; f < end_patch_face_; ++f) {
    const Tri& t = m.faces[f];
    const Vec3 a = point(t[0]), b = point(t[1]), c = point(t[2]);
    Vec3 centre;
    const double radius = bounding_ball(a, b, c, centre);
    for (const Obstacle& o : obstacles_) {
      if (lower_bound(o, centre, radius) >= options_.thickness) continue;
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
  }
  return sum;
}

double PatchContact::obstacle_step_bound(double t_max) const {
  if (obstacles_.empty()) return t_max;
  const CollisionMesh& m = mesh();
  const double* p = points_.data();
  const double* d = displacement_.data();
  const auto point = [&](const double* q, int v) {
    return Vec3{q[3 * v], q[3 * v + 1], q[3 * v + 2]};
  };
  CcdOptions ccd = options_.ccd;
  for (int f = first_patch_face_; f < end_patch_face_ && t_max > 0; ++f) {
    const Tri& t = m.faces[f];
    const Vec3 a = point(p, t[0]), b = point(p, t[1]), c = point(p, t[2]);
    const Vec3 da = point(d, t[0]), db = point(d, t[1]), dc = point(d, t[2]);
    const double move = std::sqrt(std::max({da[0] * da[0] + da[1] * da[1] + da[2] * da[2],
                                            db[0] * db[0] + db[1] * db[1] + db[2] * db[2],
                                            dc[0] * dc[0] + dc[1] * dc[1] + dc[2] * dc[2]}));
    Vec3 centre;
    const double radius = bounding_ball(a, b, c, centre);
    for (const Obstacle& o : obstacles_) {
      // A face that cannot reach the obstacle within t_max: its distance
      // falls by at most its largest corner's move.
      if (lower_bound(o, centre, radius) > move * t_max) continue;
      ccd.t_max = t_max;
      t_max = triangle_obstacle_ccd(o, a, b, c, da, db, dc, ccd);
    }
  }
  return t_max;
}

double PatchContact::min_distance(const Eigen::VectorXd& x, double limit) const {
  const double* p = place(x);
  CollisionCandidates near;
  broad_phase_.find(p, nullptr, limit, near);
  const CollisionMesh& m = mesh();
  const auto point = [&](int v) { return Vec3{p[3 * v], p[3 * v + 1], p[3 * v + 2]}; };
  double smallest = limit * limit;
  for (const IndexPair& pair : near.point_triangle) {
    const Tri& f = m.faces[pair[1]];
    smallest = std::min(smallest, point_triangle_distance_squared(point(pair[0]), point(f[0]),
                                                                  point(f[1]), point(f[2])));
  }
  for (const IndexPair& pair : near.edge_edge) {
    const auto& a = m.edges[pair[0]];
    const auto& b = m.edges[pair[1]];
    smallest = std::min(
        smallest, edge_edge_distance_squared(point(a[0]), point(a[1]), point(b[0]), point(b[1])));
  }
  double nearest = std::sqrt(smallest);
  for (int f = first_patch_face_; f < end_patch_face_; ++f) {
    const Tri& t = m.faces[f];
    for (const Obstacle& o : obstacles_)
      nearest = std::min(nearest, std::max(0.0, triangle_obstacle_distance(
                                                    o, point(t[0]), point(t[1]), point(t[2]))));
  }
  return nearest;
}

std::vector<Vec3> PatchContact::positions(const Eigen::VectorXd& x) const {
  const double* p = place(x);
  std::vector<Vec3> result(points_.size() / 3);
  for (size_t v = 0; v < result.size(); ++v) result[v] = {p[3 * v], p[3 * v + 1], p[3 * v + 2]};
  return result;
}

double PatchObjective::step_bound(const Eigen::VectorXd& x, const Eigen::VectorXd& dx) const {
  return contact_ ? contact_->step_bound(x, dx) : 1.0;
}

double PatchObjective::value(const Eigen::VectorXd& x, Eigen::VectorXd* gradient) const {
  const double fabric = energy_.evaluate(x, gradient).total;
  if (!contact_) return fabric;
  const double barrier = contact_->evaluate(x, gradient);
  return std::isfinite(barrier) ? fabric + barrier : std::numeric_limits<double>::infinity();
}

}  // namespace foldfill
