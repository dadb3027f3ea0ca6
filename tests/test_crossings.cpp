// Crossings of a fill measured on the output: a patch through the other
// layer of a folded sheet, into obstacles, none on a clean fill, and the
// work following the hole on a large mesh.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "foldfill/examples.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/liepa.h"
#include "foldfill/metrics.h"
#include "foldfill/obstacles.h"
#include "test_geometry.h"

namespace foldfill {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// A flat n x n vertex grid at height z, spacing `e`, with grid_faces' diagonals
// (examples.cpp): vertex (i, j) at index j * n + i.
Mesh flat_grid(int n, double e, double z) {
  Mesh mesh;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) mesh.positions.push_back({i * e, j * e, z});
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      if ((i + j) % 2 == 0) {
        mesh.faces.push_back({a, b, c});
        mesh.faces.push_back({a, c, d});
      } else {
        mesh.faces.push_back({a, b, d});
        mesh.faces.push_back({b, c, d});
      }
    }
  return mesh;
}

bool has_vertex(const Tri& f, int v) { return f[0] == v || f[1] == v || f[2] == v; }

// The faces around `centre` removed from `mesh` and appended again with a new
// vertex at `apex` in its place: a tent standing in the hole they leave, as a
// fill would (its faces are the last ones). Returns the tent's faces.
std::vector<int> raise_tent(Mesh& mesh, int centre, const Vec3& apex) {
  std::vector<Tri> kept, star;
  for (const Tri& f : mesh.faces) (has_vertex(f, centre) ? star : kept).push_back(f);
  const int top = mesh.vertex_count();
  mesh.positions.push_back(apex);
  mesh.faces = kept;
  std::vector<int> tent;
  for (Tri f : star) {
    for (int& v : f) v = v == centre ? top : v;
    tent.push_back(mesh.face_count());
    mesh.faces.push_back(f);
  }
  return tent;
}

// The report of one filled hole whose patch is `faces`, measured on `mesh`.
HoleReport measured(const Mesh& mesh, const std::vector<int>& faces, double length_scale,
                    const std::vector<Obstacle>& obstacles = {}) {
  FillReport report;
  HoleReport hole;
  hole.filled = true;
  hole.length_scale = length_scale;
  hole.patch_face_count = static_cast<int>(faces.size());
  report.holes.push_back(hole);
  measure_crossings(mesh, {faces}, obstacles, "sheet.obj", report);
  return report.holes[0];
}

Kernel::Triangle_3 triangle(const Mesh& mesh, int f) {
  const auto p = [&](int k) {
    const Vec3& x = mesh.positions[mesh.faces[f][k]];
    return Kernel::Point_3(x[0], x[1], x[2]);
  };
  return {p(0), p(1), p(2)};
}

constexpr double kEdge = 0.1, kGap = 1.5 * kEdge;

// Two layers: a flat sheet with a hole around its middle vertex, a tent
// standing in it whose apex is 4 gaps high, and a single quad a gap above the
// sheet. The tent crosses the quad's plane in a ring 0.75 edge lengths
// around its axis, all within the quad's first triangle (the quad's diagonal
// passes 2 edge lengths away): each of the tent's 8 faces crosses it once.
struct TentScene {
  Mesh mesh;
  std::vector<int> tent;
  Vec3 apex;
};
TentScene tent_under_a_quad() {
  TentScene scene;
  scene.mesh = flat_grid(7, kEdge, 0);
  const Vec3 centre = scene.mesh.positions[3 * 7 + 3];
  scene.apex = {centre[0], centre[1], 4 * kGap};
  scene.tent = raise_tent(scene.mesh, 3 * 7 + 3, scene.apex);
  const int first = scene.mesh.vertex_count();
  const double x0 = centre[0] - 3 * kEdge, x1 = centre[0] + 20 * kEdge, y0 = centre[1] - 3 * kEdge,
               y1 = centre[1] + 3 * kEdge;
  for (const Vec3& p :
       std::vector<Vec3>{{x0, y0, kGap}, {x1, y0, kGap}, {x1, y1, kGap}, {x0, y1, kGap}})
    scene.mesh.positions.push_back(p);
  // The tent's faces stay last, as a fill's would.
  std::vector<Tri> tent_faces;
  for (int f : scene.tent) tent_faces.push_back(scene.mesh.faces[f]);
  scene.mesh.faces.resize(scene.mesh.faces.size() - tent_faces.size());
  scene.mesh.faces.push_back({first, first + 1, first + 2});
  scene.mesh.faces.push_back({first, first + 2, first + 3});
  scene.tent.clear();
  for (const Tri& f : tent_faces) {
    scene.tent.push_back(scene.mesh.face_count());
    scene.mesh.faces.push_back(f);
  }
  return scene;
}

