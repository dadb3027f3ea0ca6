// Collision geometry: point-triangle and edge-edge distances against known
// answers, brute-force sampling and finite differences; the IPC barrier;
// Additive CCD on known crossings and a property test on random steps
// (checked by a Lipschitz bound on sampled distances and by CGAL's exact
// orientation); the box tree and the collision broad phase against brute
// force; the step bound and the barrier potential over a mesh; a triangle
// against analytic obstacles (segment-triangle distance, the obstacle
// distance and its CCD) against sampling, finite differences and a property
// test on random steps.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include "foldfill/box_tree.h"
#include "foldfill/collision.h"
#include "foldfill/error.h"
#include "foldfill/obstacles.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Gradient = std::array<Vec3, 4>;

Vec3 unit(const Vec3& a) { return scaled(a, 1 / norm(a)); }
// a + t (b - a)
Vec3 lerp(const Vec3& a, const Vec3& b, double t) { return add(a, scaled(sub(b, a), t)); }

struct Random {
  std::mt19937 engine;
  explicit Random(unsigned seed) : engine(seed) {}
  double uniform(double low, double high) {
    return std::uniform_real_distribution<double>(low, high)(engine);
  }
  Vec3 point(double low = -1, double high = 1) {
    return {uniform(low, high), uniform(low, high), uniform(low, high)};
  }
  Vec3 direction() {
    while (true) {
      const Vec3 p = point();
      const double n = norm(p);
      if (n > 0.1 && n <= 1) return scaled(p, 1 / n);
    }
  }
  int index(int count) { return std::uniform_int_distribution<int>(0, count - 1)(engine); }
};

// A triangle that is not too thin: every angle above ~10 degrees.
std::array<Vec3, 3> proper_triangle(Random& random) {
  while (true) {
    const std::array<Vec3, 3> t = {random.point(), random.point(), random.point()};
    bool ok = true;
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = unit(sub(t[(k + 1) % 3], t[k])), v = unit(sub(t[(k + 2) % 3], t[k]));
      ok &= norm(cross(u, v)) > 0.17 && norm(sub(t[(k + 1) % 3], t[k])) > 0.3;
    }
    if (ok) return t;
  }
}

// Exact reference: distance from p to the segment [a, b].
double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = sub(b, a);
  const double l = dot(ab, ab);
  const double t = l > 0 ? std::clamp(dot(sub(p, a), ab) / l, 0.0, 1.0) : 0.0;
  return norm(sub(p, lerp(a, b, t)));
}

// Brute force: the least distance from p to points of a fine barycentric
// grid of the triangle, an upper bound within one grid step of the truth.
double sampled_point_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int n) {
  double best = HUGE_VAL;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const Vec3 q =
          add(a, add(scaled(sub(b, a), double(i) / n), scaled(sub(c, a), double(j) / n)));
      best = std::min(best, norm(sub(p, q)));
    }
  return best;
}

// Brute force: the least over a grid of s of the exact distance from
// a(s) to the segment b, within one grid step of a of the truth.
double sampled_edge_edge(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, int n) {
  double best = HUGE_VAL;
  for (int i = 0; i <= n; ++i)
    best = std::min(best, segment_distance(lerp(a0, a1, double(i) / n), b0, b1));
  return best;
}

using Distance = std::function<double(const std::array<Vec3, 4>&, Gradient*)>;
double pt_distance(const std::array<Vec3, 4>& x, Gradient* g) {
  return point_triangle_distance_squared(x[0], x[1], x[2], x[3], g);
}
double ee_distance(const std::array<Vec3, 4>& x, Gradient* g) {
  return edge_edge_distance_squared(x[0], x[1], x[2], x[3], g);
}

// The gradient of `distance` at `x` against central differences of step
// h (relative to the configuration's size), to `tolerance` relative.
void expect_gradient(const Distance& distance, const std::array<Vec3, 4>& x, double scale) {
  Gradient g;
  distance(x, &g);
  const double h = 1e-6 * scale;
  double largest = 0;
  for (const Vec3& v : g) largest = std::max(largest, norm(v));
  for (int k = 0; k < 4; ++k) {
    for (int c = 0; c < 3; ++c) {
      std::array<Vec3, 4> plus = x, minus = x;
      plus[k][c] += h;
      minus[k][c] -= h;
      const double fd = (distance(plus, nullptr) - distance(minus, nullptr)) / (2 * h);
      EXPECT_NEAR(g[k][c], fd, 1e-6 * std::max(largest, scale)) << "vertex " << k << " axis " << c;
    }
  }
}

// ---------------------------------------------------------------------------
// Point-triangle distance

TEST(PointTriangleDistance, KnownRegions) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  EXPECT_DOUBLE_EQ(point_triangle_distance_squared({0.2, 0.3, 0.5}, a, b, c), 0.25);   // face
  EXPECT_DOUBLE_EQ(point_triangle_distance_squared({0.2, 0.3, -0.5}, a, b, c), 0.25);  // back
  EXPECT_DOUBLE_EQ(point_triangle_distance_squared({0.5, -1, 0.5}, a, b, c), 1.25);    // ab
  EXPECT_DOUBLE_EQ(point_triangle_distance_squared({-2, 0.5, 0}, a, b, c), 4);         // ca
  EXPECT_DOUBLE_EQ(point_triangle_distance_squared({1, 1, 0}, a, b, c), 0.5);          // bc
  EXPECT_DOUBLE_EQ(point_triangle_distance_squared({-1, -1, 1}, a, b, c), 3);          // a
  EXPECT_DOUBLE_EQ(point_triangle_distance_squared({2, -1, 0}, a, b, c), 2);           // b
  EXPECT_DOUBLE_EQ(point_triangle_distance_squared({-1, 3, 0}, a, b, c), 5);           // c
  EXPECT_EQ(point_triangle_distance_squared({0.25, 0.25, 0}, a, b, c), 0);             // on it
  EXPECT_EQ(point_triangle_distance_squared(b, a, b, c), 0);                           // corner
}

// Random triangles and points placed at a known distance from a chosen
// feature (the face, an edge, a corner) inside that feature's normal cone.
// Returns p; `region` 0 face, 1-3 edge k-1 (from corner k-1), 4-6 corner.
Vec3 point_near_feature(Random& random, const std::array<Vec3, 3>& t, int region, double distance,
                        double margin) {
  const Vec3 n = unit(cross(sub(t[1], t[0]), sub(t[2], t[0])));
  if (region == 0) {
    double u, v;
    do {
      u = random.uniform(margin, 1);
      v = random.uniform(margin, 1);
    } while (1 - u - v < margin);
    const Vec3 q = add(t[0], add(scaled(sub(t[1], t[0]), u), scaled(sub(t[2], t[0]), v)));
    return add(q, scaled(n, random.uniform(0, 1) < 0.5 ? distance : -distance));
  }
  if (region <= 3) {
    const int k = region - 1;
    const Vec3 &e0 = t[k], &e1 = t[(k + 1) % 3], &other = t[(k + 2) % 3];
    const Vec3 along = unit(sub(e1, e0));
    Vec3 out = sub(e0, other);  // in-plane, away from the third corner
    out = unit(sub(out, scaled(along, dot(out, along))));
    const double angle = random.uniform(-M_PI / 2 + margin, M_PI / 2 - margin);
    const Vec3 q = lerp(e0, e1, random.uniform(margin, 1 - margin));
    return add(q, scaled(add(scaled(out, std::cos(angle)), scaled(n, std::sin(angle))), distance));
  }
  const int k = region - 4;
  const Vec3 &q = t[k], u = unit(sub(t[(k + 1) % 3], q)), v = unit(sub(t[(k + 2) % 3], q));
  while (true) {
    const Vec3 d = random.direction();
    if (dot(d, u) < -margin && dot(d, v) < -margin) return add(q, scaled(d, distance));
  }
}

TEST(PointTriangleDistance, KnownAnswersInEveryRegion) {
  Random random(1);
  for (int trial = 0; trial < 2000; ++trial) {
    const auto t = proper_triangle(random);
    const int region = trial % 7;
    const double distance = random.uniform(1e-3, 2);
    const Vec3 p = point_near_feature(random, t, region, distance, 0.05);
    const double d2 = point_triangle_distance_squared(p, t[0], t[1], t[2]);
    EXPECT_NEAR(std::sqrt(d2), distance, 1e-12) << "region " << region;
  }
}

TEST(PointTriangleDistance, AgainstSampling) {
  Random random(2);
  const int n = 300;
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 a = random.point(), b = random.point(), c = random.point(), p = random.point(-2, 2);
    const double exact = std::sqrt(point_triangle_distance_squared(p, a, b, c));
    const double sampled = sampled_point_triangle(p, a, b, c, n);
    const double step = std::max({norm(sub(b, a)), norm(sub(c, a)), norm(sub(c, b))}) / n;
    EXPECT_LE(exact, sampled + 1e-12);
    EXPECT_LE(sampled - exact, step);
  }
}

TEST(PointTriangleDistance, GradientMatchesFiniteDifferences) {
  Random random(3);
  for (int trial = 0; trial < 700; ++trial) {
    const auto t = proper_triangle(random);
    const Vec3 p = point_near_feature(random, t, trial % 7, random.uniform(0.05, 1), 0.1);
    expect_gradient(pt_distance, {p, t[0], t[1], t[2]}, 1);
  }
}

TEST(PointTriangleDistance, DegenerateTriangles) {
  Random random(4);
  for (int trial = 0; trial < 500; ++trial) {
    const Vec3 a = random.point(), b = random.point(), p = random.point(-2, 2);
    // Collinear: the hull is the segment [a, b].
    const Vec3 c = lerp(a, b, random.uniform(-0.5, 1.5));
    // The segment spanned by the three collinear points.
    const double tc = dot(sub(c, a), sub(b, a)) / dot(sub(b, a), sub(b, a));
    const Vec3 s0 = tc < 0 ? c : a, s1 = tc > 1 ? c : b;
    const double expected = segment_distance(p, s0, s1);
    for (const auto& order : {std::array<Vec3, 3>{a, b, c}, {c, a, b}, {b, c, a}, {a, c, b}}) {
      EXPECT_NEAR(std::sqrt(point_triangle_distance_squared(p, order[0], order[1], order[2])),
                  expected, 1e-12);
    }
    // Two corners in one place: a segment; all three: a point.
    EXPECT_NEAR(std::sqrt(point_triangle_distance_squared(p, a, a, b)), segment_distance(p, a, b),
                1e-12);
    EXPECT_NEAR(std::sqrt(point_triangle_distance_squared(p, a, b, b)), segment_distance(p, a, b),
                1e-12);
    EXPECT_NEAR(std::sqrt(point_triangle_distance_squared(p, a, a, a)), norm(sub(p, a)), 1e-12);
    // Nearly collinear (height 1e-9): nearly the segment's distance.
    const Vec3 lifted = add(c, scaled(random.direction(), 1e-9));
    EXPECT_NEAR(std::sqrt(point_triangle_distance_squared(p, a, b, lifted)), expected, 2e-9);
    // The gradient of a degenerate triangle's distance sums to zero
    // (translation) and matches the segment's.
    Gradient g;
    point_triangle_distance_squared(p, a, a, a, &g);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(g[0][k] + g[1][k] + g[2][k] + g[3][k], 0, 1e-12);
  }
}

TEST(PointTriangleDistance, ScaleInvariance) {
  Random random(5);
  for (int trial = 0; trial < 1000; ++trial) {
    const Vec3 p = random.point(-2, 2), a = random.point(), b = random.point(), c = random.point();
    Gradient g, g1000;
    const double d2 = point_triangle_distance_squared(p, a, b, c, &g);
    const double d2_1000 = point_triangle_distance_squared(
        scaled(p, 1000), scaled(a, 1000), scaled(b, 1000), scaled(c, 1000), &g1000);
    EXPECT_NEAR(d2_1000, 1e6 * d2, 1e-9 * 1e6 * std::max(d2, 1e-6));
    for (int k = 0; k < 4; ++k)
      for (int x = 0; x < 3; ++x) EXPECT_NEAR(g1000[k][x], 1000 * g[k][x], 1e-6 * 1000);
  }
}

// ---------------------------------------------------------------------------
// Edge-edge distance

// Segments whose closest points are known: interior points q_a and q_b =
// q_a + distance * n with n normal to both; `kind` 0 both interior, 1 a's end
// a0 against b's interior, 2 end a0 against end b0.
std::array<Vec3, 4> segments_at_distance(Random& random, int kind, double distance, double margin) {
  while (true) {
    const Vec3 qa = random.point();
    const Vec3 n = random.direction();
    const Vec3 qb = add(qa, scaled(n, distance));
    // Directions perpendicular to n.
    const auto perpendicular = [&] {
      const Vec3 d = random.direction();
      return unit(sub(d, scaled(n, dot(d, n))));
    };
    const Vec3 u = perpendicular(), v = perpendicular();
    if (norm(cross(u, v)) < 0.2) continue;
    const double la = random.uniform(0.3, 2), lb = random.uniform(0.3, 2);
    if (kind == 0) {
      const double s = random.uniform(margin, 1 - margin), t = random.uniform(margin, 1 - margin);
      return {sub(qa, scaled(u, s * la)), add(qa, scaled(u, (1 - s) * la)),
              sub(qb, scaled(v, t * lb)), add(qb, scaled(v, (1 - t) * lb))};
    }
    // a0 = qa; a's direction leaves b (any direction w with w . (qa - qb) > 0).
    Vec3 w = random.direction();
    if (dot(w, scaled(n, -1)) < margin) continue;
    if (kind == 1) {
      const double t = random.uniform(margin, 1 - margin);
      return {qa, add(qa, scaled(w, la)), sub(qb, scaled(v, t * lb)),
              add(qb, scaled(v, (1 - t) * lb))};
    }
    Vec3 z = random.direction();
    if (dot(z, n) < margin) continue;  // b leaves a from b0 = qb
    return {qa, add(qa, scaled(w, la)), qb, add(qb, scaled(z, lb))};
  }
}

