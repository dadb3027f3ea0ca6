// Obstacles: parsing of both formats, malformed input, signed distances,
// outward normals, the cheap distance test, projection to the surface, and
// tessellation near a box.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>

#include "foldfill/error.h"
#include "foldfill/obstacles.h"
#include "support/reference_cases.h"
#include "test_support.h"

namespace foldfill {
namespace {

void expect_near(const Vec3& a, const Vec3& b, double tolerance = 1e-12) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tolerance) << "coordinate " << c;
}

// The message of the Usage error that parsing `text` throws.
std::string usage_error(const std::string& text) {
  try {
    parse_obstacles(text, "scene.txt");
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Usage) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error for: " << text;
  return "";
}

TEST(ParseObstacles, JsonSphereCylinderPlane) {
  const auto obstacles = parse_obstacles(R"({"obstacles": [
      {"type": "sphere", "center": [1, 2, 3], "radius": 0.5},
      {"type": "cylinder", "center": [0, 1, 0], "radius": 2, "height": 6, "axis": [0, 0, 3]},
      {"type": "plane", "point": [0, 0, -1], "normal": [0, 2, 0]}]})",
                                         "scene.json");
  ASSERT_EQ(obstacles.size(), 3u);
  EXPECT_EQ(obstacles[0].type, Obstacle::Type::Sphere);
  expect_near(obstacles[0].center, {1, 2, 3});
  EXPECT_EQ(obstacles[0].radius, 0.5);
  EXPECT_EQ(obstacles[1].type, Obstacle::Type::Cylinder);
  EXPECT_EQ(obstacles[1].radius, 2);
  EXPECT_EQ(obstacles[1].height, 6);
  expect_near(obstacles[1].axis, {0, 0, 1});  // normalised
  EXPECT_EQ(obstacles[2].type, Obstacle::Type::Plane);
  expect_near(obstacles[2].center, {0, 0, -1});
  expect_near(obstacles[2].normal, {0, 1, 0});
}

TEST(ParseObstacles, BareJsonArray) {
  const auto obstacles =
      parse_obstacles(R"(  [{"type": "sphere", "center": [0, 0, 0], "radius": 1}])", "a.json");
  ASSERT_EQ(obstacles.size(), 1u);
  EXPECT_EQ(obstacles[0].radius, 1);
}

// sim2's first cylinder in cases.json: euler_zxz [psi, phi, theta] = [0, -1.415462, 0], so
// axis = Rz(phi) (0, 1, 0) = (-sin phi, cos phi, 0) = (sin 1.415462, cos 1.415462, 0).
TEST(ParseObstacles, EulerZxzAxisOfSim2Cylinder) {
  const auto obstacles = parse_obstacles(
      R"({"obstacles": [{"type": "cylinder", "center": [-3.65421, 0.652517, 0.0], "radius": 1.0,
          "height": 6.0, "euler_zxz": [0.0, -1.415462, 0.0]}]})",
      "cases.json");
  ASSERT_EQ(obstacles.size(), 1u);
  expect_near(obstacles[0].axis, {0.98795986215420920, 0.15471040938552270, 0}, 1e-15);
  expect_near(obstacles[0].center, {-3.65421, 0.652517, 0});
}

// theta tilts the axis out of the xy plane, psi turns it about z: with phi = 0,
// Rx(theta) (0, 1, 0) = (0, cos theta, sin theta), then Rz(psi).
TEST(ParseObstacles, EulerZxzOrderOfRotations) {
  const double psi = 0.3, theta = 0.7;
  const auto obstacles = parse_obstacles(R"([{"type": "cylinder", "center": [0, 0, 0],
      "radius": 1, "height": 2, "euler_zxz": [0.3, 0, 0.7]}])",
                                         "s.json");
  const double y = std::cos(theta), z = std::sin(theta);
  expect_near(obstacles[0].axis, {-std::sin(psi) * y, std::cos(psi) * y, z}, 1e-15);
}

TEST(ParseObstacles, PrototypeTextFormat) {
  const auto obstacles = parse_obstacles(
      "# the scene of sim2\n"
      "\n"
      "sphere -0.660382 0.749638 0 1   # shoulder\n"
      "  cylinder 0.114316 3.64177 0 1 6 0 -0.261799 0\n",
      "scene.txt");
  ASSERT_EQ(obstacles.size(), 2u);
  EXPECT_EQ(obstacles[0].type, Obstacle::Type::Sphere);
  expect_near(obstacles[0].center, {-0.660382, 0.749638, 0});
  EXPECT_EQ(obstacles[0].radius, 1);
  EXPECT_EQ(obstacles[1].type, Obstacle::Type::Cylinder);
  EXPECT_EQ(obstacles[1].height, 6);
  expect_near(obstacles[1].axis, {std::sin(0.261799), std::cos(0.261799), 0}, 1e-15);
  EXPECT_TRUE(parse_obstacles("\n# nothing\n", "empty.txt").empty());
}

// The arm cylinder of sim2 ends at the shoulder sphere's centre: a check of the
// Euler convention on real data (the opposite sign of phi misses it by 1.5).
TEST(ParseObstacles, Sim2ObstaclesFromCasesJson) {
  FOLDFILL_REQUIRE_SHARED();
  const auto cases =
      foldfill::testing::read_reference_cases(foldfill::testing::shared_dir() / "data/reference");
  const auto sim2 = std::find_if(cases.begin(), cases.end(),
                                 [](const auto& c) { return c.file == "sim2_hole.obj"; });
  ASSERT_NE(sim2, cases.end());
  const auto obstacles = foldfill::testing::reference_obstacles(*sim2);
  ASSERT_EQ(obstacles.size(), 3u);
  const Obstacle& arm = obstacles[1];
  const Obstacle& shoulder = obstacles[2];
  ASSERT_EQ(shoulder.type, Obstacle::Type::Sphere);
  const double half = 0.5 * arm.height;
  const Vec3 end{arm.center[0] - half * arm.axis[0], arm.center[1] - half * arm.axis[1],
                 arm.center[2] - half * arm.axis[2]};
  expect_near(end, shoulder.center, 0.01);
}

