// Boundary loops and hole selection on tiny meshes built in code, and on the
// reference cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/examples.h"
#include "foldfill/holes.h"
#include "foldfill/io.h"
#include "foldfill/test_surfaces.h"
#include "foldfill/topology.h"
#include "support/cloth_cases.h"
#include "support/reference_cases.h"
#include "test_support.h"

namespace foldfill {
namespace {

using Cell = std::pair<int, int>;

// A (cells x cells) grid of unit squares in the z = 0 plane, each split along
// its diagonal, counter-clockwise seen from +z, without the `removed` cells.
// Vertex (i, j) is j * (cells + 1) + i.
Mesh grid(int cells, const std::set<Cell>& removed = {}) {
  Mesh mesh;
  const int row = cells + 1;
  for (int j = 0; j < row; ++j) {
    for (int i = 0; i < row; ++i) mesh.positions.push_back({double(i), double(j), 0.0});
  }
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      if (removed.count({i, j})) continue;
      const int a = j * row + i, b = a + 1, c = a + row + 1, d = a + row;
      mesh.faces.push_back({a, b, c});
      mesh.faces.push_back({a, c, d});
    }
  }
  return mesh;
}

// An open cylinder of unit radius: `around` vertices per ring, `rings` rings
// one unit apart; vertex k of ring r is r * around + k.
Mesh tube(int around, int rings) {
  Mesh mesh;
  for (int r = 0; r < rings; ++r) {
    for (int k = 0; k < around; ++k) {
      const double angle = 2 * M_PI * k / around;
      mesh.positions.push_back({std::cos(angle), std::sin(angle), double(r)});
    }
  }
  for (int r = 0; r + 1 < rings; ++r) {
    for (int k = 0; k < around; ++k) {
      const int a = r * around + k, b = r * around + (k + 1) % around;
      mesh.faces.push_back({a, b, b + around});
      mesh.faces.push_back({a, b + around, a + around});
    }
  }
  return mesh;
}

Mesh tetrahedron() {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  return mesh;
}

// Twice the signed area of a loop projected on the xy plane.
double signed_area_xy(const BoundaryLoop& loop) {
  double area = 0;
  const size_t n = loop.positions.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec3& p = loop.positions[i];
    const Vec3& q = loop.positions[(i + 1) % n];
    area += p[0] * q[1] - q[0] * p[1];
  }
  return area;
}

// The z component of the normal of triangle (a, b, c).
double normal_z(const Mesh& mesh, int a, int b, int c) {
  const Vec3 &p = mesh.positions[a], &q = mesh.positions[b], &r = mesh.positions[c];
  return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
}

HoleSelection keeping_open(int keep_open) {
  HoleSelection selection;
  selection.mode = HoleSelection::Mode::KeepOpen;
  selection.keep_open = keep_open;
  return selection;
}

HoleSelection by_mode(HoleSelection::Mode mode) {
  HoleSelection selection;
  selection.mode = mode;
  return selection;
}

HoleSelection by_ids(std::vector<int> ids) {
  HoleSelection selection = by_mode(HoleSelection::Mode::Ids);
  selection.ids = std::move(ids);
  return selection;
}

HoleSelection near(std::vector<Vec3> points) {
  HoleSelection selection = by_mode(HoleSelection::Mode::Near);
  selection.near = std::move(points);
  return selection;
}
HoleSelection near(Vec3 point) { return near(std::vector<Vec3>{point}); }

// The message of the Error of kind `kind` that `action` throws.
template <typename Action>
std::string error_of(ErrorKind kind, Action action) {
  try {
    action();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), kind) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error thrown";
  return "";
}

using Ids = std::vector<int>;

TEST(Holes, ClosedMeshHasNoLoops) {
  const auto loops = find_boundary_loops(tetrahedron());
  EXPECT_TRUE(loops.empty());
  const HoleChoice choice = select_holes(loops, {});
  EXPECT_TRUE(choice.fill.empty());
  EXPECT_TRUE(choice.left_open.empty());
  EXPECT_EQ(error_of(ErrorKind::Usage,
                     [&] {
                       select_holes(loops, near({0, 0, 0}), "t.obj");
                     }),
            "t.obj: no loop to select near a point (the mesh has no boundary)");
}

