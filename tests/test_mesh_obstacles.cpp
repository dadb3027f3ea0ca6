// Triangle meshes as obstacles: distances, sides and normals against a box
// whose distance is known exactly, open meshes, reading them (and the errors
// of a bad file), normalisation, and fills draped over a triangulated sphere
// and a box that keep every patch vertex outside, at any scale.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/io.h"
#include "foldfill/obstacles.h"
#include "test_support.h"

namespace foldfill {
namespace {

// The box [low, high] as 12 triangles, oriented outwards (or inwards).
Mesh box_mesh(const Vec3& low, const Vec3& high, bool inwards = false) {
  Mesh mesh;
  for (int k = 0; k < 8; ++k)
    mesh.positions.push_back(
        {k & 1 ? high[0] : low[0], k & 2 ? high[1] : low[1], k & 4 ? high[2] : low[2]});
  // Quads counter-clockwise seen from outside.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.faces.push_back({q[0], q[1], q[2]});
    mesh.faces.push_back({q[0], q[2], q[3]});
  }
  if (inwards)
    for (Tri& f : mesh.faces) std::swap(f[1], f[2]);
  return mesh;
}

// The exact signed distance to the box [0, 1]^3.
// One triangle, counter-clockwise a, b, c: an open obstacle mesh.
Mesh one_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  Mesh mesh;
  mesh.positions = {a, b, c};
  mesh.faces = {{0, 1, 2}};
  return mesh;
}

double box_distance(const Vec3& p) {
  double outside = 0, inside = -HUGE_VAL;
  for (int c = 0; c < 3; ++c) {
    const double d = std::max(-p[c], p[c] - 1);
    outside += std::max(d, 0.0) * std::max(d, 0.0);
    inside = std::max(inside, d);
  }
  return outside > 0 ? std::sqrt(outside) : inside;
}

// A closed sphere of `radius` about `centre`: `rings` x 2 `rings` latitude
// and longitude lines, oriented outwards.
Mesh sphere_mesh(const Vec3& centre, double radius, int rings) {
  Mesh mesh;
  const int around = 2 * rings;
  mesh.positions.push_back({centre[0], centre[1], centre[2] + radius});
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < around; ++j) {
      const double theta = M_PI * i / rings, phi = 2 * M_PI * j / around;
      mesh.positions.push_back({centre[0] + radius * std::sin(theta) * std::cos(phi),
                                centre[1] + radius * std::sin(theta) * std::sin(phi),
                                centre[2] + radius * std::cos(theta)});
    }
  mesh.positions.push_back({centre[0], centre[1], centre[2] - radius});
  const auto at = [&](int i, int j) { return 1 + (i - 1) * around + (j % around); };
  const int bottom = mesh.vertex_count() - 1;
  for (int j = 0; j < around; ++j) mesh.faces.push_back({0, at(1, j), at(1, j + 1)});
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < around; ++j) {
      mesh.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  for (int j = 0; j < around; ++j)
    mesh.faces.push_back({at(rings - 1, j), bottom, at(rings - 1, j + 1)});
  return mesh;
}