TEST(ParseObstacles, MalformedInputThrowsUsageNamingTheSource) {
  const char* bad[] = {
      R"({"obstacles": [{"type": "sphere", "center": [0, 0, 0]}]})",
      R"({"obstacles": [{"type": "sphere", "center": [0, 0, 0], "radius": -1}]})",
      R"({"obstacles": [{"type": "sphere", "center": [0, 0], "radius": 1}]})",
      R"({"obstacles": [{"type": "sphere", "center": [0, "a", 0], "radius": 1}]})",
      R"({"obstacles": [{"type": "sphere", "center": [0, 0, 0], "raduis": 1}]})",
      R"({"obstacles": [{"type": "cube", "center": [0, 0, 0]}]})",
      R"({"obstacles": [{"center": [0, 0, 0], "radius": 1}]})",
      R"({"obstacles": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 0]}]})",
      R"({"obstacles": [{"type": "cylinder", "center": [0, 0, 0], "radius": 1, "height": 0,
          "axis": [0, 1, 0]}]})",
      R"({"obstacles": [{"type": "cylinder", "center": [0, 0, 0], "radius": 1, "height": 2}]})",
      R"({"obstacles": [{"type": "sphere", "center": [0, 0, 1e999], "radius": 1}]})",
      R"({"obstacles": [3]})",
      R"({"obstacles": {}})",
      R"({"spheres": []})",
      R"({"obstacles": [)",
      "sphere 0 0 0",
      "sphere 0 0 0 1 2",
      "cylinder 0 0 0 1 6 0 0",
      "sphere 0 0 zero 1",
      "sphere 0 0 nan 1",
      "sphere 0 0 inf 1",
      "sphere 0 0 0 -2",
      "cube 0 0 0 1",
  };
  for (const char* text : bad) {
    const std::string message = usage_error(text);
    EXPECT_EQ(message.rfind("scene.txt: ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_EQ(usage_error(R"({"obstacles": [{"type": "sphere", "center": [0, 0, 0], "radius": 1},
                                          {"type": "sphere", "center": [0, 0, 0]}]})"),
            "scene.txt: obstacle 2: missing \"radius\"");
  EXPECT_EQ(usage_error("sphere 0 0 0 1\n\nsphere 0 0 0\n"),
            "scene.txt: line 3: sphere needs 4 numbers (x y z r), got 3");
}

TEST(ReadObstacles, MissingFileIsCannotRead) {
  const auto path = foldfill::testing::scratch_dir("obstacles_missing") / "none.json";
  try {
    read_obstacles(path.string());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::CannotRead);
    EXPECT_NE(std::string(e.what()).find("none.json"), std::string::npos);
  }
}

TEST(ReadObstacles, ReadsAFile) {
  const auto path = foldfill::testing::scratch_dir("obstacles_read") / "scene.txt";
  std::ofstream(path) << "sphere 1 2 3 4\n";
  const auto obstacles = read_obstacles(path.string());
  ASSERT_EQ(obstacles.size(), 1u);
  EXPECT_EQ(obstacles[0].radius, 4);
}

Obstacle sphere(Vec3 center, double radius) {
  Obstacle o;
  o.center = center;
  o.radius = radius;
  return o;
}

Obstacle cylinder(Vec3 center, double radius, double height, Vec3 axis) {
  Obstacle o;
  o.type = Obstacle::Type::Cylinder;
  o.center = center;
  o.radius = radius;
  o.height = height;
  o.axis = axis;
  return o;
}

Obstacle plane(Vec3 point, Vec3 normal) {
  Obstacle o;
  o.type = Obstacle::Type::Plane;
  o.center = point;
  o.normal = normal;
  return o;
}

TEST(SignedDistance, KnownPoints) {
  const Obstacle s = sphere({1, 0, 0}, 2);
  EXPECT_DOUBLE_EQ(signed_distance(s, {1, 0, 0}), -2);
  EXPECT_DOUBLE_EQ(signed_distance(s, {1, 5, 0}), 3);
  EXPECT_DOUBLE_EQ(signed_distance(s, {1, 0, 2}), 0);

  // Axis along z, radius 1, from z = -2 to z = 2.
  const Obstacle c = cylinder({0, 0, 0}, 1, 4, {0, 0, 1});
  EXPECT_DOUBLE_EQ(signed_distance(c, {0, 0, 0}), -1);      // centre: side is nearest
  EXPECT_DOUBLE_EQ(signed_distance(c, {0, 0, 1.8}), -0.2);  // near the cap
  EXPECT_DOUBLE_EQ(signed_distance(c, {3, 0, 0}), 2);       // beside the side
  EXPECT_DOUBLE_EQ(signed_distance(c, {0.5, 0, 5}), 3);     // above the cap
  EXPECT_DOUBLE_EQ(signed_distance(c, {4, 0, 6}), 5);       // off the rim: hypot(3, 4)

  const Obstacle p = plane({0, 0, 1}, {0, 0, 1});
  EXPECT_DOUBLE_EQ(signed_distance(p, {5, 7, 3}), 2);
  EXPECT_DOUBLE_EQ(signed_distance(p, {5, 7, -1}), -2);
}