TEST(Holes, GridHasOneOuterLoop) {
  const auto loops = find_boundary_loops(grid(3));
  ASSERT_EQ(loops.size(), 1u);
  const BoundaryLoop& loop = loops[0];
  EXPECT_EQ(loop.id, 0);
  EXPECT_EQ(loop.vertices, Ids({0, 4, 8, 12, 13, 14, 15, 11, 7, 3, 2, 1}));
  EXPECT_DOUBLE_EQ(loop.length, 12);
  EXPECT_DOUBLE_EQ(loop.mean_edge_length, 1);
  EXPECT_DOUBLE_EQ(loop.bbox_diagonal, std::sqrt(18.0));
  EXPECT_DOUBLE_EQ(loop.centroid[0], 1.5);
  EXPECT_DOUBLE_EQ(loop.centroid[1], 1.5);
  EXPECT_TRUE(loop.is_disk);
  EXPECT_TRUE(loop.reason.empty());
  EXPECT_LT(signed_area_xy(loop), 0) << "the missing region (outside) must be on the left";
  const HoleChoice choice = select_holes(loops, {});
  EXPECT_TRUE(choice.fill.empty());
  EXPECT_EQ(choice.left_open, Ids{0});
}

TEST(Holes, GridWithOneHole) {
  const Mesh mesh = grid(4, {{1, 1}});
  const auto loops = find_boundary_loops(mesh);
  ASSERT_EQ(loops.size(), 2u);
  EXPECT_EQ(loops[0].vertices.size(), 16u);
  EXPECT_EQ(loops[1].vertices, Ids({6, 7, 12, 11}));
  EXPECT_GT(signed_area_xy(loops[1]), 0) << "a hole runs counter-clockwise seen from +z";
  EXPECT_DOUBLE_EQ(loops[1].length, 4);
  EXPECT_DOUBLE_EQ(loops[1].bbox_diagonal, std::sqrt(2.0));
  const HoleChoice choice = select_holes(loops, {});
  EXPECT_EQ(choice.fill, Ids{1});
  EXPECT_EQ(choice.left_open, Ids{0});
  EXPECT_TRUE(choice.warnings.empty());
}

TEST(Holes, GridWithTwoHoles) {
  const Mesh mesh = grid(6, {{1, 1}, {4, 3}});
  const auto loops = find_boundary_loops(mesh);
  ASSERT_EQ(loops.size(), 3u);
  EXPECT_EQ(loops[1].vertices.front(), 8);   // (1, 1)
  EXPECT_EQ(loops[2].vertices.front(), 25);  // (4, 3)
  EXPECT_EQ(select_holes(loops, {}).fill, Ids({1, 2}));
  // All: every hole, said explicitly; the outer edge stays open.
  const HoleChoice all = select_holes(loops, by_mode(HoleSelection::Mode::All));
  EXPECT_EQ(all.fill, Ids({1, 2}));
  EXPECT_EQ(all.left_open, Ids({0}));
  EXPECT_EQ(all.reasons[0], ChoiceReason::NotAHole);
  const HoleChoice ids = select_holes(loops, by_ids({2, 0, 2}));
  EXPECT_EQ(ids.fill, Ids({0, 2}));
  EXPECT_EQ(ids.left_open, Ids{1});
  EXPECT_EQ(select_holes(loops, near({4.6, 3.5, 0.3})).fill, Ids{2});
  EXPECT_EQ(select_holes(loops, near({1.5, 1.5, 0})).fill, Ids{1});
  EXPECT_EQ(select_holes(loops, near({-1, 3, 0})).fill, Ids{0});
}

// Filling each hole with a fan of triangles in loop order closes it with the
// mesh's orientation: the topology stays consistent and only the outer loop
// remains.
TEST(Holes, LoopOrderOrientsNewFacesLikeTheMesh) {
  Mesh mesh = grid(6, {{1, 1}, {2, 1}, {4, 3}});
  const auto loops = find_boundary_loops(mesh);
  ASSERT_EQ(loops.size(), 3u);
  const double hole_area[3] = {0, 2, 1};
  for (int id : {1, 2}) {
    const Ids& v = loops[id].vertices;
    double doubled_area = 0;  // positive where the new faces face +z like the grid
    for (size_t i = 1; i + 1 < v.size(); ++i) {
      mesh.faces.push_back({v[0], v[i], v[i + 1]});
      doubled_area += normal_z(mesh, v[0], v[i], v[i + 1]);
    }
    EXPECT_DOUBLE_EQ(doubled_area, 2 * hole_area[id]);
  }
  EXPECT_NO_THROW(build_edge_topology(mesh.faces, mesh.vertex_count()));
  const auto closed = find_boundary_loops(mesh);
  ASSERT_EQ(closed.size(), 1u);
  EXPECT_EQ(closed[0].vertices, loops[0].vertices);
}