TEST(MeshObstacle, DistancesAndSidesOfABoxAreExact) {
  for (const bool inwards : {false, true}) {
    SCOPED_TRACE(inwards ? "faces oriented inwards" : "faces oriented outwards");
    const Obstacle box = mesh_obstacle(box_mesh({0, 0, 0}, {1, 1, 1}, inwards), "box.obj");
    ASSERT_EQ(box.type, Obstacle::Type::Mesh);
    EXPECT_TRUE(box.mesh->closed());
    std::mt19937 random(7);
    std::uniform_real_distribution<double> coordinate(-0.5, 1.5);
    for (int k = 0; k < 2000; ++k) {
      const Vec3 p{coordinate(random), coordinate(random), coordinate(random)};
      EXPECT_NEAR(signed_distance(box, p), box_distance(p), 1e-12)
          << p[0] << " " << p[1] << " " << p[2];
      if (farther_than(box, p, 0.25)) {
        EXPECT_GT(box_distance(p), 0.25);
      }
    }
    EXPECT_DOUBLE_EQ(signed_distance(box, {0.5, 0.5, 1.3}), 0.3);
    EXPECT_DOUBLE_EQ(signed_distance(box, {0.5, 0.4, 0.9}), -0.1);
    EXPECT_EQ(signed_distance(box, {0.5, 0.4, 1.0}), 0);
    const auto expect_direction = [&](const Vec3& p, const Vec3& n) {
      const Vec3 normal = outward_normal(box, p);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(normal[c], n[c], 1e-12);
    };
    expect_direction({0.5, 0.5, 1.3}, {0, 0, 1});
    expect_direction({0.5, 0.4, 0.9}, {0, 0, 1});
    expect_direction({0.5, 0.4, 1.0}, {0, 0, 1});
    expect_direction({1.1, 1.1, 1.1}, {1 / std::sqrt(3), 1 / std::sqrt(3), 1 / std::sqrt(3)});
    expect_direction({-0.2, 0.5, -0.2}, {-1 / std::sqrt(2), 0, -1 / std::sqrt(2)});
  }
}

TEST(MeshObstacle, PushOutsidePutsAPointJustOutside) {
  const Obstacle box = mesh_obstacle(box_mesh({0, 0, 0}, {1, 1, 1}), "box.obj");
  for (Vec3 p : std::vector<Vec3>{{0.5, 0.4, 0.9},
                                  {0.5, 0.4, 1.0},
                                  {0.02, 0.03, 0.01},
                                  {0.5, 0.5, 0.5},
                                  {1.0, 1.0, 1.0}}) {
    const Vec3 before = p;
    EXPECT_TRUE(push_outside(box, p));
    EXPECT_GT(signed_distance(box, p), 0);
    EXPECT_LT(signed_distance(box, p), 1e-6);
    EXPECT_LT(std::hypot(p[0] - before[0], p[1] - before[1], p[2] - before[2]),
              -box_distance(before) + 1e-6);
    // Once outside, it stays where it is.
    const Vec3 outside = p;
    EXPECT_FALSE(push_outside(box, p));
    EXPECT_EQ(p, outside);
  }
}

TEST(MeshObstacle, AnOpenMeshHasItsFrontOutside) {
  // A square at z = 0 facing up; behind it is inside, however far.
  Mesh square;
  square.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  square.faces = {{0, 1, 2}, {0, 2, 3}};
  const Obstacle sheet = mesh_obstacle(square, "square.obj");
  EXPECT_FALSE(sheet.mesh->closed());
  EXPECT_DOUBLE_EQ(signed_distance(sheet, {0.5, 0.3, 0.25}), 0.25);
  EXPECT_DOUBLE_EQ(signed_distance(sheet, {0.5, 0.3, -0.25}), -0.25);
  EXPECT_DOUBLE_EQ(signed_distance(sheet, {0.5, 0.3, -5}), -5);
  EXPECT_FALSE(farther_than(sheet, {0.5, 0.3, -5}, 0.1));
  EXPECT_NEAR(signed_distance(sheet, {1.3, 0.5, 0.4}), 0.5, 1e-15);  // beside its edge, in front
  Vec3 p{0.5, 0.3, -0.25};
  EXPECT_TRUE(push_outside(sheet, p));
  EXPECT_GT(p[2], 0);
  EXPECT_LT(p[2], 1e-8);
  EXPECT_EQ(outward_normal(sheet, {0.2, 0.2, -1}), (Vec3{0, 0, 1}));
}

