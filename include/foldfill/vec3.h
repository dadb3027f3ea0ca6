// The small vector operations on Vec3 that the stages share.
#pragma once

#include <cmath>

#include "foldfill/mesh.h"

namespace foldfill {

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
inline double distance(const Vec3& a, const Vec3& b) { return norm(sub(a, b)); }

}  // namespace foldfill
