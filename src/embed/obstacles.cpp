// Rigid obstacles: parsing (JSON or the prototype's text lines), signed
// distances, projection of inside points to the nearest surface point, and
// whether a triangle crosses into them. Mesh obstacles are src/embed/obstacle_mesh.cpp's.
#include "foldfill/obstacles.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <sstream>

#include "embed/triangle_geometry.h"
#include "foldfill/collision.h"
#include "foldfill/error.h"
#include "foldfill/io.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

using geometry::any_perpendicular;

using Json = nlohmann::json;

Vec3 rotate_z(const Vec3& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]};
}
Vec3 rotate_x(const Vec3& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {v[0], c * v[1] - s * v[2], s * v[1] + c * v[2]};
}

// The prototype's cylinder axis: Rz(psi) Rx(theta) Rz(phi) (0, 1, 0).
Vec3 axis_from_euler_zxz(double psi, double phi, double theta) {
  return rotate_z(rotate_x(rotate_z({0, 1, 0}, phi), theta), psi);
}

[[noreturn]] void fail(const std::string& where, const std::string& problem) {
  throw UsageError(where + ": " + problem);
}

// Checks the values of a parsed obstacle and makes its directions unit.
Obstacle validated(Obstacle o, const std::string& where) {
  if (!is_finite(o.center)) fail(where, "non-finite coordinate");
  if (o.type != Obstacle::Type::Plane && !(std::isfinite(o.radius) && o.radius > 0)) {
    fail(where, "radius must be positive");
  }
  if (o.type == Obstacle::Type::Cylinder) {
    if (!(std::isfinite(o.height) && o.height > 0)) fail(where, "height must be positive");
    const double length = norm(o.axis);
    if (!(std::isfinite(length) && length > 0)) fail(where, "axis must be a non-zero vector");
    o.axis = scaled(o.axis, 1 / length);
  }
  if (o.type == Obstacle::Type::Plane) {
    const double length = norm(o.normal);
    if (!(std::isfinite(length) && length > 0)) fail(where, "normal must be a non-zero vector");
    o.normal = scaled(o.normal, 1 / length);
  }
  return o;
}

// One JSON obstacle entry, read with error messages that name it.
class JsonEntry {
 public:
  JsonEntry(const Json& entry, std::string where) : entry_(entry), where_(std::move(where)) {}

  const std::string& where() const { return where_; }
  bool has(const char* key) const { return entry_.contains(key); }

