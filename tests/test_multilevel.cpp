// The coarse-to-fine start: interpolation between levels of one hole, the
// choice of levels, and the fill it leads to.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>

#include "foldfill/error.h"
#include "foldfill/examples.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/multilevel.h"
#include "test_geometry.h"

namespace foldfill {
namespace {

CutMesh folded_sheet_with_hole(double edge_length) {
  return cut_disk_hole(testing::small_folded_sheet(edge_length), {1.9, 1.0}, 0.5);
}

// The flattened strip of a sheet's hole, meshed at any density.
struct Hole {
  Strip strip;
  Flattening flat;

  explicit Hole(const Mesh& mesh) {
    const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
    strip = extract_strip(mesh, loops.at(select_holes(loops, HoleSelection{}).fill.at(0)));
    flat = flatten_strip(strip);
  }
  EmbedDomain domain(double density) const {
    TriangulateOptions options;
    options.density = density;
    return make_embed_domain(strip, flat, triangulate_hole(hole_polygon(strip, flat), options));
  }
};

Vec3 affine(const Vec2& uv) {
  return {0.3 + 1.1 * uv[0] - 0.4 * uv[1], -0.2 + 0.7 * uv[0] + 0.9 * uv[1],
          0.5 - 0.6 * uv[0] + 0.2 * uv[1]};
}

TEST(Multilevel, InterpolationReproducesAnAffineMapExactly) {
  const Hole hole(folded_sheet_with_hole(0.08).cut.mesh);
  const EmbedDomain coarse = hole.domain(0.5), fine = hole.domain(2);
  ASSERT_GT(coarse.free_count(), 0);
  ASSERT_GT(fine.free_count(), 8 * coarse.free_count());
  std::vector<Vec3> coarse_positions;
  for (const Vec2& uv : coarse.rest_uv) coarse_positions.push_back(affine(uv));

  const std::vector<Vec3> positions = interpolate_patch(coarse, coarse_positions, fine);
  ASSERT_EQ(positions.size(), fine.rest_uv.size());
  for (int v = 0; v < fine.fixed_count; ++v) EXPECT_EQ(positions[v], fine.fixed_positions[v]);
  double worst = 0;
  for (int v = fine.fixed_count; v < fine.vertex_count(); ++v)
    for (int d = 0; d < 3; ++d)
      worst = std::max(worst, std::abs(positions[v][d] - affine(fine.rest_uv[v])[d]));
  EXPECT_LT(worst, 1e-12);
}

TEST(Multilevel, RefusesDomainsOfDifferentHoles) {
  const Hole hole(folded_sheet_with_hole(0.08).cut.mesh);
  const Hole other(folded_sheet_with_hole(0.1).cut.mesh);
  const EmbedDomain coarse = hole.domain(1), fine = other.domain(1);
  const std::vector<Vec3> coarse_positions(coarse.rest_uv.size(), Vec3{0, 0, 0});
  EXPECT_THROW(interpolate_patch(coarse, coarse_positions, fine), Error);
}

TEST(Multilevel, SmallPatchStartsFromArapWithoutCoarserLevels) {
  const Hole hole(folded_sheet_with_hole(0.08).cut.mesh);
  const EmbedDomain domain = hole.domain(1);
  MultilevelOptions options;
  options.min_patch_vertices = domain.free_count() + 1;
  int minimised = 0;
  const auto count = [&](const EmbedDomain&, const std::vector<Vec3>& start) {
    ++minimised;
    return start;
  };
  EXPECT_EQ(multilevel_start(hole.strip, hole.flat, {}, domain, {}, options, count),
            arap_embed(domain));
  EXPECT_EQ(minimised, 0);
}

TEST(Multilevel, LevelsCoarsenDownToTheThreshold) {
  const Hole hole(folded_sheet_with_hole(0.08).cut.mesh);
  TriangulateOptions triangulate;
  triangulate.density = 4;
  const EmbedDomain domain = hole.domain(triangulate.density);
  MultilevelOptions options;
  options.min_patch_vertices = 100;
  std::vector<int> level_sizes;
  const auto record = [&](const EmbedDomain& level, const std::vector<Vec3>& start) {
    level_sizes.push_back(level.free_count());
    return start;
  };
  const std::vector<Vec3> start =
      multilevel_start(hole.strip, hole.flat, triangulate, domain, {}, options, record);
  EXPECT_EQ(start.size(), domain.rest_uv.size());
  // Coarsest first; only the coarsest is below the threshold; a quarter of
  // the vertices per level, give or take the boundary.
  ASSERT_GE(level_sizes.size(), 2u);
  EXPECT_LT(level_sizes.front(), options.min_patch_vertices);
  level_sizes.push_back(domain.free_count());
  for (size_t k = 1; k < level_sizes.size(); ++k) {
    EXPECT_GE(level_sizes[k], options.min_patch_vertices);
    EXPECT_GT(level_sizes[k], 2.5 * level_sizes[k - 1]);
    EXPECT_LT(level_sizes[k], 5.5 * level_sizes[k - 1]);
  }
}

// A sheet's hole meshed at density 2, whose start has one coarser level.
struct TwoLevels {
  Hole hole{folded_sheet_with_hole(0.08).cut.mesh};
  EmbedDomain domain = hole.domain(2);

