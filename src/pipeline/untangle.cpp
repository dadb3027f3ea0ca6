#include "foldfill/untangle.h"

#include <array>
#include <cmath>
#include <memory>

#include "foldfill/metrics.h"
#include "foldfill/solver.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

// A point of a crossing curve: where edge (e0, e1) of one face passes
// through the plane of the other face (p0, p1, p2), at e0 + t (e1 - e0),
// with barycentric coordinates b in that face; or a shared vertex (e0 = e1).
struct CurvePoint {
  Vec3 at;
  int e0 = -1, e1 = -1;
  double t = 0;
  Tri face{-1, -1, -1};
  Vec3 b{0, 0, 0};
  Vec3 normal{0, 0, 0};     // the face's unit normal
  Vec3 direction{0, 0, 0};  // e1 - e0
};

// The point where segment (a, b) passes through triangle (p, q, r), strictly
// between its ends; false when it does not.
bool pierce(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q, const Vec3& r,
            CurvePoint& out) {
  Vec3 n = cross(sub(q, p), sub(r, p));
  const double length = norm(n);
  if (!(length > 0)) return false;
  n = scaled(n, 1 / length);
  const double sa = dot(n, sub(a, p)), sb = dot(n, sub(b, p));
  if (!(sa * sb < 0)) return false;
  const double t = sa / (sa - sb);
  const Vec3 x = add_scaled(a, sub(b, a), t);
  // Barycentric coordinates of x in (p, q, r), by the sub-triangles' areas.
  const double u = dot(n, cross(sub(q, x), sub(r, x))) / length;
  const double v = dot(n, cross(sub(r, x), sub(p, x))) / length;
  const double w = 1 - u - v;
  if (u < 0 || v < 0 || w < 0) return false;
  out.at = x;
  out.t = t;
  out.b = {u, v, w};
  out.normal = n;
  out.direction = sub(b, a);
  return true;
}

// The crossing segment of faces f and g (collision-mesh vertex indices):
// its two ends, false when the floating-point test finds fewer (the faces
// only touch, or are coplanar).
bool crossing_segment(const std::vector<Vec3>& p, const Tri& f, const Tri& g,
                      std::array<CurvePoint, 2>& ends) {
  std::array<CurvePoint, 6> found;
  int count = 0;
  const auto has = [](const Tri& t, int v) { return t[0] == v || t[1] == v || t[2] == v; };
  const auto edges_through = [&](const Tri& edges, const Tri& face) {
    for (int k = 0; k < 3; ++k) {
      const int a = edges[k], b = edges[(k + 1) % 3];
      if (has(face, a) || has(face, b)) continue;  // an edge at a shared vertex
      CurvePoint point;
      if (pierce(p[a], p[b], p[face[0]], p[face[1]], p[face[2]], point)) {
        point.e0 = a;
        point.e1 = b;
        point.face = face;
        found[count++] = point;
      }
    }
  };
  edges_through(f, g);
  edges_through(g, f);
  // A vertex the faces share lies on both: an end of their crossing.
  for (int v : f)
    if (has(g, v) && count < 6) {
      CurvePoint point;
      point.at = p[v];
      point.e0 = point.e1 = v;
      found[count++] = point;
    }
  if (count < 2) return false;
  // The two farthest apart (more than two only where an edge passes near a
  // corner of the other face).
  double best = -1;
  for (int i = 0; i < count; ++i)
    for (int j = i + 1; j < count; ++j) {
      const double d = distance(found[i].at, found[j].at);
      if (d > best) {
        best = d;
        ends = {found[i], found[j]};
      }
    }
  return best > 0;
}

// Adds (d point / d vertices)^T g to `gradient`, for the free vertices.
// x = e0 + t d lies on the face's plane: moving the edge moves x along the
// edge's projection onto the plane, moving the plane moves x along d by the
// plane's move at x (the face's corners weighted by x's barycentric
// coordinates).
void add_point_gradient(const CurvePoint& point, const Vec3& g, int fixed_count,
                        Eigen::VectorXd& gradient) {
  const auto add = [&](int v, const Vec3& value) {
    if (v < fixed_count) return;
    const Eigen::Index k = 3 * static_cast<Eigen::Index>(v - fixed_count);
    for (int c = 0; c < 3; ++c) gradient[k + c] += value[c];
  };
  if (point.e0 == point.e1) {  // a shared vertex
    add(point.e0, g);
    return;
  }
  const Vec3& n = point.normal;
  const double across = dot(g, point.direction) / dot(n, point.direction);
  const Vec3 along_plane = add_scaled(g, n, -across);
  add(point.e0, scaled(along_plane, 1 - point.t));
  add(point.e1, scaled(along_plane, point.t));
  for (int k = 0; k < 3; ++k) add(point.face[k], scaled(n, point.b[k] * across));
}

// crossing_curve_length at the collision-mesh positions `p`.
double curve_length(const std::vector<Vec3>& p, const CollisionMesh& mesh,
                    const std::vector<std::pair<int, int>>& pairs, Eigen::VectorXd* gradient) {
  double length = 0;
  std::array<CurvePoint, 2> ends;
  for (const auto& [f, g] : pairs) {
    if (!crossing_segment(p, mesh.faces[f], mesh.faces[g], ends)) continue;
    const Vec3 along = sub(ends[0].at, ends[1].at);
    const double l = norm(along);
    length += l;
    if (!gradient) continue;
    const Vec3 u = scaled(along, 1 / l);
    add_point_gradient(ends[0], u, mesh.fixed_count, *gradient);
    add_point_gradient(ends[1], scaled(u, -1), mesh.fixed_count, *gradient);
  }
  return length;
}