  // Rejects keys outside `allowed`, so that a misspelt key is not silently ignored.
  void check_keys(std::initializer_list<const char*> allowed, const std::string& type) const {
    for (const auto& item : entry_.items()) {
      const bool known = std::any_of(allowed.begin(), allowed.end(),
                                     [&](const char* k) { return item.key() == k; });
      if (!known) fail(where_, "unknown key \"" + item.key() + "\" for a " + type);
    }
  }
  double number(const char* key) const {
    const Json& value = field(key);
    if (!value.is_number()) fail(where_, "\"" + std::string(key) + "\" must be a number");
    return value.get<double>();
  }
  std::string text(const char* key) const {
    const Json& value = field(key);
    if (!value.is_string() || value.get<std::string>().empty()) {
      fail(where_, "\"" + std::string(key) + "\" must be a non-empty string");
    }
    return value.get<std::string>();
  }
  Vec3 vec3(const char* key) const {
    const Json& value = field(key);
    if (!value.is_array() || value.size() != 3 ||
        !std::all_of(value.begin(), value.end(), [](const Json& v) { return v.is_number(); })) {
      fail(where_, "\"" + std::string(key) + "\" must be an array of 3 numbers");
    }
    return {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
  }

 private:
  const Json& field(const char* key) const {
    if (!entry_.contains(key)) fail(where_, "missing \"" + std::string(key) + "\"");
    return entry_.at(key);
  }

  const Json& entry_;
  std::string where_;
};

// A mesh entry's file: relative paths start from the folder of `source`.
std::string mesh_path(const std::string& file, const std::string& source) {
  const std::filesystem::path path(file);
  if (path.is_absolute()) return file;
  return (std::filesystem::path(source).parent_path() / path).string();
}

Obstacle parse_json_entry(const JsonEntry& entry, const std::string& type,
                          const std::string& source) {
  Obstacle o;
  if (type == "mesh") {
    entry.check_keys({"type", "file"}, type);
    return read_mesh_obstacle(mesh_path(entry.text("file"), source));
  }
  if (type == "sphere") {
    entry.check_keys({"type", "center", "radius"}, type);
    o.type = Obstacle::Type::Sphere;
    o.center = entry.vec3("center");
    o.radius = entry.number("radius");
  } else if (type == "cylinder") {
    entry.check_keys({"type", "center", "radius", "height", "euler_zxz", "axis"}, type);
    o.type = Obstacle::Type::Cylinder;
    o.center = entry.vec3("center");
    o.radius = entry.number("radius");
    o.height = entry.number("height");
    if (entry.has("euler_zxz") == entry.has("axis")) {
      fail(entry.where(), "a cylinder needs exactly one of \"euler_zxz\" and \"axis\"");
    }
    if (entry.has("axis")) {
      o.axis = entry.vec3("axis");
    } else {
      const Vec3 angles = entry.vec3("euler_zxz");  // psi, phi, theta
      if (!is_finite(angles)) fail(entry.where(), "non-finite angle");
      o.axis = axis_from_euler_zxz(angles[0], angles[1], angles[2]);
    }
  } else if (type == "plane") {
    entry.check_keys({"type", "point", "normal"}, type);
    o.type = Obstacle::Type::Plane;
    o.center = entry.vec3("point");
    o.normal = entry.vec3("normal");
  } else {
    fail(entry.where(), "unknown type \"" + type + "\" (sphere, cylinder, plane or mesh)");
  }
  return validated(o, entry.where());
}

std::vector<Obstacle> parse_json(const std::string& text, const std::string& source) {
  Json document;
  try {
    document = Json::parse(text);
  } catch (const Json::exception& e) {     // syntax errors and number overflow
    const std::string message = e.what();  // "[json.exception.KIND] problem"
    fail(source, "invalid JSON: " + message.substr(message.find(']') + 2));
  }
  return obstacles_from_json(document, source);
}

}  // namespace

std::vector<Obstacle> obstacles_from_json(const nlohmann::json& document,
                                          const std::string& source) {
  const Json* list = &document;
  if (document.is_object()) {
    if (!document.contains("obstacles")) fail(source, "expected {\"obstacles\": [...]}");
    list = &document.at("obstacles");
  }
  if (!list->is_array()) fail(source, "\"obstacles\" must be an array");
  std::vector<Obstacle> obstacles;
  for (size_t k = 0; k < list->size(); ++k) {
    const Json& item = (*list)[k];
    const std::string where = source + ": obstacle " + std::to_string(k + 1);
    if (!item.is_object()) fail(where, "must be an object");
    if (!item.contains("type") || !item.at("type").is_string()) {
      fail(where, "missing \"type\" (sphere, cylinder, plane or mesh)");
    }
    obstacles.push_back(
        parse_json_entry(JsonEntry(item, where), item.at("type").get<std::string>(), source));
  }
  return obstacles;
}

