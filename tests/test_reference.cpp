// Every example of the authors' prototype fills with its listed hole, weights
// and obstacles (skipped when ../shared/data is absent).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/io.h"
#include "foldfill/obstacles.h"
#include "foldfill/topology.h"
#include "support/cloth_cases.h"
#include "support/loops.h"
#include "support/reference_cases.h"
#include "test_support.h"

namespace foldfill {
namespace {

using testing::loop_through;
using testing::ReferenceCase;

std::vector<ReferenceCase> load_cases() {
  return testing::read_reference_cases(testing::shared_dir() / "data" / "reference");
}

// `c`'s prototype weights, bending model and obstacles.
FillOptions prototype_options(const ReferenceCase& c) {
  FillOptions options;
  options.prototype = PrototypeWeights{};
  options.prototype->alpha = c.alpha;
  options.prototype->beta = c.beta;
  options.prototype->mu = c.mu;
  options.energy.bending = c.two_ring ? BendingModel::TwoRing : BendingModel::Quadratic;
  options.obstacles = testing::reference_obstacles(c);
  return options;
}

TEST(Reference, EveryPrototypeExampleFills) {
  FOLDFILL_REQUIRE_SHARED();
  for (const ReferenceCase& c : load_cases()) {
    SCOPED_TRACE(c.file);
    const Mesh mesh = read_mesh(c.path.string());
    const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh, c.file);
    const int hole = loop_through(loops, c.hole_vertex);
    ASSERT_GE(hole, 0);
    ASSERT_EQ(static_cast<int>(loops[hole].vertices.size()), c.hole_loop_size);

    const FillOptions options = prototype_options(c);
    const FillResult result = fill_holes(mesh, loops, {hole}, options, c.file);
    const HoleReport& report = result.report.holes.at(0);
    ASSERT_TRUE(report.filled) << report.reason;
    // Neither through itself nor through the cloth around it. Faces resting
    // on an obstacle (sim1, sim2) between vertices kept on its surface dip
    // into it: those are counted apart, and only printed here.
    EXPECT_EQ(report.crossings.patch_patch, 0);
    EXPECT_EQ(report.crossings.patch_mesh, 0);
    if (c.obstacles.empty()) {
      EXPECT_EQ(report.crossings.patch_obstacles, 0);
    }
    std::printf("%s: crossings %d / %d / %d, min distance %.3g h\n", c.file.c_str(),
                report.crossings.patch_patch, report.crossings.patch_mesh,
                report.crossings.patch_obstacles, report.min_distance);
    // Developable: the mean angle defect per vertex is a small fraction of a
    // degree (|K| times the vertex area, about 0.43 h^2 on a regular patch).
    const double h2 = report.length_scale * report.length_scale;
    EXPECT_LT(report.gaussian_mean_abs_final * h2, 0.02);
    // The paper's Fig. 8: |K| falls from the ARAP state. Not on two cases,
    // whose ARAP state is a taut, nearly flat membrane (contour's |K| h^2 is
    // 6e-6) into which the energy step brings the extra cloth as folds; their
    // figures are reported in the note of the end-to-end issue.
    const bool taut_after_arap = c.file.find("contour_hole") != std::string::npos ||
                                 c.file.find("sim2_hole") != std::string::npos;
    if (!taut_after_arap) {
      EXPECT_LT(report.gaussian_mean_abs_final, report.gaussian_mean_abs_after_arap);
    }
    EXPECT_LE(report.energy_final.total, report.energy_after_arap.total);

    // The chosen loop is closed, the outer ones stay open, the output is manifold.
    const std::vector<BoundaryLoop> after = find_boundary_loops(result.mesh, c.file);
    EXPECT_EQ(static_cast<int>(after.size()), c.outer_loops);
    EXPECT_EQ(loop_through(after, c.hole_vertex), -1);
    for (const Obstacle& o : options.obstacles) {
      for (int v = mesh.vertex_count(); v < result.mesh.vertex_count(); ++v) {
        EXPECT_GE(signed_distance(o, result.mesh.positions[v]),
                  -report.obstacle_allowance * report.length_scale);
      }
    }
    std::printf(
        "%s: %d new vertices, %d iterations, %.3f s, |K| %.4g -> %.4g, area/flat %.4f, lambda %g, "
        "start %s\n",
        c.file.c_str(), report.patch_vertex_count, report.iterations, report.seconds.total,
        report.gaussian_mean_abs_after_arap, report.gaussian_mean_abs_final,
        report.area_ratio_to_flat, report.lambda, to_string(report.start));
  }
}

// The reference case whose file name contains `name`.
ReferenceCase case_named(const std::vector<ReferenceCase>& cases, const std::string& name) {
  const auto found = std::find_if(cases.begin(), cases.end(), [&](const ReferenceCase& c) {
    return c.file.find(name) != std::string::npos;
  });
  if (found == cases.end()) throw std::runtime_error("no reference case " + name);
  return *found;
}

// Fills the hole of `c` with `options`.
FillResult fill_reference_mesh(const ReferenceCase& c, const FillOptions& options) {
  const Mesh mesh = read_mesh(c.path.string());
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh, c.file);
  const int hole = loop_through(loops, c.hole_vertex);
  if (hole < 0) throw std::runtime_error(c.file + ": the hole vertex is on no loop");
  return fill_holes(mesh, loops, {hole}, options, c.file);
}

