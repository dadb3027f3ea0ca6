// Point, segment and triangle distances (Ericson, "Real-Time Collision
// Detection", 2005, sections 5.1.5 and 5.1.9).
#include "embed/triangle_geometry.h"

#include <algorithm>
#include <cmath>

#include "foldfill/vec3.h"

namespace foldfill::geometry {
namespace {

// The point of segment [a, b] nearest to p.
Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = sub(b, a);
  const double length2 = dot(ab, ab);
  if (!(length2 > 0)) return a;
  return add_scaled(a, ab, std::clamp(dot(sub(p, a), ab) / length2, 0.0, 1.0));
}

}  // namespace

Vec3 any_perpendicular(const Vec3& a) {
  const int least = static_cast<int>(
      std::min_element(a.begin(), a.end(),
                       [](double x, double y) { return std::abs(x) < std::abs(y); }) -
      a.begin());
  Vec3 e{0, 0, 0};
  e[least] = 1;
  const Vec3 p = add_scaled(e, a, -a[least]);
  const double inverse = 1 / std::sqrt(dot(p, p));
  return {p[0] * inverse, p[1] * inverse, p[2] * inverse};
}

double smallest_angle_deg(const Triangle& t) {
  double smallest = 180;
  for (int k = 0; k < 3; ++k) {
    const Vec3& a = t[k];
    const Vec3& b = t[(k + 1) % 3];
    const Vec3& c = t[(k + 2) % 3];
    const Vec3 u = sub(b, a), w = sub(c, a);
    const Vec3 n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    const double sine = std::sqrt(dot(n, n)), cosine = dot(u, w);
    if (!(sine > 0)) return 0;
    smallest = std::min(smallest, std::atan2(sine, cosine) * 180 / M_PI);
  }
  return smallest;
}

Vec3 closest_point_on_triangle(const Vec3& p, const Triangle& t) {
  const Vec3 &a = t[0], &b = t[1], &c = t[2];
  const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) return add_scaled(a, ab, d1 / (d1 - d3));
  const Vec3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 - d6 > 0) return add_scaled(a, ac, d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0 && (d4 - d3) + (d5 - d6) > 0)
    return add_scaled(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double sum = va + vb + vc;
  if (!(sum > 0)) {
    // A degenerate triangle: the nearest of its edges' points.
    Vec3 best = closest_point_on_segment(p, a, b);
    for (const Vec3& q : {closest_point_on_segment(p, b, c), closest_point_on_segment(p, c, a)})
      if (distance(p, q) < distance(p, best)) best = q;
    return best;
  }
  const double v = vb / sum, w = vc / sum;
  return {a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w};
}

double segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const Vec3 d1 = sub(p1, p0), d2 = sub(q1, q0), r = sub(p0, q0);
  const double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
  double s = 0, t = 0;
  if (!(a > 0) && !(e > 0)) return distance(p0, q0);
  if (!(a > 0)) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = dot(d1, r);
    if (!(e > 0)) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = dot(d1, d2), denominator = a * e - b * b;
      // Parallel segments (denominator 0): any s will do; start from p0.
      s = denominator > 0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return distance(add_scaled(p0, d1, s), add_scaled(q0, d2, t));
}

double disjoint_triangle_distance(const Triangle& a, const Triangle& b) {
  double best = HUGE_VAL;
  for (int k = 0; k < 3; ++k) {
    best = std::min(best, distance(a[k], closest_point_on_triangle(a[k], b)));
    best = std::min(best, distance(b[k], closest_point_on_triangle(b[k], a)));
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      best = std::min(best, segment_distance(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]));
  return best;
}

}  // namespace foldfill::geometry