TEST(PushOutside, LandsOnTheNearestSurfacePoint) {
  const double s = 1 / std::sqrt(3.0);
  const std::vector<Obstacle> obstacles = {sphere({1, -2, 0.5}, 1.5),
                                           cylinder({0.3, 0.1, -0.2}, 1.2, 3, {s, s, s}),
                                           plane({0, 0, 1}, {0.6, 0, 0.8})};
  // {0.4, 0.2, -0.1} is on the tilted cylinder's axis, up to rounding.
  const std::vector<Vec3> inside = {
      {1.2, -2.3, 0.9}, {0.4, 0.2, -0.1}, {0.3, 0.1, 0.9}, {1.1, 0.0, 0.0}, {-1, -1, -1}};
  for (const Obstacle& o : obstacles) {
    int pushed = 0;
    for (Vec3 p : inside) {
      const double before = signed_distance(o, p);
      if (before >= 0) continue;
      ++pushed;
      const Vec3 start = p;
      EXPECT_TRUE(push_outside(o, p));
      EXPECT_LT(std::abs(signed_distance(o, p)), 1e-12);
      // Nearest surface point: moved by exactly the distance to the surface.
      const double moved = std::hypot(p[0] - start[0], p[1] - start[1], p[2] - start[2]);
      EXPECT_NEAR(moved, -before, 1e-12);
    }
    EXPECT_GT(pushed, 0);
  }
}

TEST(PushOutside, CylinderPicksTheNearerOfSideAndCap) {
  const Obstacle c = cylinder({0, 0, 0}, 1, 4, {0, 0, 1});
  Vec3 near_cap{0.2, 0, 1.9};
  EXPECT_TRUE(push_outside(c, near_cap));
  expect_near(near_cap, {0.2, 0, 2});
  Vec3 near_side{0.9, 0, -1};
  EXPECT_TRUE(push_outside(c, near_side));
  expect_near(near_side, {1, 0, -1});
  Vec3 on_axis{0, 0, 0.5};  // any side point is nearest; it must still land on the side
  EXPECT_TRUE(push_outside(c, on_axis));
  EXPECT_LT(std::abs(signed_distance(c, on_axis)), 1e-12);
  EXPECT_NEAR(on_axis[2], 0.5, 1e-15);
}

TEST(PushOutside, LeavesOutsidePointsAlone) {
  const std::vector<Obstacle> obstacles = {
      sphere({0, 0, 0}, 1), cylinder({0, 0, 0}, 1, 2, {1, 0, 0}), plane({0, 0, 0}, {0, 1, 0})};
  for (const Obstacle& o : obstacles) {
    Vec3 p{0.3, 2.5, -0.4};
    const Vec3 start = p;
    EXPECT_FALSE(push_outside(o, p));
    EXPECT_EQ(p, start);
  }
}

// The outward normal by central differences of the signed distance (the
// solver's former normal): (0, 0, 0) where the differences cancel.
Vec3 finite_difference_normal(const Obstacle& o, const Vec3& p) {
  const double h = 1e-6;
  Vec3 normal;
  for (int a = 0; a < 3; ++a) {
    Vec3 plus = p, minus = p;
    plus[a] += h;
    minus[a] -= h;
    normal[a] = signed_distance(o, plus) - signed_distance(o, minus);
  }
  const double length = std::hypot(normal[0], normal[1], normal[2]);
  if (length > 0)
    for (double& c : normal) c /= length;
  return normal;
}

TEST(OutwardNormal, MatchesFiniteDifferencesOfTheSignedDistance) {
  const double s = 1 / std::sqrt(3.0);
  // Axis along z, radius 1, from z = -2 to z = 2, and the same tilted and moved.
  const std::vector<Obstacle> cylinders = {cylinder({0, 0, 0}, 1, 4, {0, 0, 1}),
                                           cylinder({0.3, 0.1, -0.2}, 1, 4, {s, s, s})};
  // In the upright cylinder's frame: beside the side, beyond a cap, off the
  // rims, on the surface, inside near the side and near each cap.
  const std::vector<Vec3> local = {
      {3, 0.5, 0.2},   {0.3, -0.2, 5}, {0.2, 0.4, -3.5}, {4, 0, 6},        {-0.8, 1.1, -2.7},
      {0.6, 0.8, 0.4}, {0.3, 0.1, 2},  {0.7, 0.2, -0.5}, {0.1, 0.2, 1.95}, {-0.2, 0.1, -1.9}};
  for (const Obstacle& c : cylinders) {
    // A frame (u, v, axis) for the tilted cylinder; the identity for the upright one.
    const Vec3 u =
        c.axis[2] == 1 ? Vec3{1, 0, 0} : Vec3{1 / std::sqrt(2.0), -1 / std::sqrt(2.0), 0};
    const Vec3 v{c.axis[1] * u[2] - c.axis[2] * u[1], c.axis[2] * u[0] - c.axis[0] * u[2],
                 c.axis[0] * u[1] - c.axis[1] * u[0]};
    for (const Vec3& l : local) {
      Vec3 p;
      for (int k = 0; k < 3; ++k) p[k] = c.center[k] + l[0] * u[k] + l[1] * v[k] + l[2] * c.axis[k];
      expect_near(outward_normal(c, p), finite_difference_normal(c, p), 1e-6);
    }
  }
  const Obstacle ball = sphere({1, -2, 0.5}, 1.5);
  for (const Vec3& p : std::vector<Vec3>{{3, 1, 2}, {1.2, -2.3, 0.9}, {1, -0.5, 0.5}})
    expect_near(outward_normal(ball, p), finite_difference_normal(ball, p), 1e-6);
  const Obstacle wall = plane({0, 0, 1}, {0.6, 0, 0.8});
  for (const Vec3& p : std::vector<Vec3>{{5, 7, 3}, {5, 7, -1}})
    expect_near(outward_normal(wall, p), finite_difference_normal(wall, p), 1e-9);
}