TEST(MeshObstacle, BesideTheRimOfAnOpenMeshIsOutside) {
  // Behind the square but beside it: its nearest point is on the rim, so the
  // point is beside the surface, not under it.
  Mesh square;
  square.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  square.faces = {{0, 1, 2}, {0, 2, 3}};
  const Obstacle sheet = mesh_obstacle(square, "square.obj");
  EXPECT_NEAR(signed_distance(sheet, {1.5, 0.5, -0.5}), std::sqrt(0.5), 1e-15);  // edge
  EXPECT_NEAR(signed_distance(sheet, {2, 2, -1}), std::sqrt(3.0), 1e-15);        // corner
  EXPECT_GT(signed_distance(sheet, {3, 0.5, -5}), 0);
  // One triangle far above a sheet puts nothing inside.
  const Obstacle triangle =
      mesh_obstacle(one_triangle({10, 10, 10}, {11, 10, 10}, {10, 11, 10}), "stray.obj");
  EXPECT_GT(signed_distance(triangle, {0, 0, 0}), 0);
  EXPECT_LT(signed_distance(triangle, {10.2, 10.2, 9}), 0);  // right under it
}

TEST(MeshObstacle, NormalisedMovesAndScalesTheMesh) {
  const Obstacle box = mesh_obstacle(box_mesh({0, 0, 0}, {1, 1, 1}), "box.obj");
  const Vec3 origin{1, 2, 3};
  const double scale = 0.25;
  const Obstacle unit = normalized(box, origin, scale);
  ASSERT_EQ(unit.type, Obstacle::Type::Mesh);
  EXPECT_EQ(unit.mesh->source(), "box.obj");
  for (const Vec3& p : std::vector<Vec3>{{0.5, 0.5, 1.3}, {0.5, 0.4, 0.9}, {1.2, -0.3, 0.5}}) {
    const Vec3 q{(p[0] - origin[0]) / scale, (p[1] - origin[1]) / scale,
                 (p[2] - origin[2]) / scale};
    EXPECT_NEAR(signed_distance(unit, q), signed_distance(box, p) / scale, 1e-12);
  }
}