TEST(Holes, AnnulusDefaultLeavesTheLongerLoopOpen) {
  const Mesh mesh = grid(4, {{1, 1}, {2, 1}, {1, 2}, {2, 2}});
  const auto loops = find_boundary_loops(mesh);
  ASSERT_EQ(loops.size(), 2u);
  EXPECT_DOUBLE_EQ(loops[0].length, 16);
  EXPECT_DOUBLE_EQ(loops[1].length, 8);
  EXPECT_EQ(longest_loops(loops), Ids{0});
  HoleChoice choice = select_holes(loops, {});
  EXPECT_EQ(choice.fill, Ids{1});
  EXPECT_EQ(choice.left_open, Ids{0});
  choice = select_holes(loops, keeping_open(0));
  EXPECT_EQ(choice.fill, Ids({0, 1}));
  EXPECT_EQ(select_holes(loops, near({2, 2, 0})).fill, Ids{1});
  EXPECT_EQ(select_holes(loops, near({2, -0.5, 0})).fill, Ids{0});
}

TEST(Holes, TubeHasTwoEqualLoops) {
  const auto loops = find_boundary_loops(tube(8, 4));
  ASSERT_EQ(loops.size(), 2u);
  EXPECT_EQ(loops[0].vertices.size(), 8u);
  EXPECT_EQ(loops[1].vertices.front(), 24);
  EXPECT_NEAR(loops[0].length, loops[1].length, 1e-12);
  EXPECT_NEAR(loops[1].centroid[2], 3, 1e-12);
  // The default leaves both ends open: neither turns like a hole.
  HoleChoice choice = select_holes(loops, {});
  EXPECT_TRUE(choice.fill.empty());
  EXPECT_EQ(loops[0].kind, LoopKind::TubeEnd);
  EXPECT_EQ(loops[1].kind, LoopKind::TubeEnd);
  choice = select_holes(loops, keeping_open(2));
  EXPECT_TRUE(choice.fill.empty());
  EXPECT_EQ(choice.left_open, Ids({0, 1}));
  choice = select_holes(loops, keeping_open(1));
  EXPECT_EQ(choice.fill, Ids{1});  // equal lengths: the lower id stays open
  EXPECT_EQ(choice.left_open, Ids{0});
  EXPECT_EQ(longest_loops(loops, 5), Ids({0, 1}));
}

// Gauss-Bonnet: a hole in a flat sheet turns by +2 pi, the sheet's outer edge
// by -2 pi, a tube's ends by 0; the default fills only what turns like a hole.
TEST(Holes, TurningTellsHolesFromOuterEdges) {
  const auto sheet = find_boundary_loops(grid(6, {{1, 1}, {2, 1}, {4, 3}}));
  ASSERT_EQ(sheet.size(), 3u);
  EXPECT_NEAR(sheet[0].turning, -2 * M_PI, 1e-9);
  EXPECT_NEAR(sheet[1].turning, 2 * M_PI, 1e-9);
  EXPECT_NEAR(sheet[2].turning, 2 * M_PI, 1e-9);
  EXPECT_EQ(select_holes(sheet, {}).fill, Ids({1, 2}));
  EXPECT_EQ(sheet[0].kind, LoopKind::OuterEdge);
  EXPECT_EQ(sheet[0].kind_reason, LoopKindReason::TurnsLikeAnEdge);
  EXPECT_EQ(sheet[1].kind_reason, LoopKindReason::TurnsLikeAHole);
  const auto ends = find_boundary_loops(tube(16, 4));
  ASSERT_EQ(ends.size(), 2u);
  EXPECT_NEAR(ends[0].turning, 0, 1e-9);
  EXPECT_NEAR(ends[1].turning, 0, 1e-9);
  EXPECT_TRUE(select_holes(ends, {}).fill.empty());
}

