// The whole fill on exactly developable sheets, where the truth is known.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>

#include "foldfill/examples.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/metrics.h"

namespace foldfill {
namespace {

// A folded sheet with one disk-shaped hole cut across its folds.
CutMesh folded_sheet_with_hole(double radius = 0.5) {
  FoldedSheetOptions options;
  options.width = 3;
  options.height = 2;
  options.edge_length = 0.08;
  options.amplitude = 0.2;
  options.folds = 2;
  return cut_disk_hole(make_folded_sheet(options), {1.9, 1.0}, radius);
}

FillResult fill_default(const Mesh& mesh, const FillOptions& options = {}) {
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  const HoleChoice choice = select_holes(loops, HoleSelection{});
  return fill_holes(mesh, loops, choice.fill, options);
}

std::vector<Tri> new_faces(const FillResult& result, const Mesh& input) {
  return {result.mesh.faces.begin() + input.face_count(), result.mesh.faces.end()};
}

TEST(Inpaint, KeepsInputVerticesAndFacesBitForBit) {
  const CutMesh cut = folded_sheet_with_hole();
  const FillResult result = fill_default(cut.cut.mesh);
  ASSERT_EQ(result.report.holes.size(), 1u);
  ASSERT_TRUE(result.report.holes[0].filled) << result.report.holes[0].reason;
  const Mesh& in = cut.cut.mesh;
  ASSERT_GT(result.mesh.vertex_count(), in.vertex_count());
  EXPECT_TRUE(std::equal(in.positions.begin(), in.positions.end(), result.mesh.positions.begin()));
  EXPECT_TRUE(std::equal(in.faces.begin(), in.faces.end(), result.mesh.faces.begin()));
  // The hole is closed: only the sheet's outer loop is left.
  const std::vector<BoundaryLoop> loops = find_boundary_loops(result.mesh);
  EXPECT_EQ(loops.size(), 1u);
}

TEST(Inpaint, PutsBackTheMissingClothIsometrically) {
  const CutMesh cut = folded_sheet_with_hole();
  const FillResult result = fill_default(cut.cut.mesh);
  const HoleReport& hole = result.report.holes.at(0);
  ASSERT_TRUE(hole.filled) << hole.reason;
  EXPECT_LT(hole.edge_length_rms_rel_final, 0.01);
  const double patch_area = total_area(result.mesh.positions, new_faces(result, cut.cut.mesh));
  EXPECT_NEAR(patch_area / cut.removed_area, 1.0, 0.01);
  EXPECT_EQ(hole.self_intersections, 0);
  EXPECT_LE(hole.energy_final.total, hole.energy_after_arap.total);
}

TEST(Inpaint, ScalingTheInputScalesTheOutput) {
  const CutMesh cut = folded_sheet_with_hole(0.35);
  Mesh scaled = cut.cut.mesh;
  for (Vec3& p : scaled.positions) {
    for (double& x : p) x *= 1000;
  }
  const FillResult unit = fill_default(cut.cut.mesh), big = fill_default(scaled);
  ASSERT_EQ(unit.mesh.vertex_count(), big.mesh.vertex_count());
  double worst = 0;
  for (int v = cut.cut.mesh.vertex_count(); v < unit.mesh.vertex_count(); ++v) {
    for (int k = 0; k < 3; ++k) {
      worst = std::max(worst, std::abs(big.mesh.positions[v][k] / 1000 - unit.mesh.positions[v][k]));
    }
  }
  EXPECT_LT(worst, 1e-6 * unit.report.holes[0].length_scale * 10);
}

TEST(Inpaint, KeepsThePatchOutsideAnObstacle) {
  const CutMesh cut = folded_sheet_with_hole();
  // A sphere poking up into the hole from below the sheet.
  Vec3 centre{0, 0, 0};
  int n = 0;
  for (const Vec3& p : cut.cut.mesh.positions) {
    if (std::hypot(p[0] - 1.55, p[1] - 1.0) < 0.3) {
      for (int k = 0; k < 3; ++k) centre[k] += p[k];
      ++n;
    }
  }
  ASSERT_GT(n, 0);
  for (double& x : centre) x /= n;
  Obstacle sphere;
  sphere.center = {centre[0], centre[1], centre[2] - 0.45};
  sphere.radius = 0.5;
  FillOptions options;
  options.obstacles = {sphere};
  const FillResult result = fill_default(cut.cut.mesh, options);
  ASSERT_TRUE(result.report.holes.at(0).filled) << result.report.holes[0].reason;
  for (int v = cut.cut.mesh.vertex_count(); v < result.mesh.vertex_count(); ++v) {
    EXPECT_GE(signed_distance(sphere, result.mesh.positions[v]), -1e-9);
  }
}

TEST(Inpaint, ResultDoesNotDependOnTheThreadCount) {
  // Two holes, filled in parallel or one after the other.
  FoldedSheetOptions options;
  options.edge_length = 0.1;
  const DevelopableMesh sheet = make_folded_sheet(options);
  const CutMesh first = cut_disk_hole(sheet, {1.2, 1.5}, 0.4);
  const CutMesh both = cut_disk_hole(first.cut, {3.6, 1.5}, 0.4);
  omp_set_num_threads(1);
  const FillResult serial = fill_default(both.cut.mesh);
  omp_set_num_threads(2);
  const FillResult parallel = fill_default(both.cut.mesh);
  ASSERT_EQ(serial.report.holes.size(), 2u);
  EXPECT_EQ(serial.mesh.positions, parallel.mesh.positions);
  EXPECT_EQ(serial.mesh.faces, parallel.mesh.faces);
}

TEST(Inpaint, ReportsAHoleThatCannotBeFilledAndLeavesItOpen) {
  // A loop that touches the outer boundary cannot be flattened as an annulus.
  const CutMesh cut = folded_sheet_with_hole();
  const std::vector<BoundaryLoop> loops = find_boundary_loops(cut.cut.mesh);
  const std::vector<int> outer = default_outer_loops(loops);
  const FillResult result = fill_holes(cut.cut.mesh, loops, outer);
  ASSERT_EQ(result.report.holes.size(), 1u);
  EXPECT_FALSE(result.report.holes[0].filled);
  EXPECT_FALSE(result.report.holes[0].reason.empty());
  EXPECT_EQ(result.mesh.positions, cut.cut.mesh.positions);
  EXPECT_EQ(result.mesh.faces, cut.cut.mesh.faces);
}

}  // namespace
}  // namespace foldfill
