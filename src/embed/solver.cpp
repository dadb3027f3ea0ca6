// Minimisation of an Objective over its variables.
//
// Two methods share the stopping rules, the callback, the budget and the
// step bound:
// - GradientDescent: the paper's fixed step x -= step * grad E (section 3.4),
//   shortened where the objective's step bound asks for it.
// - Fast: L-BFGS (Nocedal & Wright, algorithm 7.4) with initial inverse
//   Hessian gamma * P^-1, P the objective's constant preconditioner, factored
//   once (CHOLMOD, coordinate_cholesky.h) and kept in single precision: it
//   only preconditions, and a solve then streams half the bytes. gamma = s.y /
//   y.P^-1.y from the newest curvature pair is the preconditioned form of the
//   usual scaling. One solve per iteration: with z_k = P^-1 g_k kept,
//   P^-1 y_k = z_{k+1} - z_k, and the two-loop recursion's P^-1 q is z minus
//   the same combination of those (no solve of its own). Each vertex's move
//   is clipped to max_displacement on its own (a few vertices on directions
//   of negative curvature ask for long moves while the folds form), the step
//   is then shortened to the objective's step bound (no pair of primitives
//   may cross during it), and a backtracking Armijo line search makes every
//   accepted step lower the energy.
#include "foldfill/solver.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "embed/coordinate_cholesky.h"
#include "embed/lbfgs_recursion.h"
#include "foldfill/error.h"