TEST(MeshObstacle, TrianglesCrossingIntoTheMesh) {
  const Obstacle box = mesh_obstacle(box_mesh({0, 0, 0}, {1, 1, 1}), "box.obj");
  // Through a face; wholly inside (no triangle met: a corner inside); just
  // above, and touching a face.
  EXPECT_TRUE(crosses(box, {{{0.5, 0.5, 0.8}, {0.6, 0.5, 1.2}, {0.5, 0.6, 1.2}}}, 0));
  EXPECT_TRUE(crosses(box, {{{0.4, 0.4, 0.4}, {0.6, 0.4, 0.4}, {0.5, 0.6, 0.4}}}, 0));
  EXPECT_FALSE(crosses(box, {{{0.4, 0.4, 1.01}, {0.6, 0.4, 1.01}, {0.5, 0.6, 1.2}}}, 0));
  EXPECT_TRUE(crosses(box, {{{0.4, 0.4, 1.0}, {0.6, 0.4, 1.1}, {0.5, 0.6, 1.2}}}, 0));
  EXPECT_NEAR(distance(box, {{{0.4, 0.4, 1.01}, {0.6, 0.4, 1.01}, {0.5, 0.6, 1.2}}}, 1), 0.01,
              1e-14);
  EXPECT_EQ(distance(box, {{{0.4, 0.4, 3}, {0.6, 0.4, 3}, {0.5, 0.6, 3}}}, 0.5), 0.5);
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

ErrorKind read_error(const std::filesystem::path& path, std::string& message) {
  try {
    read_obstacles(path.string());
  } catch (const Error& e) {
    message = e.what();
    return e.kind();
  }
  message.clear();
  return ErrorKind::Internal;
}

TEST(MeshObstacle, ReadFromTheObstaclesFileRelativeToItsFolder) {
  const auto dir = testing::scratch_dir("mesh_obstacles");
  std::filesystem::create_directories(dir / "scene");
  write_mesh(box_mesh({0, 0, 0}, {1, 1, 1}), (dir / "scene" / "box.obj").string());
  write_text(dir / "scene" / "obstacles.json",
             R"({"obstacles": [{"type": "sphere", "center": [0, 0, 5], "radius": 1},
                               {"type": "mesh", "file": "box.obj"}]})");
  const std::vector<Obstacle> obstacles =
      read_obstacles((dir / "scene" / "obstacles.json").string());
  ASSERT_EQ(obstacles.size(), 2u);
  ASSERT_EQ(obstacles[1].type, Obstacle::Type::Mesh);
  EXPECT_EQ(obstacles[1].mesh->source(), (dir / "scene" / "box.obj").string());
  EXPECT_DOUBLE_EQ(signed_distance(obstacles[1], {0.5, 0.5, 1.3}), 0.3);

  std::string message;
  const auto scene = [&](const std::string& entry) {
    write_text(dir / "scene" / "bad.json", "{\"obstacles\": [" + entry + "]}");
    return read_error(dir / "scene" / "bad.json", message);
  };
  const std::string bad_json = (dir / "scene" / "bad.json").string();
  EXPECT_EQ(scene(R"({"type": "mesh", "file": "missing.obj"})"), ErrorKind::CannotRead);
  EXPECT_EQ(message.rfind((dir / "scene" / "missing.obj").string() + ": ", 0), 0u) << message;
  write_text(dir / "scene" / "garbage.obj", "this is not a mesh\n");
  EXPECT_EQ(scene(R"({"type": "mesh", "file": "garbage.obj"})"), ErrorKind::BadFormat);
  EXPECT_EQ(message.rfind((dir / "scene" / "garbage.obj").string() + ": ", 0), 0u) << message;
  write_text(dir / "scene" / "fan.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  EXPECT_EQ(scene(R"({"type": "mesh", "file": "fan.obj"})"), ErrorKind::NonManifold);
  EXPECT_EQ(message.rfind((dir / "scene" / "fan.obj").string() + ": ", 0), 0u) << message;
  EXPECT_EQ(scene(R"({"type": "mesh"})"), ErrorKind::Usage);
  EXPECT_EQ(message, bad_json + ": obstacle 1: missing \"file\"");
  EXPECT_EQ(scene(R"({"type": "mesh", "file": 3})"), ErrorKind::Usage);
  EXPECT_EQ(message, bad_json + ": obstacle 1: \"file\" must be a non-empty string");
  EXPECT_EQ(scene(R"({"type": "mesh", "file": "box.obj", "scale": 2})"), ErrorKind::Usage);
  EXPECT_EQ(message, bad_json + ": obstacle 1: unknown key \"scale\" for a mesh");
}

// A sheet lying a gap above a surface z = top(x, y) (a height field over an
// n x n grid of spacing `step` centred on (0, 0)), and a hole cut out of it
// around (hole_x, hole_y).
Mesh sheet_over(int n, double step, double gap, double (*top)(double, double), double hole_x,
                double hole_y, double hole_radius) {
  Mesh grid;
  std::vector<int> index(n * n, -1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = (i - 0.5 * (n - 1)) * step, y = (j - 0.5 * (n - 1)) * step;
      grid.positions.push_back({x, y, top(x, y) + gap});
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      const std::vector<Tri> quad = (i + j) % 2 == 0 ? std::vector<Tri>{{a, b, c}, {a, c, d}}
                                                     : std::vector<Tri>{{a, b, d}, {b, c, d}};
      for (const Tri& f : quad) {
        double cx = 0, cy = 0;
        for (int v : f) {
          cx += grid.positions[v][0] / 3;
          cy += grid.positions[v][1] / 3;
        }
        if (std::hypot(cx - hole_x, cy - hole_y) >= hole_radius) grid.faces.push_back(f);
      }
    }
  return grid;
}

