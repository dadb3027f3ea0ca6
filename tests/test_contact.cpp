// The contact that keeps a patch from crossing anything (contact.h): its
// barrier against finite differences, its step bound, and minimisations of
// a crumpling patch under a layer of cloth in which no accepted step crosses
// anything, by the exact test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "foldfill/arap.h"
#include "foldfill/contact.h"
#include "foldfill/metrics.h"
#include "foldfill/solver.h"
#include "lattice_domain.h"

namespace foldfill {
namespace {

// The strip squeezed to 40% both ways: the patch must crumple.
Vec3 crumpled(const Vec2& uv) { return {0.4 * uv[0], 0.4 * uv[1], 0.2 * std::sin(0.5 * uv[0])}; }

EnergyOptions test_weights() {
  EnergyOptions options;
  options.lambda = 2e-4;  // floppy: it crumples into itself without the contact
  options.repulsion = 0;
  return options;
}

// A flat square layer of cloth over the patch at height z (normalised units).
PatchScene layer_above(const EmbedDomain& domain, double z) {
  return testing::flat_layer(domain, z, 24);
}

// The crossing triangle pairs of the patch against itself, its strip and
// the scene at the free variables x (exact predicates).
int crossings(const EmbedDomain& domain, const PatchContact& contact, const Eigen::VectorXd& x) {
  std::vector<int> patch(domain.faces.size() - domain.strip_face_count);
  std::iota(patch.begin(), patch.end(), domain.strip_face_count);
  const SubsetCrossings c =
      count_subset_crossings(contact.positions(x), contact.mesh().faces, patch, 0.0);
  return c.within + c.with_others;
}

// The patch objective, recording every point a step starts from: the start
// and each accepted iterate.
class Recording final : public Objective {
 public:
  explicit Recording(const Objective& inner) : inner_(inner) {}
  Eigen::Index size() const override { return inner_.size(); }
  double value(const Eigen::VectorXd& x, Eigen::VectorXd* gradient) const override {
    return inner_.value(x, gradient);
  }
  Eigen::SparseMatrix<double> preconditioner() const override { return inner_.preconditioner(); }
  double step_bound(const Eigen::VectorXd& x, const Eigen::VectorXd& dx) const override {
    if (iterates.empty() || iterates.back() != x) iterates.push_back(x);
    return inner_.step_bound(x, dx);
  }
  mutable std::vector<Eigen::VectorXd> iterates;