TEST(EdgeEdgeDistance, KnownAnswers) {
  Random random(6);
  for (int trial = 0; trial < 3000; ++trial) {
    const double distance = random.uniform(1e-3, 2);
    const auto x = segments_at_distance(random, trial % 3, distance, 0.05);
    // Every order of the ends and of the two segments.
    EXPECT_NEAR(std::sqrt(edge_edge_distance_squared(x[0], x[1], x[2], x[3])), distance, 1e-12);
    EXPECT_NEAR(std::sqrt(edge_edge_distance_squared(x[1], x[0], x[3], x[2])), distance, 1e-12);
    EXPECT_NEAR(std::sqrt(edge_edge_distance_squared(x[2], x[3], x[0], x[1])), distance, 1e-12);
  }
  EXPECT_DOUBLE_EQ(edge_edge_distance_squared({-1, 0, 0}, {1, 0, 0}, {0, -1, 2}, {0, 1, 2}), 4);
  EXPECT_EQ(edge_edge_distance_squared({-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}), 0);
}

TEST(EdgeEdgeDistance, AgainstSampling) {
  Random random(7);
  const int n = 20000;
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 a0 = random.point(), a1 = random.point(), b0 = random.point(), b1 = random.point();
    const double exact = std::sqrt(edge_edge_distance_squared(a0, a1, b0, b1));
    const double sampled = sampled_edge_edge(a0, a1, b0, b1, n);
    EXPECT_LE(exact, sampled + 1e-12);
    EXPECT_LE(sampled - exact, norm(sub(a1, a0)) / n);
  }
}

// Independent references: the least of every candidate (the interior
// solution when it is inside, every end against the other segment; the
// face projection when inside, every edge), on 10^5 random configurations
// of mixed scales and near-degenerate shapes.
TEST(EdgeEdgeDistance, MatchesEveryCandidateOnRandomInput) {
  Random random(19);
  for (int trial = 0; trial < 100000; ++trial) {
    Vec3 a0 = random.point(), a1 = random.point(), b0 = random.point(), b1 = random.point();
    if (trial % 4 == 1) a1 = add(a0, scaled(sub(a1, a0), 1e-3));  // short against long
    if (trial % 4 == 2) b1 = add(b0, add(scaled(sub(a1, a0), 0.7), scaled(random.point(), 1e-6)));
    const Vec3 u = sub(a1, a0), v = sub(b1, b0), w = sub(a0, b0);
    double expected = std::min({segment_distance(a0, b0, b1), segment_distance(a1, b0, b1),
                                segment_distance(b0, a0, a1), segment_distance(b1, a0, a1)});
    const Vec3 n = cross(u, v);
    if (dot(n, n) > 1e-10 * dot(u, u) * dot(v, v)) {
      const double s = dot(cross(v, w), n) / dot(n, n), t = dot(cross(u, w), n) / dot(n, n);
      if (s >= 0 && s <= 1 && t >= 0 && t <= 1)
        expected = std::min(expected, norm(sub(lerp(a0, a1, s), lerp(b0, b1, t))));
    }
    EXPECT_NEAR(std::sqrt(edge_edge_distance_squared(a0, a1, b0, b1)), expected, 1e-9)
        << "trial " << trial;
  }
}

TEST(PointTriangleDistance, MatchesEveryCandidateOnRandomInput) {
  Random random(20);
  for (int trial = 0; trial < 100000; ++trial) {
    Vec3 a = random.point(), b = random.point(), c = random.point();
    const Vec3 p = random.point(-2, 2);
    if (trial % 4 == 1) c = add(lerp(a, b, random.uniform(-1, 2)), scaled(random.point(), 1e-6));
    if (trial % 4 == 2) b = add(a, scaled(random.point(), 1e-3));
    double expected =
        std::min({segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
    const Vec3 n = cross(sub(b, a), sub(c, a));
    if (dot(n, n) > 1e-10 * dot(sub(b, a), sub(b, a)) * dot(sub(c, a), sub(c, a))) {
      const Vec3 q = sub(p, scaled(n, dot(n, sub(p, a)) / dot(n, n)));  // projection
      bool inside = true;
      const Vec3 corners[3] = {a, b, c};
      for (int k = 0; k < 3; ++k)
        inside &= dot(cross(sub(corners[(k + 1) % 3], corners[k]), sub(q, corners[k])), n) >= 0;
      if (inside) expected = std::min(expected, norm(sub(p, q)));
    }
    EXPECT_NEAR(std::sqrt(point_triangle_distance_squared(p, a, b, c)), expected, 1e-9)
        << "trial " << trial;
  }
}

TEST(EdgeEdgeDistance, GradientMatchesFiniteDifferences) {
  Random random(8);
  for (int trial = 0; trial < 600; ++trial) {
    const auto x = segments_at_distance(random, trial % 3, random.uniform(0.05, 1), 0.1);
    expect_gradient(ee_distance, x, 1);
  }
}

TEST(EdgeEdgeDistance, ParallelAndDegenerate) {
  Random random(9);
  for (int trial = 0; trial < 500; ++trial) {
    const Vec3 a0 = random.point(), d = random.direction(), offset = random.point();
    const Vec3 a1 = add(a0, scaled(d, random.uniform(0.1, 2)));
    const double s0 = random.uniform(-3, 3), s1 = random.uniform(-3, 3);
    const Vec3 b0 = add(add(a0, scaled(d, s0)), offset), b1 = add(add(a0, scaled(d, s1)), offset);
    // Parallel: the least of the four end-to-segment distances.
    const double expected = std::min({segment_distance(a0, b0, b1), segment_distance(a1, b0, b1),
                                      segment_distance(b0, a0, a1), segment_distance(b1, a0, a1)});
    EXPECT_NEAR(std::sqrt(edge_edge_distance_squared(a0, a1, b0, b1)), expected, 1e-12);
    // Nearly parallel (1e-9 rad): nearly the same.
    const Vec3 tilted = add(b1, scaled(random.direction(), 1e-9 * norm(sub(b1, b0))));
    EXPECT_NEAR(std::sqrt(edge_edge_distance_squared(a0, a1, b0, tilted)), expected, 1e-8);
    // Collinear and overlapping: 0.
    EXPECT_NEAR(edge_edge_distance_squared(a0, a1, lerp(a0, a1, 0.5), lerp(a0, a1, 2)), 0, 1e-24);
    // Zero-length segments: a point against a segment, or two points.
    EXPECT_NEAR(std::sqrt(edge_edge_distance_squared(a0, a0, b0, b1)), segment_distance(a0, b0, b1),
                1e-12);
    EXPECT_NEAR(std::sqrt(edge_edge_distance_squared(a0, a1, b0, b0)), segment_distance(b0, a0, a1),
                1e-12);
    EXPECT_NEAR(std::sqrt(edge_edge_distance_squared(a0, a0, b0, b0)), norm(sub(a0, b0)), 1e-12);
    Gradient g;
    edge_edge_distance_squared(a0, a1, b0, b1, &g);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(g[0][k] + g[1][k] + g[2][k] + g[3][k], 0, 1e-12);
  }
}

TEST(EdgeEdgeDistance, ScaleInvariance) {
  Random random(10);
  for (int trial = 0; trial < 1000; ++trial) {
    const Vec3 a0 = random.point(), a1 = random.point(), b0 = random.point(), b1 = random.point();
    Gradient g, g1000;
    const double d2 = edge_edge_distance_squared(a0, a1, b0, b1, &g);
    const double d2_1000 = edge_edge_distance_squared(scaled(a0, 1000), scaled(a1, 1000),
                                                      scaled(b0, 1000), scaled(b1, 1000), &g1000);
    EXPECT_NEAR(d2_1000, 1e6 * d2, 1e-9 * 1e6 * std::max(d2, 1e-6));
    for (int k = 0; k < 4; ++k)
      for (int x = 0; x < 3; ++x) EXPECT_NEAR(g1000[k][x], 1000 * g[k][x], 1e-6 * 1000);
  }
}

// The cheap bounds never say "farther" of a pair nearer than the distance
// asked, on random pairs of every kind and at thresholds just around their
// distances; and they do rule out the pairs they are for, neighbouring
// primitives of a sheet a little apart.
TEST(FartherBounds, NeverRuleOutANearerPair) {
  Random random(11);
  int ruled_out = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Vec3 a = random.point(), b = random.point(), c = random.point(), d = random.point();
    const Vec3 p = random.point(-3, 3);
    const double pt = point_triangle_distance_squared(p, a, b, c);
    const double ee = edge_edge_distance_squared(a, b, c, d);
    for (const double f : {0.25, 0.81, 0.999999, 1.0, 1.000001, 1.21, 4.0}) {
      const bool pt_far = point_triangle_farther(p, a, b, c, f * pt);
      const bool ee_far = edge_edge_farther(a, b, c, d, f * ee);
      if (pt_far) {
        EXPECT_GT(pt, f * pt) << trial;
      }
      if (ee_far) {
        EXPECT_GT(ee, f * ee) << trial;
      }
      ruled_out += pt_far + ee_far;
    }
    // At or beyond the distance itself: never.
    EXPECT_FALSE(point_triangle_farther(p, a, b, c, pt));
    EXPECT_FALSE(edge_edge_farther(a, b, c, d, ee));
  }
  EXPECT_GT(ruled_out, 20000);  // well below the distance, most pairs are
}

TEST(FartherBounds, RuleOutNeighboursOfASheet) {
  // Two unit triangles sharing the edge (a, b) of a flat sheet, lifted a
  // little: the corners c and d are about 0.87 from the other triangle's
  // far edge, the edges (b, c) and (a, d) about as far apart.
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0.5, 0.866, 0.05}, d{0.5, -0.866, -0.05};
  const double reach = 0.55;
  EXPECT_TRUE(edge_edge_farther(b, c, a, d, reach * reach));
  const Vec3 e{1.5, 0.866, 0.02};  // the next corner along the strip
  EXPECT_TRUE(point_triangle_farther(e, a, b, d, reach * reach));
  // Not when nearer: the same corner just above the triangle.
  EXPECT_FALSE(point_triangle_farther({0.5, -0.3, 0.2}, a, b, d, reach * reach));
  // Non-finite input is never ruled out.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(edge_edge_farther({nan, 0, 0}, c, a, d, reach * reach));
  EXPECT_FALSE(point_triangle_farther({nan, 0, 0}, a, b, d, reach * reach));
}

// ---------------------------------------------------------------------------
// Barrier

TEST(Barrier, ValueAndDerivative) {
  for (const double dhat : {1e-3, 1.0, 250.0}) {
    for (const double f : {1e-6, 1e-3, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.999}) {
      const double d = f * dhat;
      double derivative;
      const double value = barrier(d, dhat, &derivative);
      EXPECT_NEAR(value, -(d - dhat) * (d - dhat) * std::log(d / dhat), 1e-13 * dhat * dhat);
      const double h = 1e-6 * d;
      const double fd = (barrier(d + h, dhat) - barrier(d - h, dhat)) / (2 * h);
      EXPECT_NEAR(derivative, fd, 1e-6 * std::max(std::abs(fd), dhat));
      // Squared-distance form: the same value, derivative by d2.
      double derivative_sq;
      EXPECT_DOUBLE_EQ(barrier_of_squared(d * d, dhat, &derivative_sq), value);
      const double d2 = d * d, h2 = 1e-6 * d2;
      const double fd_sq =
          (barrier_of_squared(d2 + h2, dhat) - barrier_of_squared(d2 - h2, dhat)) / (2 * h2);
      EXPECT_NEAR(derivative_sq, fd_sq, 1e-6 * std::abs(fd_sq));
      // Positive and decreasing.
      EXPECT_GT(value, 0);
      EXPECT_LT(derivative, 0);
      // b(lambda d, lambda dhat) = lambda^2 b(d, dhat).
      EXPECT_NEAR(barrier(7 * d, 7 * dhat), 49 * value, 1e-12 * 49 * value);
    }
  }
}