constexpr double kRadius = 1;
double on_sphere(double x, double y) {
  return std::sqrt(std::max(kRadius * kRadius - x * x - y * y, 0.0));
}
double on_box(double x, double y) {
  // The box [-0.5, 0.5]^2 x [-1, 0]; beyond its edges the cloth falls at 45 degrees.
  return -std::max(std::max(std::abs(x), std::abs(y)) - 0.5, 0.0);
}

// With `fabric_only`, the fabric method alone (no fallback chain), which
// is what the obstacles must be seen by.
FillResult fill_over(const Mesh& sheet, const std::vector<Obstacle>& obstacles,
                     bool fabric_only = false) {
  const std::vector<BoundaryLoop> loops = find_boundary_loops(sheet);
  const HoleChoice choice = select_holes(loops, HoleSelection{});
  FillOptions options;
  options.fallback.enabled = !fabric_only;
  options.obstacles = obstacles;
  return fill_holes(sheet, loops, choice.fill, options);
}

void expect_patch_outside(const FillResult& result, const Mesh& sheet, const Obstacle& obstacle) {
  ASSERT_EQ(result.report.holes.size(), 1u);
  const HoleReport& hole = result.report.holes[0];
  ASSERT_TRUE(hole.filled) << hole.reason;
  int inside = 0;
  for (int v = sheet.vertex_count(); v < result.mesh.vertex_count(); ++v)
    inside += signed_distance(obstacle, result.mesh.positions[v]) < 0;
  EXPECT_EQ(inside, 0);
  std::printf("%d patch vertices, crossings %d / %d / %d, min distance %.3g h\n",
              hole.patch_vertex_count, hole.crossings.patch_patch, hole.crossings.patch_mesh,
              hole.crossings.patch_obstacles, hole.min_distance);
}

// The patch vertices that the fill of `sheet` without obstacles puts inside `obstacle`.
int inside_without_obstacles(const Mesh& sheet, const Obstacle& obstacle) {
  const FillResult free = fill_over(sheet, {}, true);
  int inside = 0;
  for (int v = sheet.vertex_count(); v < free.mesh.vertex_count(); ++v)
    inside += signed_distance(obstacle, free.mesh.positions[v]) < 0;
  return inside;
}

// The sheet's cap lies a hair above the sphere; a flat patch across the
// hole's loop would cut through the sphere.
TEST(MeshObstacle, AFillDrapedOverATriangulatedSphereStaysOutside) {
  const Mesh sheet = sheet_over(25, 0.05, 0.01, on_sphere, 0, 0, 0.3);
  const Obstacle sphere = mesh_obstacle(sphere_mesh({0, 0, 0}, kRadius, 24), "sphere.obj");
  EXPECT_GT(inside_without_obstacles(sheet, sphere), 0);
  expect_patch_outside(fill_over(sheet, {sphere}, true), sheet, sphere);
  // By default the sheet's cap is curved like the sphere, so the smooth
  // fill comes first; it must stay outside too.
  expect_patch_outside(fill_over(sheet, {sphere}), sheet, sphere);
}

// The hole is over the box's corner: the patch must fold over it.
TEST(MeshObstacle, AFillDrapedOverABoxCornerStaysOutside) {
  const Mesh sheet = sheet_over(41, 0.05, 0.01, on_box, 0.5, 0.5, 0.3);
  const Obstacle box = mesh_obstacle(box_mesh({-0.5, -0.5, -1}, {0.5, 0.5, 0}), "box.obj");
  EXPECT_GT(inside_without_obstacles(sheet, box), 0);
  expect_patch_outside(fill_over(sheet, {box}), sheet, box);
}

// A stray open triangle far from the cloth changes nothing: the fill is
// the one without obstacles, in the same time.
TEST(MeshObstacle, AStrayOpenTriangleFarAwayChangesNothing) {
  const Mesh sheet = sheet_over(21, 0.05, 0.01, on_box, 0, 0, 0.25);
  const Mesh stray = one_triangle({10, 10, 10}, {11, 10, 10}, {10, 11, 10});
  const FillResult with = fill_over(sheet, {mesh_obstacle(stray, "stray.obj")});
  const FillResult without = fill_over(sheet, {});
  ASSERT_TRUE(with.report.holes.at(0).filled) << with.report.holes.at(0).reason;
  EXPECT_EQ(with.mesh.positions, without.mesh.positions);
  EXPECT_EQ(with.report.holes[0].crossings.total(), 0);
}