TEST(Crossings, ATentThroughTheLayerAboveCrossesItOncePerFace) {
  const TentScene scene = tent_under_a_quad();
  ASSERT_EQ(scene.tent.size(), 8u);
  const HoleReport hole = measured(scene.mesh, scene.tent, kEdge);
  EXPECT_EQ(hole.crossings.patch_patch, 0);
  EXPECT_EQ(hole.crossings.patch_mesh, 8);
  EXPECT_EQ(hole.crossings.patch_obstacles, 0);
  EXPECT_EQ(hole.self_intersections, 8);
  EXPECT_EQ(hole.min_distance, 0);
  EXPECT_EQ(hole.warning,
            "sheet.obj: loop 0: the fill crosses the rest of the mesh (patch_mesh 8)");
}

TEST(Crossings, ATentUnderTheLayerAboveKeepsItsDistance) {
  // The same tent with its apex half a gap under the quad: nothing crosses.
  // The nearest faces that share no vertex with a tent face are the quad,
  // half a gap (0.75 h) above the apex, and the sheet's faces around the
  // hole, 0.707 h from the loop vertices of the faces beside them.
  TentScene scene = tent_under_a_quad();
  scene.mesh.positions[scene.mesh.faces[scene.tent[0]][2]][2] = 0.5 * kGap;
  ASSERT_EQ(scene.mesh.positions[scene.mesh.faces[scene.tent[0]][2]][0], scene.apex[0]);
  const HoleReport hole = measured(scene.mesh, scene.tent, kEdge);
  EXPECT_EQ(hole.crossings.total(), 0);
  EXPECT_EQ(hole.self_intersections, 0);
  EXPECT_TRUE(hole.warning.empty()) << hole.warning;
  EXPECT_NEAR(hole.min_distance, std::sqrt(0.5), 1e-12);
}

// A sheet folded over itself with the upper layer 1.5 edge lengths above the
// lower; a tent in a hole of the lower layer, its apex off the grid's lines,
// pokes through the upper layer. Its crossings are the pairs that CGAL's
// exact test finds among all pairs (the tent's faces share vertices only
// with the lower layer's faces around the hole, which they do not cross).
TEST(Crossings, AFillThroughTheUpperLayerOfAFoldedSheetCountsEachPairOnce) {
  const DevelopableMesh folded = make_profile_sheet(u_fold_profile(1.2, kGap, kEdge), 1.0, kEdge);
  Mesh mesh = folded.mesh;
  // A lower-layer vertex with 8 faces around it, away from the fold.
  int centre = -1;
  for (int v = 0; v < mesh.vertex_count() && centre < 0; ++v) {
    const Vec3& p = mesh.positions[v];
    if (p[2] != 0 || std::abs(p[0] - 0.6) > 0.11 || std::abs(p[1] - 0.5) > 0.11) continue;
    int around = 0;
    for (const Tri& f : mesh.faces) around += has_vertex(f, v);
    if (around == 8) centre = v;
  }
  ASSERT_GE(centre, 0);
  const Vec3 c = mesh.positions[centre];
  const std::vector<int> tent =
      raise_tent(mesh, centre, {c[0] + 0.137 * kEdge, c[1] + 0.291 * kEdge, 3 * kGap});
  int expected = 0;
  for (int f : tent)
    for (int g = 0; g < mesh.face_count(); ++g) {
      if (std::find(tent.begin(), tent.end(), g) != tent.end()) continue;
      bool shared = false;
      for (int v : mesh.faces[g]) shared = shared || has_vertex(mesh.faces[f], v);
      if (!shared) expected += CGAL::do_intersect(triangle(mesh, f), triangle(mesh, g));
    }
  ASSERT_GE(expected, 8);
  const HoleReport hole = measured(mesh, tent, kEdge);
  EXPECT_EQ(hole.crossings.patch_mesh, expected);
  EXPECT_EQ(hole.crossings.patch_patch, 0);
  EXPECT_EQ(hole.self_intersections, expected);
  EXPECT_NE(hole.warning.find("(patch_mesh " + std::to_string(expected) + ")"), std::string::npos)
      << hole.warning;
}

