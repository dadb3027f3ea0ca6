// Minimisation of the fabric energy.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "foldfill/budget.h"
#include "foldfill/energy.h"
#include "foldfill/obstacles.h"

namespace foldfill {

enum class SolverKind {
  GradientDescent,  // the paper's fixed-step descent, kept for reference
  Fast,             // the default (see solver.cpp for the method)
};

struct SolverProgress {
  int iteration = 0;
  double energy = 0;
  double gradient_norm = 0;
};

struct SolverOptions {
  SolverKind kind = SolverKind::Fast;
  int max_iterations = 20000;
  double step = 0.05;  // gradient descent: fixed step (normalised units)
  // Stop when |dE| / E stays below this for 10 iterations in a row (unset:
  // the method's own, 1e-9 for gradient descent, 1e-7 for Fast, which leave
  // each about as close to its minimum: see solver.cpp) ...
  std::optional<double> relative_energy_tol;
  double gradient_tol = 1e-6;     // ... or when the RMS gradient per vertex falls below this
  double time_limit_seconds = 0;  // 0: none
  // Fast: no vertex moves further than this in one step (normalised units), so
  // that the repulsion sees vertices approach before they pass each other;
  // each vertex's move is clipped on its own. Two vertices close in by at most
  // 0.4 per step, well under the about one edge length a vertex must travel
  // to cross a sheet covered by repulsion balls (radius 1 / 1.3 of the
  // shortest edge). 0.2 instead of 0.1 took 14% to 45% fewer iterations on
  // the reference and cloth cases (7% more on contour), with the same
  // energies and no new self-intersections.
  double max_displacement = 0.2;
  // Called every iteration; returning false cancels (the best state is kept).
  std::function<bool(const SolverProgress&)> progress;
  // Called once, after iteration `watch_iteration` (0: never), with the
  // positions then (all domain vertices, normalised); returning false abandons
  // the minimisation there (stop reason "abandoned", the best state kept).
  int watch_iteration = 0;
  std::function<bool(const std::vector<Vec3>&)> watch;
};

struct SolverResult {
  std::vector<Vec3> positions;  // all domain vertices, normalised
  int iterations = 0;
  // "converged", "max_iterations", "time_limit", "cancelled", "abandoned", "diverged"
  std::string stop_reason;
};

// Minimises `energy` from `start` (all domain vertices), keeping free vertices
// outside `obstacles` (in normalised coordinates) by projection. It stops at
// the earlier of `budget`'s deadline and options.time_limit_seconds from the
// call (stop reason "time_limit"), or when `budget` is cancelled
// ("cancelled"), keeping the best state: both are looked at before each
// iteration and before each trial point of the line search, so the work past
// them is at most one energy evaluation, or the preconditioner's
// factorisation when they pass during it.
SolverResult minimize_energy(const FabricEnergy& energy, const std::vector<Obstacle>& obstacles,
                             const std::vector<Vec3>& start, const SolverOptions& options = {},
                             const Budget& budget = {});

}  // namespace foldfill
