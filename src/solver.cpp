// Minimisation of the fabric energy over the free vertices.
//
// Two methods share the stopping rules, the callback and the guards:
// - GradientDescent: the paper's fixed step x -= step * grad E, each iterate
//   then projected outside the obstacles (section 3.4).
// - Fast: L-BFGS (Nocedal & Wright, algorithm 7.4) whose initial inverse
//   Hessian is the inverse of the constant matrix P = L + lambda * H_B + eps I,
//   with L the unit-weight Laplacian of the spring graph over the free vertices
//   (the global matrix of projective dynamics, Bouaziz et al. 2014; its use as
//   an L-BFGS preconditioner follows Liu et al. 2017, "Quasi-Newton methods for
//   real-time simulation of hyperelastic materials") and H_B the constant
//   bending Hessian, factored once. A backtracking Armijo line search makes
//   every accepted step lower the energy. After each accepted step the free
//   vertices are projected outside the obstacles; when that raises the energy
//   the step is still accepted (the constraint wins) but the L-BFGS memory is
//   cleared, since its curvature pairs then describe a different problem.
#include "foldfill/solver.h"

#include <Eigen/SparseCholesky>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <limits>
#include <string>

#include "foldfill/error.h"

namespace foldfill {
namespace {
int evaluations = 0;
using Eigen::VectorXd;
using Coordinates = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

constexpr int kStallIterations = 10;       // consecutive small relative changes to converge
constexpr double kDivergenceFactor = 1e3;  // energy above this times the start's: diverged
constexpr int kLbfgsMemory = 10;
constexpr double kArmijo = 1e-4;          // sufficient-decrease constant
constexpr int kMaxBacktracks = 40;        // the step shrinks to 2^-40 at most
constexpr double kRegularisation = 1e-8;  // relative to the mean diagonal of P

struct Iterate {
  VectorXd x;
  double energy = 0;
  VectorXd gradient;
};

bool is_finite(const Iterate& it) { return std::isfinite(it.energy) && it.gradient.allFinite(); }

Iterate evaluate(const FabricEnergy& energy, VectorXd x) {
  Iterate it;
  if (!x.allFinite()) {
    it.energy = std::numeric_limits<double>::quiet_NaN();
    return it;
  }
  it.gradient.resize(x.size());
  it.energy = energy.evaluate(x, &it.gradient).total;
  it.x = std::move(x);
  return it;
}

// Root mean square of the per-vertex gradient norms.
double rms_gradient(const VectorXd& gradient) {
  return gradient.size() == 0 ? 0.0 : std::sqrt(3.0 * gradient.squaredNorm() / gradient.size());
}

// Projects every free vertex outside every obstacle; returns whether one moved.
bool project_outside(const std::vector<Obstacle>& obstacles, VectorXd& x) {
  bool moved = false;
  for (Eigen::Index v = 0; v + 2 < x.size(); v += 3) {
    Vec3 p{x[v], x[v + 1], x[v + 2]};
    for (const Obstacle& obstacle : obstacles) moved = push_outside(obstacle, p) || moved;
    x[v] = p[0];
    x[v + 1] = p[1];
    x[v + 2] = p[2];
  }
  return moved;
}

// One step of a method: replaces `current` by the next iterate, or returns
// false when no step can lower the energy any more.
class Stepper {
 public:
  virtual ~Stepper() = default;
  virtual bool advance(Iterate& current) = 0;
};

class GradientDescent final : public Stepper {
 public:
  GradientDescent(const FabricEnergy& energy, const std::vector<Obstacle>& obstacles, double step)
      : energy_(energy), obstacles_(obstacles), step_(step) {}

  bool advance(Iterate& current) override {
    VectorXd x = current.x - step_ * current.gradient;
    project_outside(obstacles_, x);
    current = evaluate(energy_, std::move(x));
    return true;
  }