namespace {

double parse_number(const std::string& token, const std::string& where) {
  char* end = nullptr;
  const double value = std::strtod(token.c_str(), &end);
  if (token.empty() || *end != '\0') fail(where, "\"" + token + "\" is not a number");
  if (!std::isfinite(value)) fail(where, "non-finite number \"" + token + "\"");
  return value;
}

// One line of the prototype's format: `sphere x y z r` or
// `cylinder x y z r h psi phi theta`.
Obstacle parse_text_line(const std::vector<std::string>& tokens, const std::string& where) {
  const std::string& type = tokens[0];
  const size_t expected = type == "sphere" ? 4 : type == "cylinder" ? 8 : 0;
  if (expected == 0) fail(where, "unknown obstacle type \"" + type + "\" (sphere or cylinder)");
  if (tokens.size() - 1 != expected) {
    fail(where, type + " needs " + std::to_string(expected) + " numbers (" +
                    (expected == 4 ? "x y z r" : "x y z r h psi phi theta") + "), got " +
                    std::to_string(tokens.size() - 1));
  }
  std::vector<double> v;
  for (size_t k = 1; k < tokens.size(); ++k) v.push_back(parse_number(tokens[k], where));
  Obstacle o;
  o.center = {v[0], v[1], v[2]};
  o.radius = v[3];
  if (type == "cylinder") {
    o.type = Obstacle::Type::Cylinder;
    o.height = v[4];
    o.axis = axis_from_euler_zxz(v[5], v[6], v[7]);
  }
  return validated(o, where);
}

std::vector<Obstacle> parse_text(const std::string& text, const std::string& source) {
  std::vector<Obstacle> obstacles;
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    std::istringstream words(line.substr(0, line.find('#')));
    std::vector<std::string> tokens;
    for (std::string word; words >> word;) tokens.push_back(word);
    if (!tokens.empty()) {
      obstacles.push_back(parse_text_line(tokens, source + ": line " + std::to_string(number)));
    }
  }
  return obstacles;
}

// Cylinder coordinates of `p`: signed position along the axis and the radial offset.
struct AxialSplit {
  double t;
  Vec3 radial;
};
AxialSplit split(const Obstacle& cylinder, const Vec3& p) {
  const Vec3 d = sub(p, cylinder.center);
  const double t = dot(d, cylinder.axis);
  return {t, sub(d, scaled(cylinder.axis, t))};
}

// Signed distances of `p` from a cylinder's side (infinitely long) and from
// the plane of its nearer cap, with the split they come from.
struct CylinderGaps {
  AxialSplit split;
  double side, cap;
};
CylinderGaps gaps(const Obstacle& cylinder, const Vec3& p) {
  const AxialSplit s = split(cylinder, p);
  return {s, norm(s.radial) - cylinder.radius, std::abs(s.t) - 0.5 * cylinder.height};
}

double cylinder_distance(const Obstacle& cylinder, const Vec3& p) {
  const auto [s, side, cap] = gaps(cylinder, p);
  if (side > 0 && cap > 0) return std::hypot(side, cap);  // nearest is the rim
  return std::max(side, cap);
}

// The unit vector along `v`, or (0, 0, 0) for the zero vector.
Vec3 direction_or_zero(const Vec3& v) {
  const double length = norm(v);
  return length > 0 ? scaled(v, 1 / length) : Vec3{0, 0, 0};
}

// The gradient of cylinder_distance: the radial direction beside the side,
// the axis' direction beyond a cap, their blend by hypot's gradient off the
// rim, and inside the direction of the nearer of side and caps.
Vec3 cylinder_normal(const Obstacle& cylinder, const Vec3& p) {
  const auto [s, side, cap] = gaps(cylinder, p);
  const Vec3 radial = direction_or_zero(s.radial);
  const double axial_sign = s.t > 0 ? 1.0 : s.t < 0 ? -1.0 : 0.0;
  const Vec3 axial = scaled(cylinder.axis, axial_sign);
  if (side > 0 && cap > 0) {
    const double rim = std::hypot(side, cap);
    return add(scaled(radial, side / rim), scaled(axial, cap / rim));
  }
  return side >= cap ? radial : axial;
}

Vec3 nearest_on_sphere(const Obstacle& sphere, const Vec3& p) {
  const Vec3 d = sub(p, sphere.center);
  const double length = norm(d);
  const Vec3 direction = length > 0 ? scaled(d, 1 / length) : Vec3{0, 0, 1};
  return add(sphere.center, scaled(direction, sphere.radius));
}