TEST(Holes, BowtieLoopsAreNotDisks) {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-2, 0, 0}, {0, -2, 0}};
  mesh.faces = {{0, 1, 2}, {0, 3, 4}};
  const auto loops = find_boundary_loops(mesh, "bowtie.obj");
  ASSERT_EQ(loops.size(), 2u);
  EXPECT_EQ(loops[0].vertices, Ids({0, 2, 1}));
  EXPECT_EQ(loops[1].vertices, Ids({0, 4, 3}));
  EXPECT_FALSE(loops[0].is_disk);
  EXPECT_FALSE(loops[1].is_disk);
  EXPECT_EQ(loops[0].reason, "touches loop 1 at vertex 0");
  EXPECT_EQ(loops[1].reason, "touches loop 0 at vertex 0");

  const HoleChoice choice = select_holes(loops, {});
  EXPECT_TRUE(choice.fill.empty());
  EXPECT_EQ(choice.left_open, Ids({0, 1}));
  EXPECT_EQ(loops[0].kind, LoopKind::NotADisk);
  ASSERT_EQ(choice.warnings.size(), 2u);
  EXPECT_EQ(choice.warnings[0],
            "loop 0 is not a disk boundary (touches loop 1 at vertex 0): left open");
  // Keeping the longest open, only the other one is skipped.
  EXPECT_EQ(select_holes(loops, keeping_open(1)).warnings.size(), 1u);
  EXPECT_EQ(select_holes(loops, by_mode(HoleSelection::Mode::All)).warnings.size(), 2u);

  EXPECT_EQ(error_of(ErrorKind::NotADisk, [&] { select_holes(loops, by_ids({0}), "bowtie.obj"); }),
            "bowtie.obj: loop 0 is not a disk boundary (touches loop 1 at vertex 0)");
  EXPECT_NE(error_of(ErrorKind::NotADisk,
                     [&] {
                       select_holes(loops, near({0.4, 0.4, 0}));
                     })
                .find("loop 0 is not a disk"),
            std::string::npos);
}

// Two holes meeting at a corner: the boundary passes that vertex twice and is
// split there into the two holes, each a disk boundary the default fills.
TEST(Holes, TwoHolesMeetingAtACornerAreSplitThere) {
  const Mesh mesh = grid(4, {{1, 1}, {2, 2}});
  const auto loops = find_boundary_loops(mesh);
  ASSERT_EQ(loops.size(), 3u);
  EXPECT_TRUE(loops[0].split_at.empty());
  for (int id : {1, 2}) {
    EXPECT_EQ(loops[id].vertices.size(), 4u);
    EXPECT_EQ(std::count(loops[id].vertices.begin(), loops[id].vertices.end(), 12), 1);
    EXPECT_TRUE(loops[id].is_disk);
    EXPECT_EQ(loops[id].split_at, Ids({12}));
    EXPECT_NEAR(loops[id].turning, 2 * M_PI, 1e-9);
  }
  const HoleChoice choice = select_holes(loops, {});
  EXPECT_EQ(choice.fill, Ids({1, 2}));
  EXPECT_TRUE(choice.warnings.empty());
  EXPECT_EQ(select_holes(loops, by_ids({1})).fill, Ids({1}));
}

// A strip around a square whose two ends meet at one vertex (5); vertex 0 is
// left unreferenced. The boundary is split at 5 into the square's and the
// outer one.
TEST(Holes, AStripWhoseEndsMeetAtOneVertexIsSplitThere) {
  const Mesh mesh = grid(3, {{0, 0}, {1, 1}});
  const auto loops = find_boundary_loops(mesh);
  ASSERT_EQ(loops.size(), 2u);
  for (const BoundaryLoop& loop : loops) {
    EXPECT_EQ(std::count(loop.vertices.begin(), loop.vertices.end(), 5), 1);
    EXPECT_EQ(std::count(loop.vertices.begin(), loop.vertices.end(), 0), 0);
    EXPECT_TRUE(loop.is_disk);
    EXPECT_EQ(loop.split_at, Ids({5}));
  }
  EXPECT_EQ(loops[0].vertices.size() + loops[1].vertices.size(), 16u);
}

TEST(Holes, ClosedFanWithDanglingTriangleThrows) {
  Mesh mesh = tetrahedron();
  mesh.positions.push_back({-1, 0, 0});
  mesh.positions.push_back({0, -1, 0});
  mesh.faces.push_back({0, 4, 5});
  EXPECT_EQ(error_of(ErrorKind::NonManifold, [&] { find_boundary_loops(mesh, "m.obj"); }),
            "m.obj: vertex 0 is non-manifold (its faces form 2 separate fans)");
}

