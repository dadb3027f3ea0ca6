// Minimisation of the fabric energy over the free vertices.
//
// Two methods share the stopping rules, the callback and the guards:
// - GradientDescent: the paper's fixed step x -= step * grad E, each iterate
//   then projected outside the obstacles (section 3.4).
// - Fast: L-BFGS (Nocedal & Wright, algorithm 7.4) with initial inverse
//   Hessian gamma * P^-1. P = L + lambda * H_B + eps I is constant and
//   factored once (CHOLMOD, coordinate_cholesky.h; the factorisation counts
//   against the time limit): L is the unit-weight Laplacian of the spring
//   graph over the free vertices (the global matrix of projective dynamics, Bouaziz et al.
//   2014, used as an L-BFGS preconditioner by Liu et al. 2017, "Quasi-Newton
//   methods for real-time simulation of hyperelastic materials"), H_B the
//   constant bending Hessian (left out on very large patches and where it weighs little, see
//   preconditioner_matrix). gamma = s.y / y.P^-1.y from the newest curvature
//   pair is the preconditioned form of the usual scaling; it took 308 instead
//   of 404 iterations (gamma = 1) on Curtain. One solve per iteration: with z_k =
//   P^-1 g_k kept, P^-1 y_k = z_{k+1} - z_k, and the two-loop recursion's
//   P^-1 q is z minus the same combination of those (no solve of its own).
//   A backtracking Armijo line search makes every accepted step lower the
//   energy. Projective dynamics' own local/global iteration is this method
//   with no curvature pairs and gamma = 1 (x - P^-1 grad E is its global step
//   for springs); to the stopping rule it took 172 instead of 70 iterations on
//   sim1, 2982 instead of 307 on Curtain (prototype weights), so L-BFGS it is.
//
// Steps are limited per vertex: a vertex moves at most max_displacement per
// iteration, so the repulsion sees vertices approach before they can pass
// through each other. While the folds form, a few vertices on directions of
// negative curvature ask for long moves; clipping just those, rather than
// shortening the whole step to theirs, took 308 instead of 368 iterations on
// Curtain. (Measurements here: Curtain's hole with 3218 patch vertices and the
// prototype's weights, max_displacement 0.1.)
//
// Obstacles: the start and every trial point of the line search are projected
// outside (push_outside), and the Armijo test is made along the displacement
// the projection left, so the energy never rises with obstacles either. Like
// projected quasi-Newton methods, L-BFGS models the reduced gradient (without
// the parts that press touching vertices into an obstacle) and the step stops
// at the obstacles' surfaces, so that the projection changes it little. The
// previous version, which left contacts to the projection alone, stalled on
// sim2 (two cylinders and a sphere) at energy 7.75 where gradient descent
// reaches 2.38. A preconditioned step can be wrong near a contact (the
// projection is not in P's metric), so when both the L-BFGS and the P^-1
// directions fail, a plain projected gradient step is tried before declaring
// convergence. Vertices pressed against an obstacle (the parts of the
// gradient removed above) move only along its tangent plane: the normal part
// of their move is removed, outward as well as inward. With only the inward
// part stopped, the outward parts (lift-offs the coupling through P^-1 asks
// for, which the pressing gradient makes uphill) defeated both the L-BFGS and
// the P^-1 directions near contacts on almost every iteration, leaving the
// plain projected gradient step: sim2 took 8485 iterations instead of 1878
// now (same energy within 2e-6), and sim1 with the default weights (the
// patch lying on the sphere) crawled to the iteration cap (47658 iterations
// over its retries, 16 s) instead of converging in 2110 (0.6 s).
#include "foldfill/solver.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <string>
#include <vector>

#include "coordinate_cholesky.h"
#include "foldfill/error.h"
#include "lbfgs_recursion.h"