TEST(Barrier, SmoothAtDhatAndInfiniteAtContact) {
  const double dhat = 0.01;
  double derivative;
  EXPECT_EQ(barrier(dhat, dhat, &derivative), 0);
  EXPECT_EQ(derivative, 0);
  EXPECT_EQ(barrier(2 * dhat, dhat, &derivative), 0);
  EXPECT_EQ(derivative, 0);
  // Approaching dhat from below, value and derivative go to 0 (C1; in fact
  // b ~ (dhat - d)^3 / dhat, b' ~ -3 (dhat - d)^2 / dhat).
  for (const double e : {1e-2, 1e-4, 1e-6}) {
    const double d = dhat * (1 - e);
    const double value = barrier(d, dhat, &derivative);
    EXPECT_NEAR(value, std::pow(e * dhat, 3) / dhat, 0.02 * std::pow(e * dhat, 3) / dhat);
    EXPECT_NEAR(derivative, -3 * std::pow(e * dhat, 2) / dhat,
                0.02 * 3 * std::pow(e * dhat, 2) / dhat);
  }
  // Growing without bound as d -> 0, infinite at 0 and below.
  double previous = 0;
  for (double d = 0.5 * dhat; d > 1e-300; d *= 1e-10) {
    const double value = barrier(d, dhat, &derivative);
    EXPECT_GT(value, previous);
    EXPECT_TRUE(std::isfinite(value));
    previous = value;
  }
  EXPECT_GT(previous, 600 * dhat * dhat);  // -dhat^2 ln(1e-300 / dhat)
  EXPECT_EQ(barrier(0, dhat, &derivative), HUGE_VAL);
  EXPECT_EQ(derivative, -HUGE_VAL);
  EXPECT_EQ(barrier(-1, dhat), HUGE_VAL);
  EXPECT_EQ(barrier_of_squared(0, dhat), HUGE_VAL);
}

// ---------------------------------------------------------------------------
// Additive CCD

const Vec3 kZero{0, 0, 0};

TEST(AdditiveCcd, PointThroughTriangle) {
  const Vec3 a{-1, -1, 0}, b{2, -1, 0}, c{-1, 2, 0};
  // Falls from z = 1 by 2: crosses at t = 0.5.
  const double toi = point_static_triangle_ccd({0.1, 0.2, 1}, {0, 0, -2}, a, b, c);
  EXPECT_GT(toi, 0.4);
  EXPECT_LT(toi, 0.5);
  // The same relative motion shared between point and triangle.
  const Vec3 up{0, 0, 1};
  const double shared = point_triangle_ccd({0.1, 0.2, 1}, a, b, c, {0, 0, -1}, up, up, up);
  EXPECT_GT(shared, 0.4);
  EXPECT_LT(shared, 0.5);
  // Slanted through the face.
  const double slanted = point_static_triangle_ccd({0.5, 0.5, 1}, {-0.4, -0.2, -4}, a, b, c);
  EXPECT_GT(slanted, 0.2);
  EXPECT_LT(slanted, 0.25);
}

TEST(AdditiveCcd, EdgeEdgeCrossing) {
  // An edge along x at z = 1 falls through one along y at z = 0: t = 0.25.
  const double toi = edge_edge_ccd({-1, 0, 1}, {1, 0, 1}, {0, -1, 0}, {0, 1, 0}, {0, 0, -4},
                                   {0, 0, -4}, kZero, kZero);
  EXPECT_GT(toi, 0.2);
  EXPECT_LT(toi, 0.25);
  // Both moving towards each other, crossing at t = 0.5.
  const double both = edge_edge_ccd({-1, 0.3, 1}, {1, -0.2, 1}, {0.4, -1, -1}, {-0.3, 1, -1},
                                    {0, 0, -2}, {0, 0, -2}, {0, 0, 2}, {0, 0, 2});
  EXPECT_GT(both, 0.4);
  EXPECT_LT(both, 0.5);
}

TEST(AdditiveCcd, ParallelAndDegenerate) {
  // Parallel edges 1 apart closing at 2 per unit time: contact at 0.5.
  const double parallel = edge_edge_ccd({0, 0, 1}, {1, 0, 1}, {0.5, 0, 0}, {1.5, 0, 0}, {0, 0, -2},
                                        {0, 0, -2}, kZero, kZero);
  EXPECT_GT(parallel, 0.4);
  EXPECT_LT(parallel, 0.5);
  // Zero-length edges (two points), head on: contact at 0.5.
  const double points = edge_edge_ccd({0, 0, 1}, {0, 0, 1}, {0, 0, 0}, {0, 0, 0}, {0, 0, -1},
                                      {0, 0, -1}, {0, 0, 1}, {0, 0, 1});
  EXPECT_GT(points, 0.4);
  EXPECT_LT(points, 0.5);
  // A point falling onto a degenerate (collinear) triangle, i.e. a segment.
  const double sliver =
      point_static_triangle_ccd({0.5, 0, 1}, {0, 0, -2}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0});
  EXPECT_GT(sliver, 0.4);
  EXPECT_LT(sliver, 0.5);
  // Parallel edges sliding along each other at a constant distance: never meet.
  EXPECT_EQ(
      edge_edge_ccd({0, 0, 1}, {1, 0, 1}, {0, 0, 0}, {1, 0, 0}, {3, 0, 0}, {3, 0, 0}, kZero, kZero),
      1);
}

TEST(AdditiveCcd, NearMissesAndSeparation) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  // Falls past the triangle, 0.7 away from its corner b at the closest.
  EXPECT_EQ(point_static_triangle_ccd({1.5, 0.5, 1}, {0, 0, -2}, a, b, c), 1);
  // Moves away.
  EXPECT_EQ(point_static_triangle_ccd({0.2, 0.2, 1}, {0, 0, 3}, a, b, c), 1);
  // Edges passing each other 0.5 apart.
  EXPECT_EQ(edge_edge_ccd({-1, 0, 0.5}, {1, 0, 0.5}, {3, -1, 0}, {3, 1, 0}, {6, 0, 0}, {6, 0, 0},
                          kZero, kZero),
            1);
  // Zero relative motion: the same translation for all, or none.
  const Vec3 move{5, -3, 7};
  EXPECT_EQ(point_triangle_ccd({0.2, 0.2, 0.01}, a, b, c, move, move, move, move), 1);
  EXPECT_EQ(point_triangle_ccd({0.2, 0.2, 0.01}, a, b, c, kZero, kZero, kZero, kZero), 1);
  EXPECT_EQ(edge_edge_ccd({-1, 0, 0.5}, {1, 0, 0.5}, {0, -1, 0}, {0, 1, 0}, move, move, move, move),
            1);
  // Starting in contact: 0.
  EXPECT_EQ(point_static_triangle_ccd({0.2, 0.2, 0}, {0, 0, 1}, a, b, c), 0);
  // t_max bounds the answer.
  CcdOptions options;
  options.t_max = 0.3;
  EXPECT_EQ(point_static_triangle_ccd({0.2, 0.2, 1}, {0, 0, 3}, a, b, c, options), 0.3);
  EXPECT_EQ(point_static_triangle_ccd({0.2, 0.2, 1}, {0, 0, -2}, a, b, c, options), 0.3);
}

TEST(AdditiveCcd, ExactTouchAtTheEndOfTheStep) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  // Reaches the face exactly at t = 1.
  const double toi = point_static_triangle_ccd({0.25, 0.25, 1}, {0, 0, -1}, a, b, c);
  EXPECT_LT(toi, 1);
  EXPECT_GT(toi, 0.8);
  // Reaches the corner b exactly at t = 1, coming diagonally.
  const double corner = point_static_triangle_ccd({2, -1, 1}, {-1, 1, -1}, a, b, c);
  EXPECT_LT(corner, 1);
  EXPECT_GT(corner, 0.5);
  // Edges meeting exactly at t = 1.
  const double edges = edge_edge_ccd({-1, 0, 1}, {1, 0, 1}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1},
                                     {0, 0, -1}, kZero, kZero);
  EXPECT_LT(edges, 1);
  EXPECT_GT(edges, 0.8);
}

TEST(AdditiveCcd, ScaleInvariance) {
  Random random(11);
  for (int trial = 0; trial < 300; ++trial) {
    std::array<Vec3, 8> x;
    for (Vec3& v : x) v = random.point();
    for (int k = 4; k < 8; ++k) x[k] = scaled(x[k], 3);
    const double toi = point_triangle_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]);
    std::array<Vec3, 8> y;
    for (int k = 0; k < 8; ++k) y[k] = scaled(x[k], 1024);  // exact scaling
    EXPECT_EQ(point_triangle_ccd(y[0], y[1], y[2], y[3], y[4], y[5], y[6], y[7]), toi);
    EXPECT_EQ(edge_edge_ccd(y[0], y[1], y[2], y[3], y[4], y[5], y[6], y[7]),
              edge_edge_ccd(x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]));
  }
  // Scaled by 1000 (not exact): nearly the same times.
  const Vec3 a{-1, -1, 0}, b{2, -1, 0}, c{-1, 2, 0};
  const double toi = point_static_triangle_ccd({0.1, 0.2, 1}, {0, 0, -2}, a, b, c);
  EXPECT_NEAR(point_static_triangle_ccd({100, 200, 1000}, {0, 0, -2000}, scaled(a, 1000),
                                        scaled(b, 1000), scaled(c, 1000)),
              toi, 1e-12);
  const double ee = edge_edge_ccd({-1, 0, 1}, {1, 0, 1}, {0, -1, 0}, {0, 1, 0}, {0, 0, -4},
                                  {0, 0, -4}, kZero, kZero);
  EXPECT_NEAR(edge_edge_ccd({-1000, 0, 1000}, {1000, 0, 1000}, {0, -1000, 0}, {0, 1000, 0},
                            {0, 0, -4000}, {0, 0, -4000}, kZero, kZero),
              ee, 1e-12);
}

// The pair's squared distance at time t of x + t dx.
double distance_at(bool point_triangle, const std::array<Vec3, 4>& x, const std::array<Vec3, 4>& dx,
                   double t) {
  std::array<Vec3, 4> y;
  for (int k = 0; k < 4; ++k) y[k] = add(x[k], scaled(dx[k], t));
  return std::sqrt(point_triangle ? pt_distance(y, nullptr) : ee_distance(y, nullptr));
}

// Whether the distance stays above `floor` on [t0, t1], by samples and the
// bound |d'| <= speed: an interval is proven when its two end distances
// exceed floor + speed * length / 2, else split (to a depth). Rigorous up to
// the rounding of the distances.
bool stays_above(const std::function<double(double)>& distance, double speed, double t0, double t1,
                 double d0, double d1, double floor, int depth) {
  if (std::min(d0, d1) <= floor) return false;
  if (0.5 * (d0 + d1 - speed * (t1 - t0)) > floor) return true;
  if (depth == 0) return false;
  const double mid = 0.5 * (t0 + t1), dm = distance(mid);
  return stays_above(distance, speed, t0, mid, d0, dm, floor, depth - 1) &&
         stays_above(distance, speed, mid, t1, dm, d1, floor, depth - 1);
}

// The signed volume of (x1 - x0, x2 - x0, x3 - x0): zero when the four points
// are coplanar, which a contact of either kind needs.
double volume(const std::array<Vec3, 4>& y) {
  return dot(sub(y[1], y[0]), cross(sub(y[2], y[0]), sub(y[3], y[0])));
}

// The first time in [0, 1] the pair touches (distance below 1e-9), or
// infinity: roots of the (cubic) coplanarity volume, bracketed on a fine
// grid and bisected, checked for contact.
double first_contact(bool point_triangle, const std::array<Vec3, 4>& x,
                     const std::array<Vec3, 4>& dx) {
  const auto at = [&](double t) {
    std::array<Vec3, 4> y;
    for (int k = 0; k < 4; ++k) y[k] = add(x[k], scaled(dx[k], t));
    return y;
  };
  const int n = 2000;
  double previous = volume(at(0));
  for (int i = 1; i <= n; ++i) {
    double lo = double(i - 1) / n, hi = double(i) / n;
    const double v = volume(at(hi));
    if ((previous < 0) != (v < 0) || v == 0) {
      double vlo = previous;
      for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi), vm = volume(at(mid));
        if ((vlo < 0) == (vm < 0) && vm != 0) {
          lo = mid;
          vlo = vm;
        } else {
          hi = mid;
        }
      }
      if (distance_at(point_triangle, x, dx, hi) < 1e-9) return hi;
    }
    previous = v;
  }
  return HUGE_VAL;
}

int orientation_sign(const std::array<Vec3, 4>& y) {
  const auto p = [](const Vec3& v) { return Kernel::Point_3(v[0], v[1], v[2]); };
  return static_cast<int>(CGAL::orientation(p(y[1]), p(y[2]), p(y[3]), p(y[0])));
}

// Whether the point y[0] projects inside the proper triangle (y[1], y[2], y[3]).
bool over_triangle(const std::array<Vec3, 4>& y) {
  const Vec3 n = cross(sub(y[2], y[1]), sub(y[3], y[1]));
  if (!(dot(n, n) > 1e-12)) return false;
  for (int k = 0; k < 3; ++k) {
    const Vec3 &e0 = y[1 + k], &e1 = y[1 + (k + 1) % 3];
    if (dot(cross(sub(e1, e0), sub(y[0], e0)), n) <= 0) return false;
  }
  return true;
}

