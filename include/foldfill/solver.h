// Minimisation of a patch's energy (paper section 3.3, "gradient descent with
// a fixed step size"; METHOD.md 2d): the paper's gradient descent and a fast
// preconditioned L-BFGS, both keeping every step within the bound the
// objective sets (the contact's, so that nothing crosses during a step).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "foldfill/budget.h"
#include "foldfill/energy.h"

namespace foldfill {

enum class SolverKind {
  GradientDescent,  // the paper's fixed-step descent, kept for reference
  Fast,             // the default (see solver.cpp for the method)
};

enum class StopReason {
  Converged,      // the energy stopped changing, or no step lowers it any more
  MaxIterations,  // SolverOptions::max_iterations reached
  TimeLimit,      // the budget's deadline or SolverOptions::time_limit_seconds passed
  Cancelled,      // the budget was cancelled or the progress callback returned false
  Diverged,       // the energy became non-finite or grew far beyond its start
};

// "converged", "max_iterations", "time_limit", "cancelled", "diverged".
const char* to_string(StopReason reason);

// Which minimisation of a hole's fill a progress report comes from; each
// counts its iterations from 0.
enum class MinimisationStage {
  Main,        // with the patch's own weights
  FoldsFirst,  // the stiff one before it, which forms the large folds (stiff_start_lambda)
};

struct SolverProgress {
  int iteration = 0;
  double energy = 0;
  double gradient_norm = 0;
  MinimisationStage stage = MinimisationStage::Main;
  // 0: the patch itself; k > 0: its k-th coarser level (multilevel.h), the
  // coarsest minimised first.
  int coarse_level = 0;
};

struct SolverOptions {
  SolverKind kind = SolverKind::Fast;
  int max_iterations = 20000;
  double step = 0.05;  // gradient descent: fixed step (normalised units)
  // Stop when the energy has changed by less than this per iteration, as a
  // fraction of the energy, on average over the last stop_window iterations:
  // when its highest and lowest values there are less than stop_window times
  // this times E apart (unset: the method's own, 1e-9 for gradient descent,
  // 1e-4 for Fast; see docs/benchmarks.md) ...
  std::optional<double> relative_energy_tol;
  int stop_window = 10;           // iterations (at least 1)
  double gradient_tol = 1e-6;     // ... or when the RMS gradient per vertex falls below this
  double time_limit_seconds = 0;  // 0: none
  // Fast: no vertex moves further than this in one step (normalised units);
  // each vertex's move is clipped on its own, so that a few vertices asking
  // for long moves while the folds form do not shorten everyone's step.
  double max_displacement = 0.2;
  // Fast: curvature pairs kept by L-BFGS.
  int lbfgs_memory = 10;
  // Called every iteration; returning false cancels (the best state is kept).
  std::function<bool(const SolverProgress&)> progress;
};

// What the solver minimises, over variables that are 3 coordinates per vertex.
class Objective {
 public:
  virtual ~Objective() = default;
  // Number of variables (3 per vertex).
  virtual Eigen::Index size() const = 0;
  // The value at `x`, +infinity where `x` is not allowed (two primitives in
  // contact); fills `gradient` when non-null and the value is finite.
  virtual double value(const Eigen::VectorXd& x, Eigen::VectorXd* gradient) const = 0;
  // A constant symmetric positive definite matrix over the vertices
  // (size() / 3 square, the same for each coordinate) that approximates the
  // Hessian: the fast solver's preconditioner, factored once.
  virtual Eigen::SparseMatrix<double> preconditioner() const = 0;
  // The largest t in [0, 1] such that x + s dx stays allowed for every s in
  // [0, t]: 1 when nothing limits the step.
  virtual double step_bound(const Eigen::VectorXd& x, const Eigen::VectorXd& dx) const {
    (void)x;
    (void)dx;
    return 1;
  }
};

struct SolverResult {
  Eigen::VectorXd x;  // the lowest-energy state seen
  int iterations = 0;
  StopReason stop_reason = StopReason::Converged;
};

// Minimises `objective` from `start`, every step shortened to the
// objective's step bound. It stops at the earlier of `budget`'s deadline and
// options.time_limit_seconds from the call (TimeLimit), or when `budget` is
// cancelled (Cancelled), keeping the best state: both are looked at before
// each iteration and before each trial point of the line search, so the work
// past them is at most one evaluation, or the preconditioner's factorisation
// when they pass during it. A start where the objective is not finite is
// returned as Diverged after 0 iterations. Throws UsageError for a gradient
// descent step or a maximum displacement that is not positive,
// InternalError for a start of the wrong size (not objective.size()), and
// what the objective throws.
SolverResult minimize(const Objective& objective, const Eigen::VectorXd& start,
                      const SolverOptions& options = {}, const Budget& budget = {});

// The fast solver's preconditioner of an objective, factored once. Given to
// minimize(), it stands for the factorisation minimize() otherwise does on
// each call: for minimisations repeated many times over one objective, each
// warm-started from the last (the edit tool's drags, edit.h).
class FactoredPreconditioner {
 public:
  // Factors objective.preconditioner() as minimize() would. Throws
  // Error(Internal) where it cannot be factored.
  explicit FactoredPreconditioner(const Objective& objective);
  ~FactoredPreconditioner();
  FactoredPreconditioner(const FactoredPreconditioner&) = delete;
  FactoredPreconditioner& operator=(const FactoredPreconditioner&) = delete;
  Eigen::Index size() const { return size_; }  // the objective's size()

  struct Factor;  // solver.cpp's
  const Factor& factor() const { return *factor_; }

 private:
  std::unique_ptr<Factor> factor_;
  Eigen::Index size_ = 0;
};

// minimize() with `preconditioner` (of an objective whose preconditioner()
// is the same matrix; null: factored here) for the fast solver. Throws
// InternalError for one of another size.
SolverResult minimize(const Objective& objective, const Eigen::VectorXd& start,
                      const SolverOptions& options, const Budget& budget,
                      const FactoredPreconditioner* preconditioner);

// The fabric energy alone as an Objective (no contact, nothing bounds a step).
class FabricObjective final : public Objective {
 public:
  explicit FabricObjective(const FabricEnergy& energy) : energy_(energy) {}
  Eigen::Index size() const override { return 3 * energy_.domain().free_count(); }
  double value(const Eigen::VectorXd& x, Eigen::VectorXd* gradient) const override {
    return energy_.evaluate(x, gradient).total;
  }
  Eigen::SparseMatrix<double> preconditioner() const override { return energy_.preconditioner(); }

 private:
  const FabricEnergy& energy_;
};

}  // namespace foldfill
