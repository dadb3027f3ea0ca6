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
#include "foldfill/error.h"
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

// Too near: a step down the barrier, as a minimisation would go, whose
// longest vertex move is `longest`.
Eigen::VectorXd down_the_barrier(const PatchContact& contact, const Eigen::VectorXd& x,
                                 double longest) {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(x.size());
  contact.evaluate(x, &g);
  double largest = 0;
  for (Eigen::Index k = 0; k < g.size(); k += 3)
    largest = std::max(largest, g.segment<3>(k).norm());
  return -longest / largest * g;
}

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

// Scope::ObstaclesOnly keeps the patch out of the analytic obstacles alone:
// a move up through the layer of cloth is not cut short, one up into a
// plane above the layer is; the layer within the thickness adds nothing to
// its barrier. The whole contact, asked afterwards, gives what a fresh one
// gives: candidates searched for the obstacles alone do not stand in for
// the pairs'.
TEST(Contact, TheObstaclesOnlyScopeSeesTheObstaclesAlone) {
  const Crumpling problem;
  const double gap = 0.05;
  Obstacle ceiling;
  ceiling.type = Obstacle::Type::Plane;
  ceiling.center = {0, 0, problem.top + 1.0};
  ceiling.normal = {0, 0, -1};
  const PatchScene layer = layer_above(problem.domain, problem.top + gap);
  const PatchContact contact(problem.domain, layer, {}, {ceiling});
  const Eigen::VectorXd x = problem.energy.variables(problem.start);
  const auto only = PatchContact::Scope::ObstaclesOnly;
  EXPECT_EQ(contact.evaluate(x, nullptr, only), 0.0);
  Eigen::VectorXd through_layer = Eigen::VectorXd::Zero(x.size());
  for (Eigen::Index k = 2; k < x.size(); k += 3) through_layer[k] = 0.5;
  EXPECT_EQ(contact.step_bound(x, through_layer, only), 1.0);
  EXPECT_GT(crossings(problem.domain, contact, x + through_layer), 0);
  const Eigen::VectorXd into_ceiling = 4 * through_layer;
  const double bound = contact.step_bound(x, into_ceiling, only);
  EXPECT_GT(bound, 0.3);
  EXPECT_LT(bound, 0.5);
  const std::vector<Vec3> at_bound = contact.positions(x + bound * into_ceiling);
  for (const Vec3& p : at_bound) EXPECT_LT(p[2], problem.top + 1.0);
  Eigen::VectorXd gradient = Eigen::VectorXd::Zero(x.size());
  const double value = contact.evaluate(x, &gradient);
  ASSERT_GT(value, 0);  // the layer is within the thickness of the patch's top
  const PatchContact fresh(problem.domain, layer, {}, {ceiling});
  Eigen::VectorXd fresh_gradient = Eigen::VectorXd::Zero(x.size());
  EXPECT_EQ(value, fresh.evaluate(x, &fresh_gradient));
  EXPECT_EQ(gradient, fresh_gradient);
  EXPECT_LT(contact.step_bound(x, through_layer), 0.2);
}

