// A triangle against an analytic obstacle (sphere, cylinder as its capsule,
// plane): the segment-triangle distance the capsule needs, the least signed
// distance over the triangle with its gradient, and a conservative time of
// impact along a linear step. O(1) per triangle, no tessellation.
#include <algorithm>
#include <cmath>
#include <limits>

#include "foldfill/collision.h"
#include "foldfill/error.h"
#include "foldfill/obstacles.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

// As in collision_distance.cpp: below this squared sine of the angle between
// two edges the triangle has no reliable normal and is taken as its three
// segments (exact for a truly degenerate one, off by at most the sliver's
// height otherwise).
constexpr double kDegenerate = 1e-14;

// Whether the segment crosses the plane of the proper triangle (normal n)
// strictly from one side to the other, through the triangle: its ends'
// heights have opposite signs and its line passes on the same side of the
// three edges (the triple products with the edges, seen from s0, share a
// sign; a zero is a line through an edge, which is a contact too).
bool pierces(const Vec3& s0, const Vec3& s1, const Vec3& a, const Vec3& b, const Vec3& c,
             const Vec3& n) {
  const double h0 = dot(n, sub(s0, a)), h1 = dot(n, sub(s1, a));
  if (!((h0 > 0 && h1 < 0) || (h0 < 0 && h1 > 0))) return false;
  const Vec3 u = sub(s1, s0), pa = sub(a, s0), pb = sub(b, s0), pc = sub(c, s0);
  const double wa = dot(u, cross(pb, pc)), wb = dot(u, cross(pc, pa)), wc = dot(u, cross(pa, pb));
  return (wa >= 0 && wb >= 0 && wc >= 0) || (wa <= 0 && wb <= 0 && wc <= 0);
}

void require_analytic(const Obstacle& obstacle, const char* function) {
  if (obstacle.type == Obstacle::Type::Mesh)
    throw UsageError(std::string(function) +
                     ": a mesh obstacle is not a sphere, cylinder or plane");
}

// The ends of a cylinder's axis segment.
void axis_segment(const Obstacle& cylinder, Vec3& s0, Vec3& s1) {
  const Vec3 half = scaled(cylinder.axis, 0.5 * cylinder.height);
  s0 = sub(cylinder.center, half);
  s1 = add(cylinder.center, half);
}

// The signed heights of the corners over a plane obstacle.
std::array<double, 3> plane_heights(const Obstacle& plane, const Vec3& a, const Vec3& b,
                                    const Vec3& c) {
  return {dot(sub(a, plane.center), plane.normal), dot(sub(b, plane.center), plane.normal),
          dot(sub(c, plane.center), plane.normal)};
}

}  // namespace

// The closest pair of the segment and the triangle, two convex sets: where
// they do not meet, a point of the pair is on one set's boundary unless the
// segment is parallel to the plane, where sliding the pair along the segment
// reaches an end or an edge at the same distance. So an end of the segment
// against the triangle, or the segment against an edge. Each candidate is
// computed without its gradient; the least one again with it.
double segment_triangle_distance_squared(const Vec3& s0, const Vec3& s1, const Vec3& a,
                                         const Vec3& b, const Vec3& c,
                                         std::array<Vec3, 5>* gradient) {
  const Vec3 ab = sub(b, a), ac = sub(c, a);
  const Vec3 n = cross(ab, ac);
  if (dot(n, n) > kDegenerate * dot(ab, ab) * dot(ac, ac) && pierces(s0, s1, a, b, c, n)) {
    if (gradient) gradient->fill({0, 0, 0});
    return 0;
  }
  const Vec3* corner[3] = {&a, &b, &c};
  // Candidates 0, 1: the ends s0, s1; 2 + e: the edge (corner e, corner e + 1).
  double best = std::numeric_limits<double>::infinity();
  int best_candidate = 0;
  for (int k = 0; k < 5; ++k) {
    const double d2 =
        k < 2 ? point_triangle_distance_squared(k == 0 ? s0 : s1, a, b, c)
              : edge_edge_distance_squared(s0, s1, *corner[k - 2], *corner[(k - 1) % 3]);
    if (d2 < best) {
      best = d2;
      best_candidate = k;
    }
  }
  if (gradient) {
    std::array<Vec3, 4> g;
    gradient->fill({0, 0, 0});
    if (best_candidate < 2) {
      point_triangle_distance_squared(best_candidate == 0 ? s0 : s1, a, b, c, &g);
      (*gradient)[best_candidate] = g[0];
      for (int k = 0; k < 3; ++k) (*gradient)[2 + k] = g[1 + k];
    } else {
      const int e = best_candidate - 2;
      edge_edge_distance_squared(s0, s1, *corner[e], *corner[(e + 1) % 3], &g);
      (*gradient)[0] = g[0];
      (*gradient)[1] = g[1];
      (*gradient)[2 + e] = g[2];
      (*gradient)[2 + (e + 1) % 3] = g[3];
    }
  }
  return best;
}