// Random pairs in the unit cube with random steps of up to 2 per corner,
// most of them colliding: the CCD time never lets the pair touch, is never
// after the first contact, and is not far before it on average.
TEST(AdditiveCcd, NeverCrossesOnRandomSteps) {
  Random random(12);
  const CcdOptions options;
  int colliding = 0;
  double ratio_sum = 0, worst_ratio = 1;
  for (int trial = 0; trial < 10000; ++trial) {
    const bool point_triangle = trial % 2 == 0;
    std::array<Vec3, 4> x, dx;
    for (Vec3& v : x) v = random.point(0, 1);
    // Aim the step so that about half of the pairs collide: the point (or
    // first edge) towards the other primitive, everything perturbed.
    const Vec3 centre_a = point_triangle ? x[0] : scaled(add(x[0], x[1]), 0.5);
    const Vec3 centre_b =
        point_triangle ? scaled(add(add(x[1], x[2]), x[3]), 1.0 / 3) : scaled(add(x[2], x[3]), 0.5);
    const Vec3 aim = scaled(sub(centre_b, centre_a), random.uniform(0.5, 2.5));
    for (int k = 0; k < 4; ++k) {
      const bool side_a = point_triangle ? k == 0 : k < 2;
      dx[k] = add(side_a ? aim : kZero, scaled(random.point(), random.uniform(0, 1)));
    }
    const double toi =
        point_triangle
            ? point_triangle_ccd(x[0], x[1], x[2], x[3], dx[0], dx[1], dx[2], dx[3], options)
            : edge_edge_ccd(x[0], x[1], x[2], x[3], dx[0], dx[1], dx[2], dx[3], options);
    ASSERT_GE(toi, 0);
    ASSERT_LE(toi, 1);
    const double d0 = distance_at(point_triangle, x, dx, 0);
    // No contact on [0, toi]; the distance stays above (1 - 0.9) * 0.1 of d0.
    const auto distance = [&](double t) { return distance_at(point_triangle, x, dx, t); };
    double speed = 0;  // |d'| <= the largest relative speed of two corners
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) speed = std::max(speed, norm(sub(dx[i], dx[j])));
    ASSERT_TRUE(stays_above(distance, speed, 0, toi, d0, distance(toi), 0, 40))
        << "trial " << trial;
    for (int s = 1; s <= 100; ++s) {
      ASSERT_GE(distance(toi * s / 100), 0.01 * d0 * (1 - 1e-9)) << "trial " << trial;
    }
    if (toi < 1) {
      EXPECT_GE(distance(toi), 0.1 * d0 * (1 - 1e-9)) << "trial " << trial;
    }
    // The exact orientation of a point over the triangle never flips
    // between samples: it does not pass through the face.
    if (point_triangle) {
      std::array<Vec3, 4> y = x, previous = x;
      const int samples = 200;
      for (int s = 1; s <= samples; ++s) {
        for (int k = 0; k < 4; ++k) y[k] = add(x[k], scaled(dx[k], toi * s / samples));
        const Vec3 n0 = cross(sub(previous[2], previous[1]), sub(previous[3], previous[1]));
        const Vec3 n1 = cross(sub(y[2], y[1]), sub(y[3], y[1]));
        if (over_triangle(previous) && over_triangle(y) && dot(n0, n1) > 0) {
          ASSERT_EQ(orientation_sign(previous), orientation_sign(y)) << "trial " << trial;
        }
        previous = y;
      }
    }
    const double contact = first_contact(point_triangle, x, dx);
    if (contact <= 1) {
      ASSERT_LE(toi, contact) << "trial " << trial;
      ++colliding;
      ratio_sum += toi / contact;
      worst_ratio = std::min(worst_ratio, toi / contact);
    }
  }
  const double mean_ratio = ratio_sum / colliding;
  std::printf("%d of 10000 random steps collide; toi / first contact: mean %.3f, worst %.3g\n",
              colliding, mean_ratio, worst_ratio);
  RecordProperty("colliding", colliding);
  RecordProperty("mean_ratio", std::to_string(mean_ratio));
  EXPECT_GT(colliding, 2000);
  EXPECT_GE(mean_ratio, 0.5);
}

// ---------------------------------------------------------------------------
// Box tree

std::vector<Box> random_boxes(Random& random, int count, double largest) {
  std::vector<Box> boxes;
  for (int i = 0; i < count; ++i) {
    const Vec3 centre = random.point(0, 10);
    Box box;
    const double size = largest * std::pow(random.uniform(0, 1), 3);
    for (int c = 0; c < 3; ++c) {
      const double half = 0.5 * size * random.uniform(0, 1);
      box.low[c] = centre[c] - half;
      box.high[c] = centre[c] + half;
    }
    if (i % 17 == 5) box.low[1] = std::numeric_limits<double>::quiet_NaN();  // empty
    if (i % 23 == 7) std::swap(box.low, box.high);              // empty if any low > high
    if (i % 29 == 3) box = boxes.empty() ? box : boxes.back();  // duplicates
    if (i % 31 == 1) box.high = box.low;                        // a point
    boxes.push_back(box);
  }
  return boxes;
}

bool nonempty(const Box& b) {
  for (int c = 0; c < 3; ++c)
    if (!(std::isfinite(b.low[c]) && std::isfinite(b.high[c]) && b.low[c] <= b.high[c]))
      return false;
  return true;
}

std::vector<IndexPair> brute_pairs(const std::vector<Box>& a, const std::vector<Box>& b,
                                   double margin, bool self) {
  std::vector<IndexPair> pairs;
  for (int i = 0; i < static_cast<int>(a.size()); ++i)
    for (int j = self ? i + 1 : 0; j < static_cast<int>(b.size()); ++j)
      if (nonempty(a[i]) && nonempty(b[j]) && boxes_meet(a[i], b[j], margin))
        pairs.push_back({i, j});
  return pairs;
}

TEST(BoxTree, EqualsBruteForce) {
  Random random(13);
  for (const int count : {0, 1, 3, 4, 5, 9, 100, 1500}) {
    for (const double margin : {0.0, 0.3}) {
      const std::vector<Box> a = random_boxes(random, count, 2);
      const std::vector<Box> b = random_boxes(random, count / 2 + 3, 4);
      BoxTree ta(a), tb(b);
      EXPECT_EQ(meeting_pairs(ta, tb, margin), brute_pairs(a, b, margin, false)) << count;
      EXPECT_EQ(meeting_pairs(ta, margin), brute_pairs(a, a, margin, true)) << count;
      // Single queries.
      for (int i = 0; i < std::min(count, 50); ++i) {
        std::vector<int> found;
        tb.for_each_meeting(a[i], margin, [&](int j) { found.push_back(j); });
        std::sort(found.begin(), found.end());
        std::vector<int> expected;
        for (int j = 0; j < static_cast<int>(b.size()); ++j)
          if (nonempty(a[i]) && nonempty(b[j]) && boxes_meet(a[i], b[j], margin))
            expected.push_back(j);
        EXPECT_EQ(found, expected);
      }
      // Refitted to boxes moved far: still exact.
      std::vector<Box> moved = random_boxes(random, count, 3);
      ta.refit(moved);
      EXPECT_EQ(meeting_pairs(ta, tb, margin), brute_pairs(moved, b, margin, false)) << count;
      EXPECT_EQ(meeting_pairs(ta, margin), brute_pairs(moved, moved, margin, true)) << count;
      EXPECT_GE(ta.cost(), 0);
    }
  }
}

// A tree built in a given order finds what a test of every pair finds,
// whatever the order: random, or coherent (another tree's leaf order).
TEST(BoxTree, BuiltInAnyOrderEqualsBruteForce) {
  Random random(19);
  for (const int count : {0, 1, 4, 5, 9, 300, 1500}) {
    const std::vector<Box> a = random_boxes(random, count, 2);
    const std::vector<Box> b = random_boxes(random, count / 2 + 3, 4);
    const BoxTree tb(b);
    std::vector<int> shuffled(count);
    std::iota(shuffled.begin(), shuffled.end(), 0);
    for (int i = count - 1; i > 0; --i) std::swap(shuffled[i], shuffled[random.index(i + 1)]);
    const BoxTree built(a);
    for (const std::vector<int>& order : {shuffled, built.leaf_order()}) {
      BoxTree ta;
      ta.build_in_order(a, order);
      EXPECT_EQ(ta.leaf_order(), order);
      for (const double margin : {0.0, 0.3}) {
        EXPECT_EQ(meeting_pairs(ta, tb, margin), brute_pairs(a, b, margin, false)) << count;
        EXPECT_EQ(meeting_pairs(ta, margin), brute_pairs(a, a, margin, true)) << count;
      }
    }
  }
  BoxTree tree;
  EXPECT_THROW(tree.build_in_order(random_boxes(random, 3, 1), {0, 1}), InternalError);
  EXPECT_THROW(tree.build_in_order(random_boxes(random, 2, 1), {0, 2}), InternalError);
  EXPECT_THROW(tree.build_in_order(random_boxes(random, 2, 1), {1, 1}), InternalError);
}

// Every way of splitting a search finds the same pairs, each once.
// closing_bound is at least every difference of two displacements (the
// still points' 0 among them), at most twice the largest, and one
// translation's length for a translation.
TEST(ClosingBound, BoundsEveryDifferenceOfDisplacements) {
  Random random(23);
  for (int trial = 0; trial < 20; ++trial) {
    const size_t n = 30, first = trial % 2 ? 10 : 0;
    std::vector<double> anchor(3 * n), points(3 * n), move(3 * n);
    const Vec3 drift = random.point(-2, 2);
    for (size_t k = 0; k < 3 * n; ++k) {
      anchor[k] = random.uniform(-5, 5);
      move[k] = random.uniform(-0.3, 0.3);
      points[k] = anchor[k] + (k >= 3 * first ? drift[k % 3] + random.uniform(-0.2, 0.2) : 0.0);
    }
    const double* no_step = nullptr;
    for (const double* step : {no_step, static_cast<const double*>(move.data())}) {
      std::vector<Vec3> displacements = {{0, 0, 0}};
      for (size_t v = first; v < n; ++v) {
        const Vec3 d{points[3 * v] - anchor[3 * v], points[3 * v + 1] - anchor[3 * v + 1],
                     points[3 * v + 2] - anchor[3 * v + 2]};
        displacements.push_back(d);
        if (step) displacements.push_back(add(d, {step[3 * v], step[3 * v + 1], step[3 * v + 2]}));
      }
      double widest = 0, longest = 0;
      for (const Vec3& a : displacements) {
        longest = std::max(longest, norm(a));
        for (const Vec3& b : displacements) widest = std::max(widest, norm(sub(a, b)));
      }
      const double bound = closing_bound(points.data(), anchor.data(), first, n, step);
      EXPECT_GE(bound, widest) << trial;
      EXPECT_LE(bound, 2 * longest * (1 + 1e-12)) << trial;
      // Moving in one direction: much less than twice the longest.
      EXPECT_LT(bound, 1.6 * longest) << trial;
    }
  }
  std::vector<double> anchor(9, 1.0), points = anchor;
  for (size_t k = 3; k < 9; k += 3) points[k] += 0.5;  // points 1 and 2 move 0.5 along x
  EXPECT_DOUBLE_EQ(closing_bound(points.data(), anchor.data(), 1, 3), 0.5);
  EXPECT_EQ(closing_bound(points.data(), anchor.data(), 0, 3), 0.5);
  points[4] = std::nan("");
  EXPECT_EQ(closing_bound(points.data(), anchor.data(), 1, 3), HUGE_VAL);
}

TEST(BoxTree, SplitSearchesFindEveryPairOnce) {
  Random random(17);
  const std::vector<Box> a = random_boxes(random, 700, 2), b = random_boxes(random, 400, 3);
  const BoxTree ta(a), tb(b);
  const double margin = 0.1;
  const auto expected_cross = brute_pairs(a, b, margin, false);
  const auto expected_self = brute_pairs(a, a, margin, true);
  std::vector<IndexPair> serial;
  ta.for_each_meeting_pair(tb, margin, [&](int i, int j) { serial.push_back({i, j}); });
  sort_index_pairs(serial, 700);
  EXPECT_EQ(serial, expected_cross);
  serial.clear();
  ta.for_each_meeting_pair(margin, [&](int i, int j) {
    serial.push_back({std::min(i, j), std::max(i, j)});
  });
  sort_index_pairs(serial, 700);
  EXPECT_EQ(serial, expected_self);
  for (const int count : {1, 2, 3, 17, 200, 100000}) {
    std::vector<IndexPair> cross, self;
    for (const auto& part : ta.split_search(tb, margin, count)) {
      ta.for_each_meeting_pair(part, tb, margin, [&](int i, int j) { cross.push_back({i, j}); });
    }
    const auto parts = ta.split_search(margin, count);
    EXPECT_GE(static_cast<int>(parts.size()), std::min(count, 100));
    for (const auto& part : parts) {
      ta.for_each_meeting_pair(part, margin, [&](int i, int j) {
        self.push_back({std::min(i, j), std::max(i, j)});
      });
    }
    sort_index_pairs(cross, 700);
    sort_index_pairs(self, 700);
    EXPECT_EQ(cross, expected_cross) << count;
    EXPECT_EQ(self, expected_self) << count;
  }
  // Empty trees.
  const BoxTree empty;
  EXPECT_TRUE(meeting_pairs(empty, tb, margin).empty());
  EXPECT_TRUE(meeting_pairs(ta, empty, margin).empty());
  EXPECT_TRUE(meeting_pairs(empty, margin).empty());
  EXPECT_TRUE(empty.split_search(margin, 10).empty());
}

TEST(BoxTree, SortIndexPairs) {
  Random random(14);
  std::vector<IndexPair> pairs;
  for (int k = 0; k < 5000; ++k) pairs.push_back({random.index(300), random.index(100000)});
  std::vector<IndexPair> expected = pairs;
  std::sort(expected.begin(), expected.end());
  sort_index_pairs(pairs, 300);
  EXPECT_EQ(pairs, expected);
}