TEST(OutwardNormal, ZeroWhereTheNearestSurfaceHasNoDirection) {
  const Vec3 zero{0, 0, 0};
  const Obstacle ball = sphere({1, -2, 0.5}, 1.5);
  expect_near(outward_normal(ball, {1, -2, 0.5}), zero, 0);
  // On the axis of a long cylinder, where the side is nearest.
  const Obstacle tall = cylinder({0, 0, 0}, 1, 4, {0, 0, 1});
  const Vec3 on_axis{0, 0, 0.5};
  expect_near(outward_normal(tall, on_axis), zero, 0);
  expect_near(finite_difference_normal(tall, on_axis), zero, 0);
  // On the mid-plane of a flat cylinder, where the caps are nearest.
  const Obstacle flat = cylinder({0, 0, 0}, 2, 1, {0, 0, 1});
  const Vec3 mid_plane{0.3, 0.4, 0};
  expect_near(outward_normal(flat, mid_plane), zero, 0);
  expect_near(finite_difference_normal(flat, mid_plane), zero, 0);
}

TEST(FartherThan, OnlyWhereTheSignedDistanceExceedsTheGap) {
  const double s = 1 / std::sqrt(2.0);
  const std::vector<Obstacle> obstacles = {sphere({1, 2, 3}, 0.8),
                                           cylinder({0.5, 0, -1}, 0.4, 2.5, {s, 0, s}),
                                           plane({0, 1, 0}, {0, s, -s})};
  for (const Obstacle& o : obstacles) {
    int farther = 0;
    // Points on a grid around the obstacle, inside and out.
    for (int i = -6; i <= 6; ++i)
      for (int j = -6; j <= 6; ++j)
        for (int k = -6; k <= 6; ++k) {
          const Vec3 p{o.center[0] + 0.3 * i, o.center[1] + 0.3 * j, o.center[2] + 0.3 * k};
          for (double gap : {0.0, 0.1, 0.5}) {
            if (!farther_than(o, p, gap)) continue;
            ++farther;
            EXPECT_GT(signed_distance(o, p), gap);
          }
        }
    EXPECT_GT(farther, 1000);  // of 6591
  }
  // Points well beside a cylinder's side or beyond its caps pass the test.
  const Obstacle c = cylinder({0, 0, 0}, 1, 4, {0, 0, 1});
  EXPECT_TRUE(farther_than(c, {1.2, 0, 1.9}, 0.1));
  EXPECT_TRUE(farther_than(c, {0, 0.9, -2.2}, 0.1));
  EXPECT_FALSE(farther_than(c, {1.05, 0, 0}, 0.1));
  EXPECT_FALSE(farther_than(c, {0.5, 0, 0}, 0));
}

TEST(Normalized, KeepsTheSignedDistanceConsistent) {
  const Vec3 origin{2, -1, 0.5};
  const double scale = 0.037;
  const double s = 1 / std::sqrt(2.0);
  const std::vector<Obstacle> obstacles = {sphere({1, 2, 3}, 0.8),
                                           cylinder({0.5, 0, -1}, 0.4, 2.5, {s, 0, s}),
                                           plane({0, 1, 0}, {0, s, -s})};
  const std::vector<Vec3> points = {{1, 2, 3.5}, {0.6, 0.1, -1}, {3, 3, 3}, {-1, 0.5, 2}};
  for (const Obstacle& o : obstacles) {
    const Obstacle n = normalized(o, origin, scale);
    for (const Vec3& p : points) {
      const Vec3 q{(p[0] - origin[0]) / scale, (p[1] - origin[1]) / scale,
                   (p[2] - origin[2]) / scale};
      EXPECT_NEAR(signed_distance(n, q) * scale, signed_distance(o, p), 1e-12);
    }
  }
  EXPECT_THROW(normalized(obstacles[0], origin, 0), Error);
}

// ---- tessellate_obstacle ----