// A step the candidates do not cover searches them again around its end,
// so that they also cover the next steps. What uses them up is how far the
// vertices' displacements since the search spread (0, the fixed vertices',
// included): moving as a whole in one direction, three steps of the fast
// solver's longest move take one search; moving apart, two.
TEST(Contact, CandidatesLastWhileTheDisplacementsSpreadLessThanTheSkin) {
  const Crumpling problem;
  const Eigen::VectorXd x = problem.energy.variables(problem.start);
  const double longest = SolverOptions{}.max_displacement;
  {
    const PatchContact contact(problem.domain, layer_above(problem.domain, problem.top + 1), {});
    Eigen::VectorXd side = Eigen::VectorXd::Zero(x.size());
    for (Eigen::Index k = 0; k < side.size(); k += 3) side[k] = longest;
    EXPECT_EQ(contact.candidate_searches(), 0);
    EXPECT_EQ(contact.step_bound(x, side), 1.0);  // searched at x + side
    EXPECT_EQ(contact.candidate_searches(), 1);
    EXPECT_EQ(contact.step_bound(x + side, side), 1.0);
    EXPECT_TRUE(std::isfinite(contact.evaluate(x + 2 * side, nullptr)));
    EXPECT_EQ(contact.step_bound(x + 2 * side, side), 1.0);
    EXPECT_EQ(contact.candidate_searches(), 1);
    EXPECT_EQ(contact.step_bound(x + 3 * side, side), 1.0);  // 3 x longest > the skin
    EXPECT_EQ(contact.candidate_searches(), 2);
    // Back towards where they were searched: covered.
    EXPECT_EQ(contact.step_bound(x + 4 * side, -side), 1.0);
    EXPECT_EQ(contact.candidate_searches(), 2);
  }
  {
    const PatchContact contact(problem.domain, layer_above(problem.domain, problem.top + 1), {});
    // The halves either side of the patch's middle move apart.
    double middle = 0;
    for (Eigen::Index k = 0; k < x.size(); k += 3) middle += x[k] / (x.size() / 3);
    Eigen::VectorXd apart = Eigen::VectorXd::Zero(x.size());
    for (Eigen::Index k = 0; k < apart.size(); k += 3)
      apart[k] = x[k] > middle ? longest : -longest;
    EXPECT_EQ(contact.step_bound(x, apart), 1.0);
    EXPECT_EQ(contact.step_bound(x + apart, apart), 1.0);
    EXPECT_EQ(contact.candidate_searches(), 1);
    EXPECT_EQ(contact.step_bound(x + 2 * apart, apart), 1.0);
    EXPECT_EQ(contact.candidate_searches(), 2);
  }
}

// Candidates kept from an earlier search give the barrier and its gradient
// that a contact searching afresh at every point gives, bit for bit, and
// steps bounded by them cross nothing: along a walk of random steps (vertices moving each their own
// way, and the whole patch drifting towards the layer above and a sphere beside it).
TEST(Contact, KeptCandidatesGiveWhatAFreshSearchGives) {
  const Crumpling problem;
  const PatchScene layer = layer_above(problem.domain, problem.top + 0.3);
  // A sphere 0.15 beyond the patch's rightmost vertex, level with it.
  const Vec3* right = &problem.start.back();
  for (const Vec3& p : problem.start)
    if (p[0] > (*right)[0]) right = &p;
  Obstacle sphere;
  sphere.type = Obstacle::Type::Sphere;
  sphere.radius = 0.5;
  sphere.center = {(*right)[0] + 0.15 + sphere.radius, (*right)[1], (*right)[2]};
  const PatchContact sphere_alone(problem.domain, PatchScene{}, {}, {sphere});
  const PatchContact kept(problem.domain, layer, {}, {sphere});
  Eigen::VectorXd x = problem.energy.variables(problem.start);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  const double longest = SolverOptions{}.max_displacement;
  int compared = 0, touching = 0;
  for (int step = 0; step < 60; ++step) {
    Eigen::VectorXd dx(x.size());
    if (kept.min_distance(x, 1.0) < 0.3 * kept.options().thickness) {
      dx = down_the_barrier(kept, x, 0.5 * longest);
    } else {
      for (Eigen::Index k = 0; k < dx.size(); ++k) dx[k] = 0.25 * longest * unit(random);
      for (Eigen::Index k = 0; k < dx.size(); k += 3) {
        dx[k] += 0.5 * longest;      // towards the sphere
        dx[k + 2] += 0.1 * longest;  // and up to the layer
      }
    }
    const double bound = kept.step_bound(x, dx);
    ASSERT_GT(bound, 0) << "step " << step;
    x += 0.9 * bound * dx;
    ASSERT_EQ(crossings(problem.domain, kept, x), 0) << "step " << step;
    // The least distance from the kept candidates (and from a fresh
    // search) is that of a contact that never searched for candidates.
    const PatchContact unsearched(problem.domain, layer, {}, {sphere});
    for (const double limit : {1e-6, 0.05, kept.options().thickness})
      ASSERT_EQ(kept.min_distance(x, limit), unsearched.min_distance(x, limit)) << "step " << step;
    const PatchContact fresh_there(problem.domain, layer, {}, {sphere});
    Eigen::VectorXd g_kept = Eigen::VectorXd::Zero(x.size()), g_fresh = g_kept;
    const double e_kept = kept.evaluate(x, &g_kept), e_fresh = fresh_there.evaluate(x, &g_fresh);
    ASSERT_EQ(e_kept, e_fresh) << "step " << step;
    ASSERT_TRUE(g_kept == g_fresh) << "step " << step;
    ++compared;
    touching += sphere_alone.evaluate(x, nullptr) > 0;
  }
  EXPECT_EQ(compared, 60);
  EXPECT_GT(touching, 10) << "the walk never came near the sphere";
  EXPECT_LT(kept.candidate_searches(), 40) << "the candidates were never kept";
}