HoleReport fill_reference(const ReferenceCase& c, const FillOptions& options) {
  return fill_reference_mesh(c, options).report.holes.at(0);
}

// sim2's patch settles into the gap between two cylinders and a sphere,
// never crossing them, in a few hundred iterations, within 2% of the energy
// gradient descent reaches in ten times as many (the two end in different
// crumpled minima).
TEST(Reference, Sim2SettlesBetweenItsObstaclesInFewIterations) {
  FOLDFILL_REQUIRE_SHARED();
  const ReferenceCase sim2 = case_named(load_cases(), "sim2_hole");
  FillOptions options = prototype_options(sim2);
  const HoleReport fast = fill_reference(sim2, options);
  options.solver.kind = SolverKind::GradientDescent;
  options.solver.max_iterations = 10 * fast.iterations;
  const HoleReport descent = fill_reference(sim2, options);
  ASSERT_TRUE(fast.filled && descent.filled);
  EXPECT_EQ(fast.self_intersections, 0);
  EXPECT_EQ(descent.self_intersections, 0);
  EXPECT_EQ(StopReason::Converged, fast.stop_reason);
  EXPECT_LT(fast.iterations, 2000);
  EXPECT_LT(fast.energy_final.total, 1.02 * descent.energy_final.total);
  std::printf("sim2: %d iterations, energy %.6g; gradient descent %d, %.6g\n", fast.iterations,
              fast.energy_final.total, descent.iterations, descent.energy_final.total);
}

// With foldfill's own (small) default bending weight the large contour hole
// crumples; it is minimised once, with that weight, and crosses nothing.
TEST(Reference, ContourFillsWithoutSelfIntersectionWithTheDefaults) {
  FOLDFILL_REQUIRE_SHARED();
  const ReferenceCase contour = case_named(load_cases(), "contour_hole");
  const FillOptions options;
  const HoleReport report = fill_reference(contour, options);
  ASSERT_TRUE(report.filled) << report.reason;
  EXPECT_NE(report.start, StartKind::Unguarded);
  EXPECT_EQ(report.self_intersections, 0);
  EXPECT_EQ(report.lambda, options.energy.lambda);
  EXPECT_TRUE(report.warning.empty()) << report.warning;
  std::printf("%s: %d iterations, start %s, %.3f s\n", contour.file.c_str(), report.iterations,
              to_string(report.start), report.seconds.total);
}

// At the prototype's weak repulsion (0.1) the patches are minimised with it,
// as asked, and cross nothing.
TEST(Reference, TheWeightsAskedForAreTheWeightsUsed) {
  FOLDFILL_REQUIRE_SHARED();
  for (const char* name : {"contour_hole", "curtain_hole"}) {
    const ReferenceCase c = case_named(load_cases(), name);
    const HoleReport report = fill_reference(c, prototype_options(c));
    ASSERT_TRUE(report.filled) << report.reason;
    EXPECT_EQ(report.self_intersections, 0) << name;
    EXPECT_EQ(report.repulsion, c.mu / c.alpha) << name;
  }
}

// The Curtain's and Contour's patches are large enough to start from a
// coarser fill: the coarse levels cross nothing either, their interpolation
// onto the patch crosses nothing (contour's, at the coarse level's clearance
// of the fill's thickness alone, crosses its strip, and the patch started
// again from ARAP), and the patch ends clean.
TEST(Reference, LargePatchesStartFromCleanCoarseLevels) {
  FOLDFILL_REQUIRE_SHARED();
  for (const char* name : {"contour_hole", "curtain_hole"}) {
    const ReferenceCase c = case_named(load_cases(), name);
    const FillOptions options;
    const HoleReport report = fill_reference(c, options);
    ASSERT_TRUE(report.filled) << report.reason;
    ASSERT_GE(report.patch_vertex_count, options.multilevel.min_patch_vertices);
    EXPECT_EQ(report.start, StartKind::CoarseLevels) << name;
    EXPECT_EQ(report.self_intersections, 0) << name;
    std::printf("%s: start %s, %d iterations\n", name, to_string(report.start), report.iterations);
  }
}

// Every simulated cloth case fills at the defaults from a start that crosses
// nothing and crosses nothing at the end, against the whole output mesh:
// dev07's cloth folds over the hole at its own edge, so its ARAP start and
// its membrane pass through that fold, and the start is untangled.
TEST(Reference, EveryClothCaseFillsWithoutCrossingAnything) {
  FOLDFILL_REQUIRE_SHARED();
  const auto cases = testing::read_cloth_cases(testing::shared_dir() / "data" / "cloth");
  ASSERT_FALSE(cases.empty());
  for (const testing::ClothCase& c : cases) {
    SCOPED_TRACE(c.name);
    const Mesh mesh = read_mesh(c.hole_mesh.string());
    const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
    int hole = -1;
    for (const BoundaryLoop& loop : loops)
      for (int v : loop.vertices)
        if (v == c.hole_vertex) hole = loop.id;
    ASSERT_GE(hole, 0);
    const FillResult result = fill_holes(mesh, loops, {hole}, FillOptions{});
    const HoleReport& report = result.report.holes.at(0);
    ASSERT_TRUE(report.filled) << report.reason;
    EXPECT_NE(report.start, StartKind::Unguarded);
    EXPECT_EQ(report.crossings.total(), 0);
    if (c.name.rfind("dev07", 0) == 0) {
      EXPECT_EQ(report.start, StartKind::Untangled);
    }
  }
}

}  // namespace
}  // namespace foldfill
