// Every hole of a scan-like surface closed: the fabric method where it
// applies, the fallback chain where it does not, no face of zero area or
// sliver, and nothing crossed. The surfaces are generated in code
// (test_surfaces.h); the holes to fill are the ones they were cut with.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <map>
#include <string>

#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/metrics.h"
#include "foldfill/test_surfaces.h"
#include "support/loops.h"

namespace foldfill {
namespace {

// The loop through `vertex`; a test failure when there is none.
int loop_through(const std::vector<BoundaryLoop>& loops, int vertex) {
  const int id = testing::loop_through(loops, vertex);
  if (id < 0) ADD_FAILURE() << "no loop through vertex " << vertex;
  return id;
}

// Fills the surface's holes and checks that every one is closed, the open
// loops stay open, the original elements are unchanged, no new face is a
// sliver, and the output crosses nothing. Returns the count per method.
std::map<FillMethod, int> expect_every_hole_closed(const HoledSurface& surface) {
  const Mesh& mesh = surface.mesh;
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  EXPECT_EQ(loops.size(), surface.hole_vertices.size() + surface.open_vertices.size());
  std::vector<int> holes;
  for (int v : surface.hole_vertices) holes.push_back(loop_through(loops, v));
  const FillResult result = fill_holes(mesh, loops, holes);
  std::map<FillMethod, int> methods;
  for (const HoleReport& hole : result.report.holes) {
    SCOPED_TRACE("loop " + std::to_string(hole.loop_id) + " of " +
                 std::to_string(hole.loop_vertex_count) + " vertices");
    EXPECT_TRUE(hole.filled) << hole.reason;
    if (!hole.filled) continue;
    ++methods[hole.method];
    // No sliver: the smooth fills are held to a degree, the fabric method's
    // quality triangulation keeps well above.
    EXPECT_GE(hole.patch_min_angle_deg, 1.0) << to_string(hole.method);
    EXPECT_EQ(hole.crossings.total(), 0) << to_string(hole.method);
    if (hole.method != FillMethod::Fabric) {
      EXPECT_FALSE(hole.fallback_reasons.empty());
    }
  }
  EXPECT_TRUE(
      std::equal(mesh.positions.begin(), mesh.positions.end(), result.mesh.positions.begin()));
  EXPECT_TRUE(std::equal(mesh.faces.begin(), mesh.faces.end(), result.mesh.faces.begin()));
  // Exactly the open loops are left.
  const std::vector<BoundaryLoop> after = find_boundary_loops(result.mesh);
  EXPECT_EQ(after.size(), surface.open_vertices.size());
  for (int v : surface.open_vertices) loop_through(after, v);
  EXPECT_EQ(count_self_intersections(result.mesh.positions, result.mesh.faces, mesh.face_count()),
            0);
  for (const auto& [method, count] : methods) std::printf("%s: %d  ", to_string(method), count);
  std::printf("\n");
  return methods;
}

TEST(EveryHole, SphereWithALargeCapAndSmallHoles) {
  const std::map<FillMethod, int> methods = expect_every_hole_closed(make_holed_sphere());
  // A sphere is not developable: no hole of it is flattened.
  EXPECT_EQ(methods.count(FillMethod::Fabric), 0u);
}

// Holes filled by every step of the chain (fabric, smooth, triangulation)
// in parallel give the same output whatever the thread count.
TEST(EveryHole, TheBlobsFillDoesNotDependOnTheThreadCount) {
  const HoledSurface blob = make_holed_blob();
  const std::vector<BoundaryLoop> loops = find_boundary_loops(blob.mesh);
  std::vector<int> holes;
  for (int v : blob.hole_vertices) holes.push_back(loop_through(loops, v));
  omp_set_num_threads(1);
  const FillResult serial = fill_holes(blob.mesh, loops, holes);
  omp_set_num_threads(2);
  const FillResult parallel = fill_holes(blob.mesh, loops, holes);
  EXPECT_EQ(serial.mesh.positions, parallel.mesh.positions);
  EXPECT_EQ(serial.mesh.faces, parallel.mesh.faces);
  for (size_t h = 0; h < serial.report.holes.size(); ++h)
    EXPECT_EQ(serial.report.holes[h].method, parallel.report.holes[h].method);
}

TEST(EveryHole, TorusOutsideInsideAndTop) { expect_every_hole_closed(make_holed_torus()); }

TEST(EveryHole, StatueLikeBlobWithSixtyHolesOfThreeToSixtyVertices) {
  const HoledSurface blob = make_holed_blob();
  ASSERT_GE(blob.hole_vertices.size(), 50u);
  expect_every_hole_closed(blob);
}

TEST(EveryHole, SleeveWhoseHoleIsLongerThanItsEnds) {
  const std::map<FillMethod, int> methods = expect_every_hole_closed(make_holed_sleeve());
  // A cylinder is developable: the fabric method fills its hole.
  EXPECT_EQ(methods.count(FillMethod::Fabric), 1u);
}

TEST(EveryHole, SheetWhoseHoleIsLongerThanItsOuterEdge) {
  expect_every_hole_closed(make_sheet_with_long_hole());
}

TEST(EveryHole, HoleOnADome) {
  const std::map<FillMethod, int> methods = expect_every_hole_closed(make_holed_dome());
  EXPECT_EQ(methods.count(FillMethod::Smooth), 1u);
}

TEST(EveryHole, FourVertexHoleAtABoxCorner) {
  expect_every_hole_closed(make_box_with_corner_hole());
}

TEST(EveryHole, HolesOfThreeFourAndFiveVertices) {
  const HoledSurface sheet = make_sheet_with_small_holes();
  const std::vector<BoundaryLoop> loops = find_boundary_loops(sheet.mesh);
  std::vector<size_t> sizes;
  for (int v : sheet.hole_vertices) sizes.push_back(loops[loop_through(loops, v)].vertices.size());
  EXPECT_EQ(sizes, (std::vector<size_t>{3, 4, 5}));
  expect_every_hole_closed(sheet);
}

TEST(EveryHole, OutlineThatDoublesBackOnItself) {
  const std::map<FillMethod, int> methods = expect_every_hole_closed(make_ruffle_with_c_slot());
  EXPECT_EQ(methods.count(FillMethod::Fabric), 0u) << "its LSCM outline overlaps itself";
}

// A rectangular hole in a flat grid: its sides are rows of collinear boundary
// vertices, which a minimal-area triangulation could join into triangles of
// zero area. Both the default (fabric) and the smooth fill close it with no
// sliver.
TEST(EveryHole, RectangularHoleWithCollinearSides) {
  Mesh grid;
  const int n = 21;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) grid.positions.push_back({i * 0.1, j * 0.1, 0.0});
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      if (i >= 5 && i < 11 && j >= 8 && j < 11) continue;
      const int a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      grid.faces.push_back({a, b, c});
      grid.faces.push_back({a, c, d});
    }
  const std::vector<BoundaryLoop> loops = find_boundary_loops(grid);
  ASSERT_EQ(loops.size(), 2u);
  const int hole = loops[0].vertices.size() < loops[1].vertices.size() ? 0 : 1;
  FillOptions smooth_first;
  smooth_first.fallback.max_developability_ratio = -1;
  for (const bool smooth : {false, true}) {
    const FillResult result =
        fill_holes(grid, loops, {hole}, smooth ? smooth_first : FillOptions{});
    const HoleReport& report = result.report.holes.at(0);
    ASSERT_TRUE(report.filled) << report.reason;
    EXPECT_EQ(report.method, smooth ? FillMethod::Smooth : FillMethod::Fabric);
    EXPECT_GE(report.patch_min_angle_deg, 20);
    EXPECT_EQ(find_boundary_loops(result.mesh).size(), 1u);
  }
}

}  // namespace
}  // namespace foldfill