// A small triangle across the tent near its apex, made part of the patch (as
// a fill folded through itself would be): its crossings with the tent's
// faces are the patch's own.
TEST(Crossings, PairsWithinThePatchArePatchPatch) {
  TentScene scene = tent_under_a_quad();
  Mesh& mesh = scene.mesh;
  const Vec3 centre{scene.apex[0] + 0.0013, scene.apex[1] + 0.0021, 0};
  const int first = mesh.vertex_count();
  mesh.positions.push_back({centre[0] - 0.3 * kEdge, centre[1], 3.5 * kGap});
  mesh.positions.push_back({centre[0] + 0.3 * kEdge, centre[1] - 0.01, 3.5 * kGap});
  mesh.positions.push_back({centre[0], centre[1] + 0.3 * kEdge, 3.6 * kGap});
  std::vector<int> patch = scene.tent;
  patch.push_back(mesh.face_count());
  mesh.faces.push_back({first, first + 1, first + 2});
  int expected = 0;
  for (int f : scene.tent)
    expected += CGAL::do_intersect(triangle(mesh, f), triangle(mesh, patch.back()));
  ASSERT_GT(expected, 0);
  const HoleReport hole = measured(mesh, patch, kEdge);
  EXPECT_EQ(hole.crossings.patch_patch, expected);
  EXPECT_EQ(hole.crossings.patch_mesh, 8);
  EXPECT_EQ(hole.self_intersections, expected + 8);
  EXPECT_NE(hole.warning.find("crosses itself and the rest of the mesh (patch_patch"),
            std::string::npos)
      << hole.warning;
}

// Another hole's patch is part of the mesh: the tent's second hole holds a
// triangle through the tent; each hole counts the pairs with the other's.
TEST(Crossings, AnotherHolesPatchIsPartOfTheMesh) {
  TentScene scene = tent_under_a_quad();
  Mesh& mesh = scene.mesh;
  const int first = mesh.vertex_count();
  mesh.positions.push_back({scene.apex[0] - 0.3 * kEdge, scene.apex[1] + 0.001, 3.5 * kGap});
  mesh.positions.push_back({scene.apex[0] + 0.3 * kEdge, scene.apex[1] - 0.01, 3.5 * kGap});
  mesh.positions.push_back({scene.apex[0] + 0.002, scene.apex[1] + 0.3 * kEdge, 3.6 * kGap});
  const int other = mesh.face_count();
  mesh.faces.push_back({first, first + 1, first + 2});
  int expected = 0;
  for (int f : scene.tent) expected += CGAL::do_intersect(triangle(mesh, f), triangle(mesh, other));
  ASSERT_GT(expected, 0);
  FillReport report;
  for (int faces : {8, 1}) {
    HoleReport hole;
    hole.filled = true;
    hole.loop_id = static_cast<int>(report.holes.size());
    hole.length_scale = kEdge;
    hole.patch_face_count = faces;
    report.holes.push_back(hole);
  }
  measure_crossings(mesh, {scene.tent, {other}}, {}, "sheet.obj", report);
  EXPECT_EQ(report.holes[0].crossings.patch_patch, 0);
  EXPECT_EQ(report.holes[0].crossings.patch_mesh, 8 + expected);
  EXPECT_EQ(report.holes[1].crossings.patch_patch, 0);
  EXPECT_EQ(report.holes[1].crossings.patch_mesh, expected);
  EXPECT_EQ(report.holes[1].warning,
            "sheet.obj: loop 1: the fill crosses the rest of the mesh (patch_mesh " +
                std::to_string(expected) + ")");
}