namespace foldfill {
namespace {

using Eigen::VectorXd;
// P^-1 only preconditions, so its factor is kept in single precision: a
// solve then streams half the bytes (25% less time at 120k vertices), and
// the operator applied is still symmetric positive definite (the exact
// inverse of L~ L~^T for the rounded factor L~).
using PreconditionerFactor = CoordinateCholesky<float>;
using Coordinates = PreconditionerFactor::Coordinates;

constexpr int kStallIterations = 10;  // consecutive small relative changes to converge
// The threshold of those changes, per method (SolverOptions::relative_energy_tol
// unset). Both rules aim at one accuracy, but how far from its minimum a
// method still is when its steps change the energy by so little depends on
// its rate of convergence. Gradient descent's fixed step converges linearly,
// at 0.9965 to 0.9998 per iteration on the reference and cloth cases that stop
// by the rule (Curtain, sim1, sim2, paper1, paper2, dev01): at changes of 1e-9
// it is still 3e-7 to 9e-6 (relative) above its limit, the rest of the
// geometric series change * r / (1 - r). L-BFGS ends much faster: stopped at
// changes of 1e-7 it is 4e-8 to 5e-7 above where it ends at 1e-9 (the nine
// cases that stop by the rule), as close as gradient descent gets, in 2 to
// 35 fewer iterations (the Curtain 118 instead of 149; dev06 381 instead of
// 686, its coarse level then ending elsewhere: a minimum 0.8% higher).
constexpr double kDescentRelativeTol = 1e-9;
constexpr double kFastRelativeTol = 1e-7;
constexpr double kDivergenceFactor = 1e3;  // energy above this times the start's: diverged
constexpr int kLbfgsMemory = 10;
constexpr double kArmijo = 1e-4;                      // sufficient-decrease constant
constexpr int kMaxBacktracks = 40;                    // the step shrinks to 2^-40 at most
constexpr double kRegularisation = 1e-8;              // relative to the mean diagonal of P
constexpr int kLargestBendingPreconditioner = 40000;  // free vertices (see preconditioner_matrix)
constexpr double kSmallestBendingShare = 0.01;        // of the springs' diagonal (ditto)
// A vertex within this fraction of max_displacement of an obstacle, pressed
// towards it, counts as touching it (see close_contact_gaps). sim2 took 1820
// iterations with 1e-6 / 0.2 (only vertices on the surface), 342, 310 and
// 346 with 0.005, 0.01 and 0.015, 523 with 0.05 and 6935 with 0.25. Its
// crumpled minima differ by a fraction of a percent: energy 2.3741, 2.3699
// and 2.3740 with those three (gradient descent 2.3705).
constexpr double kContactReach = 0.01;

struct Iterate {
  VectorXd x;
  double energy = 0;
  VectorXd gradient;
};

bool is_finite(const Iterate& it) { return std::isfinite(it.energy) && it.gradient.allFinite(); }

// Evaluates the energy and gradient at it.x (buffers reused).
void evaluate(const FabricEnergy& energy, Iterate& it) {
  if (!it.x.allFinite()) {
    it.energy = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  it.energy = energy.evaluate(it.x, &it.gradient).total;
}

// Root mean square of the per-vertex gradient norms.
double rms_gradient(const VectorXd& gradient) {
  return gradient.size() == 0 ? 0.0 : std::sqrt(3.0 * gradient.squaredNorm() / gradient.size());
}

Eigen::Map<Coordinates> per_vertex(VectorXd& v) { return {v.data(), v.size() / 3, 3}; }
Eigen::Map<const Coordinates> per_vertex(const VectorXd& v) { return {v.data(), v.size() / 3, 3}; }

Vec3 vertex(const VectorXd& x, Eigen::Index offset) {
  return {x[offset], x[offset + 1], x[offset + 2]};
}

Eigen::Vector3d surface_normal(const Obstacle& obstacle, const Vec3& p) {
  const Vec3 normal = outward_normal(obstacle, p);
  return {normal[0], normal[1], normal[2]};
}

// The obstacle helpers below test farther_than before the exact distance
// and the normal: on sim2 (two cylinders and a sphere) they were 16% of the
// fill.

// Projects every free vertex outside every obstacle.
void project_outside(const std::vector<Obstacle>& obstacles, VectorXd& x) {
  if (obstacles.empty()) return;
  for (Eigen::Index v = 0; v + 2 < x.size(); v += 3) {
    Vec3 p = vertex(x, v);
    bool moved = false;
    for (const Obstacle& obstacle : obstacles)
      if (!farther_than(obstacle, p, 0)) moved = push_outside(obstacle, p) || moved;
    if (moved) x.segment<3>(v) = Eigen::Vector3d(p[0], p[1], p[2]);
  }
}

// Limits the part of the displacement `motion` that goes into an obstacle:
// a vertex stops at the (tangent plane of the) surface, and one touching it
// slides along it. Left to the projection of the trial points, those parts
// bend the step away from its direction: on sim2 (two cylinders and a
// sphere) vertices that had lifted off the surface by a hair were pushed back
// in by a large step, the projected step went uphill, and the line search
// needed some 15 halvings every other iteration.
void stop_at_obstacles(const std::vector<Obstacle>& obstacles, const VectorXd& x,
                       VectorXd& motion) {
  for (Eigen::Index v = 0; v + 2 < x.size(); v += 3) {
    const Vec3 p = vertex(x, v);
    auto move = motion.segment<3>(v);
    for (const Obstacle& obstacle : obstacles) {
      const double length = move.norm();
      if (farther_than(obstacle, p, length)) continue;
      const double clearance = std::max(signed_distance(obstacle, p), 0.0);
      if (!(clearance < length)) continue;  // cannot reach the surface
      const Eigen::Vector3d normal = surface_normal(obstacle, p);
      const double inward = normal.dot(move);
      if (inward < -clearance) move += (-clearance - inward) * normal;
    }
  }
}

// A vertex pressed against an obstacle: its index in the variables (x, y, z
// at 3 * vertex) and the obstacle's outward normal there.
struct Contact {
  Eigen::Index offset;
  Eigen::Vector3d normal;
  double clearance;  // the distance to the surface, >= 0
};

// The gradient without the parts that press touching vertices (those within
// `reach` of an obstacle) into the obstacles (the reduced gradient of
// projected methods): what L-BFGS models. `contacts` receives the vertices
// whose part was removed.
void reduce_gradient(const std::vector<Obstacle>& obstacles, const VectorXd& x,
                     const VectorXd& gradient, double reach, VectorXd& reduced,
                     std::vector<Contact>& contacts) {
  reduced = gradient;
  contacts.clear();
  for (Eigen::Index v = 0; v + 2 < x.size(); v += 3) {
    const Vec3 p = vertex(x, v);
    for (const Obstacle& obstacle : obstacles) {
      if (farther_than(obstacle, p, reach)) continue;
      const double clearance = signed_distance(obstacle, p);
      if (!(clearance < reach)) continue;
      const Eigen::Vector3d normal = surface_normal(obstacle, p);
      const double pressing = normal.dot(reduced.segment<3>(v));  // > 0: -gradient points in
      if (pressing > 0) {
        reduced.segment<3>(v) -= pressing * normal;
        contacts.push_back({v, normal, std::max(clearance, 0.0)});
      }
    }
  }
}

// Keeps pressed vertices on their obstacle's tangent plane: the normal part
// of their move is removed, outward as well as inward.
void slide_along_contacts(const std::vector<Contact>& contacts, VectorXd& motion) {
  for (const Contact& contact : contacts) {
    auto move = motion.segment<3>(contact.offset);
    move -= contact.normal.dot(move) * contact.normal;
  }
}

// Moves pressed vertices that hover within reach of their obstacle onto its
// surface, the pressing gradient's way (down in energy): the vertices near an
// obstacle take a projected gradient step, the others the quasi-Newton one,
// as in the two-metric projection methods with an epsilon-active set
// (Bertsekas 1982, "Projected Newton methods for optimization problems with
// simple constraints"). Counted as free instead, such vertices were pushed in
// by the quasi-Newton direction, stopped at the surface by
// stop_at_obstacles, and what was left of the step often went uphill: on
// sim2, 1210 of 1878 iterations fell back to a plain gradient step.
void close_contact_gaps(const std::vector<Contact>& contacts, VectorXd& motion) {
  for (const Contact& contact : contacts)
    motion.segment<3>(contact.offset) -= contact.clearance * contact.normal;
}

enum class Advance {
  Moved,    // `current` is the next iterate
  Stuck,    // no step lowers the energy any more
  Stopped,  // the budget was spent during the step; `current` is unchanged
};

// One step of a method: replaces `current` by the next iterate.
class Stepper {
 public:
  virtual ~Stepper() = default;
  virtual Advance advance(Iterate& current) = 0;
};

class GradientDescent final : public Stepper {
 public:
  GradientDescent(const FabricEnergy& energy, const std::vector<Obstacle>& obstacles, double step)
      : energy_(energy), obstacles_(obstacles), step_(step) {}

  Advance advance(Iterate& current) override {
    current.x -= step_ * current.gradient;
    project_outside(obstacles_, current.x);
    evaluate(energy_, current);
    return Advance::Moved;
  }

 private:
  const FabricEnergy& energy_;
  const std::vector<Obstacle>& obstacles_;
  double step_;
};

// Adds weight * the Laplacian of `springs` over the free vertices to `entries`.
void add_spring_laplacian(const std::vector<FabricEnergy::Spring>& springs, int fixed,
                          double weight, std::vector<Eigen::Triplet<double>>& entries) {
  for (const FabricEnergy::Spring& s : springs) {
    const int i = s.i - fixed, j = s.j - fixed;
    if (i >= 0) entries.emplace_back(i, i, weight);
    if (j >= 0) entries.emplace_back(j, j, weight);
    if (i >= 0 && j >= 0) {
      entries.emplace_back(i, j, -weight);
      entries.emplace_back(j, i, -weight);
    }
  }
}

// Adds weight * the free block of `hessian` (over all domain vertices, the
// first `fixed` of them fixed) to `entries`.
void add_free_block(const Eigen::SparseMatrix<double>& hessian, int fixed, double weight,
                    std::vector<Eigen::Triplet<double>>& entries) {
  for (int col = fixed; col < hessian.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(hessian, col); it; ++it)
      if (it.row() >= fixed)
        entries.emplace_back(static_cast<int>(it.row()) - fixed, col - fixed, weight * it.value());
}

double diagonal_sum(const std::vector<Eigen::Triplet<double>>& entries) {
  double sum = 0;
  for (const Eigen::Triplet<double>& entry : entries)
    if (entry.row() == entry.col()) sum += entry.value();
  return sum;
}

// P = unit spring Laplacian + its bending part + eps I over the free vertices
// (one coordinate), the preconditioner described at the top. The bending part
// is lambda times the two-ring model's bending springs' Laplacian or the
// quadratic model's bending Hessian. It makes the factor denser (a two-ring
// stencil), and is left out where it buys too little:
// - where it weighs under kSmallestBendingShare of the springs' diagonal. At
//   the default lambda 2e-4 it weighs 0.2% (0.01 to 0.05% on coarse levels),
//   at the prototype's weights 6% to 110% (paper2's lambda 7e-5: 0.07%): P is
//   then the same operator to a fraction of a percent, and its solves 40%
//   cheaper (dev06, callgrind). Left out at lambda 2e-4 (bench_fill --skip-gd
//   --runs 3): dev02, dev04, dev05 and dev06 11 to 18% less time in the same
//   minima, dev01 6%, the folded sheets 13 to 25% from 1k to 22k patch
//   vertices; dev03 23% in another minimum, 2.3% higher. Left out at the
//   prototype's weights (no rule does that now), it took Contour 112 instead
//   of 82 iterations, paper1 38 instead of 21.
// - on the quadratic model's patches above kLargestBendingPreconditioner free
//   vertices, where the dearer solves outweigh the iterations it saves
//   (measured on folded sheets: 336 instead of 436 iterations and 15% less
//   time at 22k free vertices; at 120k, with the supernodal factor, whose
//   factorisation is now cheap either way, 447 instead of 545 iterations but
//   75% more time per iteration: its factor holds 106 instead of 42 entries
//   per vertex).
Eigen::SparseMatrix<double> preconditioner_matrix(const FabricEnergy& energy) {
  const int fixed = energy.domain().fixed_count;
  const int free_count = energy.domain().free_count();
  const double lambda = energy.options().lambda;
  std::vector<Eigen::Triplet<double>> entries, bending;
  add_spring_laplacian(energy.springs(), fixed, 1.0, entries);
  add_spring_laplacian(energy.two_ring_springs(), fixed, lambda, bending);
  if (free_count <= kLargestBendingPreconditioner)
    add_free_block(energy.bending_hessian(), fixed, lambda, bending);
  if (diagonal_sum(bending) >= kSmallestBendingShare * diagonal_sum(entries))
    entries.insert(entries.end(), bending.begin(), bending.end());
  Eigen::SparseMatrix<double> p(free_count, free_count);
  p.setFromTriplets(entries.begin(), entries.end());

  double mean_diagonal = 0;
  for (int k = 0; k < free_count; ++k) mean_diagonal += p.coeff(k, k);
  mean_diagonal = std::max(mean_diagonal / free_count, 1.0);
  for (int k = 0; k < free_count; ++k) p.coeffRef(k, k) += kRegularisation * mean_diagonal;
  return p;
}

// Clips each vertex's displacement in `direction` to `limit`.
void clip_per_vertex(VectorXd& direction, double limit) {
  auto rows = per_vertex(direction);
  for (Eigen::Index v = 0; v < rows.rows(); ++v) {
    const double length = rows.row(v).norm();
    if (length > limit) rows.row(v) *= limit / length;
  }
}

class Lbfgs final : public Stepper {
 public:
  Lbfgs(const FabricEnergy& energy, const std::vector<Obstacle>& obstacles, double max_displacement,
        const Budget& budget)
      : energy_(energy),
        obstacles_(obstacles),
        budget_(budget),
        max_displacement_(max_displacement),
        contact_reach_(kContactReach * max_displacement),
        factor_(preconditioner_matrix(energy), OrderingEffort::Thorough,
                "solver: the preconditioner could not be factored") {}

  Advance advance(Iterate& current) override {
    if (!started_) pressed_ = prepare(current, reduced_, preconditioned_, contacts_);
    started_ = true;
    search_direction();
    Search found = line_search(current);
    if (found == Search::Failed && !pairs_.empty()) {
      // The pairs can give a poor direction (stale ones, or one that mostly
      // presses vertices into an obstacle): step along -P^-1 g this once.
      // Dropping the pairs instead took thousands of iterations on sim2.
      direction_ = -preconditioned_;
      found = line_search(current);
    }
    if (found == Search::Failed) {  // near a contact P^-1 can point the wrong way (see the top)
      direction_ = -reduced_;
      found = line_search(current);
    }
    if (found == Search::Stopped) return Advance::Stopped;
    if (found == Search::Failed) return Advance::Stuck;
    const bool next_pressed = prepare(next_, next_reduced_, next_preconditioned_, next_contacts_);
    remember(current, pressed_ || next_pressed);
    std::swap(current, next_);
    std::swap(reduced_, next_reduced_);
    std::swap(preconditioned_, next_preconditioned_);
    std::swap(contacts_, next_contacts_);
    pressed_ = next_pressed;
    return Advance::Moved;
  }

 private:
  // result = P^-1 v.
  void solve(const VectorXd& v, VectorXd& result) const {
    result.resize(v.size());
    auto rows = per_vertex(result);
    factor_.solve(per_vertex(v), rows);
  }

  // The reduced gradient of `it` and P^-1 of it; returns whether it differs
  // from the gradient.
  bool prepare(const Iterate& it, VectorXd& reduced, VectorXd& preconditioned,
               std::vector<Contact>& contacts) const {
    reduce_gradient(obstacles_, it.x, it.gradient, contact_reach_, reduced, contacts);
    solve(reduced, preconditioned);
    return !contacts.empty();
  }

  // direction_ = -H g (g the reduced gradient) by two_loop_recursion. Falls
  // back to -P^-1 g (dropping the pairs) when the result is not a descent
  // direction.
  void search_direction() {
    if (pairs_.empty()) {
      direction_ = -preconditioned_;
      return;
    }
    const double slope =
        two_loop_recursion(pairs_, gamma_, reduced_, preconditioned_, alpha_, q_, direction_);
    if (!(slope < 0)) {
      pairs_.clear();
      direction_ = -preconditioned_;
    }
  }

  // step_ = direction_ slid along the contacts, each vertex's move clipped to
  // the maximum displacement and stopped at the obstacles, plus the moves
  // that close the contacts' gaps; false when that is no descent direction.
  bool make_step(const Iterate& current) {
    slide_along_contacts(contacts_, direction_);
    if (!(current.gradient.dot(direction_) < 0)) return false;
    step_ = direction_;
    clip_per_vertex(step_, max_displacement_);
    meet_obstacles(current);
    if (current.gradient.dot(step_) < 0) return true;
    // Clipping undid the descent: shrink the whole direction instead.
    step_ = direction_ * (max_displacement_ / per_vertex(direction_).rowwise().norm().maxCoeff());
    meet_obstacles(current);
    return current.gradient.dot(step_) < 0;
  }

  // step_ stopped at the obstacles, plus the moves that close the contacts' gaps.
  void meet_obstacles(const Iterate& current) {
    if (!obstacles_.empty()) stop_at_obstacles(obstacles_, current.x, step_);
    close_contact_gaps(contacts_, step_);
  }

  enum class Search { Found, Failed, Stopped };

  // Backtracking along direction_, each vertex's move clipped to the maximum
  // displacement, until the projected trial point satisfies the Armijo
  // condition along the displacement it actually made; the result in next_.
  // The budget is looked at before each trial point.
  Search line_search(const Iterate& current) {
    if (!make_step(current)) return Search::Failed;
    double t = 1;
    for (int k = 0; k < kMaxBacktracks; ++k, t *= 0.5) {
      if (budget_.spent()) return Search::Stopped;
      next_.x = current.x + t * step_;
      project_outside(obstacles_, next_.x);
      const double predicted = std::min(current.gradient.dot(next_.x - current.x), 0.0);
      evaluate(energy_, next_);
      if (is_finite(next_) && next_.energy <= current.energy + kArmijo * predicted &&
          next_.energy < current.energy)
        return Search::Found;
    }
    return Search::Failed;
  }

  // Keeps the pair (s, y) of the step from `current` to next_ among the last
  // kLbfgsMemory, the oldest pair's vectors reused. y is the change of the
  // full gradient, which is smooth, unlike the reduced one: a vertex that
  // comes to touch an obstacle makes the reduced gradient jump, and pairs
  // made of such jumps shrank the steps a thousandfold on sim2. P^-1 y is
  // P^-1 g_next - P^-1 g, both at hand, unless an obstacle was pressed on
  // (`pressed`): then the gradients were reduced and y needs its own solve.
  void remember(const Iterate& current, bool pressed) {
    s_ = next_.x - current.x;
    y_ = next_.gradient - current.gradient;
    const double sy = s_.dot(y_);
    // Only pairs with positive curvature keep the inverse Hessian positive.
    if (!(sy > std::numeric_limits<double>::epsilon() * s_.norm() * y_.norm())) return;
    CurvaturePair pair;
    if (static_cast<int>(pairs_.size()) == kLbfgsMemory) {
      pair = std::move(pairs_.front());
      pairs_.pop_front();
    }
    std::swap(pair.s, s_);
    std::swap(pair.y, y_);
    if (pressed) {
      solve(pair.y, pair.preconditioned_y);
    } else {
      pair.preconditioned_y = next_preconditioned_ - preconditioned_;
    }
    pair.rho = 1 / sy;
    const double y_preconditioned_y = pair.y.dot(pair.preconditioned_y);
    if (y_preconditioned_y > 0) gamma_ = sy / y_preconditioned_y;
    pairs_.push_back(std::move(pair));
  }

  const FabricEnergy& energy_;
  const std::vector<Obstacle>& obstacles_;
  const Budget& budget_;
  double max_displacement_;
  double contact_reach_;  // see kContactReach
  PreconditionerFactor factor_;
  std::deque<CurvaturePair> pairs_;  // oldest first
  double gamma_ =
      1;  // (y . s) / (y . P^-1 y) of the newest pair: P^-1 scaled to the curvature seen
  bool started_ = false;
  bool pressed_ = false;  // the current reduced gradient differs from the gradient
  // The reduced gradient and P^-1 of it at the current and the next iterate.
  VectorXd reduced_, next_reduced_, preconditioned_, next_preconditioned_;
  std::vector<Contact> contacts_, next_contacts_;  // the pressed vertices there
  VectorXd q_, direction_, step_, s_, y_;
  std::vector<double> alpha_;
  Iterate next_;
};

void check_inputs(const FabricEnergy& energy, const std::vector<Vec3>& start,
                  const SolverOptions& options) {
  if (static_cast<int>(start.size()) != energy.domain().vertex_count())
    throw Error(ErrorKind::Internal, "solver: start has " + std::to_string(start.size()) +
                                         " positions for a domain of " +
                                         std::to_string(energy.domain().vertex_count()));
  if (options.kind == SolverKind::GradientDescent &&
      !(options.step > 0 && std::isfinite(options.step)))
    throw Error(ErrorKind::Usage, "solver: the gradient descent step must be positive");
}

// Runs `stepper` under the shared stopping rules and returns the lowest-energy
// iterate seen (the last one, unless gradient descent went up). The progress
// callback's gradient_norm is the RMS per free vertex, the gradient_tol measure.
// The budget counts from the call of minimize_energy, so that it covers the
// set-up (the preconditioner's factorisation) too.
SolverResult run(const FabricEnergy& energy, Stepper& stepper, Iterate& current,
                 const SolverOptions& options, const Budget& budget) {
  const double divergence_limit = kDivergenceFactor * current.energy;
  VectorXd best_x = current.x;
  double best_energy = current.energy;
  SolverResult result;
  const double relative_tol = options.relative_energy_tol.value_or(
      options.kind == SolverKind::GradientDescent ? kDescentRelativeTol : kFastRelativeTol);
  int stalled = 0;
  auto finish = [&](const char* reason) {
    result.positions = energy.positions(best_x);
    result.stop_reason = reason;
    return result;
  };

  const auto stopped = [&] { return finish(budget.cancelled() ? "cancelled" : "time_limit"); };
  while (true) {
    if (rms_gradient(current.gradient) < options.gradient_tol) return finish("converged");
    if (result.iterations >= options.max_iterations) return finish("max_iterations");
    if (budget.spent()) return stopped();
    const double previous = current.energy;
    const Advance advanced = stepper.advance(current);
    if (advanced == Advance::Stopped) return stopped();
    if (advanced == Advance::Stuck) return finish("converged");
    ++result.iterations;
    if (!is_finite(current) || (divergence_limit > 0 && current.energy > divergence_limit))
      return finish("diverged");
    if (current.energy < best_energy) {
      best_x = current.x;
      best_energy = current.energy;
    }
    if (options.progress &&
        !options.progress({result.iterations, current.energy, rms_gradient(current.gradient)}))
      return finish("cancelled");
    if (options.watch && result.iterations == options.watch_iteration &&
        !options.watch(energy.positions(current.x)))
      return finish("abandoned");
    const double change = std::abs(current.energy - previous) /
                          std::max(current.energy, std::numeric_limits<double>::min());
    stalled = change < relative_tol ? stalled + 1 : 0;
    if (stalled >= kStallIterations) return finish("converged");
  }
}

}  // namespace

SolverResult minimize_energy(const FabricEnergy& energy, const std::vector<Obstacle>& obstacles,
                             const std::vector<Vec3>& start, const SolverOptions& options,
                             const Budget& budget) {
  const Budget limited = budget.at_most(options.time_limit_seconds);
  check_inputs(energy, start, options);
  Iterate first;
  first.x = energy.variables(start);
  if (!first.x.allFinite()) return {start, 0, "diverged"};
  project_outside(obstacles, first.x);
  evaluate(energy, first);
  if (!is_finite(first)) return {start, 0, "diverged"};
  if (energy.domain().free_count() == 0) return {energy.positions(first.x), 0, "converged"};
  if (limited.spent())  // before the preconditioner's factorisation
    return {energy.positions(first.x), 0, limited.cancelled() ? "cancelled" : "time_limit"};

  if (options.kind == SolverKind::GradientDescent) {
    GradientDescent stepper(energy, obstacles, options.step);
    return run(energy, stepper, first, options, limited);
  }
  Lbfgs stepper(energy, obstacles, options.max_displacement, limited);
  return run(energy, stepper, first, options, limited);
}

}  // namespace foldfill