TEST(Holes, TwoTetrahedraSharingAVertexThrow) {
  Mesh mesh = tetrahedron();
  for (const Vec3& p : tetrahedron().positions) mesh.positions.push_back({-p[0], -p[1], -p[2]});
  for (const Tri& f : tetrahedron().faces) mesh.faces.push_back({f[0] + 4, f[1] + 4, f[2] + 4});
  for (Tri& f : mesh.faces) std::replace(f.begin(), f.end(), 4, 0);  // glue vertex 4 onto 0
  EXPECT_NE(error_of(ErrorKind::NonManifold, [&] { find_boundary_loops(mesh); })
                .find("vertex 0 is non-manifold (its faces form 2 separate fans)"),
            std::string::npos);
}

TEST(Holes, NonManifoldEdgeThrows) {
  Mesh mesh = grid(1);
  mesh.positions.push_back({0.5, 0.5, 1});
  mesh.faces.push_back({0, 3, 4});  // a third face on the diagonal (0, 3)
  EXPECT_NE(error_of(ErrorKind::NonManifold, [&] { find_boundary_loops(mesh); })
                .find("edge (0, 3) is shared by 3 faces"),
            std::string::npos);
}

TEST(Holes, UnknownIdThrowsUsage) {
  const auto loops = find_boundary_loops(grid(6, {{1, 1}, {4, 3}}));
  EXPECT_EQ(error_of(ErrorKind::Usage,
                     [&] {
                       select_holes(loops, by_ids({1, 7}), "g.obj");
                     }),
            "g.obj: no loop with id 7 (the mesh has 3 loops)");
  EXPECT_THROW(select_holes(loops, by_ids({-1})), Error);
}

TEST(Holes, ManyHolesInALargeGrid) {
  std::set<Cell> removed;
  for (int j = 2; j < 200; j += 4) {
    for (int i = 2; i < 200; i += 4) removed.insert({i, j});
  }
  const auto loops = find_boundary_loops(grid(200, removed));
  ASSERT_EQ(loops.size(), removed.size() + 1);
  for (size_t id = 1; id < loops.size(); ++id) {
    EXPECT_EQ(loops[id].vertices.size(), 4u);
    EXPECT_TRUE(loops[id].is_disk);
  }
  EXPECT_EQ(select_holes(loops, {}).fill.size(), removed.size());
}

// A fan of many triangles around one vertex: the faces around a vertex are
// grouped in O(d log d), not O(d^2).
TEST(Holes, VertexOfVeryHighDegree) {
  const int around = 200000;
  Mesh fan;
  fan.positions.push_back({0, 0, 0});
  for (int k = 0; k < around; ++k) {
    const double angle = 2 * M_PI * k / around;
    fan.positions.push_back({std::cos(angle), std::sin(angle), 0});
  }
  for (int k = 0; k < around; ++k) fan.faces.push_back({0, 1 + k, 1 + (k + 1) % around});
  const auto loops = find_boundary_loops(fan);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].vertices.size(), static_cast<size_t>(around));
  EXPECT_TRUE(loops[0].is_disk);
}

// The reference cases: the hole loop has the documented size, the other loops
// are the outer boundaries, and the default, ids and `near` pick the hole.
TEST(Holes, ReferenceCases) {
  FOLDFILL_REQUIRE_SHARED();
  const auto cases = testing::read_reference_cases(testing::shared_dir() / "data" / "reference");
  ASSERT_FALSE(cases.empty()) << "no cases.json";
  for (const testing::ReferenceCase& entry : cases) {
    const std::string& name = entry.file;
    SCOPED_TRACE(name);
    const Mesh mesh = read_mesh(entry.path.string());
    const auto loops = find_boundary_loops(mesh, name);
    const int hole_vertex = entry.hole_vertex;
    const int outer_loops = entry.outer_loops;

    std::vector<int> holding;  // loops through hole_vertex
    for (const BoundaryLoop& loop : loops) {
      if (std::count(loop.vertices.begin(), loop.vertices.end(), hole_vertex)) {
        holding.push_back(loop.id);
      }
    }
    ASSERT_EQ(holding.size(), 1u);
    const BoundaryLoop& hole = loops[holding[0]];
    EXPECT_EQ(static_cast<int>(hole.vertices.size()), entry.hole_loop_size);
    EXPECT_TRUE(hole.is_disk) << hole.reason;
    EXPECT_EQ(static_cast<int>(loops.size()) - 1, outer_loops);

    EXPECT_EQ(select_holes(loops, near(mesh.positions[hole_vertex]), name).fill, Ids{hole.id});
    EXPECT_EQ(select_holes(loops, by_ids({hole.id}), name).fill, Ids{hole.id});

    // The default fills exactly the hole, and leaves the outer edges open.
    const HoleChoice choice = select_holes(loops, {}, name);
    EXPECT_EQ(choice.fill, Ids{hole.id});
    EXPECT_EQ(hole.kind, LoopKind::Hole);
    EXPECT_EQ(choice.left_open.size(), static_cast<size_t>(outer_loops));
    EXPECT_TRUE(choice.warnings.empty());
    // Keeping the longest loops open finds the hole only when it is shorter
    // than every outer boundary; it is not on paper1 and sim2.
    const bool hole_is_shortest = std::all_of(loops.begin(), loops.end(), [&](const auto& loop) {
      return loop.id == hole.id || loop.length > hole.length;
    });
    EXPECT_EQ(select_holes(loops, keeping_open(outer_loops), name).fill == Ids{hole.id},
              hole_is_shortest);

    std::cout << name << ": " << mesh.vertex_count() << " vertices, " << mesh.face_count()
              << " faces, " << loops.size() << " loops:";
    for (const BoundaryLoop& loop : loops) {
      std::cout << " [id " << loop.id << (loop.id == hole.id ? " hole" : "") << ", "
                << loop.vertices.size() << " vertices, length " << loop.length << ", turning "
                << loop.turning << "]";
    }
    std::cout << (hole_is_shortest ? "" : "; --keep-open leaves the hole open") << "\n";
  }
}