// ---------------------------------------------------------------------------
// Collision broad phase

struct Soup {
  std::vector<Vec3> positions;
  CollisionMesh mesh;
};

// Random triangles over `vertex_count` vertices in a cube, the first
// `fixed_count` of them fixed.
Soup random_soup(Random& random, int vertex_count, int face_count, int fixed_count, double size) {
  Soup soup;
  for (int v = 0; v < vertex_count; ++v) soup.positions.push_back(random.point(0, size));
  std::vector<Tri> faces;
  for (int f = 0; f < face_count; ++f) {
    // Corners near each other: faces of about unit size.
    const int a = random.index(vertex_count);
    std::vector<int> near;
    for (int v = 0; v < vertex_count; ++v)
      if (v != a && norm(sub(soup.positions[v], soup.positions[a])) < 1.5) near.push_back(v);
    if (near.size() < 2) continue;
    const int b = near[random.index(near.size())];
    int c = b;
    while (c == b) c = near[random.index(near.size())];
    faces.push_back({a, b, c});
  }
  soup.mesh = make_collision_mesh(faces, vertex_count, fixed_count);
  return soup;
}

Box brute_box(const std::vector<Vec3>& x, const std::vector<Vec3>* dx, const std::vector<int>& v,
              int fixed) {
  Box box{x[v[0]], x[v[0]]};
  for (int k : v) {
    std::vector<Vec3> at = {x[k]};
    if (dx && k >= fixed) at.push_back(add(x[k], (*dx)[k]));
    for (const Vec3& p : at)
      for (int c = 0; c < 3; ++c) {
        box.low[c] = std::min(box.low[c], p[c]);
        box.high[c] = std::max(box.high[c], p[c]);
      }
  }
  return box;
}

CollisionCandidates brute_candidates(const CollisionMesh& mesh, const std::vector<Vec3>& x,
                                     const std::vector<Vec3>* dx, double distance) {
  CollisionCandidates result;
  const int fixed = mesh.fixed_count;
  std::vector<Box> point_boxes, edge_boxes, face_boxes;
  for (int v = 0; v < mesh.vertex_count; ++v) point_boxes.push_back(brute_box(x, dx, {v}, fixed));
  for (const auto& e : mesh.edges) edge_boxes.push_back(brute_box(x, dx, {e[0], e[1]}, fixed));
  for (const Tri& t : mesh.faces) face_boxes.push_back(brute_box(x, dx, {t[0], t[1], t[2]}, fixed));
  for (int v = 0; v < mesh.vertex_count; ++v) {
    for (int f = 0; f < static_cast<int>(mesh.faces.size()); ++f) {
      const Tri& t = mesh.faces[f];
      if (t[0] == v || t[1] == v || t[2] == v) continue;
      if (v < fixed && std::max({t[0], t[1], t[2]}) < fixed) continue;
      if (boxes_meet(point_boxes[v], face_boxes[f], distance))
        result.point_triangle.push_back({v, f});
    }
  }
  for (int e = 0; e < static_cast<int>(mesh.edges.size()); ++e) {
    const auto& a = mesh.edges[e];
    for (int h = e + 1; h < static_cast<int>(mesh.edges.size()); ++h) {
      const auto& b = mesh.edges[h];
      if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) continue;
      if (std::max({a[0], a[1], b[0], b[1]}) < fixed) continue;
      if (boxes_meet(edge_boxes[e], edge_boxes[h], distance)) result.edge_edge.push_back({e, h});
    }
  }
  return result;
}

const double* flat(const std::vector<Vec3>& v) { return v.empty() ? nullptr : v.data()->data(); }

TEST(CollisionBroadPhase, EqualsBruteForceOnRandomSoups) {
  Random random(15);
  for (int trial = 0; trial < 12; ++trial) {
    const int n = 150 + 40 * trial, fixed = trial % 3 == 0 ? 0 : n / 3;
    Soup soup = random_soup(random, n, n, fixed, 4);
    CollisionBroadPhase broad(soup.mesh, flat(soup.positions));
    CollisionCandidates found;
    for (int step = 0; step < 3; ++step) {
      // Free vertices move (the trees are refitted); fixed ones are told to
      // move too, which the search must ignore.
      std::vector<Vec3> dx(n);
      for (Vec3& d : dx) d = scaled(random.point(), 0.3 * step);
      for (int v = fixed; v < n; ++v) soup.positions[v] = add(soup.positions[v], dx[v]);
      const double distance = 0.05 * (trial % 4);
      broad.find(flat(soup.positions), nullptr, distance, found);
      const CollisionCandidates expected =
          brute_candidates(soup.mesh, soup.positions, nullptr, distance);
      EXPECT_EQ(found.point_triangle, expected.point_triangle) << trial;
      EXPECT_EQ(found.edge_edge, expected.edge_edge) << trial;
      // Swept boxes.
      broad.find(flat(soup.positions), flat(dx), distance, found);
      const CollisionCandidates swept = brute_candidates(soup.mesh, soup.positions, &dx, distance);
      EXPECT_EQ(found.point_triangle, swept.point_triangle) << trial;
      EXPECT_EQ(found.edge_edge, swept.edge_edge) << trial;
      EXPECT_GT(found.size(), 0u);
      // The meeting faces: every pair with a moving face whose boxes meet.
      std::vector<IndexPair> meeting, expected_faces;
      broad.meeting_faces(flat(soup.positions), meeting);
      const auto& faces = soup.mesh.faces;
      const auto moving = [&](int f) {
        return std::max({faces[f][0], faces[f][1], faces[f][2]}) >= fixed;
      };
      for (int f = 0; f < static_cast<int>(faces.size()); ++f)
        for (int g = 0; g < static_cast<int>(faces.size()); ++g) {
          if (f == g || !moving(f) || (moving(g) && g < f)) continue;
          const Box bf =
              brute_box(soup.positions, nullptr, {faces[f][0], faces[f][1], faces[f][2]}, fixed);
          const Box bg =
              brute_box(soup.positions, nullptr, {faces[g][0], faces[g][1], faces[g][2]}, fixed);
          if (boxes_meet(bf, bg, 0.0)) expected_faces.push_back({f, g});
        }
      std::sort(expected_faces.begin(), expected_faces.end());
      EXPECT_EQ(meeting, expected_faces) << trial;
      // No pair shares a vertex.
      for (const IndexPair& pair : found.point_triangle) {
        const Tri& t = soup.mesh.faces[pair[1]];
        EXPECT_TRUE(t[0] != pair[0] && t[1] != pair[0] && t[2] != pair[0]);
      }
      for (const IndexPair& pair : found.edge_edge) {
        const auto &a = soup.mesh.edges[pair[0]], &b = soup.mesh.edges[pair[1]];
        EXPECT_LT(pair[0], pair[1]);
        EXPECT_TRUE(a[0] != b[0] && a[0] != b[1] && a[1] != b[0] && a[1] != b[1]);
      }
    }
  }
}

// The pairs with a moved corner are those of find_within that have one, on
// soups with a few and with most vertices moved (fixed ones flagged too,
// which the search must ignore).
TEST(CollisionBroadPhase, FindWithinTouchingKeepsThePairsOfTheMovedVertices) {
  Random random(21);
  for (int trial = 0; trial < 8; ++trial) {
    const int n = 200 + 50 * trial, fixed = trial % 2 == 0 ? 0 : n / 4;
    const Soup soup = random_soup(random, n, n, fixed, 4);
    CollisionBroadPhase broad(soup.mesh, flat(soup.positions));
    const double distance = 0.05 + 0.05 * (trial % 3);
    std::vector<char> moved(n, 0);
    const double share = trial < 4 ? 0.1 : 0.7;
    for (int v = 0; v < n; ++v) moved[v] = random.uniform(0, 1) < share;
    CollisionCandidates all, touching;
    broad.find_within(flat(soup.positions), distance, all);
    broad.find_within_touching(flat(soup.positions), distance, moved, touching);
    const auto is_moved = [&](int v) { return v >= fixed && moved[v]; };
    CollisionCandidates expected;
    for (const IndexPair& p : all.point_triangle) {
      const Tri& f = soup.mesh.faces[p[1]];
      if (is_moved(p[0]) || is_moved(f[0]) || is_moved(f[1]) || is_moved(f[2]))
        expected.point_triangle.push_back(p);
    }
    for (const IndexPair& p : all.edge_edge) {
      const auto &a = soup.mesh.edges[p[0]], &b = soup.mesh.edges[p[1]];
      if (is_moved(a[0]) || is_moved(a[1]) || is_moved(b[0]) || is_moved(b[1]))
        expected.edge_edge.push_back(p);
    }
    EXPECT_EQ(touching.point_triangle, expected.point_triangle) << trial;
    EXPECT_EQ(touching.edge_edge, expected.edge_edge) << trial;
    EXPECT_GT(expected.size(), 0u) << trial;
    EXPECT_LT(expected.size(), all.size()) << trial;
  }
  const Soup small = random_soup(random, 50, 50, 0, 4);
  CollisionBroadPhase broad(small.mesh, flat(small.positions));
  CollisionCandidates found;
  EXPECT_THROW(broad.find_within_touching(nullptr, 0.1, std::vector<char>(3), found),
               InternalError);
}

// A triangulated n x n sheet of unit spacing at height z(x, y), vertices
// numbered from `first`.
void add_sheet(int n, const std::function<Vec3(double, double)>& place, std::vector<Vec3>& x,
               std::vector<Tri>& faces) {
  const int first = static_cast<int>(x.size());
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) x.push_back(place(i, j));
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = first + j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      faces.push_back({a, b, c});
      faces.push_back({a, c, d});
    }
}

// A static wavy sheet and a free sheet above it, folding down onto it.
struct Layers {
  std::vector<Vec3> positions, step;
  CollisionMesh mesh;
};
Layers two_layers(int n, double gap, double fall) {
  Layers layers;
  std::vector<Tri> faces;
  const auto wave = [](double i, double j) { return 0.8 * std::sin(0.4 * i) * std::cos(0.3 * j); };
  add_sheet(
      n,
      [&](double i, double j) {
        return Vec3{i, j, wave(i, j)};
      },
      layers.positions, faces);
  const int fixed = n * n;
  add_sheet(
      n,
      [&](double i, double j) {
        return Vec3{i + 0.3, j + 0.2, wave(i + 0.3, j + 0.2) + gap};
      },
      layers.positions, faces);
  layers.step.assign(layers.positions.size(), kZero);
  for (int v = fixed; v < 2 * fixed; ++v) {
    const Vec3& p = layers.positions[v];
    layers.step[v] = {0.2 * std::sin(p[1]), 0.1, -fall * (0.5 + 0.5 * std::cos(0.5 * p[0]))};
  }
  layers.mesh = make_collision_mesh(faces, 2 * fixed, fixed);
  return layers;
}

TEST(CollisionMesh, EdgesAndValidation) {
  const CollisionMesh mesh = make_collision_mesh({{0, 1, 2}, {2, 1, 3}}, 5, 2);
  const std::vector<std::array<int, 2>> edges = {{0, 1}, {0, 2}, {1, 2}, {1, 3}, {2, 3}};
  EXPECT_EQ(mesh.edges, edges);
  EXPECT_EQ(mesh.vertex_count, 5);
  EXPECT_EQ(mesh.fixed_count, 2);
  EXPECT_THROW(make_collision_mesh({{0, 1, 5}}, 5, 0), Error);
  EXPECT_THROW(make_collision_mesh({{0, 1, -1}}, 5, 0), Error);
  EXPECT_THROW(make_collision_mesh({{0, 1, 2}}, 5, 6), Error);
  // Nothing moves: no candidates at all.
  const std::vector<Vec3> x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 0.1}};
  CollisionBroadPhase still(make_collision_mesh({{0, 1, 2}, {2, 1, 3}}, 5, 5), flat(x));
  CollisionCandidates found;
  still.find(flat(x), nullptr, 10, found);
  EXPECT_EQ(found.size(), 0u);
  // One free vertex over two fixed faces (whose boxes are the unit square):
  // both faces within 0.2, neither within 0.05.
  CollisionBroadPhase one(make_collision_mesh({{0, 1, 2}, {2, 1, 3}}, 5, 4), flat(x));
  one.find(flat(x), nullptr, 0.2, found);
  EXPECT_EQ(found.point_triangle, (std::vector<IndexPair>{{4, 0}, {4, 1}}));
  EXPECT_TRUE(found.edge_edge.empty());
  one.find(flat(x), nullptr, 0.05, found);
  EXPECT_EQ(found.size(), 0u);
}

