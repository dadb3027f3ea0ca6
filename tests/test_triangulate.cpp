// Tests of triangulate_hole: the boundary comes out exactly as given, the
// patch covers the polygon, its triangles are good and its density follows
// the option.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/triangulate.h"
#include "test_geometry.h"

namespace foldfill {
namespace {

const double kPi = std::acos(-1.0);

// The closed polyline through `corners`, each side cut into `pieces` edges.
std::vector<Vec2> subdivided(const std::vector<Vec2>& corners, int pieces) {
  std::vector<Vec2> polygon;
  for (size_t k = 0; k < corners.size(); ++k) {
    const Vec2& a = corners[k];
    const Vec2& b = corners[(k + 1) % corners.size()];
    for (int i = 0; i < pieces; ++i) {
      const double t = static_cast<double>(i) / pieces;
      polygon.push_back({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])});
    }
  }
  return polygon;
}

std::vector<Vec2> circle(int n, double radius) {
  std::vector<Vec2> polygon;
  for (int k = 0; k < n; ++k)
    polygon.push_back({radius * std::cos(2 * kPi * k / n), radius * std::sin(2 * kPi * k / n)});
  return polygon;
}

using testing::polygon_area;
using testing::twice_signed_area;

// The properties every patch must have: the polygon's vertices bit for bit
// first, counter-clockwise faces, a boundary made of exactly the polygon's
// edges (each in one face, in polygon order), the polygon's area.
void expect_valid_patch(const std::vector<Vec2>& polygon, const FlatPatch& patch) {
  const int n = static_cast<int>(polygon.size());
  ASSERT_EQ(patch.boundary_count, n);
  ASSERT_GE(patch.uv.size(), polygon.size());
  for (int k = 0; k < n; ++k) {
    EXPECT_EQ(patch.uv[k][0], polygon[k][0]) << "vertex " << k;
    EXPECT_EQ(patch.uv[k][1], polygon[k][1]) << "vertex " << k;
  }

  std::map<std::pair<int, int>, int> half_edges;
  double area = 0;
  for (const Tri& f : patch.faces) {
    for (int v : f) ASSERT_TRUE(v >= 0 && v < static_cast<int>(patch.uv.size()));
    const double twice = twice_signed_area(patch.uv[f[0]], patch.uv[f[1]], patch.uv[f[2]]);
    EXPECT_GT(twice, 0) << "flipped face " << f[0] << " " << f[1] << " " << f[2];
    area += twice / 2;
    for (int i = 0; i < 3; ++i) ++half_edges[{f[i], f[(i + 1) % 3]}];
  }
  int boundary_half_edges = 0;
  for (const auto& [edge, count] : half_edges) {
    EXPECT_EQ(count, 1) << "half-edge " << edge.first << "->" << edge.second << " used twice";
    if (half_edges.count({edge.second, edge.first})) continue;
    ++boundary_half_edges;
    EXPECT_TRUE(edge.first < n && edge.second == (edge.first + 1) % n)
        << "boundary half-edge " << edge.first << "->" << edge.second << " is no polygon edge";
  }
  EXPECT_EQ(boundary_half_edges, n);

  const double expected_area = polygon_area(polygon);
  EXPECT_NEAR(area, expected_area, 1e-9 * expected_area);
  EXPECT_NEAR(patch.area, expected_area, 1e-9 * expected_area);
}

int interior_count(const FlatPatch& patch) {
  return static_cast<int>(patch.uv.size()) - patch.boundary_count;
}

TEST(TriangulateHole, TriangleIsOneFace) {
  const std::vector<Vec2> triangle{{0, 0}, {1, 0}, {0.3, 0.8}};
  const FlatPatch patch = triangulate_hole(triangle);
  expect_valid_patch(triangle, patch);
  EXPECT_EQ(interior_count(patch), 0);
  ASSERT_EQ(patch.faces.size(), 1u);
}