// The cloth cases: each *_hole.obj has one hole, of the size the manifest
// gives, and the default fills exactly that loop.
TEST(Holes, ClothCasesDefaultFillsTheirHole) {
  FOLDFILL_REQUIRE_SHARED();
  const auto cases = testing::read_cloth_cases(testing::shared_dir() / "data" / "cloth");
  ASSERT_FALSE(cases.empty()) << "no cloth/manifest.json";
  for (const auto& entry : cases) {
    const std::string name = entry.hole_mesh.filename().string();
    SCOPED_TRACE(name);
    const auto loops = find_boundary_loops(read_mesh(entry.hole_mesh.string()), name);
    const HoleChoice choice = select_holes(loops, {}, name);
    ASSERT_EQ(choice.fill.size(), 1u);
    EXPECT_EQ(loops[choice.fill[0]].vertices.size(), static_cast<size_t>(entry.hole_loop_size));
    EXPECT_EQ(std::count(loops[choice.fill[0]].vertices.begin(),
                         loops[choice.fill[0]].vertices.end(), entry.hole_vertex),
              1);
    EXPECT_EQ(choice.left_open.size(), loops.size() - 1);
  }
}

// The ids of the loops through `vertices` (one vertex on each), ascending.
Ids loops_through(const std::vector<BoundaryLoop>& loops, const std::vector<int>& vertices) {
  Ids ids;
  for (int v : vertices) {
    for (const BoundaryLoop& loop : loops) {
      if (std::count(loop.vertices.begin(), loop.vertices.end(), v)) ids.push_back(loop.id);
    }
  }
  std::sort(ids.begin(), ids.end());
  return ids;
}

// Checks that the default fills exactly the holes cut from `surface` and
// leaves its other loops open, as kind `open_kind`. Returns the loops.
std::vector<BoundaryLoop> expect_default_fills_the_holes(const HoledSurface& surface,
                                                         LoopKind open_kind = LoopKind::OuterEdge) {
  const auto loops = find_boundary_loops(surface.mesh);
  const HoleChoice choice = select_holes(loops, {});
  EXPECT_EQ(choice.fill, loops_through(loops, surface.hole_vertices));
  EXPECT_EQ(choice.left_open, loops_through(loops, surface.open_vertices));
  EXPECT_TRUE(choice.warnings.empty());
  for (int id : choice.left_open) {
    EXPECT_EQ(loops[id].kind, open_kind) << "loop " << id << ": " << explain_kind(loops[id]);
  }
  for (int id : choice.fill) EXPECT_EQ(choice.reasons[id], ChoiceReason::IsAHole);
  return loops;
}

TEST(Classify, SphereHolesAllFilledTheCapByItsCurvature) {
  const HoledSurface sphere = make_holed_sphere();
  const auto loops = expect_default_fills_the_holes(sphere);
  const BoundaryLoop& cap = loops[loops_through(loops, {sphere.hole_vertices[0]}).at(0)];
  EXPECT_LT(cap.turning, M_PI);
  EXPECT_EQ(cap.kind_reason, LoopKindReason::ClosesTheCurvature);
  EXPECT_NEAR(cap.curvature_density, 1.0, 0.05);
  // The cap's area, 2 pi (1 - cos 65 degrees), as the curvature predicts it.
  EXPECT_NEAR(cap.predicted_area, 2 * M_PI * (1 - std::cos(65 * M_PI / 180)), 0.3);
  EXPECT_NE(explain_kind(cap).find("closes it"), std::string::npos) << explain_kind(cap);
}

