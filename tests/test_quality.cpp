// The comparison metrics on tiny meshes with known answers, and the
// foldfill-against-Liepa comparison of bench_quality on one generated sheet.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/examples.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/liepa.h"
#include "foldfill/metrics.h"

namespace foldfill {
namespace {

// The unit square [0,1]^2 at height z, two triangles.
void add_square(double z, std::vector<Vec3>& positions, std::vector<Tri>& faces) {
  const int first = static_cast<int>(positions.size());
  for (const Vec3& p : {Vec3{0, 0, z}, Vec3{1, 0, z}, Vec3{1, 1, z}, Vec3{0, 1, z}})
    positions.push_back(p);
  faces.push_back({first, first + 1, first + 2});
  faces.push_back({first, first + 2, first + 3});
}

TEST(SurfaceDistance, ParallelSquaresAreTheirGapApart) {
  std::vector<Vec3> a, b;
  std::vector<Tri> fa, fb;
  add_square(0, a, fa);
  add_square(0.37, b, fb);
  const SurfaceDistance d = surface_distance(a, fa, b, fb);
  EXPECT_NEAR(d.hausdorff, 0.37, 1e-12);
  EXPECT_NEAR(d.mean, 0.37, 1e-12);
}

TEST(SurfaceDistance, IsTwoSided) {
  // A square and its left half: every point of the half lies on the square,
  // but the square's right edge is 0.5 from the half.
  std::vector<Vec3> square, half{{0, 0, 0}, {0.5, 0, 0}, {0.5, 1, 0}, {0, 1, 0}};
  std::vector<Tri> square_faces, half_faces{{0, 1, 2}, {0, 2, 3}};
  add_square(0, square, square_faces);
  EXPECT_NEAR(surface_distance(square, square_faces, half, half_faces).hausdorff, 0.5, 1e-12);
  EXPECT_NEAR(surface_distance(half, half_faces, square, square_faces).hausdorff, 0.5, 1e-12);
  EXPECT_THROW(surface_distance(square, square_faces, half, {}), Error);
}

// Two triangles hinged on the edge 0-1 (along y), the second turned by `angle`
// out of the plane of the first.
std::vector<Vec3> hinge(double angle) {
  return {{0, 0, 0}, {0, 1, 0}, {1, 0.5, 0}, {-std::cos(angle), 0.5, std::sin(angle)}};
}
const std::vector<Tri> kHingeFaces{{0, 2, 1}, {0, 1, 3}};

TEST(DihedralAngles, FoldedPairGivesItsFoldAngle) {
  for (double angle : {0.0, 0.3, 1.2, 2.5}) {
    const std::vector<double> angles = dihedral_angles(hinge(angle), kHingeFaces, {{1, 0}});
    ASSERT_EQ(angles.size(), 1u);
    EXPECT_NEAR(angles[0], angle, 1e-12) << angle;
  }
}

TEST(DihedralAngles, RejectsAnEdgeWithoutTwoFaces) {
  EXPECT_THROW(dihedral_angles(hinge(0.5), kHingeFaces, {{0, 2}}), Error);
  EXPECT_THROW(dihedral_angles(hinge(0.5), kHingeFaces, {{2, 3}}), Error);
}

std::vector<int> interior_vertices(const Mesh& mesh) {
  std::vector<char> on_boundary(mesh.positions.size(), 0);
  for (const BoundaryLoop& loop : find_boundary_loops(mesh)) {
    for (int v : loop.vertices) on_boundary[v] = 1;
  }
  std::vector<int> interior;
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    if (!on_boundary[v]) interior.push_back(v);
  }
  return interior;
}

TEST(MeanCurvature, CylinderHasHalfItsInverseRadius) {
  for (double radius : {0.5, 2.0}) {
    const Mesh cylinder = make_cylinder_section(radius, 2.0, 1.5, 0.05).mesh;
    EXPECT_NEAR(
        mean_abs_mean_curvature(cylinder.positions, cylinder.faces, interior_vertices(cylinder)),
        0.5 / radius, 0.005 / radius);
  }
}

TEST(MeanCurvature, PlaneHasNone) {
  FoldedSheetOptions flat;
  flat.amplitude = 0;
  const Mesh plane = make_folded_sheet(flat).mesh;
  EXPECT_NEAR(mean_abs_mean_curvature(plane.positions, plane.faces, interior_vertices(plane)), 0,
              1e-12);
  EXPECT_EQ(mean_abs_mean_curvature(plane.positions, plane.faces, {}), 0);
}

TEST(TriangleQuality, FindsTheSmallestAngleAndTheSlivers) {
  const std::vector<Vec3> positions{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {10, 0.5, 0}};
  // A right isosceles triangle (45 degrees) and a sliver whose angle at
  // (10, 0.5), between (-9, -0.5) and (-10, 0.5), is about 6 degrees.
  const TriangleQuality quality = triangle_quality(positions, {{0, 1, 2}, {1, 3, 2}});
  EXPECT_NEAR(quality.min_angle_deg, std::atan2(9.5, 89.75) * 180 / M_PI, 1e-9);
  EXPECT_DOUBLE_EQ(quality.share_below_20deg, 0.5);
  EXPECT_NEAR(triangle_quality(positions, {{0, 1, 2}}).min_angle_deg, 45, 1e-9);
}

TEST(VerticesWithinRings, GrowsRingByRing) {
  // A hexagonal fan: centre 0, rim 1..6.
  std::vector<Tri> fan;
  for (int k = 0; k < 6; ++k) fan.push_back({0, 1 + k, 1 + (k + 1) % 6});
  EXPECT_EQ(vertices_within_rings(7, fan, {0}, 1), (std::vector<int>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(vertices_within_rings(7, fan, {1}, 1), (std::vector<int>{0, 2, 6}));
  EXPECT_EQ(vertices_within_rings(7, fan, {1}, 2), (std::vector<int>{0, 2, 3, 4, 5, 6}));
  EXPECT_EQ(vertices_within_rings(7, fan, {1}, 0), std::vector<int>{});
  EXPECT_THROW(vertices_within_rings(7, fan, {7}, 1), Error);
}

// count_self_intersections follows PMP::self_intersections's rules (its
// former implementation ran PMP over the whole mesh; the answers below are
// PMP's). The triangle (0,0,0), (2,0,0), (0,2,0) is face {0, 1, 2}.
std::vector<Vec3> with_right_triangle(std::vector<Vec3> others) {
  others.insert(others.begin(), {Vec3{0, 0, 0}, Vec3{2, 0, 0}, Vec3{0, 2, 0}});
  return others;
}

TEST(SelfIntersections, NeighboursAcrossAnEdgeIntersectOnlyFoldedFlatOntoEachOther) {
  const std::vector<Tri> faces{{0, 1, 2}, {1, 0, 3}};
  EXPECT_EQ(count_self_intersections(with_right_triangle({{1, 1, 0}}), faces), 1);
  EXPECT_EQ(count_self_intersections(with_right_triangle({{1, -1, 0}}), faces), 0);
  EXPECT_EQ(count_self_intersections(with_right_triangle({{1, 1, 1e-9}}), faces), 0);
}

TEST(SelfIntersections, NeighboursAtAVertexIntersectWhereAnOppositeEdgeMeetsTheOther) {
  const std::vector<Tri> faces{{0, 1, 2}, {0, 3, 4}};
  // The edge 3-4 pierces face 0, or face 0's edge 1-2 pierces face 1.
  EXPECT_EQ(count_self_intersections(with_right_triangle({{0.5, 0.5, -1}, {0.5, 0.5, 1}}), faces),
            1);
  EXPECT_EQ(count_self_intersections(with_right_triangle({{2, 2, -1}, {2, 2, 1}}), faces), 1);
  // Touching at the shared vertex only; coplanar, along face 0's edge 0-1.
  EXPECT_EQ(count_self_intersections(with_right_triangle({{1, 0, 1}, {0, 1, 1}}), faces), 0);
  EXPECT_EQ(count_self_intersections(with_right_triangle({{1, 0, 0}, {1, -1, 0}}), faces), 1);
}

TEST(SelfIntersections, CountsOnlyPairsWithACountedFace) {
  // Faces 0 and 1 cross, face 2 is far from both.
  const std::vector<Vec3> positions = with_right_triangle(
      {{0.5, 0.5, -1}, {0.5, 0.5, 1}, {5, 5, 0}, {10, 0, 0}, {11, 0, 0}, {10, 1, 0}});
  const std::vector<Tri> faces{{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
  EXPECT_EQ(count_self_intersections(positions, faces, 0), 1);
  EXPECT_EQ(count_self_intersections(positions, faces, 1), 1);
  EXPECT_EQ(count_self_intersections(positions, faces, 2), 0);
  EXPECT_EQ(count_self_intersections(positions, faces, 3), 0);
}

TEST(SelfIntersections, CountsEachDegenerateCountedFaceOnce) {
  // Faces 1 and 2 are segments (collinear corners) through face 0.
  const std::vector<Vec3> positions =
      with_right_triangle({{0.5, 0.5, -1}, {0.5, 0.5, 1}, {0.5, 0.5, 0}, {0.5, 0.5, 0}});
  const std::vector<Tri> faces{{0, 1, 2}, {3, 4, 5}, {5, 6, 3}};
  EXPECT_EQ(count_self_intersections(positions, faces, 0), 2);
  EXPECT_EQ(count_self_intersections(positions, faces, 2), 1);
}

// A crumpled grid sheet (every vertex moved at random by up to an edge length
// along each axis, so that faces cross) whose cells widen from 0.3 to 3.3
// across it, far from the origin: the count over all faces is the sum of the
// counts over each pair of faces alone.
TEST(SelfIntersections, CountsEachCrossingPairOnceWhateverTheFaceSizes) {
  constexpr int kSide = 12;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> shift(-1, 1);
  std::vector<Vec3> positions;
  for (int i = 0; i < kSide; ++i) {
    for (int j = 0; j < kSide; ++j) {
      const double x = 0.15 * j * j + 0.3 * j, y = i;
      positions.push_back({1e4 + x + shift(random), -3e3 + y + shift(random), 7e2 + shift(random)});
    }
  }
  std::vector<Tri> faces;
  for (int i = 0; i + 1 < kSide; ++i) {
    for (int j = 0; j + 1 < kSide; ++j) {
      const int v = i * kSide + j;
      faces.push_back({v, v + 1, v + kSide + 1});
      faces.push_back({v, v + kSide + 1, v + kSide});
    }
  }
  const int counted_from = static_cast<int>(faces.size()) / 3;
  int pairwise = 0, passing = 0;  // passing: pairs with no common vertex
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    for (int g = std::max(f + 1, counted_from); g < static_cast<int>(faces.size()); ++g) {
      const int crossing = count_self_intersections(positions, {faces[f], faces[g]});
      pairwise += crossing;
      if (!passes_through_itself(positions, {faces[f], faces[g]})) continue;
      EXPECT_EQ(crossing, 1);
      ++passing;
    }
  }
  EXPECT_GT(passing, 10);
  EXPECT_GT(pairwise, passing);
  EXPECT_EQ(count_self_intersections(positions, faces, counted_from), pairwise);
  EXPECT_TRUE(passes_through_itself(positions, faces, counted_from));
}

// Passing through itself takes two faces with no common vertex: neighbours
// folded onto each other intersect, but do not pass through.
TEST(SelfIntersections, PassingThroughItselfTakesFacesWithNoCommonVertex) {
  const std::vector<Vec3> positions = with_right_triangle(
      {{1, 1, 0}, {0.5, 0.5, -1}, {0.5, 0.5, 1}, {5, 5, 0}, {10, 0, 0}, {11, 0, 0}, {10, 1, 0}});
  const std::vector<Tri> folded{{0, 1, 2}, {1, 0, 3}};
  EXPECT_EQ(count_self_intersections(positions, folded), 1);
  EXPECT_FALSE(passes_through_itself(positions, folded));
  // Face 1 crosses face 0; face 2 is far from both.
  const std::vector<Tri> crossing{{0, 1, 2}, {4, 5, 6}, {7, 8, 9}};
  EXPECT_TRUE(passes_through_itself(positions, crossing, 0));
  EXPECT_TRUE(passes_through_itself(positions, crossing, 1));
  EXPECT_FALSE(passes_through_itself(positions, crossing, 2));
  EXPECT_FALSE(passes_through_itself(positions, {{0, 1, 2}, {7, 8, 9}}));
}

// Coordinates so far apart that their differences overflow still give the
// pairs (all boxes then share one cell).
TEST(SelfIntersections, CountsFacesAsFarApartAsDoublesGo) {
  const std::vector<Vec3> positions = with_right_triangle(
      {{0.5, 0.5, -1}, {0.5, 0.5, 1}, {5, 5, 0}, {-1e308, 0, 5}, {-1e308, 1, 5}, {1e308, 1, 5}});
  const std::vector<Tri> faces{{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
  EXPECT_EQ(count_self_intersections(positions, faces), 1);
  EXPECT_TRUE(passes_through_itself(positions, faces));
}

// bench_quality's comparison, on one folded sheet whose hole spans a fold:
// the truth is the uncut sheet.
struct Figures {
  double area_ratio, hausdorff, mean_distance, fold_ratio;
  int self_intersections;
};

class QualityComparison : public ::testing::Test {
 protected:
  static constexpr double kRadius = 0.8;
  static constexpr Vec2 kCentre{2.1, 1.5};

  void SetUp() override {
    FoldedSheetOptions options;
    options.edge_length = 0.1;
    options.folds = 4;
    options.amplitude = 0.2;
    sheet_ = make_folded_sheet(options);
    cut_ = cut_disk_hole(sheet_, kCentre, kRadius);
    loops_ = find_boundary_loops(cut_.cut.mesh);
    hole_ = select_holes(loops_, HoleSelection{}).fill.at(0);
    // The removed faces: those whose flat centroid lies in the disk; the
    // truth's interior vertices touch removed faces only.
    std::vector<int> touches(sheet_.flat.size(), 0);  // 1: removed faces only, 2: kept ones too
    for (const Tri& f : sheet_.mesh.faces) {
      double x = 0, y = 0;
      for (int v : f) {
        x += sheet_.flat[v][0] / 3;
        y += sheet_.flat[v][1] / 3;
      }
      const bool removed = std::hypot(x - kCentre[0], y - kCentre[1]) < kRadius;
      if (removed) truth_faces_.push_back(f);
      for (int v : f) touches[v] = removed ? std::max(touches[v], 1) : 2;
    }
    for (int v = 0; v < static_cast<int>(touches.size()); ++v) {
      if (touches[v] == 1) truth_interior_.push_back(v);
    }
  }

  Figures measure(const FillResult& result) const {
    const Mesh& input = cut_.cut.mesh;
    const std::vector<Tri> patch(result.mesh.faces.begin() + input.face_count(),
                                 result.mesh.faces.end());
    std::vector<int> patch_vertices;
    for (int v = input.vertex_count(); v < result.mesh.vertex_count(); ++v)
      patch_vertices.push_back(v);
    const double h = loops_[hole_].mean_edge_length;
    const SurfaceDistance d =
        surface_distance(result.mesh.positions, patch, sheet_.mesh.positions, truth_faces_);
    return {total_area(result.mesh.positions, patch) / cut_.removed_area, d.hausdorff / h,
            d.mean / h,
            mean_abs_mean_curvature(result.mesh.positions, result.mesh.faces, patch_vertices) /
                mean_abs_mean_curvature(sheet_.mesh.positions, sheet_.mesh.faces, truth_interior_),
            count_self_intersections(result.mesh.positions, result.mesh.faces, input.face_count())};
  }

  DevelopableMesh sheet_;
  CutMesh cut_;
  std::vector<BoundaryLoop> loops_;
  int hole_ = -1;
  std::vector<Tri> truth_faces_;
  std::vector<int> truth_interior_;
};

TEST_F(QualityComparison, TruthIsTheRemovedPiece) {
  EXPECT_NEAR(total_area(sheet_.mesh.positions, truth_faces_), cut_.removed_area, 1e-9);
  EXPECT_FALSE(truth_interior_.empty());
}

TEST_F(QualityComparison, FoldfillPutsBackTheClothAndItsFoldsBetterThanLiepa) {
  const FillResult ours = fill_holes(cut_.cut.mesh, loops_, {hole_});
  const FillResult liepa = fill_holes_liepa(cut_.cut.mesh, loops_, {hole_});
  ASSERT_TRUE(ours.report.holes.at(0).filled) << ours.report.holes[0].reason;
  ASSERT_TRUE(liepa.report.holes.at(0).filled) << liepa.report.holes[0].reason;
  const Figures f = measure(ours), l = measure(liepa);
  // With the default (small) bending weight the sheet's own piece comes back:
  // area 1.001, Hausdorff 0.15 h, fold ratio 1.09.
  EXPECT_NEAR(f.area_ratio, 1, 0.01);
  EXPECT_LT(l.area_ratio, 0.95);  // the smooth fill puts back too little cloth
  EXPECT_TRUE(std::isfinite(f.hausdorff));
  EXPECT_LT(f.hausdorff, 0.5);  // in mean edge lengths, for a hole 16 of them wide
  EXPECT_LE(f.mean_distance, f.hausdorff);
  EXPECT_LT(f.mean_distance, l.mean_distance);
  EXPECT_GT(f.fold_ratio, 0.9);
  EXPECT_LT(f.fold_ratio, 1.25);
  EXPECT_LT(std::abs(f.fold_ratio - 1), std::abs(l.fold_ratio - 1));
  EXPECT_EQ(f.self_intersections, 0);
}

}  // namespace
}  // namespace foldfill
