// Point-triangle and edge-edge distances with their gradients, and the IPC
// log barrier on them.
#include <algorithm>
#include <cmath>
#include <limits>

#include "foldfill/collision.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

// Below this squared sine of the angle between two edge vectors, their cross
// product is too inaccurate to give a normal (a relative error of about
// 1e-16 / 1e-7): the triangle is taken as degenerate, the edges as parallel.
// The closest points are then on the boundary (the triangle's edges, the
// segments' ends), which is exact for truly degenerate inputs and off by at
// most the squared height of the sliver, below 1e-14 of its squared edge
// lengths, otherwise.
constexpr double kDegenerate = 1e-14;

// Squared distance from `p` to the segment [a, b] (a point when a == b), with
// the parameter t of the closest point a + t (b - a) and p minus that point.
double point_segment(const Vec3& p, const Vec3& a, const Vec3& b, double& t, Vec3& difference) {
  const Vec3 ab = sub(b, a), ap = sub(p, a);
  const double length_sq = dot(ab, ab);
  t = length_sq > 0 ? std::clamp(dot(ap, ab) / length_sq, 0.0, 1.0) : 0.0;
  difference = {ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
  return dot(difference, difference);
}

}  // namespace

// In the plane of a proper triangle the projection of p has barycentric
// weights (u, v, w); all >= 0: the face is nearest. Otherwise the nearest
// point is on the edges opposite the negative weights (one, or two meeting
// at the corner of the positive weight): the triangle lies on the inner side
// of the line of each edge, and a point on the inner side of an edge's line
// is never nearest to that edge's interior. A degenerate triangle is its
// three segments.
namespace {

// Whether separation / |m| is at least sqrt(distance_sq), a hair more, where
// `separation` is the least of (q - p) . m over the points of two sets.
constexpr double kSeparationSlack = 1 + 1e-9;
bool separated(double separation, const Vec3& m, double distance_sq) {
  return separation > 0 && separation * separation > kSeparationSlack * distance_sq * dot(m, m);
}

}  // namespace

bool point_triangle_farther(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                            double distance_sq) {
  // From the centroid to the point: every point q of the triangle has
  // (p - q) . m at least its least corner's.
  const Vec3 m{p[0] - (a[0] + b[0] + c[0]) / 3, p[1] - (a[1] + b[1] + c[1]) / 3,
               p[2] - (a[2] + b[2] + c[2]) / 3};
  if (separated(std::min({dot(sub(p, a), m), dot(sub(p, b), m), dot(sub(p, c), m)}), m,
                distance_sq))
    return true;
  const Vec3 n = cross(sub(b, a), sub(c, a));
  return separated(std::abs(dot(sub(p, a), n)), n, distance_sq);
}

bool edge_edge_farther(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                       double distance_sq) {
  // m from one middle to the other: along any w, the segments' points lie
  // within half their projections of their middles. Along m itself, and
  // along m made square to each segment (side by side segments, parallel
  // in a regular sheet, are separated across them, not along m).
  const Vec3 m{0.5 * (b0[0] + b1[0] - a0[0] - a1[0]), 0.5 * (b0[1] + b1[1] - a0[1] - a1[1]),
               0.5 * (b0[2] + b1[2] - a0[2] - a1[2])};
  const Vec3 a = sub(a1, a0), b = sub(b1, b0);
  const auto separated_along = [&](const Vec3& w) {
    return separated(dot(m, w) - 0.5 * (std::abs(dot(a, w)) + std::abs(dot(b, w))), w, distance_sq);
  };
  if (separated_along(m)) return true;
  const auto square_to = [&](const Vec3& e) {
    const double ee = dot(e, e);
    return ee > 0 ? sub(m, scaled(e, dot(m, e) / ee)) : m;
  };
  return separated_along(square_to(a)) || separated_along(square_to(b));
}

double point_triangle_distance_squared(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                       std::array<Vec3, 4>* gradient) {
  const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const Vec3 n = cross(ab, ac);
  const double nn = dot(n, n);
  // Edges to try: bit 0 for (a, b), bit 1 for (b, c), bit 2 for (c, a).
  int edges = 7;
  if (nn > kDegenerate * dot(ab, ab) * dot(ac, ac)) {
    const double inverse = 1 / nn;
    const double v = dot(n, cross(ap, ac)) * inverse, w = dot(n, cross(ab, ap)) * inverse;
    const double u = 1 - v - w;
    if (u >= 0 && v >= 0 && w >= 0) {
      // Height over the plane from the normal (accurate when p is close).
      const double height = dot(n, ap);
      if (gradient) {
        const Vec3 d = scaled(n, 2 * height * inverse);  // 2 (p - q)
        (*gradient)[0] = d;
        (*gradient)[1] = scaled(d, -u);
        (*gradient)[2] = scaled(d, -v);
        (*gradient)[3] = scaled(d, -w);
      }
      return height * height * inverse;
    }
    edges = (w < 0 ? 1 : 0) | (u < 0 ? 2 : 0) | (v < 0 ? 4 : 0);
  }
  const Vec3* corner[3] = {&a, &b, &c};
  double best = std::numeric_limits<double>::infinity(), best_t = 0;
  int best_edge = 0;
  Vec3 best_difference{0, 0, 0};
  for (int e = 0; e < 3; ++e) {
    if (!(edges >> e & 1)) continue;
    double t;
    Vec3 difference;
    const double d2 = point_segment(p, *corner[e], *corner[(e + 1) % 3], t, difference);
    if (d2 < best) {
      best = d2;
      best_t = t;
      best_edge = e;
      best_difference = difference;
    }
  }
  if (gradient) {
    const Vec3 d = scaled(best_difference, 2);
    (*gradient)[0] = d;
    for (int k = 1; k < 4; ++k) (*gradient)[k] = {0, 0, 0};
    (*gradient)[1 + best_edge] = scaled(d, -(1 - best_t));
    (*gradient)[1 + (best_edge + 1) % 3] = scaled(d, -best_t);
  }
  return best;
}