// An obstacle that holds the whole cloth (misplaced, or turned inside out)
// is not where the cloth is: the hole is left open, and the reason says so.
TEST(MeshObstacle, AnObstacleThatHoldsTheClothIsRefusedByName) {
  const Mesh sheet = sheet_over(21, 0.05, 0.01, on_box, 0, 0, 0.25);
  const Obstacle around = mesh_obstacle(box_mesh({-5, -5, -5}, {5, 5, 5}), "room.obj");
  const FillResult result = fill_over(sheet, {around});
  const HoleReport& hole = result.report.holes.at(0);
  EXPECT_FALSE(hole.filled);
  EXPECT_NE(hole.reason.find("deep inside obstacle 1 (room.obj)"), std::string::npos)
      << hole.reason;
  EXPECT_EQ(result.mesh.positions, sheet.positions);
}

// An obstacle 1e300 away cannot be computed with (its squares overflow): it
// is refused by name rather than crashing the exact predicates.
TEST(MeshObstacle, AnObstacleTooFarToComputeWithIsRefusedByName) {
  const Mesh sheet = sheet_over(21, 0.05, 0.01, on_box, 0, 0, 0.25);
  const Mesh far = one_triangle({1e300, 0, 0}, {0, 1e300, 0}, {0, 0, 1e300});
  const FillResult result = fill_over(sheet, {mesh_obstacle(far, "far.obj")});
  const HoleReport& hole = result.report.holes.at(0);
  EXPECT_FALSE(hole.filled);
  EXPECT_NE(hole.reason.find("obstacle 1 (far.obj) reaches farther than 1e80 hole lengths"),
            std::string::npos)
      << hole.reason;
}

TEST(MeshObstacle, AFillAgainstAMeshObstacleScalesWithTheMesh) {
  const Mesh sheet = sheet_over(21, 0.05, 0.01, on_sphere, 0, 0, 0.25);
  const Mesh sphere = sphere_mesh({0, 0, 0}, kRadius, 16);
  Mesh big_sheet = sheet, big_sphere = sphere;
  for (Mesh* mesh : {&big_sheet, &big_sphere})
    for (Vec3& p : mesh->positions)
      for (double& x : p) x *= 1000;
  const FillResult unit = fill_over(sheet, {mesh_obstacle(sphere, "sphere.obj")});
  const FillResult big = fill_over(big_sheet, {mesh_obstacle(big_sphere, "sphere.obj")});
  ASSERT_TRUE(unit.report.holes.at(0).filled && big.report.holes.at(0).filled);
  ASSERT_EQ(unit.mesh.vertex_count(), big.mesh.vertex_count());
  double worst = 0;
  for (int v = sheet.vertex_count(); v < unit.mesh.vertex_count(); ++v)
    for (int k = 0; k < 3; ++k)
      worst =
          std::max(worst, std::abs(big.mesh.positions[v][k] / 1000 - unit.mesh.positions[v][k]));
  // The contacts make the minimisation follow the rounding more closely
  // than without obstacles (Inpaint.ScalingTheInputScalesTheOutput: 1e-5 h).
  EXPECT_LT(worst, 1e-4 * unit.report.holes[0].length_scale);
  EXPECT_EQ(unit.report.holes[0].iterations, big.report.holes[0].iterations);
  EXPECT_EQ(unit.report.holes[0].crossings.patch_obstacles,
            big.report.holes[0].crossings.patch_obstacles);
  std::printf("largest difference %.3g h\n", worst / unit.report.holes[0].length_scale);
}

}  // namespace
}  // namespace foldfill
