// Obstacles: parsing of both formats, malformed input, signed distances,
// outward normals, the cheap distance test and projection to the surface.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "foldfill/error.h"
#include "foldfill/obstacles.h"
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
  std::ifstream in(foldfill::testing::shared_dir() / "data/reference/cases.json");
  const auto cases = nlohmann::json::parse(in).at("cases");
  nlohmann::json sim2;
  for (const auto& c : cases) {
    if (c.at("file") == "sim2_hole.obj") sim2 = c;
  }
  ASSERT_FALSE(sim2.is_null());
  const auto obstacles =
      parse_obstacles(nlohmann::json{{"obstacles", sim2.at("obstacles")}}.dump(), "cases.json");
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

}  // namespace
}  // namespace foldfill