Vec3 plus(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 minus(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 times(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot3(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross3(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double length3(const Vec3& a) { return std::sqrt(dot3(a, a)); }
Vec3 unit3(const Vec3& a) { return times(a, 1 / length3(a)); }

Box3 cube_around(const Vec3& center, double half) {
  return {minus(center, {half, half, half}), plus(center, {half, half, half})};
}
bool in_box(const Vec3& p, const Box3& box) {
  for (int c = 0; c < 3; ++c)
    if (p[c] < box.low[c] || p[c] > box.high[c]) return false;
  return true;
}

// The largest value of dot(direction, x) over the obstacle shrunk by `inset`
// (sphere or cylinder, convex): a face's plane with `direction` its normal
// leaves the shrunk solid on its inner side where this is no more than its
// offset.
double shrunk_support(const Obstacle& o, double inset, const Vec3& direction) {
  const double rho = o.radius - inset;
  if (o.type == Obstacle::Type::Sphere) return dot3(direction, o.center) + rho;
  const double along = dot3(direction, o.axis);
  const double across = length3(minus(direction, times(o.axis, along)));
  return dot3(direction, o.center) + (0.5 * o.height - inset) * std::abs(along) + rho * across;
}

// Where the ray from `origin` along the unit `direction` meets the triangle
// (with a little slack at its edges, for rays through shared edges), or -1.
double ray_hit(const Vec3& origin, const Vec3& direction, const std::array<Vec3, 3>& t) {
  const Vec3 e1 = minus(t[1], t[0]), e2 = minus(t[2], t[0]);
  const Vec3 p = cross3(direction, e2);
  const double det = dot3(e1, p);
  if (std::abs(det) < 1e-300) return -1;
  const Vec3 s = minus(origin, t[0]);
  const double u = dot3(s, p) / det;
  const Vec3 q = cross3(s, e1);
  const double v = dot3(direction, q) / det;
  const double slack = 1e-9;
  if (u < -slack || v < -slack || u + v > 1 + slack) return -1;
  return dot3(e2, q) / det;
}

std::array<Vec3, 3> face_corners(const Mesh& mesh, int f) {
  const Tri& t = mesh.faces[f];
  return {mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]};
}

// Whether the ray from `origin` along `direction` meets a face at a distance
// in [low, high].
bool ray_meets_mesh(const Mesh& mesh, const Vec3& origin, const Vec3& direction, double low,
                    double high) {
  for (int f = 0; f < mesh.face_count(); ++f) {
    const double t = ray_hit(origin, direction, face_corners(mesh, f));
    if (t >= low && t <= high) return true;
  }
  return false;
}

// Points of the obstacle's surface shrunk by `inset` inside `box`, each with
// the ray that is to meet the mesh there: from `origin` along `direction`,
// the point `distance` along it.
struct SurfaceSample {
  Vec3 point, origin, direction;
  double distance;
};
std::vector<SurfaceSample> shrunk_surface_samples(const Obstacle& o, double inset, const Box3& box,
                                                  int tries) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<SurfaceSample> samples;
  for (int k = 0; k < tries; ++k) {
    Vec3 q;
    for (int c = 0; c < 3; ++c) q[c] = box.low[c] + unit(random) * (box.high[c] - box.low[c]);
    SurfaceSample s;
    if (o.type == Obstacle::Type::Sphere) {
      s.origin = o.center;
      s.direction = unit3(minus(q, o.center));
      s.distance = o.radius - inset;
      s.point = plus(s.origin, times(s.direction, s.distance));
    } else if (o.type == Obstacle::Type::Plane) {
      s.point = minus(q, times(o.normal, dot3(minus(q, o.center), o.normal) + inset));
      s.distance = 1 + length3(minus(box.high, box.low));
      s.origin = plus(s.point, times(o.normal, s.distance));
      s.direction = times(o.normal, -1);
    } else {
      const double half = 0.5 * o.height - inset, rho = o.radius - inset;
      const Vec3 d = minus(q, o.center);
      const double t = dot3(d, o.axis);
      const Vec3 radial = minus(d, times(o.axis, t));
      if (k % 2 == 0) {  // onto the side
        if (std::abs(t) > half) continue;
        s.origin = plus(o.center, times(o.axis, t));
        s.direction = unit3(radial);
        s.distance = rho;
      } else {  // onto the nearer cap
        const double r = length3(radial);
        const Vec3 inside = r > rho ? times(radial, rho / r) : radial;
        s.origin = plus(o.center, inside);
        s.direction = times(o.axis, t < 0 ? -1 : 1);
        s.distance = half;
      }
      s.point = plus(s.origin, times(s.direction, s.distance));
    }
    if (in_box(s.point, box)) samples.push_back(s);
  }
  return samples;
}

// The checks every tessellation must pass; returns the mesh. `scale`: the
// size of the scene, for the rounding tolerance; `tries` points of the box
// are projected to the shrunk surface for the coverage, and at least
// `min_samples` of them must land inside the box.
Mesh check_tessellation(const Obstacle& o, const Box3& box, double edge, double inset, double scale,
                        int tries = 400, TessellationBounds* bounds_out = nullptr,
                        int min_samples = 10) {
  SCOPED_TRACE(::testing::Message() << "edge " << edge << ", inset " << inset);
  TessellationBounds bounds;
  const Mesh mesh = tessellate_obstacle(o, box, edge, inset, &bounds);
  if (bounds_out) *bounds_out = bounds;
  const double tolerance = 1e-12 * scale;
  EXPECT_GE(bounds.edge_length, edge);
  EXPECT_GE(bounds.gap, 0);
  EXPECT_LE(bounds.gap, 0.25 * bounds.edge_length);
  EXPECT_LE(mesh.face_count(), kMaxObstacleFaces);
  for (const Tri& t : mesh.faces)
    for (int v : t) EXPECT_TRUE(v >= 0 && v < mesh.vertex_count());
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(0, 1);
  const Box3 reach = {minus(box.low, {bounds.edge_length, bounds.edge_length, bounds.edge_length}),
                      plus(box.high, {bounds.edge_length, bounds.edge_length, bounds.edge_length})};
  double longest = 0;
  for (int f = 0; f < mesh.face_count(); ++f) {
    const auto corners = face_corners(mesh, f);
    // (a) The face lies between the shrunk surface and `gap` beyond it.
    for (int k = 0; k < 4; ++k) {
      double a = unit(random), b = unit(random);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const Vec3 p = k < 3 ? corners[k]
                           : plus(corners[0], plus(times(minus(corners[1], corners[0]), a),
                                                   times(minus(corners[2], corners[0]), b)));
      const double d = signed_distance(o, p);
      EXPECT_GE(d, -inset - tolerance) << "face " << f;
      EXPECT_LE(d, bounds.gap - inset + tolerance) << "face " << f;
    }
    // (b) The shrunk solid is on the inner side of the face's plane, (c) which
    // faces outwards.
    const Vec3 normal = unit3(cross3(minus(corners[1], corners[0]), minus(corners[2], corners[0])));
    const double offset = dot3(normal, corners[0]);
    if (o.type == Obstacle::Type::Plane) {
      EXPECT_NEAR(length3(minus(normal, o.normal)), 0, 1e-12);
      EXPECT_NEAR(offset, dot3(o.normal, o.center) - inset, tolerance);
    } else {
      EXPECT_LE(shrunk_support(o, inset, normal), offset + tolerance) << "face " << f;
      const Vec3 centroid = times(plus(plus(corners[0], corners[1]), corners[2]), 1.0 / 3);
      EXPECT_GT(dot3(normal, minus(centroid, o.center)), 0) << "face " << f;
    }
    // (d) Near the box.
    for (int c = 0; c < 3; ++c) {
      const double low = std::min({corners[0][c], corners[1][c], corners[2][c]});
      const double high = std::max({corners[0][c], corners[1][c], corners[2][c]});
      EXPECT_TRUE(high >= reach.low[c] && low <= reach.high[c]) << "face " << f;
    }
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, length3(minus(corners[(k + 1) % 3], corners[k])));
  }
  if (o.type != Obstacle::Type::Plane) {
    EXPECT_LE(longest, 2 * bounds.edge_length);
  }
  // (d) The shrunk surface inside the box is covered.
  const auto samples = shrunk_surface_samples(o, inset, box, tries);
  EXPECT_GE(static_cast<int>(samples.size()), min_samples);
  for (const SurfaceSample& s : samples) {
    EXPECT_TRUE(ray_meets_mesh(mesh, s.origin, s.direction, s.distance - tolerance,
                               s.distance + bounds.gap + tolerance))
        << "uncovered point " << s.point[0] << " " << s.point[1] << " " << s.point[2];
  }
  return mesh;
}

// Whether every edge has two faces, which run along it in opposite
// directions, and the surface is a sphere's (Euler characteristic 2).
void expect_closed(const Mesh& mesh) {
  std::map<std::array<int, 2>, int> directed;
  for (const Tri& t : mesh.faces)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  int edges = 0;
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << "edge " << edge[0] << " " << edge[1] << " repeated";
    EXPECT_EQ(directed.count({edge[1], edge[0]}), 1u)
        << "edge " << edge[0] << " " << edge[1] << " without its twin";
    ++edges;
  }
  EXPECT_EQ(mesh.vertex_count() - edges / 2 + mesh.face_count(), 2);
}

const Obstacle& tilted_cylinder() {
  static const Obstacle c = cylinder({0.3, 0.1, -0.2}, 1.2, 3, unit3({0.2, 0.9, -0.3}));
  return c;
}

// The cylinder's point at `t` along its axis, `r` from it at `angle`.
Vec3 on_cylinder(const Obstacle& c, double t, double r, double angle) {
  const Vec3 e1 = unit3(cross3(c.axis, {1, 0, 0})), e2 = cross3(c.axis, e1);
  return plus(plus(c.center, times(c.axis, t)),
              plus(times(e1, r * std::cos(angle)), times(e2, r * std::sin(angle))));
}

TEST(TessellateObstacle, SphereNearABoxContainsTheShrunkBall) {
  const Obstacle ball = sphere({0.3, -0.2, 0.5}, 1.5);
  // Across the surface where three faces of the cube meet, across the middle
  // of a cube face, and inside the ball but for a corner.
  const std::vector<Box3> boxes = {
      cube_around(plus(ball.center, times(unit3({1, 1, 1}), 1.5)), 0.4),
      cube_around(plus(ball.center, {0, 0, -1.5}), 0.3),
      cube_around(plus(ball.center, {1.1, 0.7, 0.3}), 0.2)};
  for (const Box3& box : boxes) {
    for (double inset : {0.0, 0.05}) {
      for (double edge : {0.04, 0.2, 1.0, 2.5, 8.0}) {
        const Mesh mesh = check_tessellation(ball, box, edge, inset, 3);
        EXPECT_GT(mesh.face_count(), 0);
      }
    }
  }
}

TEST(TessellateObstacle, SphereInABoxAroundItIsClosed) {
  const Obstacle ball = sphere({0.3, -0.2, 0.5}, 1.5);
  const Box3 all = cube_around(ball.center, 2);
  for (double edge : {0.1, 0.7, 3.0}) {
    TessellationBounds bounds;
    const Mesh mesh = check_tessellation(ball, all, edge, 0.1, 3, 200, &bounds);
    expect_closed(mesh);
    // Steps of about the edge length on the shrunk ball: 6 n^2 cells.
    const int n = static_cast<int>(std::ceil(M_PI / 2 * 1.4 / edge));
    if (edge < 1) {
      EXPECT_EQ(mesh.face_count(), 12 * n * n);
    }
  }
}

TEST(TessellateObstacle, SphereGapIsAQuarterOfTheEdgeAtMost) {
  // The gap bound, for edges from three hundredths to many times the radius: the
  // grid is made finer than the edge length where needed.
  const Obstacle ball = sphere({0, 0, 0}, 1);
  const Box3 all = cube_around(ball.center, 1.5);
  for (double edge : {0.03, 0.1, 0.5, 1.0, 1.5, 2.0, 3.0, 5.0, 100.0}) {
    TessellationBounds bounds;
    const Mesh mesh = tessellate_obstacle(ball, all, edge, 0, &bounds);
    EXPECT_EQ(bounds.edge_length, edge);
    EXPECT_LE(bounds.gap, 0.25 * edge) << edge;
    double farthest = 0;
    for (const Vec3& p : mesh.positions) farthest = std::max(farthest, length3(p));
    EXPECT_NEAR(farthest, 1 + bounds.gap, 1e-14);
  }
}

TEST(TessellateObstacle, CylinderNearABoxContainsTheShrunkCylinder) {
  const Obstacle& c = tilted_cylinder();
  // Across the rim, across the side, across a cap around its centre, and
  // inside near the side.
  const std::vector<Box3> boxes = {cube_around(on_cylinder(c, 1.5, 1.2, 0.7), 0.4),
                                   cube_around(on_cylinder(c, 0.3, 1.2, 2.5), 0.3),
                                   cube_around(on_cylinder(c, -1.5, 0.1, 1.0), 0.3),
                                   cube_around(on_cylinder(c, -0.6, 1.0, 4.0), 0.15)};
  for (const Box3& box : boxes) {
    for (double inset : {0.0, 0.05}) {
      for (double edge : {0.04, 0.2, 1.0, 3.0, 8.0}) {
        const Mesh mesh = check_tessellation(c, box, edge, inset, 4);
        EXPECT_GT(mesh.face_count(), 0);
      }
    }
  }
}

TEST(TessellateObstacle, CylinderInABoxAroundItIsClosed) {
  const Obstacle& c = tilted_cylinder();
  const Box3 all = cube_around(c.center, 2.5);
  for (double edge : {0.05, 0.3, 1.0, 4.0}) {
    TessellationBounds bounds;
    const Mesh mesh = check_tessellation(c, all, edge, 0.1, 4, 200, &bounds);
    expect_closed(mesh);
    // The faces of each cap tile its n-gon (no overlaps, no holes), and the
    // side's the prism's side: the areas add up.
    const double rho = 1.1, half = 1.4, vertex_radius = rho + bounds.gap;
    const int n = static_cast<int>(std::lround(M_PI / std::acos(rho / vertex_radius)));
    double cap_area = 0, side_area = 0;
    for (int f = 0; f < mesh.face_count(); ++f) {
      const auto t = face_corners(mesh, f);
      const Vec3 area = times(cross3(minus(t[1], t[0]), minus(t[2], t[0])), 0.5);
      const double along = dot3(area, c.axis);
      if (std::abs(along) > 0.5 * length3(area)) {
        cap_area += std::abs(along);
      } else {
        side_area += length3(area);
      }
    }
    const double polygon = 0.5 * n * vertex_radius * vertex_radius * std::sin(2 * M_PI / n);
    const double prism_side = n * 2 * vertex_radius * std::sin(M_PI / n) * 2 * half;
    EXPECT_NEAR(cap_area, 2 * polygon, 1e-12 * polygon);
    EXPECT_NEAR(side_area, prism_side, 1e-12 * prism_side);
  }
}

TEST(TessellateObstacle, CylinderGapIsAQuarterOfTheEdgeAtMost) {
  const Obstacle c = cylinder({0, 0, 0}, 1, 2, {0, 0, 1});
  const Box3 all = cube_around(c.center, 2);
  for (double edge : {0.02, 0.1, 1.0, 2.0, 3.0, 5.0, 100.0}) {
    TessellationBounds bounds;
    // The box's middle is on the axis.
    expect_closed(check_tessellation(c, all, edge, 0, 3, 100, &bounds));
    EXPECT_EQ(bounds.edge_length, edge);
    EXPECT_LE(bounds.gap, 0.25 * edge) << edge;
  }
}

// Random spheres and cylinders, boxes across their surfaces (at the rims
// too), edges from a thirtieth of the radius to ten times it.
// FOLDFILL_TESSELLATION_SCENES sets how many (40), for longer runs by hand.
TEST(TessellateObstacle, RandomScenes) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0, 1);
  const auto between = [&](double low, double high) { return low + (high - low) * unit(random); };
  const auto direction = [&]() {
    for (;;) {
      const Vec3 v{between(-1, 1), between(-1, 1), between(-1, 1)};
      if (length3(v) > 0.1 && length3(v) < 1) return unit3(v);
    }
  };
  const int scenes = std::getenv("FOLDFILL_TESSELLATION_SCENES")
                         ? std::atoi(std::getenv("FOLDFILL_TESSELLATION_SCENES"))
                         : 40;
  for (int scene = 0; scene < scenes; ++scene) {
    SCOPED_TRACE(::testing::Message() << "scene " << scene);
    const Vec3 center{between(-1, 1), between(-1, 1), between(-1, 1)};
    const double r = between(0.2, 2);
    Obstacle o;
    Vec3 on_surface;
    if (scene % 2 == 0) {
      o = sphere(center, r);
      on_surface = plus(center, times(direction(), r));
    } else {
      o = cylinder(center, r, r * between(0.3, 4), direction());
      const double angle = between(0, 2 * M_PI), half = 0.5 * o.height;
      const int where = scene / 2 % 3;  // side, cap, rim
      on_surface = where == 0   ? on_cylinder(o, between(-half, half), r, angle)
                   : where == 1 ? on_cylinder(o, half, between(0, r), angle)
                                : on_cylinder(o, -half, r, angle);
    }
    Box3 box;
    for (int c = 0; c < 3; ++c) {
      const double middle = on_surface[c] + r * between(-0.2, 0.2);
      const double extent = r * between(0.05, 0.6);
      box.low[c] = middle - extent;
      box.high[c] = middle + extent;
    }
    const double edge = r * std::pow(10, between(-1.5, 1));
    const double inset = scene % 3 == 0 ? 0 : r * between(0, 0.15);
    check_tessellation(o, box, edge, inset, 4 + r, 100, nullptr, 0);
  }
}