TEST(TriangulateHole, QuadrilateralAndPentagonNeedNoInteriorVertex) {
  const std::vector<Vec2> square{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const FlatPatch square_patch = triangulate_hole(square);
  expect_valid_patch(square, square_patch);
  EXPECT_EQ(square_patch.faces.size(), 2u);

  const std::vector<Vec2> pentagon = circle(5, 1.0);
  const FlatPatch pentagon_patch = triangulate_hole(pentagon);
  expect_valid_patch(pentagon, pentagon_patch);
  EXPECT_EQ(interior_count(pentagon_patch), 0);
  EXPECT_EQ(pentagon_patch.faces.size(), 3u);
}

TEST(TriangulateHole, SquareGetsGoodInteriorTriangles) {
  const std::vector<Vec2> square = subdivided({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 12);
  const FlatPatch patch = triangulate_hole(square);
  expect_valid_patch(square, patch);
  // About one vertex per equilateral-lattice cell of the boundary spacing.
  const double spacing = 1.0 / 12;
  const double lattice_count = 1.0 / (spacing * spacing * std::sqrt(3.0) / 2);
  EXPECT_GT(interior_count(patch), 0.6 * lattice_count);
  EXPECT_LT(interior_count(patch), 1.1 * lattice_count);
  EXPECT_GT(patch.min_angle_deg, 25);
  EXPECT_LT(patch.share_below_20deg, 0.001);
}

TEST(TriangulateHole, LShapeKeepsItsReflexCorner) {
  const std::vector<Vec2> l_shape = subdivided({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, 8);
  const FlatPatch patch = triangulate_hole(l_shape);
  expect_valid_patch(l_shape, patch);
  EXPECT_GT(patch.min_angle_deg, 25);
}

TEST(TriangulateHole, UnevenBoundarySpacingStaysValid) {
  // One side finely cut, the others single edges: the interior spacing is the
  // mean, and no point may come near the long edges.
  std::vector<Vec2> polygon;
  for (int i = 0; i < 40; ++i) polygon.push_back({i / 40.0, 0});
  for (const Vec2& p : std::vector<Vec2>{{1, 0}, {1, 1}, {0, 1}}) polygon.push_back(p);
  const FlatPatch patch = triangulate_hole(polygon);
  expect_valid_patch(polygon, patch);
  EXPECT_GT(patch.min_angle_deg, 1);
}

// Whether d lies strictly inside the circumcircle of the counter-clockwise
// triangle (a, b, c), by more than rounding.
bool strictly_in_circle(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  double rows[3][3], scale = 0;
  for (int i = 0; i < 3; ++i) {
    const Vec2& p = i == 0 ? a : i == 1 ? b : c;
    rows[i][0] = p[0] - d[0];
    rows[i][1] = p[1] - d[1];
    rows[i][2] = rows[i][0] * rows[i][0] + rows[i][1] * rows[i][1];
    scale = std::max(scale, rows[i][2]);
  }
  const double determinant = rows[0][0] * (rows[1][1] * rows[2][2] - rows[1][2] * rows[2][1]) -
                             rows[0][1] * (rows[1][0] * rows[2][2] - rows[1][2] * rows[2][0]) +
                             rows[0][2] * (rows[1][0] * rows[2][1] - rows[1][1] * rows[2][0]);
  return determinant > 1e-12 * scale * scale;
}

// The smoothing rounds restore the Delaunay property by edge flips: no face's
// circumcircle may hold the far vertex of a face across an interior edge.
TEST(TriangulateHole, SmoothedPatchIsConstrainedDelaunay) {
  const std::vector<Vec2> l_shape = subdivided({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, 9);
  for (const std::vector<Vec2>& polygon : {l_shape, circle(150, 1.0)}) {
    const FlatPatch patch = triangulate_hole(polygon);
    expect_valid_patch(polygon, patch);
    std::map<std::pair<int, int>, int> far_vertex;  // half-edge -> vertex of its face
    for (const Tri& f : patch.faces)
      for (int i = 0; i < 3; ++i) far_vertex[{f[i], f[(i + 1) % 3]}] = f[(i + 2) % 3];
    for (const Tri& f : patch.faces)
      for (int i = 0; i < 3; ++i) {
        const auto across = far_vertex.find({f[(i + 1) % 3], f[i]});
        if (across == far_vertex.end()) continue;  // a polygon edge
        EXPECT_FALSE(strictly_in_circle(patch.uv[f[0]], patch.uv[f[1]], patch.uv[f[2]],
                                        patch.uv[across->second]))
            << "edge " << f[i] << "-" << f[(i + 1) % 3] << " is not Delaunay";
      }
  }
}

TEST(TriangulateHole, LargeCircleIsQuick) {
  // 5000 boundary vertices and, at density 0.2, about 100k interior ones.
  const std::vector<Vec2> polygon = circle(5000, 1.0);
  const double density = 0.2;
  const FlatPatch patch = triangulate_hole(polygon, TriangulateOptions{density});
  expect_valid_patch(polygon, patch);
  const double spacing = 2 * kPi / 5000 / density;
  const double lattice_count = kPi / (spacing * spacing * std::sqrt(3.0) / 2);
  EXPECT_GT(interior_count(patch), 0.9 * lattice_count);
  EXPECT_LT(interior_count(patch), 1.05 * lattice_count);
  // Boundary edges five times shorter than the interior ones make fans there.
  EXPECT_GT(patch.min_angle_deg, 5);
}

TEST(TriangulateHole, FinelyCutCircleIsGood) {
  const std::vector<Vec2> polygon = circle(400, 1.0);
  const FlatPatch patch = triangulate_hole(polygon);
  expect_valid_patch(polygon, patch);
  EXPECT_GT(patch.min_angle_deg, 25);
  EXPECT_LT(patch.share_below_20deg, 0.001);
}

TEST(TriangulateHole, DensityTwoGivesAboutFourTimesTheVertices) {
  const std::vector<Vec2> polygon = circle(200, 1.0);
  const FlatPatch coarse = triangulate_hole(polygon);
  const FlatPatch fine = triangulate_hole(polygon, TriangulateOptions{2.0});
  expect_valid_patch(polygon, fine);
  const double ratio = static_cast<double>(interior_count(fine)) / interior_count(coarse);
  EXPECT_GT(ratio, 3.5);
  EXPECT_LT(ratio, 4.5);
  EXPECT_GT(fine.min_angle_deg, 22);
}

TEST(TriangulateHole, SameInputSameOutput) {
  const std::vector<Vec2> polygon = circle(300, 2.5);
  const FlatPatch first = triangulate_hole(polygon);
  const FlatPatch second = triangulate_hole(polygon);
  EXPECT_EQ(first.uv, second.uv);
  EXPECT_EQ(first.faces, second.faces);
}

void expect_error(const std::vector<Vec2>& polygon, const TriangulateOptions& options,
                  ErrorKind kind) {
  try {
    triangulate_hole(polygon, options);
    ADD_FAILURE() << "no error thrown";
  } catch (const Error& error) {
    EXPECT_EQ(error.kind(), kind) << error.what();
  }
}

TEST(TriangulateHole, SelfIntersectingPolygonFails) {
  const std::vector<Vec2> bowtie{{0, 0}, {1, 1}, {1, 0}, {0, 1}};
  expect_error(bowtie, {}, ErrorKind::FillFailed);
}

TEST(TriangulateHole, ClockwisePolygonFails) {
  std::vector<Vec2> polygon = circle(20, 1.0);
  std::reverse(polygon.begin(), polygon.end());
  expect_error(polygon, {}, ErrorKind::FillFailed);
}

TEST(TriangulateHole, RepeatedVertexAndTooFewVerticesFail) {
  expect_error({{0, 0}, {1, 0}, {1, 0}, {0, 1}}, {}, ErrorKind::FillFailed);
  expect_error({{0, 0}, {1, 0}}, {}, ErrorKind::FillFailed);
}

TEST(TriangulateHole, BadDensityIsAUsageError) {
  expect_error(circle(10, 1.0), TriangulateOptions{0.0}, ErrorKind::Usage);
  expect_error(circle(10, 1.0), TriangulateOptions{1e9}, ErrorKind::FillFailed);
}

}  // namespace
}  // namespace foldfill