namespace foldfill {
namespace {

using Eigen::VectorXd;
using PreconditionerFactor = CoordinateCholesky<float>;
using Coordinates = PreconditionerFactor::Coordinates;

// The stopping rule's mean relative change per iteration over its window, per
// method (SolverOptions::relative_energy_tol unset). Gradient descent
// converges linearly with tiny steps, so at the same change it is farther
// from its minimum than L-BFGS is. The fast solver's threshold was chosen on
// the fills' quality against the truth (docs/benchmarks.md, issue 17, fourth
// speed round: area errors, distances to the truth and fold ratios within
// 0.01 of those of a stop ten times stricter, 1e-5): on the reference and
// cloth cases its final energy lies within +0.05 % and +0.7 % of that
// stricter stop's (sim2, whose energy falls in long plateaus, +4 %), in 24 %
// fewer iterations over the 13 cases.
constexpr double kDescentRelativeTol = 1e-9;
constexpr double kFastRelativeTol = 1e-4;
constexpr double kDivergenceFactor = 1e3;  // energy above this times the start's: diverged
constexpr double kArmijo = 1e-4;           // sufficient-decrease constant
constexpr int kMaxBacktracks = 40;         // the step shrinks to 2^-40 at most
constexpr double kRegularisation = 1e-8;   // relative to the mean diagonal of P

struct Iterate {
  VectorXd x;
  double energy = 0;
  VectorXd gradient;
};

bool is_finite(const Iterate& it) { return std::isfinite(it.energy) && it.gradient.allFinite(); }

// Evaluates the objective and its gradient at it.x (buffers reused).
void evaluate(const Objective& objective, Iterate& it) {
  if (!it.x.allFinite()) {
    it.energy = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  it.energy = objective.value(it.x, &it.gradient);
}

// Root mean square of the per-vertex gradient norms.
double rms_gradient(const VectorXd& gradient) {
  return gradient.size() == 0 ? 0.0 : std::sqrt(3.0 * gradient.squaredNorm() / gradient.size());
}

Eigen::Map<Coordinates> per_vertex(VectorXd& v) { return {v.data(), v.size() / 3, 3}; }
Eigen::Map<const Coordinates> per_vertex(const VectorXd& v) { return {v.data(), v.size() / 3, 3}; }

// Clips each vertex's displacement in `direction` to `limit`.
void clip_per_vertex(VectorXd& direction, double limit) {
  auto rows = per_vertex(direction);
  for (Eigen::Index v = 0; v < rows.rows(); ++v) {
    const double length = rows.row(v).norm();
    if (length > limit) rows.row(v) *= limit / length;
  }
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
  GradientDescent(const Objective& objective, double step) : objective_(objective), step_(step) {}

  Advance advance(Iterate& current) override {
    motion_ = -step_ * current.gradient;
    const double bound = objective_.step_bound(current.x, motion_);
    if (!(bound > 0)) return Advance::Stuck;
    current.x += bound * motion_;
    evaluate(objective_, current);
    return Advance::Moved;
  }

 private:
  const Objective& objective_;
  double step_;
  VectorXd motion_;
};

// P with a small multiple of the identity added, so that a P that is only
// semidefinite (a free vertex without springs) can still be factored.
Eigen::SparseMatrix<double> regularised(Eigen::SparseMatrix<double> p) {
  const Eigen::Index n = p.rows();
  double mean_diagonal = 0;
  for (Eigen::Index k = 0; k < n; ++k) mean_diagonal += p.coeff(k, k);
  mean_diagonal = std::max(n > 0 ? mean_diagonal / n : 1.0, 1.0);
  for (Eigen::Index k = 0; k < n; ++k) p.coeffRef(k, k) += kRegularisation * mean_diagonal;
  return p;
}

std::unique_ptr<PreconditionerFactor> factor_of(const Objective& objective) {
  return std::make_unique<PreconditionerFactor>(regularised(objective.preconditioner()),
                                                OrderingEffort::Thorough,
                                                "solver: the preconditioner could not be factored");
}

class Lbfgs final : public Stepper {
 public:
  // `factor`: the objective's preconditioner factored, or null to factor it here.
  Lbfgs(const Objective& objective, const SolverOptions& options, const Budget& budget,
        const PreconditionerFactor* factor)
      : objective_(objective),
        budget_(budget),
        max_displacement_(options.max_displacement),
        memory_(std::max(options.lbfgs_memory, 1)),
        own_factor_(factor ? nullptr : factor_of(objective)),
        factor_(factor ? *factor : *own_factor_) {}

  Advance advance(Iterate& current) override {
    if (!started_) solve(current.gradient, preconditioned_);
    started_ = true;
    search_direction(current);
    Search found = line_search(current);
    if (found == Search::Failed && !pairs_.empty()) {
      // The pairs can give a poor direction (stale ones, or one the step
      // bound cuts short): step along -P^-1 g this once, keeping them.
      direction_ = -preconditioned_;
      found = line_search(current);
    }
    if (found == Search::Failed) {  // a last resort where P^-1 g is a poor direction
      direction_ = -current.gradient;
      found = line_search(current);
    }
    if (found == Search::Stopped) return Advance::Stopped;
    if (found == Search::Failed) return Advance::Stuck;
    solve(next_.gradient, next_preconditioned_);
    remember(current);
    std::swap(current, next_);
    std::swap(preconditioned_, next_preconditioned_);
    return Advance::Moved;
  }

 private:
  enum class Search { Found, Failed, Stopped };

  // result = P^-1 v.
  void solve(const VectorXd& v, VectorXd& result) const {
    result.resize(v.size());
    auto rows = per_vertex(result);
    factor_.solve(per_vertex(v), rows);
  }

  // direction_ = -H g by two_loop_recursion; -P^-1 g (dropping the pairs)
  // when that is not a descent direction.
  void search_direction(const Iterate& current) {
    if (pairs_.empty()) {
      direction_ = -preconditioned_;
      return;
    }
    const double slope = two_loop_recursion(pairs_, gamma_, current.gradient, preconditioned_,
                                            alpha_, q_, direction_);
    if (!(slope < 0)) {
      pairs_.clear();
      direction_ = -preconditioned_;
    }
  }

  // step_ = direction_ with each vertex's move clipped to the maximum
  // displacement (the whole direction shrunk instead when clipping undid the
  // descent), then shortened to the objective's step bound; false when that
  // leaves no descent step.
  bool make_step(const Iterate& current) {
    if (!(current.gradient.dot(direction_) < 0)) return false;
    step_ = direction_;
    clip_per_vertex(step_, max_displacement_);
    if (!(current.gradient.dot(step_) < 0))
      step_ = direction_ * (max_displacement_ / per_vertex(direction_).rowwise().norm().maxCoeff());
    const double bound = objective_.step_bound(current.x, step_);
    if (!(bound > 0)) return false;
    if (bound < 1) step_ *= bound;
    return current.gradient.dot(step_) < 0;
  }

  // Backtracking along step_ until the Armijo condition holds; the result in
  // next_. The budget is looked at before each trial point.
  Search line_search(const Iterate& current) {
    if (!make_step(current)) return Search::Failed;
    const double slope = current.gradient.dot(step_);
    double t = 1;
    for (int k = 0; k < kMaxBacktracks; ++k, t *= 0.5) {
      if (budget_.spent()) return Search::Stopped;
      next_.x = current.x + t * step_;
      evaluate(objective_, next_);
      if (is_finite(next_) && next_.energy <= current.energy + kArmijo * t * slope &&
          next_.energy < current.energy)
        return Search::Found;
    }
    return Search::Failed;
  }

  // Keeps the pair (s, y) of the step from `current` to next_ among the last
  // `memory_`, the oldest pair's vectors reused; P^-1 y is P^-1 g_next -
  // P^-1 g, both at hand.
  void remember(const Iterate& current) {
    s_ = next_.x - current.x;
    y_ = next_.gradient - current.gradient;
    const double sy = s_.dot(y_);
    // Only pairs with positive curvature keep the inverse Hessian positive.
    if (!(sy > std::numeric_limits<double>::epsilon() * s_.norm() * y_.norm())) return;
    CurvaturePair pair;
    if (static_cast<int>(pairs_.size()) == memory_) {
      pair = std::move(pairs_.front());
      pairs_.pop_front();
    }
    std::swap(pair.s, s_);
    std::swap(pair.y, y_);
    pair.preconditioned_y = next_preconditioned_ - preconditioned_;
    pair.rho = 1 / sy;
    const double y_preconditioned_y = pair.y.dot(pair.preconditioned_y);
    if (y_preconditioned_y > 0) gamma_ = sy / y_preconditioned_y;
    pairs_.push_back(std::move(pair));
  }

  const Objective& objective_;
  const Budget& budget_;
  double max_displacement_;
  int memory_;
  std::unique_ptr<PreconditionerFactor> own_factor_;
  const PreconditionerFactor& factor_;
  std::deque<CurvaturePair> pairs_;  // oldest first
  double gamma_ =
      1;  // (y . s) / (y . P^-1 y) of the newest pair: P^-1 scaled to the curvature seen
  bool started_ = false;
  VectorXd preconditioned_, next_preconditioned_;  // P^-1 g at the current and the next iterate
  VectorXd q_, direction_, step_, s_, y_;
  std::vector<double> alpha_;
  Iterate next_;
};

void check_inputs(const Objective& objective, const VectorXd& start, const SolverOptions& options) {
  if (start.size() != objective.size() || objective.size() % 3 != 0)
    throw InternalError("solver: start has " + std::to_string(start.size()) +
                        " variables for an objective of " + std::to_string(objective.size()));
  if (options.kind == SolverKind::GradientDescent &&
      !(options.step > 0 && std::isfinite(options.step)))
    throw UsageError("solver: the gradient descent step must be positive");
  if (!(options.max_displacement > 0))
    throw UsageError("solver: the maximum displacement must be positive");
  if (options.stop_window < 1)
    throw UsageError("solver: the stopping rule's window must be at least 1 iteration");
}

// The energies of the last `window` iterations and the one before them.
class EnergyWindow {
 public:
  explicit EnergyWindow(int window) : capacity_(static_cast<size_t>(window) + 1) {}
  void add(double energy) {
    energies_.push_back(energy);
    if (energies_.size() > capacity_) energies_.pop_front();
  }
  bool full() const { return energies_.size() == capacity_; }
  // The highest energy less the lowest: for a descent, the decrease over the
  // window; where the energy goes up and down, more than the net change.
  double spread() const {
    const auto [lowest, highest] = std::minmax_element(energies_.begin(), energies_.end());
    return *highest - *lowest;
  }

 private:
  size_t capacity_;
  std::deque<double> energies_;
};

// Runs `stepper` under the shared stopping rules and returns the lowest-energy
// iterate seen (the last one, unless gradient descent went up). The progress
// callback's gradient_norm is the RMS per vertex, the gradient_tol measure.
SolverResult run(Stepper& stepper, Iterate& current, const SolverOptions& options,
                 const Budget& budget) {
  const double divergence_limit = kDivergenceFactor * current.energy;
  SolverResult result;
  result.x = current.x;
  double best_energy = current.energy;
  const double relative_tol = options.relative_energy_tol.value_or(
      options.kind == SolverKind::GradientDescent ? kDescentRelativeTol : kFastRelativeTol);
  const int window = options.stop_window;
  EnergyWindow recent(window);
  recent.add(current.energy);
  auto finish = [&](StopReason reason) {
    result.stop_reason = reason;
    return result;
  };
  const auto stopped = [&] {
    return finish(budget.cancelled() ? StopReason::Cancelled : StopReason::TimeLimit);
  };

  while (true) {
    if (rms_gradient(current.gradient) < options.gradient_tol) return finish(StopReason::Converged);
    if (result.iterations >= options.max_iterations) return finish(StopReason::MaxIterations);
    if (budget.spent()) return stopped();
    const Advance advanced = stepper.advance(current);
    if (advanced == Advance::Stopped) return stopped();
    if (advanced == Advance::Stuck) return finish(StopReason::Converged);
    ++result.iterations;
    if (!is_finite(current) || (divergence_limit > 0 && current.energy > divergence_limit))
      return finish(StopReason::Diverged);
    if (current.energy < best_energy) {
      result.x = current.x;
      best_energy = current.energy;
    }
    if (options.progress) {
      SolverProgress progress;
      progress.iteration = result.iterations;
      progress.energy = current.energy;
      progress.gradient_norm = rms_gradient(current.gradient);
      if (!options.progress(progress)) return finish(StopReason::Cancelled);
    }
    recent.add(current.energy);
    if (recent.full() && recent.spread() < window * relative_tol * std::abs(current.energy))
      return finish(StopReason::Converged);
  }
}

}  // namespace

const char* to_string(StopReason reason) {
  switch (reason) {
    case StopReason::Converged:
      return "converged";
    case StopReason::MaxIterations:
      return "max_iterations";
    case StopReason::TimeLimit:
      return "time_limit";
    case StopReason::Cancelled:
      return "cancelled";
    case StopReason::Diverged:
      return "diverged";
  }
  return "converged";
}

struct FactoredPreconditioner::Factor {
  std::unique_ptr<PreconditionerFactor> factor;
};

FactoredPreconditioner::FactoredPreconditioner(const Objective& objective)
    : factor_(std::make_unique<Factor>(Factor{factor_of(objective)})), size_(objective.size()) {}

FactoredPreconditioner::~FactoredPreconditioner() = default;

SolverResult minimize(const Objective& objective, const VectorXd& start,
                      const SolverOptions& options, const Budget& budget) {
  return minimize(objective, start, options, budget, nullptr);
}

SolverResult minimize(const Objective& objective, const VectorXd& start,
                      const SolverOptions& options, const Budget& budget,
                      const FactoredPreconditioner* preconditioner) {
  if (preconditioner && preconditioner->size() != objective.size())
    throw InternalError("solver: the factored preconditioner is of another size");
  const Budget limited = budget.at_most(options.time_limit_seconds);
  check_inputs(objective, start, options);
  Iterate first;
  first.x = start;
  evaluate(objective, first);
  if (!is_finite(first)) return {start, 0, StopReason::Diverged};
  if (objective.size() == 0) return {start, 0, StopReason::Converged};
  if (limited.spent())  // before the preconditioner's factorisation
    return {start, 0, limited.cancelled() ? StopReason::Cancelled : StopReason::TimeLimit};

  if (options.kind == SolverKind::GradientDescent) {
    GradientDescent stepper(objective, options.step);
    return run(stepper, first, options, limited);
  }
  Lbfgs stepper(objective, options, limited,
                preconditioner ? preconditioner->factor().factor.get() : nullptr);
  return run(stepper, first, options, limited);
}

}  // namespace foldfill
