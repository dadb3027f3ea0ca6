// The small vector operations on Vec3 and Vec2 that the stages share, so that
// a robustness fix to one of them is made once.
#pragma once

#include <cmath>

#include "foldfill/mesh.h"

namespace foldfill {

// ---- Vec3 -------------------------------------------------------------------

inline Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 scaled(const Vec3& a, double s) { return {s * a[0], s * a[1], s * a[2]}; }
// a + s d
inline Vec3 add_scaled(const Vec3& a, const Vec3& d, double s) {
  return {a[0] + s * d[0], a[1] + s * d[1], a[2] + s * d[2]};
}
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
// Point v of an array of 3 doubles per point (positions, displacements).
inline Vec3 point_at(const double* points, long v) {
  const double* p = points + 3 * v;
  return {p[0], p[1], p[2]};
}
inline double distance(const Vec3& a, const Vec3& b) { return norm(sub(a, b)); }

// Interior angle at corner `a` of triangle (a, b, c), in [0, pi]. The atan2
// of |u x v| and u . v stays accurate for slivers, where acos of the
// normalised dot product loses all its digits near 0 and pi.
inline double corner_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u = sub(b, a), v = sub(c, a);
  return std::atan2(norm(cross(u, v)), dot(u, v));
}

// ---- Vec2 -------------------------------------------------------------------

inline Vec2 sub(const Vec2& a, const Vec2& b) { return {a[0] - b[0], a[1] - b[1]}; }
inline double dot(const Vec2& a, const Vec2& b) { return a[0] * b[0] + a[1] * b[1]; }
inline double norm(const Vec2& a) { return std::hypot(a[0], a[1]); }
inline double distance(const Vec2& a, const Vec2& b) { return norm(sub(b, a)); }
// The z component of the 3D cross product of a and b.
inline double cross(const Vec2& a, const Vec2& b) { return a[0] * b[1] - a[1] * b[0]; }
// Twice the signed area of triangle (o, a, b): positive when it turns
// counter-clockwise.
inline double cross(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

// Interior angle at corner `a` of triangle (a, b, c), in [0, pi] (as the Vec3
// version).
inline double corner_angle(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 u = sub(b, a), v = sub(c, a);
  return std::atan2(std::abs(cross(u, v)), dot(u, v));
}

}  // namespace foldfill