// Angle defects are summed over a band, so noise in the positions mostly
// cancels: the cap of a sphere whose vertices are moved at random by a tenth
// of an edge is still a hole.
TEST(Classify, SphereCapIsAHoleThroughNoise) {
  HoledSurface sphere = make_holed_sphere();
  std::mt19937_64 random(7);
  const double edge = mean_edge_length(sphere.mesh);
  for (Vec3& p : sphere.mesh.positions) {
    for (double& c : p) c += 0.1 * edge * (static_cast<double>(random() >> 11) * 0x1.0p-53 - 0.5);
  }
  expect_default_fills_the_holes(sphere);
}

TEST(Classify, TorusHolesOutsideInsideAndOnTopAreHoles) {
  expect_default_fills_the_holes(make_holed_torus());
}

TEST(Classify, BlobHolesAreAllHoles) {
  const HoledSurface blob = make_holed_blob();
  const auto loops = expect_default_fills_the_holes(blob);
  EXPECT_EQ(loops.size(), blob.hole_vertices.size());
}

TEST(Classify, BoxCornerHoleIsAHole) {
  expect_default_fills_the_holes(make_box_with_corner_hole());
}

TEST(Classify, SleeveEndsStayOpenAndItsLongerHoleIsFilled) {
  expect_default_fills_the_holes(make_holed_sleeve(), LoopKind::TubeEnd);
}

TEST(Classify, SheetHoleLongerThanTheOuterEdgeIsFilled) {
  expect_default_fills_the_holes(make_sheet_with_long_hole());
}

TEST(Classify, SmallHolesOfThreeFourAndFiveVerticesAreFilled) {
  expect_default_fills_the_holes(make_sheet_with_small_holes());
}

TEST(Classify, RuffleSlotIsAHole) { expect_default_fills_the_holes(make_ruffle_with_c_slot()); }

// A dome's rim turns by less than a hole's would, and its curvature would
// close it only with the rest of the sphere, larger than the dome: an edge,
// however deep the dome, up to a hemisphere (where it turns by 0, a tube's end).
TEST(Classify, DomeRimStaysOpenAndItsHoleIsFilled) {
  for (double rim : {50.0, 60.0, 70.0, 80.0}) {
    SCOPED_TRACE(rim);
    DomeSurfaceOptions options;
    options.rim_degrees = rim;
    const HoledSurface dome = make_holed_dome(options);
    const auto loops = find_boundary_loops(dome.mesh);
    const BoundaryLoop& edge = loops[loops_through(loops, dome.open_vertices).at(0)];
    EXPECT_GT(edge.predicted_area, edge.component_area);
    expect_default_fills_the_holes(dome, rim < 75 ? LoopKind::OuterEdge : LoopKind::TubeEnd);
  }
}

// Each piece of surface is judged by its own area: a dome beside a large
// sheet keeps its rim open although the sheet's area exceeds what the dome's
// curvature would need to close it.
TEST(Classify, EachPieceIsJudgedOnItsOwn) {
  HoledSurface dome = make_holed_dome();
  SheetSurfaceOptions big;
  big.size = 6;
  big.edge_length = 0.1;
  const HoledSurface sheet = make_sheet_with_long_hole(big);
  HoledSurface both = dome;
  const int offset = both.mesh.vertex_count();
  for (const Vec3& p : sheet.mesh.positions) both.mesh.positions.push_back({p[0] + 5, p[1], p[2]});
  for (const Tri& f : sheet.mesh.faces) {
    both.mesh.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  }
  for (int v : sheet.hole_vertices) both.hole_vertices.push_back(v + offset);
  for (int v : sheet.open_vertices) both.open_vertices.push_back(v + offset);
  const auto loops = expect_default_fills_the_holes(both);
  const BoundaryLoop& rim = loops[loops_through(loops, dome.open_vertices).at(0)];
  EXPECT_LT(rim.predicted_area, 36.0);
  EXPECT_GT(rim.predicted_area, rim.component_area);
}

