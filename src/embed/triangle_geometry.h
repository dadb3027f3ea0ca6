// Distances between points, segments and triangles in floating point, shared
// by the obstacles and the crossing measurements (private to src/). Whether
// two triangles intersect is not decided here: the callers use CGAL's exact
// predicates for that, and these distances only for triangles that do not.
#pragma once

#include <algorithm>
#include <array>

#include "foldfill/mesh.h"

namespace foldfill::geometry {

using Triangle = std::array<Vec3, 3>;

// A unit vector perpendicular to the unit vector `a`.
Vec3 any_perpendicular(const Vec3& a);

// The triangle's smallest angle, in degrees (0 for a degenerate one).
double smallest_angle_deg(const Triangle& t);

// The point of the triangle (a degenerate one too) nearest to `p`.
Vec3 closest_point_on_triangle(const Vec3& p, const Triangle& t);

// The distance between the segments [p0, p1] and [q0, q1] (either may be a point).
double segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

// The distance between two triangles that do not intersect: the least of the
// distances from each corner to the other triangle and between the edges.
double disjoint_triangle_distance(const Triangle& a, const Triangle& b);

// The smallest value of `f` over [0, 1], `f` convex: a golden-section search
// of kGoldenSteps steps, the least value seen (the ends included). Stops at
// once at a value below `stop_below`.
constexpr int kGoldenSteps = 48;  // the bracket shrinks to 1e-10 of its length
template <typename F>
double golden_minimum(F f, double stop_below) {
  constexpr double kRatio = 0.6180339887498949;  // (sqrt(5) - 1) / 2
  double best = std::min(f(0.0), f(1.0));
  double low = 0, high = 1, x1 = high - kRatio, x2 = low + kRatio;
  double f1 = f(x1), f2 = f(x2);
  for (int step = 0; step < kGoldenSteps && best >= stop_below; ++step) {
    best = std::min({best, f1, f2});
    if (f1 <= f2) {
      high = x2;
      x2 = x1;
      f2 = f1;
      x1 = high - kRatio * (high - low);
      f1 = f(x1);
    } else {
      low = x1;
      x1 = x2;
      f1 = f2;
      x2 = low + kRatio * (high - low);
      f2 = f(x2);
    }
  }
  return std::min({best, f1, f2});
}

// The smallest value of `f`, a convex function, over the triangle `t`:
// nested golden-section searches, the outer one across the segments parallel
// to (t[1], t[2]), the inner one along each (the least of `f` along them is a
// convex function of their place). Its error is that of each search's
// bracket, 1e-10 of the triangle's size, times the slope of `f` (at most 1
// for a distance). Stops at once at a value below `stop_below`.
template <typename F>
double minimum_over_triangle(const Triangle& t, F f, double stop_below) {
  const auto along = [&](double s) {
    return golden_minimum(
        [&](double u) {
          Vec3 p;
          for (int c = 0; c < 3; ++c)
            p[c] = t[0][c] + s * ((1 - u) * (t[1][c] - t[0][c]) + u * (t[2][c] - t[0][c]));
          return f(p);
        },
        stop_below);
  };
  return golden_minimum(along, stop_below);
}

}  // namespace foldfill::geometry