TEST(TessellateObstacle, PlaneIsARectangleOnTheMovedPlane) {
  const Obstacle wall = plane({0, 0, 1}, unit3({0.6, 0, 0.8}));
  const Box3 box = {{-0.5, 0.2, 0.6}, {0.4, 0.9, 1.3}};
  for (double inset : {0.0, 0.05}) {
    const Mesh mesh = check_tessellation(wall, box, 0.1, inset, 3);
    EXPECT_EQ(mesh.face_count(), 2);
    // The rectangle covers the box's projection grown by the edge length.
    for (const Vec3& corner : {box.low, box.high, Vec3{box.low[0], box.high[1], box.low[2]}}) {
      const Vec3 grown_corner = plus(corner, {0.1, -0.1, 0.1});
      const Vec3 projected = minus(
          grown_corner, times(wall.normal, dot3(minus(grown_corner, wall.center), wall.normal)));
      EXPECT_TRUE(ray_meets_mesh(mesh, plus(projected, wall.normal), times(wall.normal, -1),
                                 1 - 1e-12, 1 + inset + 1e-12));
    }
  }
}

TEST(TessellateObstacle, NothingFarFromTheBoxOrLeftOnceShrunk) {
  const Box3 far = cube_around({10, 10, 10}, 0.5);
  EXPECT_EQ(tessellate_obstacle(sphere({0, 0, 0}, 1), far, 0.1, 0).face_count(), 0);
  EXPECT_EQ(tessellate_obstacle(tilted_cylinder(), far, 0.1, 0).face_count(), 0);
  EXPECT_EQ(tessellate_obstacle(plane({0, 0, 0}, {0, 0, 1}), far, 0.1, 0).face_count(), 0);
  // Deep inside, away from the surface.
  EXPECT_EQ(
      tessellate_obstacle(sphere({0, 0, 0}, 1), cube_around({0, 0, 0}, 0.2), 0.1, 0).face_count(),
      0);
  const Box3 near = cube_around({0, 0, 0}, 2);
  EXPECT_EQ(tessellate_obstacle(sphere({0, 0, 0}, 1), near, 0.1, 1).face_count(), 0);
  EXPECT_EQ(tessellate_obstacle(cylinder({0, 0, 0}, 1, 1, {0, 0, 1}), near, 0.1, 0.5).face_count(),
            0);
}