// For a point inside: the nearest of the side and the caps.
Vec3 nearest_on_cylinder_from_inside(const Obstacle& cylinder, const Vec3& p) {
  const AxialSplit s = split(cylinder, p);
  const double rho = norm(s.radial), half = 0.5 * cylinder.height;
  Vec3 radial = s.radial;
  double t = s.t;
  if (cylinder.radius - rho <= half - std::abs(t)) {
    // Near the axis the radial offset is rounding noise with no direction: any
    // perpendicular is as near. Elsewhere a second projection keeps it exactly
    // perpendicular to the axis.
    const Vec3 perpendicular = sub(radial, scaled(cylinder.axis, dot(radial, cylinder.axis)));
    const Vec3 direction = rho > 1e-12 * cylinder.radius
                               ? scaled(perpendicular, 1 / norm(perpendicular))
                               : any_perpendicular(cylinder.axis);
    radial = scaled(direction, cylinder.radius);
  } else {
    t = t < 0 ? -half : half;
  }
  return add(cylinder.center, add(scaled(cylinder.axis, t), radial));
}

// The smallest signed distance from the triangle to a sphere, a cylinder or
// a plane (the signed distance of each is a convex function). A cylinder's is
// searched for; the search stops at a value below `stop_below`, and is
// skipped where the corners or the bound by the centroid settle it.
double smallest_signed_distance(const Obstacle& obstacle, const geometry::Triangle& triangle,
                                double stop_below) {
  switch (obstacle.type) {
    case Obstacle::Type::Sphere:
      return norm(sub(geometry::closest_point_on_triangle(obstacle.center, triangle),
                      obstacle.center)) -
             obstacle.radius;
    case Obstacle::Type::Plane: {
      double least = HUGE_VAL;
      for (const Vec3& corner : triangle)
        least = std::min(least, dot(sub(corner, obstacle.center), obstacle.normal));
      return least;
    }
    case Obstacle::Type::Cylinder: {
      double least = HUGE_VAL;
      for (const Vec3& corner : triangle)
        least = std::min(least, cylinder_distance(obstacle, corner));
      if (least < stop_below) return least;
      return std::min(
          least,
          geometry::minimum_over_triangle(
              triangle, [&](const Vec3& p) { return cylinder_distance(obstacle, p); }, stop_below));
    }
    case Obstacle::Type::Mesh:
      break;
  }
  return HUGE_VAL;
}

// A lower bound of the signed distance over the triangle: it is
// 1-Lipschitz, so the centroid's less the farthest corner's distance from it.
double lower_bound(const Obstacle& obstacle, const geometry::Triangle& triangle) {
  const Vec3 centroid = scaled(add(add(triangle[0], triangle[1]), triangle[2]), 1.0 / 3);
  double spread = 0;
  for (const Vec3& corner : triangle) spread = std::max(spread, norm(sub(corner, centroid)));
  return signed_distance(obstacle, centroid) - spread;
}

}  // namespace

std::vector<Obstacle> parse_obstacles(const std::string& text, const std::string& source) {
  const auto first =
      std::find_if(text.begin(), text.end(), [](unsigned char c) { return !std::isspace(c); });
  const bool json = first != text.end() && (*first == '{' || *first == '[');
  return json ? parse_json(text, source) : parse_text(text, source);
}