// `weight` times the crossing curves' length of a fixed list of face pairs,
// plus (x - anchor)^T P (x - anchor) / 2 with P the fabric energy's
// preconditioner (an elastic operator over the free vertices): the curves'
// pull moves the whole patch smoothly, not the crossing faces alone, and no
// further than shrinking the curves asks for.
class CrossingCurveObjective final : public Objective {
 public:
  CrossingCurveObjective(const PatchContact& contact, const std::vector<std::pair<int, int>>& pairs,
                         double weight, const Eigen::SparseMatrix<double>& stiffness,
                         const Eigen::VectorXd& anchor)
      : contact_(contact),
        pairs_(pairs),
        weight_(weight),
        stiffness_(stiffness),
        anchor_(anchor),
        points_(contact.positions(anchor)) {}
  Eigen::Index size() const override { return anchor_.size(); }
  double value(const Eigen::VectorXd& x, Eigen::VectorXd* gradient) const override {
    const Eigen::Index n = stiffness_.rows();
    double elastic = 0;
    d_.resize(n);
    if (gradient) gradient->resize(x.size());
    for (int c = 0; c < 3; ++c) {
      for (Eigen::Index v = 0; v < n; ++v) d_[v] = x[3 * v + c] - anchor_[3 * v + c];
      pd_.noalias() = stiffness_ * d_;
      elastic += 0.5 * d_.dot(pd_);
      if (gradient)
        for (Eigen::Index v = 0; v < n; ++v) (*gradient)[3 * v + c] = pd_[v];
    }
    // The fixed vertices stay where the anchor's positions put them.
    const size_t fixed = static_cast<size_t>(contact_.mesh().fixed_count);
    for (size_t v = fixed; v < points_.size(); ++v)
      for (int c = 0; c < 3; ++c) points_[v][c] = x[3 * static_cast<Eigen::Index>(v - fixed) + c];
    if (!gradient)
      return elastic + weight_ * curve_length(points_, contact_.mesh(), pairs_, nullptr);
    curve_.setZero(x.size());
    const double length = curve_length(points_, contact_.mesh(), pairs_, &curve_);
    *gradient += weight_ * curve_;
    return elastic + weight_ * length;
  }
  Eigen::SparseMatrix<double> preconditioner() const override { return stiffness_; }

 private:
  const PatchContact& contact_;
  const std::vector<std::pair<int, int>>& pairs_;
  double weight_;
  const Eigen::SparseMatrix<double>& stiffness_;
  const Eigen::VectorXd& anchor_;
  mutable std::vector<Vec3> points_;  // all collision-mesh positions, the free ones from x
  // Scratch of value(): one coordinate's move from the anchor, P times it,
  // the curves' gradient.
  mutable Eigen::VectorXd d_, pd_, curve_;
};

bool clean(const PatchContact& contact, const Eigen::VectorXd& x) {
  return crossing_pairs(contact, x).empty() && std::isfinite(contact.evaluate(x, nullptr));
}

}  // namespace

double crossing_curve_length(const PatchContact& contact,
                             const std::vector<std::pair<int, int>>& pairs,
                             const Eigen::VectorXd& x, Eigen::VectorXd* gradient) {
  return curve_length(contact.positions(x), contact.mesh(), pairs, gradient);
}

std::vector<std::pair<int, int>> crossing_pairs(const PatchContact& contact,
                                                const Eigen::VectorXd& x) {
  return intersecting_pairs(contact.positions(x), contact.mesh().faces, contact.first_patch_face(),
                            contact.end_patch_face(), contact.patch_face_pairs(x));
}

std::optional<Eigen::VectorXd> untangle(const FabricEnergy& energy, const PatchContact& contact,
                                        const Eigen::VectorXd& start,
                                        const UntangleOptions& options, const Budget& budget) {
  // What stays the same through the rounds: the contact's box trees, and P
  // (factored at the first round).
  if (clean(contact, start)) return start;
  const Eigen::SparseMatrix<double> stiffness = energy.preconditioner();
  const Eigen::Index n = stiffness.rows();
  if (n == 0) return std::nullopt;
  // The weights in units of P's mean diagonal, so that they mean the same
  // whatever the energy's weights.
  double diagonal = 0;
  for (Eigen::Index v = 0; v < n; ++v) diagonal += stiffness.coeff(v, v);
  diagonal /= static_cast<double>(n);
  // Determinism: the solver's defaults (no callback, no time limit of its
  // own) and the pairs in the box tree's order.
  SolverOptions solver;
  solver.max_iterations = options.iterations_per_round;
  solver.relative_energy_tol = options.relative_energy_tol;
  std::unique_ptr<FactoredPreconditioner> factor;
  for (double weight : options.weights) {
    Eigen::VectorXd x = start;
    for (int round = 0; round < options.rounds && !budget.spent(); ++round) {
      const std::vector<std::pair<int, int>> pairs = crossing_pairs(contact, x);
      if (pairs.empty()) break;
      const Eigen::VectorXd anchor = x;
      const CrossingCurveObjective objective(contact, pairs, weight * diagonal, stiffness, anchor);
      if (!factor) factor = std::make_unique<FactoredPreconditioner>(objective);
      x = minimize(objective, anchor, solver, budget, factor.get()).x;
    }
    if (clean(contact, x)) return x;
  }
  return std::nullopt;
}

}  // namespace foldfill