TEST(TessellateObstacle, ScalesWithTheScene) {
  const std::vector<Obstacle> obstacles = {sphere({0.3, -0.2, 0.5}, 1.5), tilted_cylinder(),
                                           plane({0, 0, 1}, unit3({0.6, 0, 0.8}))};
  const Box3 box = {{0.1, 0.2, 0.45}, {1.4, 1.3, 1.9}};
  for (const Obstacle& o : obstacles) {
    const double s = 1000;
    Obstacle big = o;
    big.center = times(o.center, s);
    big.radius = o.radius * s;
    big.height = o.height * s;
    const Box3 big_box = {times(box.low, s), times(box.high, s)};
    TessellationBounds bounds, big_bounds;
    const Mesh mesh = tessellate_obstacle(o, box, 0.15, 0.02, &bounds);
    const Mesh big_mesh = tessellate_obstacle(big, big_box, 0.15 * s, 0.02 * s, &big_bounds);
    EXPECT_GT(mesh.face_count(), 0);
    ASSERT_EQ(big_mesh.face_count(), mesh.face_count());
    ASSERT_EQ(big_mesh.vertex_count(), mesh.vertex_count());
    EXPECT_EQ(big_mesh.faces, mesh.faces);
    for (int v = 0; v < mesh.vertex_count(); ++v)
      expect_near(big_mesh.positions[v], times(mesh.positions[v], s), 1e-9 * s);
    EXPECT_NEAR(big_bounds.gap, bounds.gap * s, 1e-12 * s);
    EXPECT_NEAR(big_bounds.edge_length, bounds.edge_length * s, 1e-12 * s);
  }
}