// The tent, alone, into obstacles: its apex inside a sphere (each face
// reaches in), through a plane it must stay under, and across a thin
// cylinder along x at three quarters of its height, which only the four
// faces at the tent's two edges along x reach (the others keep 0.247 edge
// lengths from its axis, the cylinder's radius is 0.2).
TEST(Crossings, FacesReachingIntoObstaclesArePatchObstacles) {
  Mesh mesh = flat_grid(7, kEdge, 0);
  const Vec3 c = mesh.positions[3 * 7 + 3];
  const Vec3 apex{c[0], c[1], 4 * kGap};
  const std::vector<int> tent = raise_tent(mesh, 3 * 7 + 3, apex);
  Obstacle sphere;
  sphere.center = {apex[0], apex[1], apex[2] + 0.5 * kEdge};
  sphere.radius = kEdge;
  Obstacle plane;
  plane.type = Obstacle::Type::Plane;
  plane.center = {0, 0, 2 * kGap};
  plane.normal = {0, 0, -1};
  Obstacle cylinder;
  cylinder.type = Obstacle::Type::Cylinder;
  cylinder.center = {c[0], c[1], 3 * kGap};
  cylinder.axis = {1, 0, 0};
  cylinder.radius = 0.2 * kEdge;
  cylinder.height = 10 * kEdge;
  EXPECT_EQ(measured(mesh, tent, kEdge, {sphere}).crossings.patch_obstacles, 8);
  EXPECT_EQ(measured(mesh, tent, kEdge, {plane}).crossings.patch_obstacles, 8);
  const HoleReport through_cylinder = measured(mesh, tent, kEdge, {cylinder});
  EXPECT_EQ(through_cylinder.crossings.patch_obstacles, 4);
  EXPECT_EQ(through_cylinder.crossings.patch_mesh, 0);
  EXPECT_EQ(through_cylinder.min_distance, 0);
  EXPECT_EQ(through_cylinder.warning,
            "sheet.obj: loop 0: the fill crosses obstacles (patch_obstacles 4)");
  // A face counts once, whatever it crosses.
  EXPECT_EQ(measured(mesh, tent, kEdge, {sphere, plane, cylinder}).crossings.patch_obstacles, 8);
  // Thicker, short of the other faces: the same four.
  cylinder.radius = 0.24 * kEdge;
  EXPECT_EQ(measured(mesh, tent, kEdge, {cylinder}).crossings.patch_obstacles, 4);
  // Beside the tent: nothing reaches it, and the distance is the gap.
  cylinder.center[1] += 1.5 * kEdge;
  const HoleReport beside = measured(mesh, tent, kEdge, {cylinder});
  EXPECT_EQ(beside.crossings.patch_obstacles, 0);
  EXPECT_TRUE(beside.warning.empty()) << beside.warning;
}