 private:
  const FabricEnergy& energy_;
  const std::vector<Obstacle>& obstacles_;
  double step_;
};

// P = unit spring Laplacian + lambda * bending Hessian + eps I over the free
// vertices (one coordinate), the preconditioner described at the top.
Eigen::SparseMatrix<double> preconditioner_matrix(const FabricEnergy& energy) {
  const int fixed = energy.domain().fixed_count;
  const int free_count = energy.domain().free_count();
  std::vector<Eigen::Triplet<double>> entries;
  for (const FabricEnergy::Spring& s : energy.springs()) {
    const int i = s.i - fixed, j = s.j - fixed;
    if (i >= 0) entries.emplace_back(i, i, 1.0);
    if (j >= 0) entries.emplace_back(j, j, 1.0);
    if (i >= 0 && j >= 0) {
      entries.emplace_back(i, j, -1.0);
      entries.emplace_back(j, i, -1.0);
    }
  }
  const Eigen::SparseMatrix<double>& bending = energy.bending_hessian();
  const double lambda = energy.options().lambda;
  for (int col = fixed; col < bending.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(bending, col); it; ++it)
      if (it.row() >= fixed)
        entries.emplace_back(static_cast<int>(it.row()) - fixed, col - fixed, lambda * it.value());
  Eigen::SparseMatrix<double> p(free_count, free_count);
  p.setFromTriplets(entries.begin(), entries.end());

  double mean_diagonal = 0;
  for (int k = 0; k < free_count; ++k) mean_diagonal += p.coeff(k, k);
  mean_diagonal = std::max(mean_diagonal / free_count, 1.0);
  for (int k = 0; k < free_count; ++k) p.coeffRef(k, k) += kRegularisation * mean_diagonal;
  return p;
}

class Lbfgs final : public Stepper {
 public:
  Lbfgs(const FabricEnergy& energy, const std::vector<Obstacle>& obstacles)
      : energy_(energy), obstacles_(obstacles) {
    factor_.compute(preconditioner_matrix(energy));
    if (factor_.info() != Eigen::Success)
      throw Error(ErrorKind::FillFailed, "solver: the preconditioner could not be factored");
  }

  bool advance(Iterate& current) override {
    Iterate next;
    if (!line_search(current, search_direction(current.gradient), next)) {
      if (memory_.empty()) return false;
      // Stale curvature pairs can give a poor direction: retry without them.
      memory_.clear();
      if (!line_search(current, search_direction(current.gradient), next)) return false;
    }
    if (project_outside(obstacles_, next.x)) {
      next = evaluate(energy_, std::move(next.x));
      if (!(next.energy <= current.energy)) {
        memory_.clear();
        current = std::move(next);
        return true;
      }
    }
    remember(next.x - current.x, next.gradient - current.gradient);
    current = std::move(next);
    return true;
  }

 private:
  struct CurvaturePair {
    VectorXd s, y;
    double rho;  // 1 / (y . s)
  };

  VectorXd apply_preconditioner_inverse(const VectorXd& v) const {
    const Eigen::Map<const Coordinates> per_vertex(v.data(), v.size() / 3, 3);
    Coordinates solved = factor_.solve(Eigen::MatrixX3d(per_vertex));
    return Eigen::Map<const VectorXd>(solved.data(), v.size());
  }

  // The two-loop recursion with P^-1 as the initial inverse Hessian; falls back
  // to the preconditioned gradient when the result is not a descent direction.
  VectorXd search_direction(const VectorXd& gradient) {
    VectorXd q = gradient;
    std::vector<double> alpha(memory_.size());
    for (size_t k = memory_.size(); k-- > 0;) {
      alpha[k] = memory_[k].rho * memory_[k].s.dot(q);
      q -= alpha[k] * memory_[k].y;
    }
    VectorXd r = apply_preconditioner_inverse(q);
    if (std::getenv("GAMMA") && !memory_.empty()) {
      const VectorXd py = apply_preconditioner_inverse(memory_.back().y);
      r *= memory_.back().s.dot(memory_.back().y) / memory_.back().y.dot(py);
    }
    for (size_t k = 0; k < memory_.size(); ++k) {
      const double beta = memory_[k].rho * memory_[k].y.dot(r);
      r += (alpha[k] - beta) * memory_[k].s;
    }
    if (r.dot(gradient) > 0) return -r;
    memory_.clear();
    return -apply_preconditioner_inverse(gradient);
  }