  std::vector<Vec3> start(const LevelMinimiser& minimise) const {
    TriangulateOptions triangulate;
    triangulate.density = 2;
    MultilevelOptions options;
    options.min_patch_vertices = domain.free_count();
    return multilevel_start(hole.strip, hole.flat, triangulate, domain, {}, options, minimise);
  }
};

TEST(Multilevel, ACoarseLevelFoldedThroughItselfGivesWayToArap) {
  const TwoLevels levels;
  // The half u > 0 folded over onto the half u < 0, through it at u = 1.
  const auto fold_through = [](const EmbedDomain& level, const std::vector<Vec3>& start) {
    std::vector<Vec3> folded = start;
    for (int v = level.fixed_count; v < level.vertex_count(); ++v) {
      const double u = level.rest_uv[v][0], w = level.rest_uv[v][1];
      folded[v] = u < 0 ? Vec3{u, w, 0} : Vec3{-u, w, 0.3 * (u - 1)};
    }
    return folded;
  };
  EXPECT_EQ(levels.start(fold_through), arap_embed(levels.domain));
}

TEST(Multilevel, ACoarseLevelThatGivesNothingGivesWayToArap) {
  const TwoLevels levels;
  int minimised = 0;
  const auto no_start = [&](const EmbedDomain&, const std::vector<Vec3>&) {
    ++minimised;
    return std::optional<std::vector<Vec3>>{};
  };
  EXPECT_EQ(levels.start(no_start), arap_embed(levels.domain));
  EXPECT_EQ(minimised, 1);
}

TEST(Multilevel, RefusesACoarseningThatDoesNotCoarsen) {
  const Hole hole(folded_sheet_with_hole(0.08).cut.mesh);
  const EmbedDomain domain = hole.domain(1);
  MultilevelOptions options;
  options.min_patch_vertices = 1;
  options.coarsening = 1;
  const auto identity = [](const EmbedDomain&, const std::vector<Vec3>& start) { return start; };
  EXPECT_THROW(multilevel_start(hole.strip, hole.flat, {}, domain, {}, options, identity), Error);
}

FillResult fill(const Mesh& mesh, const FillOptions& options) {
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  return fill_holes(mesh, loops, select_holes(loops, HoleSelection{}).fill, options);
}

// A patch of about 1,000 vertices here, filled from two coarser levels.
FillOptions multilevel_fill() {
  FillOptions options;
  options.multilevel.min_patch_vertices = 200;
  return options;
}

TEST(Multilevel, FillEndsAtTheSingleLevelEnergy) {
  const CutMesh cut = folded_sheet_with_hole(0.025);
  FillOptions single;
  single.multilevel.enabled = false;
  const HoleReport one = fill(cut.cut.mesh, single).report.holes.at(0);
  const HoleReport multi = fill(cut.cut.mesh, multilevel_fill()).report.holes.at(0);
  ASSERT_TRUE(one.filled) << one.reason;
  ASSERT_TRUE(multi.filled) << multi.reason;
  ASSERT_GT(multi.patch_vertex_count, 900);
  EXPECT_EQ(multi.stop_reason, "converged");
  EXPECT_EQ(multi.self_intersections, 0);
  EXPECT_NEAR(multi.energy_final.total / one.energy_final.total, 1, 0.01);
  // The coarse levels put the patch near its minimum already.
  EXPECT_LT(multi.energy_after_arap.total, one.energy_after_arap.total);
}

// The paper's gradient descent is the reference for the fast solver: it
// starts from ARAP whatever the multilevel options.
TEST(Multilevel, GradientDescentStartsFromArap) {
  const CutMesh cut = folded_sheet_with_hole(0.025);
  FillOptions options = multilevel_fill();
  options.solver.kind = SolverKind::GradientDescent;
  options.solver.max_iterations = 5;
  const FillResult multi = fill(cut.cut.mesh, options);
  options.multilevel.enabled = false;
  const FillResult single = fill(cut.cut.mesh, options);
  ASSERT_TRUE(multi.report.holes.at(0).filled);
  ASSERT_GT(multi.report.holes.at(0).patch_vertex_count, 900);
  EXPECT_EQ(multi.mesh.positions, single.mesh.positions);
}

TEST(Multilevel, FillDoesNotDependOnTheThreadCount) {
  const CutMesh cut = folded_sheet_with_hole(0.04);
  omp_set_num_threads(1);
  const FillResult serial = fill(cut.cut.mesh, multilevel_fill());
  omp_set_num_threads(2);
  const FillResult parallel = fill(cut.cut.mesh, multilevel_fill());
  ASSERT_TRUE(serial.report.holes.at(0).filled);
  EXPECT_EQ(serial.mesh.positions, parallel.mesh.positions);
  EXPECT_EQ(serial.mesh.faces, parallel.mesh.faces);
}

}  // namespace
}  // namespace foldfill