TEST(CollisionBroadPhase, DeterministicAcrossThreadsAndCalls) {
  Layers layers = two_layers(24, 0.4, 1.5);
  const int threads = omp_get_max_threads();
  CollisionCandidates reference, again;
  {
    CollisionBroadPhase broad(layers.mesh, flat(layers.positions));
    omp_set_num_threads(1);
    broad.find(flat(layers.positions), flat(layers.step), 0.1, reference);
    omp_set_num_threads(std::max(threads, 4));
    broad.find(flat(layers.positions), flat(layers.step), 0.1, again);
    EXPECT_EQ(again.point_triangle, reference.point_triangle);
    EXPECT_EQ(again.edge_edge, reference.edge_edge);
  }
  // A search that had to rebuild its trees, or a fresh object.
  CollisionBroadPhase other(layers.mesh, flat(layers.positions));
  std::vector<Vec3> far = layers.positions;
  for (int v = layers.mesh.fixed_count; v < layers.mesh.vertex_count; ++v)
    far[v] = scaled(far[v], 3);
  other.find(flat(far), nullptr, 0.1, again);
  other.find(flat(layers.positions), flat(layers.step), 0.1, again);
  omp_set_num_threads(threads);
  EXPECT_EQ(again.point_triangle, reference.point_triangle);
  EXPECT_EQ(again.edge_edge, reference.edge_edge);
  EXPECT_TRUE(std::is_sorted(reference.point_triangle.begin(), reference.point_triangle.end()));
  EXPECT_TRUE(std::is_sorted(reference.edge_edge.begin(), reference.edge_edge.end()));
  const CollisionCandidates brute =
      brute_candidates(layers.mesh, layers.positions, &layers.step, 0.1);
  EXPECT_EQ(reference.point_triangle, brute.point_triangle);
  EXPECT_EQ(reference.edge_edge, brute.edge_edge);
}

// ---------------------------------------------------------------------------
// Step bound and barrier potential over a mesh

// The least distance over all non-static PT and EE pairs of the mesh.
double least_distance(const CollisionMesh& mesh, const std::vector<Vec3>& x) {
  const CollisionCandidates all = brute_candidates(mesh, x, nullptr, HUGE_VAL);
  double least = HUGE_VAL;
  for (const IndexPair& p : all.point_triangle) {
    const Tri& f = mesh.faces[p[1]];
    least = std::min(least, point_triangle_distance_squared(x[p[0]], x[f[0]], x[f[1]], x[f[2]]));
  }
  for (const IndexPair& p : all.edge_edge) {
    const auto &a = mesh.edges[p[0]], &b = mesh.edges[p[1]];
    least = std::min(least, edge_edge_distance_squared(x[a[0]], x[a[1]], x[b[0]], x[b[1]]));
  }
  return std::sqrt(least);
}

TEST(CollisionStepBound, StopsBeforeContactAndIsDeterministic) {
  Layers layers = two_layers(10, 0.4, 1.5);
  CollisionBroadPhase broad(layers.mesh, flat(layers.positions));
  CollisionCandidates candidates;
  broad.find(flat(layers.positions), flat(layers.step), 0, candidates);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const double one =
      collision_step_bound(layers.mesh, flat(layers.positions), flat(layers.step), candidates);
  omp_set_num_threads(std::max(threads, 4));
  const double many =
      collision_step_bound(layers.mesh, flat(layers.positions), flat(layers.step), candidates);
  omp_set_num_threads(threads);
  EXPECT_EQ(one, many);
  // The full step passes the upper sheet through the lower one.
  EXPECT_GT(one, 0);
  EXPECT_LT(one, 1);
  // The minimum of the pairs' own times, one by one.
  const auto& x = layers.positions;
  const auto& dx = layers.step;
  double least = 1;
  for (const IndexPair& p : candidates.point_triangle) {
    const Tri& f = layers.mesh.faces[p[1]];
    least = std::min(least, point_triangle_ccd(x[p[0]], x[f[0]], x[f[1]], x[f[2]], dx[p[0]],
                                               dx[f[0]], dx[f[1]], dx[f[2]]));
  }
  for (const IndexPair& p : candidates.edge_edge) {
    const auto &a = layers.mesh.edges[p[0]], &b = layers.mesh.edges[p[1]];
    least = std::min(least, edge_edge_ccd(x[a[0]], x[a[1]], x[b[0]], x[b[1]], dx[a[0]], dx[a[1]],
                                          dx[b[0]], dx[b[1]]));
  }
  EXPECT_EQ(one, least);
  // Along the step up to the bound, the sheets never touch.
  const double start = least_distance(layers.mesh, layers.positions);
  for (int s = 1; s <= 20; ++s) {
    std::vector<Vec3> y = x;
    for (size_t v = 0; v < y.size(); ++v) y[v] = add(y[v], scaled(dx[v], one * s / 20));
    EXPECT_GT(least_distance(layers.mesh, y), 0.01 * start);
  }
  // Displacements given to fixed vertices are ignored.
  std::vector<Vec3> told = layers.step;
  for (int v = 0; v < layers.mesh.fixed_count; ++v) told[v] = {0, 0, 5};
  EXPECT_EQ(collision_step_bound(layers.mesh, flat(x), flat(told), candidates), one);
  // No candidates: t_max.
  EXPECT_EQ(collision_step_bound(layers.mesh, flat(layers.positions), flat(layers.step), {}), 1);
}

TEST(KeepCandidatesWithin, KeepsExactlyTheClosePairs) {
  Layers layers = two_layers(12, 0.25, 0);
  Random random(18);
  for (int v = layers.mesh.fixed_count; v < layers.mesh.vertex_count; ++v)
    layers.positions[v] = add(layers.positions[v], scaled(random.point(), 0.1));
  const double distance = 0.3;
  CollisionBroadPhase broad(layers.mesh, flat(layers.positions));
  CollisionCandidates candidates;
  broad.find(flat(layers.positions), nullptr, distance, candidates);
  const CollisionCandidates all = candidates;
  keep_candidates_within(layers.mesh, flat(layers.positions), distance, candidates);
  EXPECT_LT(candidates.size(), all.size());
  EXPECT_GT(candidates.size(), 0u);
  const auto& x = layers.positions;
  std::vector<IndexPair> pt, ee;
  for (const IndexPair& p : all.point_triangle) {
    const Tri& f = layers.mesh.faces[p[1]];
    if (point_triangle_distance_squared(x[p[0]], x[f[0]], x[f[1]], x[f[2]]) < distance * distance)
      pt.push_back(p);
  }
  for (const IndexPair& p : all.edge_edge) {
    const auto &a = layers.mesh.edges[p[0]], &b = layers.mesh.edges[p[1]];
    if (edge_edge_distance_squared(x[a[0]], x[a[1]], x[b[0]], x[b[1]]) < distance * distance)
      ee.push_back(p);
  }
  EXPECT_EQ(candidates.point_triangle, pt);
  EXPECT_EQ(candidates.edge_edge, ee);
  // The same in one pass.
  CollisionCandidates within;
  broad.find_within(flat(layers.positions), distance, within);
  EXPECT_EQ(within.point_triangle, pt);
  EXPECT_EQ(within.edge_edge, ee);
  // The barrier needs no more than these.
  const double kept = barrier_potential(layers.mesh, flat(x), candidates, distance);
  EXPECT_NEAR(kept, barrier_potential(layers.mesh, flat(x), all, distance), 1e-14 * kept);
}

TEST(BarrierPotential, GradientAndCompleteness) {
  Layers layers = two_layers(8, 0.25, 0);
  // Crumple the free sheet a little so that every kind of pair is active.
  Random random(16);
  for (int v = layers.mesh.fixed_count; v < layers.mesh.vertex_count; ++v)
    layers.positions[v] = add(layers.positions[v], scaled(random.point(), 0.08));
  const double dhat = 0.3;
  CollisionBroadPhase broad(layers.mesh, flat(layers.positions));
  CollisionCandidates candidates;
  broad.find(flat(layers.positions), nullptr, dhat, candidates);
  const int n = layers.mesh.vertex_count;
  std::vector<double> gradient(3 * n, 0.0);
  const double value =
      barrier_potential(layers.mesh, flat(layers.positions), candidates, dhat, 2, gradient.data());
  EXPECT_GT(value, 0);
  // Every pair closer than dhat is a candidate: the same sum as over all pairs.
  const CollisionCandidates all =
      brute_candidates(layers.mesh, layers.positions, nullptr, HUGE_VAL);
  EXPECT_NEAR(barrier_potential(layers.mesh, flat(layers.positions), all, dhat), value,
              1e-12 * value);
  // The same bit for bit on any number of threads.
  {
    const int threads = omp_get_max_threads();
    std::vector<double> g1(3 * n, 0.0), g4(3 * n, 0.0);
    omp_set_num_threads(1);
    const double v1 =
        barrier_potential(layers.mesh, flat(layers.positions), all, dhat, 2, g1.data());
    omp_set_num_threads(std::max(4, threads));
    const double v4 =
        barrier_potential(layers.mesh, flat(layers.positions), all, dhat, 2, g4.data());
    omp_set_num_threads(threads);
    EXPECT_EQ(v1, v4);
    EXPECT_EQ(g1, g4);
  }
  // Gradient (weight 2) against central differences, free vertices only.
  double largest = 0;
  for (double g : gradient) largest = std::max(largest, std::abs(g));
  for (int v = layers.mesh.fixed_count; v < n; v += 7) {
    for (int c = 0; c < 3; ++c) {
      std::vector<Vec3> plus = layers.positions, minus = layers.positions;
      const double h = 1e-7;
      plus[v][c] += h;
      minus[v][c] -= h;
      const double fd = 2 *
                        (barrier_potential(layers.mesh, flat(plus), all, dhat) -
                         barrier_potential(layers.mesh, flat(minus), all, dhat)) /
                        (2 * h);
      EXPECT_NEAR(gradient[3 * v + c], fd, 1e-5 * largest) << v << " " << c;
    }
  }
}

// ---------------------------------------------------------------------------
// Triangles against analytic obstacles

Obstacle sphere_obstacle(const Vec3& center, double radius) {
  Obstacle o;
  o.type = Obstacle::Type::Sphere;
  o.center = center;
  o.radius = radius;
  return o;
}
Obstacle cylinder_obstacle(const Vec3& center, const Vec3& axis, double height, double radius) {
  Obstacle o;
  o.type = Obstacle::Type::Cylinder;
  o.center = center;
  o.axis = unit(axis);
  o.height = height;
  o.radius = radius;
  return o;
}
Obstacle plane_obstacle(const Vec3& point, const Vec3& normal) {
  Obstacle o;
  o.type = Obstacle::Type::Plane;
  o.center = point;
  o.normal = unit(normal);
  return o;
}

// A random obstacle of the given type (0 sphere, 1 cylinder, 2 plane) about
// the unit cube.
Obstacle random_obstacle(Random& random, int type) {
  if (type == 0) return sphere_obstacle(random.point(-0.5, 0.5), random.uniform(0.1, 1.2));
  if (type == 1)
    return cylinder_obstacle(random.point(-0.5, 0.5), random.direction(), random.uniform(0, 2),
                             random.uniform(0.05, 0.8));
  return plane_obstacle(random.point(-0.5, 0.5), random.direction());
}

// The signed distance of the solid that triangle_obstacle_distance measures:
// the sphere, the capsule around a cylinder's axis segment, the half-space.
double solid_distance(const Obstacle& o, const Vec3& p) {
  if (o.type != Obstacle::Type::Cylinder) return signed_distance(o, p);
  const Vec3 half = scaled(o.axis, 0.5 * o.height);
  return segment_distance(p, sub(o.center, half), add(o.center, half)) - o.radius;
}

// The least of f over a barycentric grid of n steps of the triangle: an upper
// bound of its minimum, within (longest edge) / n of it for a 1-Lipschitz f.
double sampled_minimum(const std::array<Vec3, 3>& t, int n,
                       const std::function<double(const Vec3&)>& f) {
  double best = HUGE_VAL;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j)
      best = std::min(best, f(add(t[0], add(scaled(sub(t[1], t[0]), double(i) / n),
                                            scaled(sub(t[2], t[0]), double(j) / n)))));
  return best;
}

double longest_edge(const std::array<Vec3, 3>& t) {
  return std::max({norm(sub(t[1], t[0])), norm(sub(t[2], t[1])), norm(sub(t[0], t[2]))});
}

// Compares `gradient` (of f at x) with central differences of step h,
// coordinate by coordinate, to `tolerance`; skips (and counts) a coordinate
// where the forward and backward differences disagree by more than that: f
// has a kink (a tie of two nearest pairs) within h, where no difference
// quotient is the derivative.
template <size_t N>
void expect_gradient_away_from_ties(const std::function<double(const std::array<Vec3, N>&)>& f,
                                    const std::array<Vec3, N>& x,
                                    const std::array<Vec3, N>& gradient, double h, double tolerance,
                                    int& checked, int& skipped) {
  const double f0 = f(x);
  for (size_t k = 0; k < N; ++k) {
    for (int c = 0; c < 3; ++c) {
      std::array<Vec3, N> plus = x, minus = x;
      plus[k][c] += h;
      minus[k][c] -= h;
      const double fp = f(plus), fm = f(minus);
      const double forward = (fp - f0) / h, backward = (f0 - fm) / h;
      // The one-sided quotients differ by O(h f'') where f is smooth.
      if (std::abs(forward - backward) > 100 * tolerance) {
        ++skipped;
        continue;
      }
      ++checked;
      EXPECT_NEAR(gradient[k][c], (fp - fm) / (2 * h), tolerance) << "point " << k << " axis " << c;
    }
  }
}