std::vector<Obstacle> read_obstacles(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CannotReadError(path + ": cannot read obstacles file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw CannotReadError(path + ": cannot read obstacles file");
  return parse_obstacles(text.str(), path);
}

Obstacle read_mesh_obstacle(const std::string& path) {
  return mesh_obstacle(read_mesh(path), path);
}

double signed_distance(const Obstacle& obstacle, const Vec3& p) {
  switch (obstacle.type) {
    case Obstacle::Type::Sphere:
      return norm(sub(p, obstacle.center)) - obstacle.radius;
    case Obstacle::Type::Cylinder:
      return cylinder_distance(obstacle, p);
    case Obstacle::Type::Plane:
      return dot(sub(p, obstacle.center), obstacle.normal);
    case Obstacle::Type::Mesh:
      return obstacle.mesh->signed_distance(p);
  }
  return 0;
}

Vec3 outward_normal(const Obstacle& obstacle, const Vec3& p) {
  switch (obstacle.type) {
    case Obstacle::Type::Sphere:
      return direction_or_zero(sub(p, obstacle.center));
    case Obstacle::Type::Cylinder:
      return cylinder_normal(obstacle, p);
    case Obstacle::Type::Plane:
      return obstacle.normal;
    case Obstacle::Type::Mesh:
      return obstacle.mesh->outward_normal(p);
  }
  return {0, 0, 0};
}

bool farther_than(const Obstacle& obstacle, const Vec3& p, double gap) {
  // The thresholds are grown by a hair, so that rounding here and in
  // signed_distance cannot disagree.
  const double grown = 1 + 1e-6;
  const Vec3 d = sub(p, obstacle.center);
  switch (obstacle.type) {
    case Obstacle::Type::Sphere: {
      const double reach = grown * (obstacle.radius + gap);
      return dot(d, d) > reach * reach;
    }
    case Obstacle::Type::Cylinder: {
      // Beside the side or beyond a cap: either one alone bounds the distance.
      const double t = dot(d, obstacle.axis);
      const double side_reach = grown * (obstacle.radius + gap);
      return dot(d, d) - t * t > side_reach * side_reach ||
             std::abs(t) > grown * (0.5 * obstacle.height + gap);
    }
    case Obstacle::Type::Plane:
      return dot(d, obstacle.normal) > grown * gap;
    case Obstacle::Type::Mesh:
      return obstacle.mesh->farther_than(p, gap);
  }
  return false;
}

bool push_outside(const Obstacle& obstacle, Vec3& p) {
  if (obstacle.type == Obstacle::Type::Mesh) return obstacle.mesh->push_outside(p);
  const double distance = signed_distance(obstacle, p);
  if (!(distance < 0)) return false;
  switch (obstacle.type) {
    case Obstacle::Type::Sphere:
      p = nearest_on_sphere(obstacle, p);
      break;
    case Obstacle::Type::Cylinder:
      p = nearest_on_cylinder_from_inside(obstacle, p);
      break;
    case Obstacle::Type::Plane:
      p = sub(p, scaled(obstacle.normal, distance));
      break;
    case Obstacle::Type::Mesh:
      break;
  }
  return true;
}

Obstacle normalized(const Obstacle& obstacle, const Vec3& origin, double scale) {
  if (!(std::isfinite(scale) && scale > 0)) {
    throw InternalError("obstacles: normalisation scale must be positive");
  }
  Obstacle result = obstacle;
  result.center = scaled(sub(obstacle.center, origin), 1 / scale);
  result.radius = obstacle.radius / scale;
  result.height = obstacle.height / scale;
  if (obstacle.type == Obstacle::Type::Mesh) {
    Mesh mesh = obstacle.mesh->mesh();
    for (Vec3& p : mesh.positions) p = scaled(sub(p, origin), 1 / scale);
    result.mesh = std::make_shared<const ObstacleMesh>(std::move(mesh), obstacle.mesh->source());
  }
  return result;
}

// Each: the bound by the centroid, and for a cylinder its capsule's value
// (at most its own, equal where it says so), before a search over the triangle.
bool crosses(const Obstacle& obstacle, const std::array<Vec3, 3>& triangle, double tolerance) {
  if (obstacle.type == Obstacle::Type::Mesh) return obstacle.mesh->crosses(triangle);
  if (lower_bound(obstacle, triangle) >= -tolerance) return false;
  bool exact = false;
  if (obstacle.type == Obstacle::Type::Cylinder &&
      triangle_cylinder_distance(obstacle, triangle[0], triangle[1], triangle[2], exact) >=
          -tolerance)
    return false;
  return smallest_signed_distance(obstacle, triangle, -tolerance) < -tolerance;
}

double distance(const Obstacle& obstacle, const std::array<Vec3, 3>& triangle, double limit) {
  if (obstacle.type == Obstacle::Type::Mesh) return obstacle.mesh->distance(triangle, limit);
  if (lower_bound(obstacle, triangle) >= limit) return limit;
  if (obstacle.type == Obstacle::Type::Cylinder) {
    bool exact = false;
    const double capsule =
        triangle_cylinder_distance(obstacle, triangle[0], triangle[1], triangle[2], exact);
    if (capsule >= limit) return limit;
    if (exact) return std::clamp(capsule, 0.0, limit);
  }
  return std::clamp(smallest_signed_distance(obstacle, triangle, 0.0), 0.0, limit);
}

}  // namespace foldfill
