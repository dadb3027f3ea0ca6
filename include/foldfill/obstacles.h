// Rigid obstacles the patch must stay outside of (spheres, cylinders, planes).
#pragma once

#include <string>
#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

struct Obstacle {
  enum class Type { Sphere, Cylinder, Plane };
  Type type = Type::Sphere;
  Vec3 center{};         // sphere, cylinder (centre of the axis segment); plane: a point on it
  double radius = 0;     // sphere, cylinder
  double height = 0;     // cylinder: length of the axis segment
  Vec3 axis{0, 1, 0};    // cylinder: unit axis
  Vec3 normal{0, 0, 1};  // plane: unit normal, pointing to the allowed side
};

// Parses obstacles from text: either JSON `{"obstacles": [...]}` with entries
// {"type": "sphere", "center", "radius"}, {"type": "cylinder", "center",
// "radius", "height", "euler_zxz": [psi, phi, theta]} (axis = Rz(psi) Rx(theta)
// Rz(phi) (0,1,0)) or "axis": [x,y,z], {"type": "plane", "point", "normal"};
// or the prototype's text lines `sphere x y z r` / `cylinder x y z r h a1 a2 a3`.
// Throws Error(Usage) naming `source` for malformed input.
std::vector<Obstacle> parse_obstacles(const std::string& text, const std::string& source);
std::vector<Obstacle> read_obstacles(const std::string& path);

// Signed distance from `p` to the obstacle's surface (negative inside).
double signed_distance(const Obstacle& obstacle, const Vec3& p);

// The outward unit normal of the obstacle's surface seen from `p`: the
// gradient of signed_distance. (0, 0, 0) where that has no direction: a
// sphere's centre, and inside a cylinder on its axis (where the side is
// nearest) or on its mid-plane (where the caps are).
Vec3 outward_normal(const Obstacle& obstacle, const Vec3& p);

// Whether `p` is certainly farther than `gap` (>= 0) from the obstacle's
// surface, by a test cheaper than signed_distance (no square root): true
// only where signed_distance(obstacle, p) > gap, and false when in doubt
// (near a cylinder's rims, within a hair of the distance `gap`).
bool farther_than(const Obstacle& obstacle, const Vec3& p, double gap);

// Moves `p` to the nearest point of the surface when it is inside; returns
// whether it moved.
bool push_outside(const Obstacle& obstacle, Vec3& p);

// The obstacle in normalised coordinates (p - origin) / scale.
Obstacle normalized(const Obstacle& obstacle, const Vec3& origin, double scale);

}  // namespace foldfill