 private:
  const Objective& inner_;
};

struct Crumpling {
  EmbedDomain domain = testing::lattice_domain(16, 12, crumpled);
  FabricEnergy energy{domain, test_weights()};
  std::vector<Vec3> start = arap_embed(domain, {0.5, 30});
  double top = 0;
  Crumpling() {
    for (const Vec3& p : start) top = std::max(top, p[2]);
  }
};

TEST(Contact, BarrierGradientMatchesFiniteDifferences) {
  const Crumpling problem;
  const PatchContact contact(problem.domain, layer_above(problem.domain, problem.top + 0.05), {});
  const Eigen::VectorXd x = problem.energy.variables(problem.start);
  Eigen::VectorXd gradient = Eigen::VectorXd::Zero(x.size());
  const double value = contact.evaluate(x, &gradient);
  ASSERT_GT(value, 0);  // the layer is within the thickness of the patch's top
  ASSERT_TRUE(std::isfinite(value));
  std::mt19937 random(7);
  std::uniform_int_distribution<Eigen::Index> pick(0, x.size() - 1);
  int checked = 0;
  for (int k = 0; k < 200 && checked < 20; ++k) {
    const Eigen::Index i = pick(random);
    if (gradient[i] == 0) continue;
    const double step = 1e-6;
    Eigen::VectorXd plus = x, minus = x;
    plus[i] += step;
    minus[i] -= step;
    const double numeric =
        (contact.evaluate(plus, nullptr) - contact.evaluate(minus, nullptr)) / (2 * step);
    EXPECT_NEAR(gradient[i], numeric, 1e-5 * std::max(1.0, std::abs(numeric))) << i;
    ++checked;
  }
  EXPECT_GE(checked, 5);
}

// Moved up as one piece, the patch would pass through the layer: the step
// is cut short before it touches, and no pair crosses at the bound.
TEST(Contact, StepBoundStopsARigidMoveBeforeTheLayer) {
  const Crumpling problem;
  const double gap = 0.3;
  const PatchContact contact(problem.domain, layer_above(problem.domain, problem.top + gap), {});
  const Eigen::VectorXd x = problem.energy.variables(problem.start);
  Eigen::VectorXd up = Eigen::VectorXd::Zero(x.size());
  for (Eigen::Index k = 2; k < up.size(); k += 3) up[k] = 2 * gap;
  const double bound = contact.step_bound(x, up);
  EXPECT_GT(bound, 0.1);
  EXPECT_LT(bound, 0.5);
  EXPECT_EQ(crossings(problem.domain, contact, x + bound * up), 0);
  EXPECT_GT(crossings(problem.domain, contact, x + up), 0);
  // Sideways it may move freely.
  Eigen::VectorXd side = Eigen::VectorXd::Zero(x.size());
  for (Eigen::Index k = 0; k < side.size(); k += 3) side[k] = 1e-3;
  EXPECT_EQ(contact.step_bound(x, side), 1.0);
}

// A step the candidates do not cover searches them again around its end,
// so that they also cover the next step of the same length: steps of the
// fast solver's longest move search once every second step.
TEST(Contact, CandidatesSearchedAtAStepsEndLastForTheNextStep) {
  const Crumpling problem;
  const PatchContact contact(problem.domain, layer_above(problem.domain, problem.top + 1), {});
  const Eigen::VectorXd x = problem.energy.variables(problem.start);
  Eigen::VectorXd side = Eigen::VectorXd::Zero(x.size());
  for (Eigen::Index k = 0; k < side.size(); k += 3) side[k] = SolverOptions{}.max_displacement;
  EXPECT_EQ(contact.candidate_searches(), 0);
  EXPECT_EQ(contact.step_bound(x, side), 1.0);
  EXPECT_EQ(contact.candidate_searches(), 1);
  EXPECT_EQ(contact.step_bound(x + side, side), 1.0);
  EXPECT_TRUE(std::isfinite(contact.evaluate(x + 2 * side, nullptr)));
  EXPECT_EQ(contact.candidate_searches(), 1);
  EXPECT_EQ(contact.step_bound(x + 2 * side, side), 1.0);
  EXPECT_EQ(contact.candidate_searches(), 2);
  // Back to where they were searched: covered.
  EXPECT_EQ(contact.step_bound(x + 3 * side, -side), 1.0);
  EXPECT_EQ(contact.candidate_searches(), 2);
}

// A floppy patch crumpling under a layer a little above its start: without
// the contact it crosses itself or the layer; with it, neither the result
// nor any iterate in between crosses anything, with either solver.
TEST(Contact, NoAcceptedStepCrossesAnything) {
  const Crumpling problem;
  const PatchContact contact(problem.domain, layer_above(problem.domain, problem.top + 0.3), {});
  const Eigen::VectorXd start = problem.energy.variables(problem.start);
  ASSERT_EQ(crossings(problem.domain, contact, start), 0);

  const PatchObjective unguarded(problem.energy, nullptr);
  const SolverResult free = minimize(unguarded, start);
  EXPECT_GT(crossings(problem.domain, contact, free.x), 0) << "the case does not test anything";

  for (SolverKind kind : {SolverKind::Fast, SolverKind::GradientDescent}) {
    SolverOptions options;
    options.kind = kind;
    options.max_iterations = kind == SolverKind::Fast ? 20000 : 500;
    const PatchObjective guarded(problem.energy, &contact);
    const Recording recording(guarded);
    const SolverResult result = minimize(recording, start, options);
    ASSERT_GT(recording.iterates.size(), 10u);
    int crossing_iterates = 0;
    for (const Eigen::VectorXd& x : recording.iterates)
      crossing_iterates += crossings(problem.domain, contact, x) > 0;
    EXPECT_EQ(crossing_iterates, 0);
    EXPECT_EQ(crossings(problem.domain, contact, result.x), 0);
    EXPECT_LT(problem.energy.evaluate(result.x).total, problem.energy.evaluate(start).total);
    EXPECT_GT(contact.min_distance(result.x, 1.0), 0);
  }
}

}  // namespace
}  // namespace foldfill