// The closest points are a0 + s (a1 - a0) and b0 + t (b1 - b0) with (s, t)
// minimising a convex quadratic F over the unit square: where the lines are
// closest when that is inside the square, else on the square's boundary,
// i.e. an end of one segment against the other segment. Which ends: F
// decreases from any point of the square towards the lines' closest pair
// (s*, t*), so the square's minimum is on a side whose bound (s*, t*)
// breaks (s* < 0: the side s = 0); one or two sides. Parallel or degenerate
// segments try all four.
double edge_edge_distance_squared(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                                  std::array<Vec3, 4>* gradient) {
  const Vec3 u = sub(a1, a0), v = sub(b1, b0), w = sub(a0, b0);
  const Vec3 n = cross(u, v);
  const double nn = dot(n, n);
  // Sides to try: bit 0 for s = 0 (end a0), 1 for s = 1, 2 for t = 0, 3 for t = 1.
  int sides = 15;
  if (nn > kDegenerate * dot(u, u) * dot(v, v)) {
    // w + s u - t v is parallel to n: cross with v (resp. u) and dot with n.
    const double inverse = 1 / nn;
    const double s = dot(n, cross(v, w)) * inverse, t = dot(n, cross(u, w)) * inverse;
    sides = (s < 0 ? 1 : 0) | (s > 1 ? 2 : 0) | (t < 0 ? 4 : 0) | (t > 1 ? 8 : 0);
    if (sides == 0) {
      const double height = dot(n, w);
      if (gradient) {
        const Vec3 d = scaled(n, 2 * height * inverse);  // 2 (qa - qb)
        (*gradient)[0] = scaled(d, 1 - s);
        (*gradient)[1] = scaled(d, s);
        (*gradient)[2] = scaled(d, -(1 - t));
        (*gradient)[3] = scaled(d, -t);
      }
      return height * height * inverse;
    }
  }
  // Ends against the other segment; `difference` is qa - qb.
  double best = std::numeric_limits<double>::infinity(), best_s = 0, best_t = 0;
  Vec3 best_difference{0, 0, 0};
  const auto consider = [&](double d2, double s, double t, const Vec3& difference) {
    if (d2 < best) {
      best = d2;
      best_s = s;
      best_t = t;
      best_difference = difference;
    }
  };
  double parameter;
  Vec3 difference;
  if (sides & 1) {
    const double d2 = point_segment(a0, b0, b1, parameter, difference);
    consider(d2, 0, parameter, difference);
  }
  if (sides & 2) {
    const double d2 = point_segment(a1, b0, b1, parameter, difference);
    consider(d2, 1, parameter, difference);
  }
  if (sides & 4) {
    const double d2 = point_segment(b0, a0, a1, parameter, difference);
    consider(d2, parameter, 0, scaled(difference, -1));
  }
  if (sides & 8) {
    const double d2 = point_segment(b1, a0, a1, parameter, difference);
    consider(d2, parameter, 1, scaled(difference, -1));
  }
  if (gradient) {
    const Vec3 d = scaled(best_difference, 2);
    (*gradient)[0] = scaled(d, 1 - best_s);
    (*gradient)[1] = scaled(d, best_s);
    (*gradient)[2] = scaled(d, -(1 - best_t));
    (*gradient)[3] = scaled(d, -best_t);
  }
  return best;
}

// ln(d / dhat) by log1p near dhat, where d / dhat rounds to a few bits of 1,
// and by log far below it, where (d - dhat) / dhat would round to -1.
double barrier(double d, double dhat, double* derivative) {
  if (!(d > 0)) {
    if (derivative) *derivative = -std::numeric_limits<double>::infinity();
    return std::numeric_limits<double>::infinity();
  }
  if (d >= dhat) {
    if (derivative) *derivative = 0;
    return 0;
  }
  const double gap = d - dhat;
  const double log = d > 0.5 * dhat ? std::log1p(gap / dhat) : std::log(d / dhat);
  if (derivative) *derivative = -2 * gap * log - gap * gap / d;
  return -gap * gap * log;
}

double barrier_of_squared(double d2, double dhat, double* derivative) {
  const double d = std::sqrt(d2);
  double db = 0;
  const double value = barrier(d, dhat, derivative ? &db : nullptr);
  if (derivative) *derivative = d > 0 ? db / (2 * d) : db;
  return value;
}

}  // namespace foldfill