  // Backtracking from the full step until the Armijo condition holds.
  bool line_search(const Iterate& current, const VectorXd& direction, Iterate& next) const {
    const double slope = current.gradient.dot(direction);
    if (!(slope < 0)) return false;
    double t = 1;
    for (int k = 0; k < kMaxBacktracks; ++k, t *= 0.5) {
      ++evaluations;
      if (getenv("VERB") && k > 0) fprintf(stderr, "bt %d\n", k);
      next = evaluate(energy_, current.x + t * direction);
      if (is_finite(next) && next.energy <= current.energy + kArmijo * t * slope) return true;
    }
    return false;
  }

  void remember(VectorXd s, VectorXd y) {
    const double sy = s.dot(y);
    // Only pairs with positive curvature keep the inverse Hessian positive.
    if (!(sy > std::numeric_limits<double>::epsilon() * s.norm() * y.norm())) return;
    if (static_cast<int>(memory_.size()) == kLbfgsMemory) memory_.pop_front();
    memory_.push_back({std::move(s), std::move(y), 1 / sy});
  }

  const FabricEnergy& energy_;
  const std::vector<Obstacle>& obstacles_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor_;
  std::deque<CurvaturePair> memory_;
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

// Runs `stepper` under the shared stopping rules, keeping the lowest-energy
// iterate seen.
SolverResult run(const FabricEnergy& energy, Stepper& stepper, Iterate current,
                 const SolverOptions& options) {
  const auto started = std::chrono::steady_clock::now();
  const double divergence_limit = kDivergenceFactor * current.energy;
  Iterate best = current;
  SolverResult result;
  int stalled = 0;
  auto finish = [&](const char* reason) {
    result.positions = energy.positions(best.x);
    result.stop_reason = reason;
    fprintf(stderr, "evals %d\n", evaluations);
    evaluations = 0;
    return result;
  };

  while (true) {
    if (rms_gradient(current.gradient) < options.gradient_tol) return finish("converged");
    if (result.iterations >= options.max_iterations) return finish("max_iterations");
    const double previous = current.energy;
    if (!stepper.advance(current)) return finish("converged");
    ++result.iterations;
    if (!is_finite(current) || (divergence_limit > 0 && current.energy > divergence_limit))
      return finish("diverged");
    if (current.energy < best.energy) best = current;
    if (options.progress &&
        !options.progress({result.iterations, current.energy, rms_gradient(current.gradient)}))
      return finish("cancelled");
    const double change = std::abs(current.energy - previous) /
                          std::max(current.energy, std::numeric_limits<double>::min());
    stalled = change < options.relative_energy_tol ? stalled + 1 : 0;
    if (stalled >= kStallIterations) return finish("converged");
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - started;
    if (options.time_limit_seconds > 0 && elapsed.count() >= options.time_limit_seconds)
      return finish("time_limit");
  }
}

}  // namespace

SolverResult minimize_energy(const FabricEnergy& energy, const std::vector<Obstacle>& obstacles,
                             const std::vector<Vec3>& start, const SolverOptions& options) {
  check_inputs(energy, start, options);
  VectorXd x = energy.variables(start);
  if (!x.allFinite()) return {start, 0, "diverged"};
  project_outside(obstacles, x);
  const Iterate first = evaluate(energy, std::move(x));
  if (!is_finite(first)) return {start, 0, "diverged"};
  if (energy.domain().free_count() == 0) return {energy.positions(first.x), 0, "converged"};

  if (options.kind == SolverKind::GradientDescent) {
    GradientDescent stepper(energy, obstacles, options.step);
    return run(energy, stepper, first, options);
  }
  Lbfgs stepper(energy, obstacles);
  return run(energy, stepper, first, options);
}

}  // namespace foldfill