TEST(SegmentTriangleDistance, KnownAnswers) {
  const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
  std::array<Vec3, 5> g;
  // Through the face: 0, with a zero gradient.
  EXPECT_EQ(segment_triangle_distance_squared({0.2, 0.2, -1}, {0.2, 0.2, 1}, a, b, c, &g), 0);
  for (const Vec3& v : g) EXPECT_EQ(norm(v), 0);
  EXPECT_EQ(segment_triangle_distance_squared({0.2, 0.3, 1}, {0.1, 0.1, -2}, b, c, a), 0);
  // Through an edge and through a corner: 0.
  EXPECT_EQ(segment_triangle_distance_squared({0.5, 0, -1}, {0.5, 0, 1}, a, b, c), 0);
  EXPECT_EQ(segment_triangle_distance_squared({0, 0, -1}, {0, 0, 1}, a, b, c), 0);
  // An end over the face; the segment above it, parallel; beside it.
  EXPECT_DOUBLE_EQ(segment_triangle_distance_squared({0.2, 0.2, 0.5}, {0.2, 0.2, 2}, a, b, c),
                   0.25);
  EXPECT_DOUBLE_EQ(segment_triangle_distance_squared({0.1, 0.1, 0.3}, {0.3, 0.2, 0.3}, a, b, c),
                   0.09);
  EXPECT_DOUBLE_EQ(segment_triangle_distance_squared({2, 2, -1}, {2, 2, 1}, a, b, c), 4.5);
  // Across the line of edge ab, outside the triangle: the edge-edge pair.
  EXPECT_DOUBLE_EQ(segment_triangle_distance_squared({0.5, -0.5, -1}, {0.5, -0.5, 1}, a, b, c),
                   0.25);
  EXPECT_DOUBLE_EQ(segment_triangle_distance_squared({-1, -1, 1}, {2, -1, 1}, a, b, c), 2);
  // In the triangle's plane, across it: 0; inside it: 0.
  EXPECT_EQ(segment_triangle_distance_squared({-1, 0.25, 0}, {2, 0.25, 0}, a, b, c), 0);
  EXPECT_EQ(segment_triangle_distance_squared({0.1, 0.1, 0}, {0.2, 0.3, 0}, a, b, c), 0);
  // A zero-length segment is a point.
  EXPECT_DOUBLE_EQ(segment_triangle_distance_squared({0.3, 0.4, 2}, {0.3, 0.4, 2}, a, b, c), 4);
  EXPECT_DOUBLE_EQ(segment_triangle_distance_squared({2, 0, 1}, {2, 0, 1}, a, b, c), 2);
  // A collinear triangle is its segment: above it, across it, along it.
  const Vec3 d{2, 0, 0};
  EXPECT_DOUBLE_EQ(segment_triangle_distance_squared({0.5, -1, 1}, {0.5, 1, 1}, a, b, d), 1);
  EXPECT_EQ(segment_triangle_distance_squared({0.5, -1, 0}, {0.5, 1, 0}, a, d, b), 0);
  EXPECT_DOUBLE_EQ(segment_triangle_distance_squared({3, 0, 0}, {5, 0, 0}, a, b, d), 1);
  // All of it in one point.
  EXPECT_DOUBLE_EQ(segment_triangle_distance_squared({0, 0, 3}, {0, 0, 3}, a, a, a), 9);
}

// Random segments and triangles, many of them through each other: the exact
// distance against the least exact point-triangle distance over points of
// the segment (within one grid step of the truth), and the candidates'
// minimum where they do not meet.
TEST(SegmentTriangleDistance, AgainstSampling) {
  Random random(41);
  const int n = 2000;
  int piercing = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 a = random.point(), b = random.point(), c = random.point();
    const Vec3 s0 = random.point(-2, 2);
    // Half of them aimed through the triangle's centroid.
    const Vec3 centroid = scaled(add(add(a, b), c), 1.0 / 3);
    const Vec3 s1 = trial % 2 ? random.point(-2, 2) : lerp(s0, centroid, random.uniform(0.5, 2));
    const double exact = std::sqrt(segment_triangle_distance_squared(s0, s1, a, b, c));
    double sampled = HUGE_VAL;
    for (int i = 0; i <= n; ++i)
      sampled = std::min(sampled, std::sqrt(point_triangle_distance_squared(
                                      lerp(s0, s1, double(i) / n), a, b, c)));
    EXPECT_LE(exact, sampled + 1e-12) << "trial " << trial;
    EXPECT_LE(sampled - exact, norm(sub(s1, s0)) / n + 1e-12) << "trial " << trial;
    piercing += exact == 0;
  }
  EXPECT_GT(piercing, 50);
}

TEST(SegmentTriangleDistance, GradientMatchesFiniteDifferences) {
  Random random(42);
  const std::function<double(const std::array<Vec3, 5>&)> f = [](const std::array<Vec3, 5>& x) {
    return segment_triangle_distance_squared(x[0], x[1], x[2], x[3], x[4]);
  };
  int checked = 0, skipped = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const auto t = proper_triangle(random);
    const std::array<Vec3, 5> x = {random.point(-2, 2), random.point(-2, 2), t[0], t[1], t[2]};
    if (f(x) < 1e-2) continue;
    std::array<Vec3, 5> g;
    segment_triangle_distance_squared(x[0], x[1], x[2], x[3], x[4], &g);
    // Translation invariance: the gradients sum to zero.
    const Vec3 sum = add(add(add(g[0], g[1]), add(g[2], g[3])), g[4]);
    EXPECT_LT(norm(sum), 1e-12);
    expect_gradient_away_from_ties(f, x, g, 1e-6, 1e-6, checked, skipped);
  }
  std::printf("segment-triangle gradient: %d coordinates checked, %d skipped at ties\n", checked,
              skipped);
  EXPECT_LT(skipped, checked / 100);
}

TEST(ObstacleDistance, KnownAnswers) {
  const Obstacle ball = sphere_obstacle({0, 0, 0}, 1);
  const Vec3 a{-1, -1, 2}, b{2, -1, 2}, c{-1, 2, 2};  // over the centre, at z = 2
  EXPECT_DOUBLE_EQ(triangle_obstacle_distance(ball, a, b, c), 1);
  std::array<Vec3, 3> g;
  triangle_obstacle_distance(ball, a, b, c, &g);
  // The nearest point (0, 0, 2) has weights (1/3, 1/3, 1/3) along +z.
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(g[k][2], 1.0 / 3, 1e-15);
    EXPECT_NEAR(norm(g[k]), 1.0 / 3, 1e-15);
  }
  const Vec3 down{0, 0, -2}, deep{0, 0, -1.5};
  EXPECT_DOUBLE_EQ(triangle_obstacle_distance(ball, add(a, deep), add(b, deep), add(c, deep)),
                   -0.5);  // minus the depth of the deepest point (0, 0, 0.5)
  EXPECT_DOUBLE_EQ(triangle_obstacle_distance(ball, add(a, down), add(b, down), add(c, down)),
                   -1);  // through the centre: the gradient has no direction
  triangle_obstacle_distance(ball, add(a, down), add(b, down), add(c, down), &g);
  for (const Vec3& v : g) EXPECT_EQ(norm(v), 0);

  // A cylinder along y of height 2 and radius 0.5: beside the side the
  // capsule's value is the cylinder's distance; over a cap it is R less.
  const Obstacle post = cylinder_obstacle({0, 0, 0}, {0, 1, 0}, 2, 0.5);
  const Vec3 p{1.5, -0.5, -1}, q{1.5, 0.5, -1}, r{1.5, 0, 1};  // the plane x = 1.5
  EXPECT_DOUBLE_EQ(triangle_obstacle_distance(post, p, q, r), 1);
  const Vec3 u{-1, 2, -1}, v{1, 2, -1}, w{0, 2, 1};  // the plane y = 2, across the axis
  EXPECT_DOUBLE_EQ(triangle_obstacle_distance(post, u, v, w), 0.5);
  EXPECT_DOUBLE_EQ(signed_distance(post, {0, 2, 0}), 1);
  // Through the axis segment: -R.
  EXPECT_DOUBLE_EQ(triangle_obstacle_distance(post, {-1, 0.3, -1}, {1, 0.3, -1}, {0, 0.3, 1}),
                   -0.5);
  // A degenerate cylinder of height 0 is a sphere.
  const Obstacle disc = cylinder_obstacle({0, 0, 0}, {0, 1, 0}, 0, 1);
  EXPECT_DOUBLE_EQ(triangle_obstacle_distance(disc, a, b, c), 1);

  // A plane: the lowest corner, with the normal as its gradient.
  const Obstacle floor = plane_obstacle({0, 0, 1}, {0, 0, 1});
  EXPECT_DOUBLE_EQ(triangle_obstacle_distance(floor, {0, 0, 3}, {1, 0, 2}, {0, 1, 4}, &g), 1);
  EXPECT_EQ(g[0], kZero);
  EXPECT_EQ(g[1], (Vec3{0, 0, 1}));
  EXPECT_EQ(g[2], kZero);
  EXPECT_DOUBLE_EQ(triangle_obstacle_distance(floor, {0, 0, 3}, {1, 0, 0}, {0, 1, 4}), -1);
  EXPECT_EQ(triangle_obstacle_distance(floor, {0, 0, 3}, {1, 0, 1}, {0, 1, 4}), 0);  // touching

  // A mesh obstacle is not analytic.
  Obstacle mesh;
  mesh.type = Obstacle::Type::Mesh;
  EXPECT_THROW(triangle_obstacle_distance(mesh, a, b, c), Error);
  EXPECT_THROW(triangle_obstacle_ccd(mesh, a, b, c, down, down, down), Error);
}

// The value is the least signed distance of the solid (sphere, capsule,
// half-space) over the triangle, outside and inside alike: against a dense
// grid of the triangle. For a cylinder it is also at most the cylinder's own
// least signed distance and at least that less R.
TEST(ObstacleDistance, AgainstSampling) {
  Random random(43);
  const int n = 200;
  int inside[3] = {0, 0, 0}, outside[3] = {0, 0, 0};
  for (int trial = 0; trial < 900; ++trial) {
    const int type = trial % 3;
    const Obstacle o = random_obstacle(random, type);
    const std::array<Vec3, 3> t = {random.point(-2, 2), random.point(-2, 2), random.point(-2, 2)};
    const double exact = triangle_obstacle_distance(o, t[0], t[1], t[2]);
    const double step = longest_edge(t) / n;
    const double sampled =
        sampled_minimum(t, n, [&](const Vec3& p) { return solid_distance(o, p); });
    EXPECT_LE(exact, sampled + 1e-12) << "trial " << trial;
    EXPECT_LE(sampled - exact, step + 1e-12) << "trial " << trial;
    if (type == 1) {
      const double cylinder =
          sampled_minimum(t, n, [&](const Vec3& p) { return signed_distance(o, p); });
      EXPECT_LE(exact, cylinder + 1e-12) << "trial " << trial;
      EXPECT_GE(exact, cylinder - step - o.radius - 1e-12) << "trial " << trial;
    }
    (exact > 0 ? outside : inside)[type] += 1;
  }
  for (int type = 0; type < 3; ++type) {
    EXPECT_GT(inside[type], 30) << type;
    EXPECT_GT(outside[type], 30) << type;
  }
}

// A cylinder's capsule value is at most the cylinder's least signed
// distance over the triangle, and equal to it (to the sampling's step) where
// it says so: in many trials beside the side, never beyond a cap.
TEST(ObstacleDistance, CylinderCapsuleValueAndWhereItIsExact) {
  Random random(47);
  const int n = 200;
  int exact_count = 0, inexact_count = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const Obstacle o = random_obstacle(random, 1);
    const std::array<Vec3, 3> t = {random.point(-2, 2), random.point(-2, 2), random.point(-2, 2)};
    bool exact = false;
    const double value = triangle_cylinder_distance(o, t[0], t[1], t[2], exact);
    EXPECT_EQ(value, triangle_obstacle_distance(o, t[0], t[1], t[2])) << "trial " << trial;
    const double step = longest_edge(t) / n;
    const double cylinder =
        sampled_minimum(t, n, [&](const Vec3& p) { return signed_distance(o, p); });
    EXPECT_LE(value, cylinder + 1e-12) << "trial " << trial;
    if (exact) {
      EXPECT_GT(value, 0) << "trial " << trial;
      EXPECT_GE(value, cylinder - step - 1e-12) << "trial " << trial;
    }
    (exact ? exact_count : inexact_count) += 1;
  }
  EXPECT_GT(exact_count, 50);
  EXPECT_GT(inexact_count, 50);
  Obstacle sphere;
  sphere.type = Obstacle::Type::Sphere;
  bool exact = false;
  EXPECT_THROW(triangle_cylinder_distance(sphere, kZero, kZero, kZero, exact), UsageError);
}

// Triangles through the solid, with every corner outside it (the face
// crosses) or one corner inside: never a positive value.
TEST(ObstacleDistance, CrossingTrianglesAreNotPositive) {
  Random random(44);
  for (int trial = 0; trial < 3000; ++trial) {
    const int type = trial % 3;
    const Obstacle o = random_obstacle(random, type);
    // A point inside the true solid (the cylinder, not only its capsule).
    Vec3 inner;
    do inner = random.point(-2, 2);
    while (!(signed_distance(o, inner) < 0));
    std::array<Vec3, 3> t;
    if (trial % 2) {
      // Corners on a circle of radius 5 around it, in a random plane.
      const Vec3 n = random.direction();
      const Vec3 e1 = unit(cross(n, random.direction())), e2 = cross(n, e1);
      const double phase = random.uniform(0, 2 * M_PI);
      for (int k = 0; k < 3; ++k) {
        const double angle = phase + 2 * M_PI * k / 3;
        t[k] = add(inner, add(scaled(e1, 5 * std::cos(angle)), scaled(e2, 5 * std::sin(angle))));
      }
    } else {
      t = {inner, random.point(-3, 3), random.point(-3, 3)};
    }
    EXPECT_LE(triangle_obstacle_distance(o, t[0], t[1], t[2]), 0) << "trial " << trial;
  }
}