// d = sqrt(d2) - R for the sphere and the capsule; the gradient of sqrt(d2)
// is that of d2 over 2 sqrt(d2), and taken as zero at d2 = 0.
double triangle_cylinder_distance(const Obstacle& cylinder, const Vec3& a, const Vec3& b,
                                  const Vec3& c, bool& exact) {
  if (cylinder.type != Obstacle::Type::Cylinder)
    throw UsageError("triangle_cylinder_distance: not a cylinder");
  Vec3 s0, s1;
  axis_segment(cylinder, s0, s1);
  // The weights of the segment's ends in its nearest point are the shares
  // of their gradients: both non-zero where that point is inside.
  std::array<Vec3, 5> g;
  const double d = std::sqrt(segment_triangle_distance_squared(s0, s1, a, b, c, &g));
  exact = d > cylinder.radius && norm(g[0]) > 0 && norm(g[1]) > 0;
  return d - cylinder.radius;
}

double triangle_obstacle_distance(const Obstacle& obstacle, const Vec3& a, const Vec3& b,
                                  const Vec3& c, std::array<Vec3, 3>* gradient) {
  require_analytic(obstacle, "triangle_obstacle_distance");
  switch (obstacle.type) {
    case Obstacle::Type::Sphere: {
      std::array<Vec3, 4> g;
      const double d = std::sqrt(
          point_triangle_distance_squared(obstacle.center, a, b, c, gradient ? &g : nullptr));
      if (gradient) {
        const double s = d > 0 ? 0.5 / d : 0.0;
        for (int k = 0; k < 3; ++k) (*gradient)[k] = scaled(g[1 + k], s);
      }
      return d - obstacle.radius;
    }
    case Obstacle::Type::Cylinder: {
      Vec3 s0, s1;
      axis_segment(obstacle, s0, s1);
      std::array<Vec3, 5> g;
      const double d =
          std::sqrt(segment_triangle_distance_squared(s0, s1, a, b, c, gradient ? &g : nullptr));
      if (gradient) {
        const double s = d > 0 ? 0.5 / d : 0.0;
        for (int k = 0; k < 3; ++k) (*gradient)[k] = scaled(g[2 + k], s);
      }
      return d - obstacle.radius;
    }
    case Obstacle::Type::Plane: {
      const std::array<double, 3> h = plane_heights(obstacle, a, b, c);
      const int least = static_cast<int>(std::min_element(h.begin(), h.end()) - h.begin());
      if (gradient) {
        gradient->fill({0, 0, 0});
        (*gradient)[least] = obstacle.normal;
      }
      return h[least];
    }
    case Obstacle::Type::Mesh:
      break;
  }
  return std::numeric_limits<double>::quiet_NaN();  // not reached
}

// Plane: corner k's height is h_k + t v_k (v_k its speed along the normal),
// and falls to gap * d0 at (h_k - gap d0) / -v_k when v_k < 0; the least of
// those times is where the value (their minimum) first does.
//
// Sphere and cylinder: Additive CCD as in ccd.cpp, with the speed bound of a
// fixed obstacle: the largest of the corners' moves (no mean motion to take
// out, the obstacle not moving). A step of eta d / speed leaves at least
// (1 - eta) d; the times do not depend on t_max, which only ends them.
double triangle_obstacle_ccd(const Obstacle& obstacle, const Vec3& a, const Vec3& b, const Vec3& c,
                             const Vec3& da, const Vec3& db, const Vec3& dc,
                             const CcdOptions& options) {
  require_analytic(obstacle, "triangle_obstacle_ccd");
  const double t_max = options.t_max;
  if (obstacle.type == Obstacle::Type::Plane) {
    const std::array<double, 3> h = plane_heights(obstacle, a, b, c);
    const std::array<double, 3> v = {dot(da, obstacle.normal), dot(db, obstacle.normal),
                                     dot(dc, obstacle.normal)};
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(h[k]) || !std::isfinite(v[k])) return 0;  // not finite
    const double d0 = std::min({h[0], h[1], h[2]});
    if (!(d0 > 0)) return 0;  // in contact
    const double target = options.gap * d0;
    double toi = t_max;
    for (int k = 0; k < 3; ++k)
      if (v[k] < 0) toi = std::min(toi, (h[k] - target) / -v[k]);
    return toi;
  }
  const double speed = std::max({norm(da), norm(db), norm(dc)});
  const double d0 = triangle_obstacle_distance(obstacle, a, b, c);
  if (speed == 0) return d0 > 0 ? t_max : 0;
  if (!(d0 > 0) || !(speed < HUGE_VAL)) return 0;  // in contact, or not finite
  const double target = options.gap * d0;
  double t = 0, step = (1 - options.gap) * d0 / speed;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    const double next = t + step;
    if (t == 0 && next > t_max) return t_max;  // no check after the first step
    const double d = triangle_obstacle_distance(obstacle, add(a, scaled(da, next)),
                                                add(b, scaled(db, next)), add(c, scaled(dc, next)));
    if (!(d >= target)) {
      if (t > 0) return t;
      // The first step leaves gap * d0 by construction, up to the rounding of
      // d (relative to R, not to d0): go on unless that left nothing.
      if (!(d > 0)) return 0;
    }
    t = next;
    if (t > t_max) return t_max;
    step = options.rescaling * d / speed;
  }
  return t;
}

}  // namespace foldfill