// A loop the user names is selected whatever its kind: the fill's own checks
// decide what can be done with it.
TEST(Selection, NamedOuterEdgeIsSelected) {
  const auto loops = find_boundary_loops(grid(6, {{1, 1}, {4, 3}}));
  ASSERT_EQ(loops[0].kind, LoopKind::OuterEdge);
  const HoleChoice choice = select_holes(loops, by_ids({0}));
  EXPECT_EQ(choice.fill, Ids{0});
  EXPECT_EQ(choice.reasons[0], ChoiceReason::Named);
  EXPECT_EQ(choice.reasons[1], ChoiceReason::NotNamed);
  EXPECT_EQ(select_holes(loops, near({-0.5, 2, 0})).fill, Ids{0});
}

TEST(Selection, EachNearPointPicksItsLoop) {
  const auto loops = find_boundary_loops(grid(6, {{1, 1}, {4, 3}}));
  EXPECT_EQ(select_holes(loops, near({{1.5, 1.5, 0}, {4.5, 3.5, 0}})).fill, Ids({1, 2}));
  // With ids as well: every loop named.
  HoleSelection both = near(Vec3{4.5, 3.5, 0});
  both.ids = {0};
  EXPECT_EQ(select_holes(loops, both).fill, Ids({0, 2}));
}

TEST(Selection, NearAPointFarFromEveryLoopIsAnError) {
  const auto loops = find_boundary_loops(grid(6, {{1, 1}, {4, 3}}));
  EXPECT_EQ(error_of(ErrorKind::Usage,
                     [&] {
                       select_holes(loops, near({{1.5, 1.5, 0}, {3, 3, 20}}), "g.obj");
                     }),
            "g.obj: no loop near the point (3, 3, 20): the nearest, loop 2, is 20 away, farther "
            "than its size (1.41)");
}

TEST(Selection, FiltersBySizeAndDiameterOnTopOfTheMode) {
  // Holes of 4, 6 and 8 vertices (one, two and four cells).
  const auto loops =
      find_boundary_loops(grid(12, {{1, 1}, {5, 5}, {6, 5}, {8, 8}, {9, 8}, {8, 9}, {9, 9}}));
  ASSERT_EQ(loops.size(), 4u);
  HoleSelection small;
  small.max_hole_size = 6;
  HoleChoice choice = select_holes(loops, small);
  EXPECT_EQ(choice.fill, Ids({1, 2}));
  EXPECT_EQ(choice.reasons[3], ChoiceReason::TooManyEdges);
  EXPECT_EQ(choice.reasons[0], ChoiceReason::NotAHole);
  HoleSelection narrow;
  narrow.max_hole_diameter = 2.5;  // the 2 x 2 hole's diagonal is 2.83
  choice = select_holes(loops, narrow);
  EXPECT_EQ(choice.fill, Ids({1, 2}));
  EXPECT_EQ(choice.reasons[3], ChoiceReason::TooWide);
  // On named loops too.
  HoleSelection named = by_ids({1, 3});
  named.max_hole_size = 6;
  EXPECT_EQ(select_holes(loops, named).fill, Ids({1}));
  EXPECT_DOUBLE_EQ(mean_edge_length(grid(2)), (12 + 4 * std::sqrt(2.0)) / 16);
}

}  // namespace
// A loop turns by the same angle at any unit: the corner angles are computed
// from edges scaled by a power of two where their products would underflow
// or overflow, so a mesh scaled by 2^-1000 or 2^1000 has the same loops, of
// the same kinds.
TEST(Holes, TurningIsTheSameAtAnyScale) {
  FoldedSheetOptions options;
  options.edge_length = 0.2;
  const Mesh mesh = cut_disk_hole(make_folded_sheet(options), {2, 1.5}, 0.6).cut.mesh;
  Mesh tiny = mesh, huge = mesh;
  for (Vec3& p : tiny.positions)
    for (double& x : p) x = std::ldexp(x, -1000);
  for (Vec3& p : huge.positions)
    for (double& x : p) x = std::ldexp(x, 1000);
  const auto loops = find_boundary_loops(mesh);
  ASSERT_EQ(loops.size(), 2u);
  for (const Mesh* scaled : {&tiny, &huge}) {
    const auto same = find_boundary_loops(*scaled);
    ASSERT_EQ(same.size(), loops.size());
    for (size_t k = 0; k < loops.size(); ++k) {
      EXPECT_DOUBLE_EQ(same[k].turning, loops[k].turning) << k;
      EXPECT_EQ(same[k].kind, loops[k].kind) << k;
    }
  }
}

}  // namespace foldfill