TEST(ObstacleDistance, GradientMatchesFiniteDifferences) {
  Random random(45);
  int checked = 0, skipped = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    const Obstacle o = random_obstacle(random, trial % 3);
    const auto t = proper_triangle(random);
    const std::function<double(const std::array<Vec3, 3>&)> f = [&](const std::array<Vec3, 3>& x) {
      return triangle_obstacle_distance(o, x[0], x[1], x[2]);
    };
    // Away from the centre or axis (where the value has a kink, -R).
    if (f(t) < 1e-2 - o.radius) continue;
    std::array<Vec3, 3> g;
    triangle_obstacle_distance(o, t[0], t[1], t[2], &g);
    const Vec3 sum = add(add(g[0], g[1]), g[2]);  // a unit direction: translation
    EXPECT_NEAR(norm(sum), 1, 1e-12);
    expect_gradient_away_from_ties(f, t, g, 1e-6, 1e-6, checked, skipped);
  }
  std::printf("obstacle distance gradient: %d coordinates checked, %d skipped at ties\n", checked,
              skipped);
  EXPECT_LT(skipped, checked / 100);
}

TEST(ObstacleDistance, ScaleInvariance) {
  Random random(46);
  for (int trial = 0; trial < 900; ++trial) {
    const Obstacle o = random_obstacle(random, trial % 3);
    const std::array<Vec3, 3> t = {random.point(-2, 2), random.point(-2, 2), random.point(-2, 2)};
    for (const double scale : {1024.0, 1000.0}) {
      Obstacle big = o;
      big.center = scaled(o.center, scale);
      big.radius = o.radius * scale;
      big.height = o.height * scale;
      std::array<Vec3, 3> g, g_big;
      const double d = triangle_obstacle_distance(o, t[0], t[1], t[2], &g);
      const double d_big = triangle_obstacle_distance(big, scaled(t[0], scale), scaled(t[1], scale),
                                                      scaled(t[2], scale), &g_big);
      if (scale == 1024) {
        EXPECT_EQ(d_big, scale * d);  // exact scaling
        EXPECT_EQ(g_big, g);
      } else {
        EXPECT_NEAR(d_big, scale * d, 1e-12 * scale) << "trial " << trial;
        for (int k = 0; k < 3; ++k)
          for (int c = 0; c < 3; ++c) EXPECT_NEAR(g_big[k][c], g[k][c], 1e-9);
      }
    }
  }
}

TEST(ObstacleCcd, KnownAnswers) {
  // A triangle 1 above a unit sphere's top, over its centre, falling by 2:
  // contact at t = 0.5.
  const Obstacle ball = sphere_obstacle({0, 0, 0}, 1);
  const Vec3 a{-1, -1, 2}, b{2, -1, 2}, c{-1, 2, 2}, down{0, 0, -2};
  const double on_ball = triangle_obstacle_ccd(ball, a, b, c, down, down, down);
  EXPECT_GT(on_ball, 0.4);
  EXPECT_LT(on_ball, 0.5);
  // Tilting as it falls (corners at different speeds), contact later.
  const double tilted = triangle_obstacle_ccd(ball, a, b, c, down, {0, 0, -1}, {0, 0, -3});
  EXPECT_GT(tilted, 0.2);
  EXPECT_LT(tilted, 0.5);
  // Onto the side of a cylinder along y (radius 0.5, height 4) from 1 above.
  const Obstacle post = cylinder_obstacle({0, 0, 0}, {0, 1, 0}, 4, 0.5);
  const Vec3 p{-1, -1, 1.5}, q{1, -1, 1.5}, r{0, 1, 1.5};
  const double on_post = triangle_obstacle_ccd(post, p, q, r, down, down, down);
  EXPECT_GT(on_post, 0.4);
  EXPECT_LT(on_post, 0.5);
  // Onto a plane from 1 above: exactly where the gap falls to 0.1.
  const Obstacle floor = plane_obstacle({0, 0, 1}, {0, 0, 1});
  EXPECT_DOUBLE_EQ(triangle_obstacle_ccd(floor, a, b, c, down, down, down), 0.45);
  // Tilted: corner b reaches z = 1.1 first, at 0.9 / 3.
  EXPECT_DOUBLE_EQ(triangle_obstacle_ccd(floor, a, b, c, down, {0, 0, -3}, {0, 0, 1}), 0.3);

  // Near misses: falling past the sphere 0.6 from it; past the cylinder's
  // end; parallel to the plane.
  const Vec3 far_a{1.6, -0.2, 3}, far_b{2, 0.2, 3}, far_c{2, -0.2, 3}, fall{0, 0, -6};
  EXPECT_EQ(triangle_obstacle_ccd(ball, far_a, far_b, far_c, fall, fall, fall), 1);
  const Vec3 beyond{0, 4, 0};  // the nearest corner 1 beyond the end, the capsule's R = 0.5
  EXPECT_EQ(
      triangle_obstacle_ccd(post, add(p, beyond), add(q, beyond), add(r, beyond), down, down, down),
      1);
  const Vec3 slide{5, -3, 0};
  EXPECT_EQ(triangle_obstacle_ccd(floor, a, b, c, slide, slide, slide), 1);
  // Sliding along the cylinder at a constant distance.
  const Vec3 along{0, 1, 0};
  EXPECT_EQ(triangle_obstacle_ccd(post, p, q, r, along, along, along), 1);
  // Moving away.
  const Vec3 up{0, 0, 3};
  EXPECT_EQ(triangle_obstacle_ccd(ball, a, b, c, up, up, up), 1);
  EXPECT_EQ(triangle_obstacle_ccd(post, p, q, r, up, up, up), 1);
  EXPECT_EQ(triangle_obstacle_ccd(floor, a, b, c, up, up, up), 1);
  // Not moving.
  EXPECT_EQ(triangle_obstacle_ccd(ball, a, b, c, kZero, kZero, kZero), 1);
  EXPECT_EQ(triangle_obstacle_ccd(floor, a, b, c, kZero, kZero, kZero), 1);
  // Starting in contact (or touching): 0, whatever the motion.
  const Vec3 sunk{0, 0, -1.5};
  EXPECT_EQ(triangle_obstacle_ccd(ball, add(a, sunk), add(b, sunk), add(c, sunk), up, up, up), 0);
  EXPECT_EQ(triangle_obstacle_ccd(post, {-1, 0, 0}, {1, 0, 0}, {0, 1, 1}, up, up, up), 0);
  EXPECT_EQ(triangle_obstacle_ccd(floor, {0, 0, 1}, b, c, up, up, up), 0);
  EXPECT_EQ(triangle_obstacle_ccd(floor, {0, 0, 1}, b, c, kZero, kZero, kZero), 0);
  // t_max bounds the answer, and a lower t_max does not change a time below it.
  CcdOptions options;
  options.t_max = 0.3;
  EXPECT_EQ(triangle_obstacle_ccd(ball, a, b, c, down, down, down, options), 0.3);
  EXPECT_EQ(triangle_obstacle_ccd(floor, a, b, c, down, down, down, options), 0.3);
  EXPECT_EQ(triangle_obstacle_ccd(ball, a, b, c, up, up, up, options), 0.3);
  options.t_max = 0.48;
  EXPECT_EQ(triangle_obstacle_ccd(ball, a, b, c, down, down, down, options), on_ball);
}

TEST(ObstacleCcd, ScaleInvariance) {
  Random random(47);
  for (int trial = 0; trial < 600; ++trial) {
    const Obstacle o = random_obstacle(random, trial % 3);
    std::array<Vec3, 6> x;
    for (Vec3& v : x) v = random.point(-2, 2);
    const double toi = triangle_obstacle_ccd(o, x[0], x[1], x[2], x[3], x[4], x[5]);
    for (const double scale : {1024.0, 1000.0}) {
      Obstacle big = o;
      big.center = scaled(o.center, scale);
      big.radius = o.radius * scale;
      big.height = o.height * scale;
      std::array<Vec3, 6> y;
      for (int k = 0; k < 6; ++k) y[k] = scaled(x[k], scale);
      const double scaled = triangle_obstacle_ccd(big, y[0], y[1], y[2], y[3], y[4], y[5]);
      if (scale == 1024) {
        EXPECT_EQ(scaled, toi) << "trial " << trial;
      } else {
        EXPECT_NEAR(scaled, toi, 1e-9) << "trial " << trial;
      }
    }
  }
}

// Random triangles in [-2, 2]^3 near random spheres, cylinders and planes,
// most of them starting outside, with steps of up to about 3 per corner
// aimed at the obstacle: 0 for a triangle that starts inside; otherwise the
// value never reaches 0 on [0, toi] (proven by samples and its Lipschitz
// bound) and stays above (1 - 0.9) * 0.1 of its start, no sampled point of
// the triangle enters the true obstacle (the cylinder itself, through
// signed_distance), and toi is never after the first contact (found by a
// fine grid of times and bisection) and not far before it on average.
TEST(ObstacleCcd, NeverTouchesOnRandomSteps) {
  Random random(48);
  const CcdOptions options;
  int colliding = 0, started_inside = 0;
  double ratio_sum = 0, worst_ratio = 1;
  for (int trial = 0; trial < 10000; ++trial) {
    const int type = trial % 3;
    const Obstacle o = random_obstacle(random, type);
    // Mostly triangles that start outside (a few tries), some inside.
    std::array<Vec3, 3> x, dx;
    for (int attempt = 0; attempt < (trial % 10 ? 20 : 1); ++attempt) {
      for (Vec3& v : x) v = random.point(-2, 2);
      if (triangle_obstacle_distance(o, x[0], x[1], x[2]) > 0) break;
    }
    const Vec3 centroid = scaled(add(add(x[0], x[1]), x[2]), 1.0 / 3);
    // Towards the obstacle (a plane's point may be far to the side: its normal).
    const Vec3 towards = o.type == Obstacle::Type::Plane
                             ? scaled(o.normal, -signed_distance(o, centroid))
                             : sub(o.center, centroid);
    const Vec3 aim = scaled(towards, random.uniform(0.5, 2.5));
    for (Vec3& d : dx) d = add(aim, scaled(random.point(), random.uniform(0, 1)));
    const double toi = triangle_obstacle_ccd(o, x[0], x[1], x[2], dx[0], dx[1], dx[2], options);
    ASSERT_GE(toi, 0);
    ASSERT_LE(toi, 1);
    const auto at = [&](double t) {
      return std::array<Vec3, 3>{add(x[0], scaled(dx[0], t)), add(x[1], scaled(dx[1], t)),
                                 add(x[2], scaled(dx[2], t))};
    };
    const auto distance = [&](double t) {
      const auto y = at(t);
      return triangle_obstacle_distance(o, y[0], y[1], y[2]);
    };
    const double d0 = distance(0);
    if (!(d0 > 0)) {
      ASSERT_EQ(toi, 0) << "trial " << trial;
      ++started_inside;
      continue;
    }
    const double speed = std::max({norm(dx[0]), norm(dx[1]), norm(dx[2])});
    ASSERT_TRUE(stays_above(distance, speed, 0, toi, d0, distance(toi), 0, 40))
        << "trial " << trial;
    // Rounding of the value is relative to the obstacle's size.
    const double slack = 1e-12 * (1 + o.radius);
    for (int s = 1; s <= 100; ++s)
      ASSERT_GE(distance(toi * s / 100), 0.01 * d0 - slack) << "trial " << trial;
    if (toi < 1) {
      EXPECT_GE(distance(toi), 0.1 * d0 - slack) << "trial " << trial;
    }
    for (int s = 0; s <= 40; ++s) {
      const auto y = at(toi * s / 40);
      ASSERT_GT(sampled_minimum(y, 6, [&](const Vec3& p) { return signed_distance(o, p); }), 0)
          << "trial " << trial;
    }
    // The first contact: a sign change of the value on a grid, bisected.
    const int n = 400;
    double contact = HUGE_VAL;
    for (int i = 1; i <= n && contact > 1; ++i) {
      double lo = double(i - 1) / n, hi = double(i) / n;
      if (distance(hi) > 0) continue;
      for (int k = 0; k < 50; ++k) {
        const double mid = 0.5 * (lo + hi);
        (distance(mid) > 0 ? lo : hi) = mid;
      }
      contact = hi;
    }
    if (contact <= 1) {
      ASSERT_LE(toi, contact) << "trial " << trial;
      ++colliding;
      ratio_sum += toi / contact;
      worst_ratio = std::min(worst_ratio, toi / contact);
    }
  }
  const double mean_ratio = ratio_sum / colliding;
  std::printf(
      "%d of 10000 random steps reach the obstacle, %d start inside; toi / first contact: mean "
      "%.3f, worst %.3g\n",
      colliding, started_inside, mean_ratio, worst_ratio);
  RecordProperty("colliding", colliding);
  RecordProperty("mean_ratio", std::to_string(mean_ratio));
  EXPECT_GT(colliding, 4000);
  EXPECT_GT(started_inside, 200);
  EXPECT_GE(mean_ratio, 0.5);
}

}  // namespace
}  // namespace foldfill
