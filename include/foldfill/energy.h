// The fabric energy of section 3.3-3.4 of Gisbert et al. 2023 over an
// EmbedDomain: isometric edge springs, quadratic bending (Bergou et al. 2006)
// or two-ring springs, and soft vertex repulsion.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "foldfill/box_tree.h"
#include "foldfill/domain.h"

namespace foldfill {

enum class BendingModel { Quadratic, TwoRing };

// Weights are for the normalised domain (unit = mean loop edge length).
struct EnergyOptions {
  // Bending weight relative to the isometric term. Small, so that the patch
  // keeps the cloth's area and folds (docs/quality.md, "Tuning the defaults");
  // a patch that crumples into itself at this weight is minimised again with
  // a stiffer one (see fill_holes).
  double lambda = 2e-4;
  BendingModel bending = BendingModel::Quadratic;
  double repulsion = 1.0;             // kappa, relative to the isometric term
  double repulsion_radius = 1 / 1.3;  // r_i = shortest incident rest edge * this
};

struct EnergyTerms {
  double isometric = 0;  // 1/2 sum (|e| - l)^2 over edges with a free end
  double bending = 0;    // lambda-free bending energy (quadratic or two-ring)
  double repulsion = 0;  // kappa-free repulsion energy
  double total = 0;      // isometric + lambda * bending + kappa * repulsion
};

// The energy E = E_I + lambda E_B + kappa E_C of paper sections 3.3 (E_I,
// E_B) and 3.4 (E_C); METHOD.md 2b and 2c.
//
// Precomputes everything that does not change during the minimisation (rest
// lengths, the constant bending Hessian, repulsion radii). Variables are the
// free vertices' positions, a vector of 3 * free_count (x, y, z interleaved).
// evaluate() reuses scratch buffers of the object and the repulsion's list of
// candidate pairs (kept while vertices move little; the result does not depend
// on it, bit for bit), so one object must not be evaluated from two threads at
// once (each hole has its own energy object).
class FabricEnergy {
 public:
  // Precondition: `domain` from make_embed_domain. Throws UsageError for a
  // weight or radius that is negative or not finite, FillFailedError for a
  // degenerate rest triangle, InternalError for a domain whose parts do not
  // match.
  FabricEnergy(const EmbedDomain& domain, const EnergyOptions& options);

  // Energy at `x`; adds nothing to and fills `gradient` when non-null.
  // Throws InternalError unless `x` has 3 * free_count entries (so do
  // positions(), and variables() unless given one position per vertex).
  EnergyTerms evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* gradient = nullptr) const;

  // The fast solver's preconditioner over the free vertices (per coordinate):
  // the unit-weight Laplacian of the springs (the global matrix of projective
  // dynamics, Bouaziz et al. 2014, used as an L-BFGS preconditioner by Liu et
  // al. 2017) plus lambda times the bending part where it weighs enough (see
  // energy.cpp). Constant: it does not depend on the positions.
  Eigen::SparseMatrix<double> preconditioner() const;

  // Full domain positions from the free variables.
  std::vector<Vec3> positions(const Eigen::VectorXd& x) const;
  // Free variables from full domain positions.
  Eigen::VectorXd variables(const std::vector<Vec3>& positions) const;

  const EmbedDomain& domain() const { return domain_; }
  const EnergyOptions& options() const { return options_; }

  // Springs with at least one free end: (i, j, rest length), domain indices.
  struct Spring {
    int i, j;
    double rest_length;
  };
  const std::vector<Spring>& springs() const { return springs_; }
  // A pair of vertices that may repel: j < i, i free, pair radius (r_i + r_j) / 2.
  struct RepulsionPair {
    int i, j;
    double radius;
  };
  // The repulsion's candidate pairs as of the last evaluation (none before one,
  // or when nothing repels): every pair closer than its radius plus
  // repulsion_skin() when they were last searched, sorted by (i, j).
  const std::vector<RepulsionPair>& repulsion_candidates() const { return repulsion_pairs_; }
  double repulsion_skin() const { return repulsion_skin_; }
  // The two-ring model's bending springs (weight lambda), empty for quadratic.
  const std::vector<Spring>& two_ring_springs() const { return two_ring_springs_; }
  // Constant bending Hessian over all domain vertices (per coordinate) for the
  // quadratic model, empty for two-ring.
  const Eigen::SparseMatrix<double>& bending_hessian() const { return bending_hessian_; }

 private:
  EmbedDomain domain_;
  EnergyOptions options_;
  std::vector<Spring> springs_;           // isometric edges
  std::vector<Spring> two_ring_springs_;  // bending springs of the two-ring model
  Eigen::SparseMatrix<double> bending_hessian_;
  std::vector<double> repulsion_radius_;  // per domain vertex
  // Domain vertex adjacency (CSR, sorted): pairs joined by an edge do not repel.
  std::vector<int> neighbour_start_, neighbours_;
  using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  // The bending Hessian split by free (f) and fixed (x) vertices: H_ff, H_fx
  // p_x and p_x^T H_xx p_x summed over coordinates.
  Eigen::SparseMatrix<double, Eigen::RowMajor> free_bending_hessian_;
  Points fixed_bending_force_;
  double fixed_bending_energy_ = 0;
  void split_bending_hessian();
  // Scratch of evaluate(): all domain positions (fixed rows set once) and forces.
  mutable Points points_, forces_;
  // The repulsion's candidate pairs and the positions they were found at
  // (see energy.cpp); the energy does not depend on when they were found.
  mutable std::vector<RepulsionPair> repulsion_pairs_;
  mutable Points repulsion_anchor_;
  double repulsion_skin_ = 0;  // 0: no vertex repels (all radii 0)
  // The pair search's box trees (energy.cpp: build_repulsion_pairs).
  mutable BoxTree repulsion_fixed_tree_, repulsion_free_tree_;
  mutable double repulsion_free_tree_cost_ = 0;
  void build_repulsion_pairs() const;
  void update_repulsion_pairs() const;
};

}  // namespace foldfill