// Where only a part of the patch moves, the candidates are searched again
// for the pairs of the vertices that moved far alone (partial searches), and
// give what searches of everything give, bit for bit: the barrier, its
// gradient, the least distance and the step bounds, along a walk of one
// corner of the patch rising into the layer above and crumpling.
TEST(Contact, PartialSearchesGiveWhatWholeSearchesGive) {
  const Crumpling problem;
  const PatchScene layer = layer_above(problem.domain, problem.top + 0.3);
  ContactOptions whole_options;
  whole_options.moved_share = 0;  // every search is whole
  const PatchContact partial(problem.domain, layer, {});
  const PatchContact whole(problem.domain, layer, whole_options);
  Eigen::VectorXd x = problem.energy.variables(problem.start);
  double corner_x = HUGE_VAL, corner_y = HUGE_VAL;
  for (Eigen::Index k = 0; k < x.size(); k += 3)
    corner_x = std::min(corner_x, x[k]), corner_y = std::min(corner_y, x[k + 1]);
  // The free vertices within 1.8 of the lowest corner: about a fifth.
  std::vector<bool> moving(x.size() / 3);
  int moving_count = 0;
  for (Eigen::Index k = 0; k < x.size(); k += 3) {
    moving[k / 3] = std::hypot(x[k] - corner_x, x[k + 1] - corner_y) < 1.8;
    moving_count += moving[k / 3];
  }
  ASSERT_GT(moving_count, 5);
  ASSERT_LT(moving_count, static_cast<int>(x.size() / 3) / 3);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1, 1);
  const double longest = SolverOptions{}.max_displacement;
  int near_layer = 0;
  for (int step = 0; step < 120; ++step) {
    Eigen::VectorXd dx = Eigen::VectorXd::Zero(x.size());
    if (partial.min_distance(x, 1.0) < 0.3 * partial.options().thickness) {
      dx = down_the_barrier(partial, x, 0.5 * longest);
    } else {
      for (Eigen::Index k = 0; k < dx.size(); k += 3) {
        if (!moving[k / 3]) continue;
        for (int c = 0; c < 3; ++c) dx[k + c] = 0.8 * longest * unit(random);
        dx[k + 2] += 0.3 * longest;  // up to the layer
      }
    }
    const double bound = partial.step_bound(x, dx);
    ASSERT_EQ(bound, whole.step_bound(x, dx)) << "step " << step;
    ASSERT_GT(bound, 0) << "step " << step;
    x += 0.9 * bound * dx;
    ASSERT_EQ(crossings(problem.domain, partial, x), 0) << "step " << step;
    Eigen::VectorXd g_partial = Eigen::VectorXd::Zero(x.size()), g_whole = g_partial;
    const double e_partial = partial.evaluate(x, &g_partial);
    ASSERT_EQ(e_partial, whole.evaluate(x, &g_whole)) << "step " << step;
    ASSERT_TRUE(g_partial == g_whole) << "step " << step;
    for (const double limit : {0.05, partial.options().thickness})
      ASSERT_EQ(partial.min_distance(x, limit), whole.min_distance(x, limit)) << "step " << step;
    near_layer += e_partial > 0;
  }
  EXPECT_GT(near_layer, 10) << "the walk never came near anything";
  EXPECT_GT(partial.partial_candidate_searches(), 5)
      << partial.candidate_searches() << " " << whole.candidate_searches() << " " << near_layer;
  EXPECT_EQ(whole.partial_candidate_searches(), 0);
}

