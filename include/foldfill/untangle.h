// A start that crosses nothing, made from one that does: the length of the
// curves along which the patch's faces cross other faces (its own, its
// strip's, the scene's) is minimised against the patch's stiffness until no
// pair crosses (intersection contour minimisation: Volino and
// Magnenat-Thalmann 2006, "Resolving surface collisions through
// intersection contour minimization"). Shrinking a crossing curve moves the
// patch through the face it crosses, towards the side where less of the
// patch is wrong; a closed curve shrinks to a point and is gone.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <utility>
#include <vector>

#include "foldfill/budget.h"
#include "foldfill/contact.h"
#include "foldfill/energy.h"

namespace foldfill {

struct UntangleOptions {
  // Searches for the crossing pairs; after each, a short minimisation of the
  // length of those pairs' crossing curves against the patch's stiffness.
  int rounds = 150;
  int iterations_per_round = 16;
  // A round's minimisation, and the separation below, also stop once their
  // objective changes by less than this per iteration over the solver's
  // window (SolverOptions::relative_energy_tol): rounds cut short by the
  // fill's looser stop move the patch too little, and more holes then end
  // with no untangled start (docs/benchmarks.md).
  double relative_energy_tol = 1e-5;
  // Weights of the curves' length (normalised units), in units of the mean
  // diagonal of the fabric energy's preconditioner: each tried in turn from
  // the start until one untangles it. The pull of the curves against the
  // stiffness sets how far the patch moves in a round; which of them gets
  // through first depends on the case.
  std::array<double, 3> weights = {0.3, 0.1, 1};
  // Once nothing crosses, pairs may still touch: the fill then minimises the
  // fabric energy with the contact's barrier for up to this many iterations,
  // which pushes them apart without letting anything cross.
  int separation_iterations = 30;
};

// The crossing curves' summed length at `x` over the pairs of faces of
// contact.mesh() in `pairs` (one face a patch face), and its gradient over
// the free vertices (added to `gradient` when non-null). A pair that does not
// cross, or only touches, adds nothing.
double crossing_curve_length(const PatchContact& contact,
                             const std::vector<std::pair<int, int>>& pairs,
                             const Eigen::VectorXd& x, Eigen::VectorXd* gradient);

// The intersecting pairs of contact.mesh()'s faces with one face a patch face
// (exact predicates), at `x`.
std::vector<std::pair<int, int>> crossing_pairs(const PatchContact& contact,
                                                const Eigen::VectorXd& x);

// Round by round, minimises the crossing curves' length of the pairs that
// cross (found again each round) plus the patch's stiffness (the fabric
// energy's preconditioner P) against its move from the round's start, so
// that the patch moves smoothly, as a whole, until no pair crosses. Returns
// free-vertex positions at which no face pair of the patch crosses (exact
// test) and the barrier is finite (pairs may still be very near: see
// separation_iterations), or nothing when no weight gets there within `options.rounds` rounds or
// the budget is spent. A clean `start` comes back as it is.
std::optional<Eigen::VectorXd> untangle(const FabricEnergy& energy, const PatchContact& contact,
                                        const Eigen::VectorXd& start,
                                        const UntangleOptions& options, const Budget& budget);

}  // namespace foldfill
