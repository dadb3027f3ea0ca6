// The generated test surfaces: manifold, consistently oriented, and holed
// with the loops they promise.
#include "foldfill/test_surfaces.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/flatten.h"
#include "foldfill/holes.h"
#include "foldfill/topology.h"
#include "support/loops.h"

namespace foldfill {
namespace {

using testing::loop_through;

struct Range {
  size_t low, high;
};

// Checks that `surface` is manifold and consistently oriented, that its
// boundary loops are simple disk boundaries, exactly one through each listed
// vertex, and that the holes' loops have vertex counts in `hole_sizes` (one
// range for all, or one per hole). Returns the loops.
std::vector<BoundaryLoop> check_surface(const HoledSurface& surface,
                                        const std::vector<Range>& hole_sizes) {
  const Mesh& mesh = surface.mesh;
  EXPECT_NO_THROW(build_edge_topology(mesh.faces, mesh.vertex_count()));
  std::vector<char> used(mesh.positions.size(), 0);
  for (const Tri& f : mesh.faces) {
    for (int v : f) used[v] = 1;
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << "unreferenced vertices";
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  EXPECT_EQ(loops.size(), surface.hole_vertices.size() + surface.open_vertices.size());
  for (const BoundaryLoop& loop : loops) {
    EXPECT_TRUE(loop.is_disk) << "loop " << loop.id << ": " << loop.reason;
    EXPECT_TRUE(loop.split_at.empty()) << "loop " << loop.id << " passes a vertex twice";
  }
  std::vector<int> seen;
  for (size_t k = 0; k < surface.hole_vertices.size(); ++k) {
    const int id = loop_through(loops, surface.hole_vertices[k]);
    EXPECT_GE(id, 0) << "hole " << k << " has no loop";
    if (id < 0) continue;
    seen.push_back(id);
    const Range range = hole_sizes.size() == 1 ? hole_sizes[0] : hole_sizes.at(k);
    EXPECT_GE(loops[id].vertices.size(), range.low) << "hole " << k;
    EXPECT_LE(loops[id].vertices.size(), range.high) << "hole " << k;
  }
  for (int v : surface.open_vertices) seen.push_back(loop_through(loops, v));
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(std::unique(seen.begin(), seen.end()), seen.end()) << "two marks on one loop";
  EXPECT_EQ(std::count(seen.begin(), seen.end(), -1), 0) << "a mark on no loop";
  return loops;
}

// Whether every face's normal points away from the point `outward_from`
// returns for its centroid.
void expect_outward(const Mesh& mesh, const std::function<Vec3(const Vec3&)>& outward_from) {
  int inward = 0;
  for (const Tri& f : mesh.faces) {
    const Vec3 &a = mesh.positions[f[0]], &b = mesh.positions[f[1]], &c = mesh.positions[f[2]];
    const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const Vec3 n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    Vec3 centre{};
    for (int k = 0; k < 3; ++k) centre[k] = (a[k] + b[k] + c[k]) / 3;
    const Vec3 from = outward_from(centre);
    double d = 0;
    for (int k = 0; k < 3; ++k) d += n[k] * (centre[k] - from[k]);
    inward += d <= 0;
  }
  EXPECT_EQ(inward, 0) << "faces not counter-clockwise seen from outside";
}

const auto from_origin = [](const Vec3&) { return Vec3{0, 0, 0}; };

TEST(TestSurfaces, SphereWithACapHoleThatTurnsLessThanHalfATurn) {
  const HoledSurface sphere = make_holed_sphere();
  const auto loops = check_surface(sphere, {{60, 150}, {8, 40}, {8, 40}, {8, 40}});
  EXPECT_EQ(sphere.hole_vertices.size(), 4u);
  expect_outward(sphere.mesh, from_origin);
  const BoundaryLoop& cap = loops[loop_through(loops, sphere.hole_vertices[0])];
  EXPECT_LT(cap.turning, M_PI);
  EXPECT_GT(cap.turning, 0);
}

TEST(TestSurfaces, TorusWithHolesOutsideInsideAndOnTop) {
  const TorusSurfaceOptions options;
  const HoledSurface torus = make_holed_torus(options);
  check_surface(torus, {{10, 60}});
  EXPECT_EQ(torus.hole_vertices.size(), 3u);
  expect_outward(torus.mesh, [&](const Vec3& p) {
    const double r = std::hypot(p[0], p[1]);
    return Vec3{options.major * p[0] / r, options.major * p[1] / r, 0};
  });
}

TEST(TestSurfaces, BlobWithManyHolesOfThreeToSixtyVertices) {
  const BlobSurfaceOptions options;
  const HoledSurface blob = make_holed_blob(options);
  std::vector<Range> sizes;
  for (int i = 0; i < options.holes; ++i) {
    const size_t exact = static_cast<size_t>(3 + i % 10);
    sizes.push_back(i % 10 < 3 ? Range{exact, exact} : Range{6, 60});
  }
  check_surface(blob, sizes);
  EXPECT_EQ(blob.hole_vertices.size(), static_cast<size_t>(options.holes));
  expect_outward(blob.mesh, from_origin);
  // Deterministic, and the seed changes the layout.
  EXPECT_EQ(make_holed_blob(options).mesh.positions, blob.mesh.positions);
  BlobSurfaceOptions other = options;
  other.seed = 2;
  other.holes = 50;
  other.subdivisions = 5;
  const HoledSurface second = make_holed_blob(other);
  EXPECT_NE(second.mesh.positions, blob.mesh.positions);
  EXPECT_EQ(find_boundary_loops(second.mesh).size(), 50u);
}

TEST(TestSurfaces, SleeveWhoseHoleIsLongerThanItsEnds) {
  const HoledSurface sleeve = make_holed_sleeve();
  const auto loops = check_surface(sleeve, {{20, 400}});
  ASSERT_EQ(sleeve.open_vertices.size(), 2u);
  const BoundaryLoop& hole = loops[loop_through(loops, sleeve.hole_vertices[0])];
  for (int v : sleeve.open_vertices) {
    const BoundaryLoop& end = loops[loop_through(loops, v)];
    EXPECT_GT(hole.length, end.length);
    EXPECT_GT(hole.vertices.size(), end.vertices.size());
  }
  expect_outward(sleeve.mesh, [](const Vec3& p) { return Vec3{0, 0, p[2]}; });
}

TEST(TestSurfaces, SheetWhoseHoleIsLongerThanItsOuterEdge) {
  const HoledSurface sheet = make_sheet_with_long_hole();
  const auto loops = check_surface(sheet, {{100, 2000}});
  ASSERT_EQ(loops.size(), 2u);
  const BoundaryLoop& hole = loops[loop_through(loops, sheet.hole_vertices[0])];
  const BoundaryLoop& edge = loops[loop_through(loops, sheet.open_vertices[0])];
  EXPECT_GT(hole.length, edge.length);
  EXPECT_GT(hole.vertices.size(), edge.vertices.size());
}

TEST(TestSurfaces, DomeWithAHoleNearItsTop) {
  const HoledSurface dome = make_holed_dome();
  check_surface(dome, {{10, 60}});
  EXPECT_EQ(dome.open_vertices.size(), 1u);
  expect_outward(dome.mesh, from_origin);
}

TEST(TestSurfaces, BoxWithAFourVertexHoleAtACorner) {
  const HoledSurface box = make_box_with_corner_hole();
  check_surface(box, {{4, 4}});
  expect_outward(box.mesh, [](const Vec3&) { return Vec3{0.5, 0.5, 0.5}; });
}

TEST(TestSurfaces, SheetWithHolesOfThreeFourAndFiveVertices) {
  const HoledSurface sheet = make_sheet_with_small_holes();
  check_surface(sheet, {{3, 3}, {4, 4}, {5, 5}});
  EXPECT_EQ(sheet.open_vertices.size(), 1u);
}

// The C-shaped slot goes around the ruffle's apex by more than a full turn of
// the plane: its strip cannot be flattened without overlapping itself.
TEST(TestSurfaces, RuffleWithASlotWhoseFlatteningOverlapsItself) {
  const HoledSurface ruffle = make_ruffle_with_c_slot();
  const auto loops = check_surface(ruffle, {{100, 3000}});
  const BoundaryLoop& slot = loops[loop_through(loops, ruffle.hole_vertices[0])];
  EXPECT_NEAR(slot.turning, 2 * M_PI, 0.3);
  const Strip strip = extract_strip(ruffle.mesh, slot);
  bool overlaps = false;
  try {
    overlaps = !flatten_strip(strip).simple_polygon;
  } catch (const Error& e) {
    overlaps = e.kind() == ErrorKind::FillFailed;
  }
  EXPECT_TRUE(overlaps);
}

}  // namespace
}  // namespace foldfill