TEST(Contact, MovedDriftAndShareAreChecked) {
  const Crumpling problem;
  for (const auto& [drift, share] : {std::pair{0.5, 0.5}, {-0.1, 0.5}, {0.25, 1.5}, {0.25, -1.0}}) {
    ContactOptions options;
    options.moved_drift = drift;
    options.moved_share = share;
    EXPECT_THROW(PatchContact contact(problem.domain, PatchScene{}, options), UsageError)
        << drift << " " << share;
  }
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
  // The contact's meeting face pairs find the crossings too.
  const auto crosses = [&](const Eigen::VectorXd& x) {
    return any_crossing(contact.positions(x), contact.mesh().faces, contact.first_patch_face(),
                        contact.end_patch_face(), contact.patch_face_pairs(x));
  };
  EXPECT_TRUE(crosses(free.x));
  EXPECT_FALSE(crosses(start));

  for (SolverKind kind : {SolverKind::Fast, SolverKind::GradientDescent}) {
    SolverOptions options;
    options.kind = kind;
    options.max_iterations = kind == SolverKind::Fast ? 20000 : 500;
    const PatchObjective guarded(problem.energy, &contact);
    const Recording recording(guarded);
    const SolverResult result = minimize(recording, start, options);
    ASSERT_GT(recording.iterates.size(), 10u);
    int crossing_iterates = 0;
    for (const Eigen::VectorXd& x : recording.iterates) {
      crossing_iterates += crossings(problem.domain, contact, x) > 0;
      crossing_iterates += crosses(x);
    }
    EXPECT_EQ(crossing_iterates, 0);
    EXPECT_EQ(crossings(problem.domain, contact, result.x), 0);
    EXPECT_LT(problem.energy.evaluate(result.x).total, problem.energy.evaluate(start).total);
    EXPECT_GT(contact.min_distance(result.x, 1.0), 0);
  }
}

// The patch's face pairs are every pair of faces whose closed boxes meet,
// one of them the patch's, as a test of every pair finds them: the patch's
// faces with all three corners on the loop (at the lattice's corners, which
// never move) among them, at the start and after random moves.
TEST(Contact, PatchFacePairsAreEveryPairOfMeetingBoxes) {
  const Crumpling problem;
  const PatchContact contact(problem.domain, layer_above(problem.domain, problem.top + 0.3), {});
  const std::vector<Tri>& faces = contact.mesh().faces;
  const int first = contact.first_patch_face(), end = contact.end_patch_face();
  const int fixed = static_cast<int>(contact.mesh().fixed_count);
  int fixed_patch_faces = 0;
  for (int f = first; f < end; ++f)
    fixed_patch_faces += std::max({faces[f][0], faces[f][1], faces[f][2]}) < fixed;
  ASSERT_GT(fixed_patch_faces, 0) << "no patch face has all its corners fixed";
  Eigen::VectorXd x = problem.energy.variables(problem.start);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int trial = 0; trial < 3; ++trial) {
    const std::vector<Vec3> p = contact.positions(x);
    std::vector<Box> boxes;
    for (const Tri& t : faces) {
      Box box{p[t[0]], p[t[0]]};
      for (int v : t)
        for (int c = 0; c < 3; ++c) {
          box.low[c] = std::min(box.low[c], p[v][c]);
          box.high[c] = std::max(box.high[c], p[v][c]);
        }
      boxes.push_back(box);
    }
    std::vector<IndexPair> expected;
    const int count = static_cast<int>(faces.size());
    for (int f = 0; f < count; ++f)
      for (int g = f + 1; g < count; ++g) {
        const bool patch = (f >= first && f < end) || (g >= first && g < end);
        if (patch && boxes_meet(boxes[f], boxes[g], 0.0)) expected.push_back({f, g});
      }
    std::vector<IndexPair> found = contact.patch_face_pairs(x);
    for (IndexPair& pair : found) pair = {std::min(pair[0], pair[1]), std::max(pair[0], pair[1])};
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, expected) << "trial " << trial;
    for (Eigen::Index k = 0; k < x.size(); ++k) x[k] += 0.3 * unit(random);
  }
}

}  // namespace
}  // namespace foldfill