TEST(Crossings, ACleanFillCrossesNothing) {
  const CutMesh cut = cut_disk_hole(testing::small_folded_sheet(0.08), {1.9, 1.0}, 0.5);
  const std::vector<BoundaryLoop> loops = find_boundary_loops(cut.cut.mesh);
  const HoleChoice choice = select_holes(loops, HoleSelection{});
  for (const bool liepa : {false, true}) {
    SCOPED_TRACE(liepa ? "Liepa" : "foldfill");
    const FillResult result = liepa ? fill_holes_liepa(cut.cut.mesh, loops, choice.fill)
                                    : fill_holes(cut.cut.mesh, loops, choice.fill);
    const HoleReport& hole = result.report.holes.at(0);
    ASSERT_TRUE(hole.filled) << hole.reason;
    EXPECT_EQ(hole.crossings.patch_patch, 0);
    EXPECT_EQ(hole.crossings.patch_mesh, 0);
    EXPECT_EQ(hole.crossings.patch_obstacles, 0);
    EXPECT_EQ(hole.self_intersections, 0);
    EXPECT_TRUE(hole.warning.empty()) << hole.warning;
    // Faces two rings apart on a smooth sheet: about half an edge length.
    EXPECT_GT(hole.min_distance, 0.2);
    EXPECT_LT(hole.min_distance, kCrossingReach);
    EXPECT_NEAR(hole.length_scale, loops[choice.fill[0]].mean_edge_length, 1e-12);
  }
}

// The crossings of a patch look at the faces near it only: on a grid 16
// times as large, the same hole looks at the same faces.
TEST(Crossings, TheWorkFollowsTheHoleNotTheMesh) {
  std::vector<int> examined;
  for (const int n : {40, 160}) {
    Mesh mesh = flat_grid(n, kEdge, 0);
    const int centre = 20 * n + 20;
    const Vec3 c = mesh.positions[centre];
    const std::vector<int> tent = raise_tent(mesh, centre, {c[0], c[1], 0.5 * kEdge});
    const Box3 box = bounding_box(mesh.positions, mesh.faces, tent, kCrossingReach * kEdge);
    const std::vector<int> nearby = faces_near_boxes(mesh.positions, mesh.faces, {box})[0];
    const SubsetCrossings found =
        count_subset_crossings(mesh.positions, mesh.faces, tent, kCrossingReach * kEdge, &nearby);
    EXPECT_EQ(found.within + found.with_others, 0);
    EXPECT_LT(found.faces_examined, 200);
    examined.push_back(found.faces_examined);
    // Without the faces near it, the subset's box is looked up in one pass.
    const SubsetCrossings alone =
        count_subset_crossings(mesh.positions, mesh.faces, tent, kCrossingReach * kEdge);
    EXPECT_EQ(alone.faces_examined, found.faces_examined);
    EXPECT_EQ(alone.min_distance, found.min_distance);
  }
  EXPECT_EQ(examined[0], examined[1]);
}

// Several boxes at once: each gets the faces whose boxes overlap it.
TEST(Crossings, FacesNearBoxesMatchesATestOfEveryFace) {
  const Mesh mesh = make_folded_sheet().mesh;
  const std::vector<Box3> boxes = {{{0.5, 0.5, -1}, {0.7, 0.6, 1}},
                                   {{3.0, 0.0, -0.1}, {4.5, 0.2, 0.0}},
                                   {{-2, -2, -2}, {-1, -1, -1}},
                                   {{1.0, 1.0, 0.1}, {1.0, 1.0, 0.1}}};
  const std::vector<std::vector<int>> near = faces_near_boxes(mesh.positions, mesh.faces, boxes);
  ASSERT_EQ(near.size(), boxes.size());
  for (size_t b = 0; b < boxes.size(); ++b) {
    std::vector<int> expected;
    for (int f = 0; f < mesh.face_count(); ++f) {
      bool overlaps = true;
      for (int c = 0; c < 3; ++c) {
        double low = HUGE_VAL, high = -HUGE_VAL;
        for (int v : mesh.faces[f]) {
          low = std::min(low, mesh.positions[v][c]);
          high = std::max(high, mesh.positions[v][c]);
        }
        overlaps = overlaps && !(high < boxes[b].low[c] || boxes[b].high[c] < low);
      }
      if (overlaps) expected.push_back(f);
    }
    EXPECT_EQ(near[b], expected) << "box " << b;
  }
  EXPECT_TRUE(near[2].empty());
}

}  // namespace
}  // namespace foldfill
