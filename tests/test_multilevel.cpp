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

TEST(Multilevel, SmallPatchHasNoCoarserLevels) {
  const Hole hole(folded_sheet_with_hole(0.08).cut.mesh);
  const EmbedDomain domain = hole.domain(1);
  MultilevelOptions options;
  options.min_patch_vertices = domain.free_count() + 1;
  EXPECT_TRUE(coarser_levels(hole.strip, hole.flat, {}, domain, options).empty());
  options.min_patch_vertices = 0;  // never
  EXPECT_TRUE(coarser_levels(hole.strip, hole.flat, {}, domain, options).empty());
}

TEST(Multilevel, LevelsCoarsenDownToTheThreshold) {
  const Hole hole(folded_sheet_with_hole(0.08).cut.mesh);
  TriangulateOptions triangulate;
  triangulate.density = 4;
  const EmbedDomain domain = hole.domain(triangulate.density);
  MultilevelOptions options;
  options.min_patch_vertices = 100;
  const std::vector<EmbedDomain> levels =
      coarser_levels(hole.strip, hole.flat, triangulate, domain, options);
  // Finest first; only the coarsest is below the threshold; a quarter of the
  // vertices per level, give or take the boundary; all share the strip.
  ASSERT_GE(levels.size(), 2u);
  std::vector<int> sizes{domain.free_count()};
  for (const EmbedDomain& level : levels) {
    sizes.push_back(level.free_count());
    EXPECT_EQ(level.fixed_positions, domain.fixed_positions);
    EXPECT_EQ(level.length_scale, domain.length_scale);
  }
  EXPECT_LT(sizes.back(), options.min_patch_vertices);
  for (size_t k = 1; k < sizes.size(); ++k) {
    EXPECT_GE(sizes[k - 1], options.min_patch_vertices);
    EXPECT_GT(sizes[k - 1], 2.5 * sizes[k]);
    EXPECT_LT(sizes[k - 1], 5.5 * sizes[k]);
  }
}

TEST(Multilevel, RefusesACoarseningThatDoesNotCoarsen) {
  const Hole hole(folded_sheet_with_hole(0.08).cut.mesh);
  const EmbedDomain domain = hole.domain(1);
  MultilevelOptions options;
  options.min_patch_vertices = 1;
  options.coarsening = 1;
  EXPECT_THROW(coarser_levels(hole.strip, hole.flat, {}, domain, options), Error);
}

TEST(Multilevel, RefusesANegativeInterpolationClearance) {
  const Hole hole(folded_sheet_with_hole(0.08).cut.mesh);
  const EmbedDomain domain = hole.domain(1);
  MultilevelOptions options;
  options.min_patch_vertices = 1;
  options.interpolation_clearance = -0.1;
  EXPECT_THROW(coarser_levels(hole.strip, hole.flat, {}, domain, options), Error);
  options.interpolation_clearance = std::nan("");
  EXPECT_THROW(coarser_levels(hole.strip, hole.flat, {}, domain, options), Error);
}

// The mean over the patch faces' edges (an interior edge counted once per
// face), the strip's faces left out.
TEST(Multilevel, MeanPatchEdgeLengthIsOverThePatchFacesOnly) {
  EmbedDomain domain;
  domain.rest_uv = {{0, 0}, {10, 0}, {0, 10}, {1, 0}, {0, 2}};
  domain.fixed_count = 3;
  domain.faces = {{0, 1, 2}, {0, 3, 4}};
  domain.strip_face_count = 1;
  EXPECT_NEAR(mean_patch_edge_length(domain), (1 + std::sqrt(5.0) + 2) / 3, 1e-15);
  domain.strip_face_count = 2;
  EXPECT_EQ(mean_patch_edge_length(domain), 0);
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
  single.multilevel.min_patch_vertices = 0;
  const HoleReport one = fill(cut.cut.mesh, single).report.holes.at(0);
  const HoleReport multi = fill(cut.cut.mesh, multilevel_fill()).report.holes.at(0);
  ASSERT_TRUE(one.filled) << one.reason;
  ASSERT_TRUE(multi.filled) << multi.reason;
  ASSERT_GT(multi.patch_vertex_count, 900);
  EXPECT_EQ(multi.stop_reason, StopReason::Converged);
  EXPECT_EQ(multi.start, StartKind::CoarseLevels);
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
  options.multilevel.min_patch_vertices = 0;
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