TEST(TessellateObstacle, FaceCountIsCapped) {
  // Edges a thousandth of the radius over a box around the whole obstacle
  // would be millions of faces: they are made larger until they fit.
  const std::vector<Obstacle> obstacles = {sphere({0.3, -0.2, 0.5}, 1.5), tilted_cylinder()};
  for (const Obstacle& o : obstacles) {
    const Box3 all = cube_around(o.center, 2.5);
    TessellationBounds bounds;
    const Mesh mesh = check_tessellation(o, all, 0.0015, 0.01, 4, 40, &bounds);
    EXPECT_LE(mesh.face_count(), kMaxObstacleFaces);
    EXPECT_GT(mesh.face_count(), kMaxObstacleFaces / 4);
    EXPECT_GT(bounds.edge_length, 0.0015);
    expect_closed(mesh);
  }
  // A small box needs no coarser faces.
  TessellationBounds bounds;
  const Obstacle ball = sphere({0, 0, 0}, 1);
  const Mesh mesh = tessellate_obstacle(ball, cube_around({0, 0, 1}, 0.01), 0.001, 0, &bounds);
  EXPECT_EQ(bounds.edge_length, 0.001);
  EXPECT_LT(mesh.face_count(), 2000);
}

TEST(TessellateObstacle, RejectsBadArguments) {
  const Box3 box = cube_around({0, 0, 0}, 1);
  const Obstacle ball = sphere({0, 0, 0}, 1);
  EXPECT_THROW(tessellate_obstacle(ball, box, 0, 0), Error);
  EXPECT_THROW(tessellate_obstacle(ball, box, NAN, 0), Error);
  EXPECT_THROW(tessellate_obstacle(ball, box, 0.1, -1), Error);
  EXPECT_THROW(tessellate_obstacle(ball, {{0, 0, 0}, {-1, 1, 1}}, 0.1, 0), Error);
  EXPECT_THROW(tessellate_obstacle(ball, {{0, 0, 0}, {INFINITY, 1, 1}}, 0.1, 0), Error);
  Mesh triangle;
  triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  triangle.faces = {{0, 1, 2}};
  EXPECT_THROW(tessellate_obstacle(mesh_obstacle(triangle, "triangle"), box, 0.1, 0), Error);
}

}  // namespace
}  // namespace foldfill
