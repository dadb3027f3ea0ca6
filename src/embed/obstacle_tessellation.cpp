// Sphere, cylinder and plane obstacles as triangles near a box: pieces of
// convex polyhedra around the obstacle shrunk by an inset (see
// tessellate_obstacle in obstacles.h for what they guarantee).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/obstacles.h"
#include "foldfill/vec3.h"
#include "embed/triangle_geometry.h"

namespace foldfill {
namespace {

using geometry::any_perpendicular;

constexpr double kPi = 3.14159265358979323846;
// Faces are never finer than this fraction of the obstacle's size, which
// keeps every count of cells within an int.
constexpr double kFinestStep = 1.0 / (1 << 24);
// Where the faces near the box would be more than kMaxObstacleFaces, the edge
// length grows by the square root of the excess and this much more, so that
// few rounds reach a count that fits.
constexpr double kCoarsening = 1.05;

Box3 grown(const Box3& box, double margin) {
  Box3 result = box;
  for (int c = 0; c < 3; ++c) {
    result.low[c] -= margin;
    result.high[c] += margin;
  }
  return result;
}

std::array<Vec3, 8> corners(const Box3& box) {
  std::array<Vec3, 8> result;
  for (int k = 0; k < 8; ++k)
    for (int c = 0; c < 3; ++c) result[k][c] = (k >> c & 1) ? box.high[c] : box.low[c];
  return result;
}

// How many cells of at most `length` cover `extent`: at least 1, at most
// 1 / kFinestStep.
int cells_for(double extent, double length) {
  const double count = std::ceil(extent / length);
  return static_cast<int>(std::clamp(count, 1.0, 1 / kFinestStep));
}

// The indices in [0, count) of the cells of width 1 / count that meet [low,
// high] (fractions of the whole), with one more on each side for rounding.
std::array<int, 2> cell_range(double low, double high, int count) {
  const double first = std::floor(low * count) - 1, last = std::floor(high * count) + 1;
  return {static_cast<int>(std::max(first, 0.0)),
          static_cast<int>(std::min(last, static_cast<double>(count - 1)))};
}

// A mesh built face by face, each vertex made once from its key, keeping only
// the faces whose bounding boxes overlap `reach`.
class MeshBuilder {
 public:
  using Key = std::array<std::int64_t, 3>;
  struct Corner {
    Key key;
    Vec3 position;
  };

  explicit MeshBuilder(const Box3& reach) : reach_(reach) {}

  // Adds the triangle if it is near the box, turned so that its normal points
  // along `outward`.
  void add(Corner a, Corner b, Corner c, const Vec3& outward) {
    for (int axis = 0; axis < 3; ++axis) {
      const double low = std::min({a.position[axis], b.position[axis], c.position[axis]});
      const double high = std::max({a.position[axis], b.position[axis], c.position[axis]});
      if (high < reach_.low[axis] || low > reach_.high[axis]) return;
    }
    const Vec3 normal = cross(sub(b.position, a.position), sub(c.position, a.position));
    if (dot(normal, outward) < 0) std::swap(b, c);
    mesh_.faces.push_back({vertex(a), vertex(b), vertex(c)});
  }

  Mesh take() { return std::move(mesh_); }

 private:
  int vertex(const Corner& corner) {
    const auto [it, added] = index_.emplace(corner.key, mesh_.vertex_count());
    if (added) mesh_.positions.push_back(corner.position);
    return it->second;
  }

  Box3 reach_;
  Mesh mesh_;
  std::map<Key, int> index_;
};

// ---- Sphere: a cube-sphere. ----
//
// Cube face (a, s) is where s x_a >= |x_b|, |x_c| (b, c the next axes); its
// grid points are the directions of (t[k_0], t[k_1], t[k_2]) with k_a = n (s
// > 0) or 0 (s < 0), t[k] = tan(-pi/4 + k pi / (2 n)). The grid lines are
// great circles, so the flat triangles of a cell, seen from the centre, cover
// it exactly. t is made exactly odd (t[n - k] = -t[k], t[0] = -1, t[n] = 1)
// and a point's direction depends only on its indices, so that the cube
// faces meet at the same vertices.

struct CubeGrid {
  int n = 1;  // cells along each side of a cube face

  double tangent(std::int64_t k) const {
    if (2 * k > n) return -tangent(n - k);
    if (k == 0) return -1;
    if (2 * k == n) return 0;
    return std::tan(-kPi / 4 + k * (kPi / 2) / n);
  }
  Vec3 direction(const MeshBuilder::Key& key) const {
    const Vec3 v{tangent(key[0]), tangent(key[1]), tangent(key[2])};
    return scaled(v, 1 / norm(v));
  }
};

// The distance from the origin to the plane through three unit vectors: the
// cosine of the angular radius of their circumcircle on the unit sphere.
double plane_distance(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 normal = cross(sub(b, a), sub(c, a));
  return std::abs(dot(a, normal)) / norm(normal);
}

// The cells of cube face (a, s) whose directions may see points of `box`
// (relative to the centre) at distances in [inner, outer] from the centre:
// index ranges along axes b and c, empty when first > last.
struct CellRange {
  std::array<int, 2> along_b{1, 0}, along_c{1, 0};
  bool empty() const { return along_b[0] > along_b[1] || along_c[0] > along_c[1]; }
  std::int64_t count() const {
    return empty() ? 0 : std::int64_t{along_b[1] - along_b[0] + 1} * (along_c[1] - along_c[0] + 1);
  }
};

CellRange cell_range_on_face(int a, int s, const Box3& box, double inner, double outer, int n) {
  CellRange range;
  // Along the face's axis, a point at distance r from the centre in this face's
  // part of the cube-sphere is at least r / sqrt(3) out.
  const double z_low = std::max(s > 0 ? box.low[a] : -box.high[a], inner / std::sqrt(3.0));
  const double z_high = std::min(s > 0 ? box.high[a] : -box.low[a], outer);
  if (!(z_low <= z_high)) return range;
  std::array<std::array<int, 2>, 2> ranges;
  for (int m = 1; m <= 2; ++m) {
    const int axis = (a + m) % 3;
    const double x_low = std::max(box.low[axis], -outer), x_high = std::min(box.high[axis], outer);
    if (!(x_low <= x_high)) return range;
    // The grid coordinate x / z over the box, within the face's [-1, 1].
    const double u_low = std::max(std::min(x_low / z_low, x_low / z_high), -1.0);
    const double u_high = std::min(std::max(x_high / z_low, x_high / z_high), 1.0);
    const auto fraction = [](double u) { return (std::atan(u) + kPi / 4) / (kPi / 2); };
    ranges[m - 1] = cell_range(fraction(u_low), fraction(u_high), n);
  }
  range.along_b = ranges[0];
  range.along_c = ranges[1];
  return range;
}

struct GridTriangle {
  std::array<MeshBuilder::Key, 3> keys;
  std::array<Vec3, 3> directions;
};

// The triangles of the cells that may see the box, each cell split along the
// diagonal that makes the circumcircles smaller, and the least plane distance
// among them.
struct SphereCandidates {
  std::vector<GridTriangle> triangles;
  double least_plane_distance = 1;
};

SphereCandidates sphere_candidates(const CubeGrid& grid, const std::array<CellRange, 6>& ranges) {
  SphereCandidates result;
  for (int face = 0; face < 6; ++face) {
    const int a = face / 2, s = face % 2 == 0 ? 1 : -1;
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const CellRange& range = ranges[face];
    if (range.empty()) continue;
    for (int i = range.along_b[0]; i <= range.along_b[1]; ++i) {
      for (int j = range.along_c[0]; j <= range.along_c[1]; ++j) {
        std::array<MeshBuilder::Key, 4> keys;  // (i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)
        std::array<Vec3, 4> d;
        for (int q = 0; q < 4; ++q) {
          keys[q][a] = s > 0 ? grid.n : 0;
          keys[q][b] = i + (q == 1 || q == 2);
          keys[q][c] = j + (q >= 2);
          d[q] = grid.direction(keys[q]);
        }
        const std::array<std::array<int, 3>, 2> split_a{{{0, 1, 2}, {0, 2, 3}}};
        const std::array<std::array<int, 3>, 2> split_b{{{0, 1, 3}, {1, 2, 3}}};
        const auto least = [&](const std::array<std::array<int, 3>, 2>& split) {
          return std::min(plane_distance(d[split[0][0]], d[split[0][1]], d[split[0][2]]),
                          plane_distance(d[split[1][0]], d[split[1][1]], d[split[1][2]]));
        };
        const double least_a = least(split_a), least_b = least(split_b);
        const auto& split = least_b > least_a ? split_b : split_a;
        result.least_plane_distance =
            std::min(result.least_plane_distance, std::max(least_a, least_b));
        for (const auto& corner : split) {
          result.triangles.push_back({{keys[corner[0]], keys[corner[1]], keys[corner[2]]},
                                      {d[corner[0]], d[corner[1]], d[corner[2]]}});
        }
      }
    }
  }
  return result;
}

Mesh tessellate_sphere(const Obstacle& sphere, const Box3& box, double edge_length, double inset,
                       TessellationBounds& bounds) {
  const double rho = sphere.radius - inset;
  bounds = {edge_length, 0};
  if (!(rho > 0)) return {};
  double length = std::max(edge_length, rho * kFinestStep);
  Box3 reach;
  std::array<CellRange, 6> ranges;
  // The cells that may see the reach box, for n cells a side.
  const auto find_ranges = [&](int n) {
    Box3 relative;
    relative.low = sub(reach.low, sphere.center);
    relative.high = sub(reach.high, sphere.center);
    // Faces reach out to at most rho + 0.25 * length once the gap fits.
    const double outer = std::min(std::sqrt(3.0) * rho, rho + 0.25 * length);
    std::int64_t count = 0;
    for (int face = 0; face < 6; ++face) {
      ranges[face] = cell_range_on_face(face / 2, face % 2 == 0 ? 1 : -1, relative, rho, outer, n);
      count += 2 * ranges[face].count();
    }
    return count;
  };
  // Cells a side for steps of `length` on the ball, coarser while the faces
  // near the box would be too many.
  int n = 1;
  for (;;) {
    reach = grown(box, length);
    n = cells_for(kPi / 2 * rho, length);
    const std::int64_t count = find_ranges(n);
    if (count <= kMaxObstacleFaces) break;
    length *= std::sqrt(static_cast<double>(count) / kMaxObstacleFaces) * kCoarsening;
  }
  // Finer where the gap would be more than a quarter of the edge length: that
  // is grids of a few cells a side, so that the count stays far below the cap.
  SphereCandidates candidates;
  for (;;) {
    candidates = sphere_candidates(CubeGrid{n}, ranges);
    const double gap = rho / candidates.least_plane_distance - rho;
    if (gap <= 0.25 * length || n >= 1 / kFinestStep) break;
    find_ranges(++n);
  }
  bounds.edge_length = length;
  if (candidates.triangles.empty()) return {};
  // One radius for every vertex, so that each face's plane is at least rho
  // from the centre.
  const double vertex_radius = rho / candidates.least_plane_distance;
  bounds.gap = vertex_radius - rho;
  MeshBuilder builder(reach);
  for (const GridTriangle& triangle : candidates.triangles) {
    std::array<MeshBuilder::Corner, 3> c;
    for (int k = 0; k < 3; ++k) {
      c[k] = {triangle.keys[k], add(sphere.center, scaled(triangle.directions[k], vertex_radius))};
    }
    builder.add(c[0], c[1], c[2],
                add(add(triangle.directions[0], triangle.directions[1]), triangle.directions[2]));
  }
  return builder.take();
}

// ---- Cylinder: a prism with ringed caps. ----
//
// Coordinates: t along the axis, angle from `e1` towards `e2` about it.
// Vertex keys: (row, ring, index): rows 0..rows along the axis (0 and rows
// the caps), ring 0 the centre of a cap and ring `rings` the prism's rim, with
// index along the ring.

struct CylinderFrame {
  Vec3 center, axis, e1, e2;
};

// The cylinder's resolution for one edge length.
struct CylinderPlan {
  int sides = 3;  // n
  int rows = 1;   // intervals along the axis
  int rings = 1;  // rings of each cap, the rim included
  double vertex_radius = 0;

  // The vertices of ring r of a cap (1 <= r <= rings), as many as the sides'
  // share of the circumference, and at least 2 r, which nests each ring
  // inside the next (cos(pi / (2 r)) >= (r - 1) / r); never fewer than the
  // ring inside it. The rim is the prism's.
  int ring_size(int r) const {
    if (r == rings) return sides;
    const double share = std::ceil(static_cast<double>(sides) * r / rings);
    return std::max({3, 2 * r, static_cast<int>(share)});
  }
};

CylinderPlan cylinder_plan(double rho, double half, double length) {
  CylinderPlan plan;
  plan.sides = std::max(3, cells_for(2 * kPi * rho, length));
  plan.rows = cells_for(2 * half, length);
  for (;;) {
    while (rho * (1 / std::cos(kPi / plan.sides) - 1) > 0.25 * length) ++plan.sides;
    plan.vertex_radius = rho / std::cos(kPi / plan.sides);
    plan.rings = cells_for(plan.vertex_radius, length);
    // The rim has no fewer vertices than the ring inside it whenever the sides
    // are no coarser than the rings, as here; this keeps it so.
    const int inside = plan.rings > 1 ? plan.ring_size(plan.rings - 1) : 0;
    if (inside <= plan.sides) break;
    plan.sides = inside;
  }
  return plan;
}

// Where the box lies around the axis: the angles (radians, in [first, last],
// last - first < pi) and distances from the axis of its points, or every
// angle (`all`) where its corners are not all beyond the line through the
// axis across the direction of its middle.
struct AngularWindow {
  bool all = true;
  double first = 0, last = 0;
  double nearest = 0, farthest = 0;  // bounds of the distance from the axis
  double t_low = 0, t_high = 0;      // bounds of t
};

AngularWindow angular_window(const CylinderFrame& frame, const Box3& box) {
  AngularWindow window;
  std::array<std::array<double, 2>, 8> planar;
  window.t_low = HUGE_VAL;
  window.t_high = -HUGE_VAL;
  Vec3 middle{0, 0, 0};
  for (const Vec3& corner : corners(box)) middle = add(middle, scaled(corner, 1.0 / 8));
  const Vec3 m = sub(middle, frame.center);
  const std::array<double, 2> towards{dot(m, frame.e1), dot(m, frame.e2)};
  const double towards_length = std::hypot(towards[0], towards[1]);
  double least_along = HUGE_VAL;
  int k = 0;
  for (const Vec3& corner : corners(box)) {
    const Vec3 d = sub(corner, frame.center);
    const double t = dot(d, frame.axis);
    window.t_low = std::min(window.t_low, t);
    window.t_high = std::max(window.t_high, t);
    planar[k] = {dot(d, frame.e1), dot(d, frame.e2)};
    window.farthest = std::max(window.farthest, std::hypot(planar[k][0], planar[k][1]));
    if (towards_length > 0) {
      least_along = std::min(
          least_along, (planar[k][0] * towards[0] + planar[k][1] * towards[1]) / towards_length);
    }
    ++k;
  }
  // The box's projection is the hull of its corners': where all of them are
  // on the far side of the line across the direction of its middle, so is
  // the whole box, within angles below pi/2 either way of that direction.
  if (!(towards_length > 0 && least_along > 0)) return window;
  window.all = false;
  window.nearest = least_along;
  const double base = std::atan2(towards[1], towards[0]);
  window.first = HUGE_VAL;
  window.last = -HUGE_VAL;
  for (const auto& p : planar) {
    const double along = p[0] * towards[0] + p[1] * towards[1];
    const double across = towards[0] * p[1] - towards[1] * p[0];
    const double angle = std::atan2(across, along);
    window.first = std::min(window.first, base + angle);
    window.last = std::max(window.last, base + angle);
  }
  return window;
}

// The edges (index, index + 1) of a ring of `size` vertices, evenly spread,
// that meet the window widened by `pad` radians: `count` of them from
// `first` on, in order (indices taken modulo `size`).
struct RingEdges {
  std::int64_t first = 0, count = 0;
  int at(std::int64_t q, int size) const {
    return static_cast<int>(((first + q) % size + size) % size);
  }
};

RingEdges ring_edges(const AngularWindow& window, int size, double pad) {
  const double first = std::floor((window.first - pad) / (2 * kPi) * size) - 1;
  const double last = std::floor((window.last + pad) / (2 * kPi) * size) + 1;
  if (window.all || last - first + 1 >= size) return {0, size};
  return {static_cast<std::int64_t>(first), static_cast<std::int64_t>(last - first) + 1};
}

class CylinderMesher {
 public:
  CylinderMesher(const CylinderFrame& frame, const CylinderPlan& plan, double half)
      : frame_(frame), plan_(plan), half_(half) {}

  double row_t(int row) const {
    if (row == 0) return -half_;
    if (row == plan_.rows) return half_;
    return -half_ + 2 * half_ * row / plan_.rows;
  }

  // Vertex `index` of ring `ring` of row `row` (a side vertex: ring = rings).
  MeshBuilder::Corner corner(int row, int ring, int index) const {
    const int size = ring == 0 ? 1 : plan_.ring_size(ring);
    index %= size;
    const double radius =
        ring == plan_.rings ? plan_.vertex_radius : plan_.vertex_radius * ring / plan_.rings;
    const double angle = 2 * kPi * index / size;
    const Vec3 radial = add(scaled(frame_.e1, radius * std::cos(angle)),
                            scaled(frame_.e2, radius * std::sin(angle)));
    return {{row, ring, index}, add(add(frame_.center, scaled(frame_.axis, row_t(row))), radial)};
  }

  // The side cells and cap triangles that may be near the box: added to
  // `builder` when it is given, and counted (where they are more than
  // kMaxObstacleFaces, the count may fall short of them, but not of the cap).
  std::int64_t visit(const AngularWindow& window, MeshBuilder* builder) const {
    std::int64_t count = 0;
    const double t_low = std::max(window.t_low, -half_), t_high = std::min(window.t_high, half_);
    if (t_low <= t_high) {
      const auto rows =
          cell_range((t_low + half_) / (2 * half_), (t_high + half_) / (2 * half_), plan_.rows);
      const RingEdges sectors = ring_edges(window, plan_.sides, 0);
      count += 2 * std::int64_t{rows[1] - rows[0] + 1} * sectors.count;
      if (builder) {
        for (int row = rows[0]; row <= rows[1]; ++row) {
          for (std::int64_t q = 0; q < sectors.count; ++q) {
            side_cell(row, sectors.at(q, plan_.sides), *builder);
          }
        }
      }
    }
    for (int end = 0; end < 2; ++end) {
      const double t = end == 0 ? -half_ : half_;
      if (t < window.t_low || t > window.t_high) continue;
      count += cap(end == 0 ? 0 : plan_.rows, end == 0 ? -1 : 1, window, builder);
    }
    return count;
  }

 private:
  void side_cell(int row, int k, MeshBuilder& builder) const {
    const auto a = corner(row, plan_.rings, k), b = corner(row, plan_.rings, k + 1),
               c = corner(row + 1, plan_.rings, k + 1), d = corner(row + 1, plan_.rings, k);
    const double middle = 2 * kPi * (k + 0.5) / plan_.sides;
    const Vec3 outward =
        add(scaled(frame_.e1, std::cos(middle)), scaled(frame_.e2, std::sin(middle)));
    builder.add(a, b, c, outward);
    builder.add(a, c, d, outward);
  }

  // The strips between consecutive rings of a cap that may be near the box.
  // Between an inner ring of m vertices and an outer one of n, the triangles
  // follow the rings' vertices in the order of their angles (an outer edge
  // first where they tie): outer edge j gets the inner vertex ceil((j + 1) m /
  // n) - 1, inner edge i the outer vertex floor((i + 1) n / m).
  std::int64_t cap(int row, int side, const AngularWindow& window, MeshBuilder* builder) const {
    const Vec3 outward = scaled(frame_.axis, side);
    // Strip r covers the distances from the axis in [(r - 2) step, r step].
    const double step = plan_.vertex_radius / plan_.rings;
    const int first =
        window.all ? 1 : std::max(1, static_cast<int>(std::floor(window.nearest / step)));
    const int last =
        std::min(plan_.rings, static_cast<int>(std::floor(window.farthest / step)) + 3);
    // Each strip has at least 3 faces near the window: too many strips are
    // too many faces, without counting them one by one.
    if (!builder && std::int64_t{last - first + 1} * 3 > kMaxObstacleFaces) {
      return std::int64_t{last - first + 1} * 3;
    }
    std::int64_t count = 0;
    for (int r = first; r <= last; ++r) {
      const int outer_size = plan_.ring_size(r);
      const int inner_size = r == 1 ? 1 : plan_.ring_size(r - 1);
      const double pad = 2 * kPi / inner_size;
      const RingEdges outer_edges = ring_edges(window, outer_size, pad);
      const RingEdges inner_edges = r == 1 ? RingEdges{} : ring_edges(window, inner_size, pad);
      count += outer_edges.count + inner_edges.count;
      if (!builder) continue;
      for (std::int64_t q = 0; q < outer_edges.count; ++q) {
        const int j = outer_edges.at(q, outer_size);
        const std::int64_t i =
            r == 1 ? 0 : (std::int64_t{j + 1} * inner_size + outer_size - 1) / outer_size - 1;
        builder->add(corner(row, r, j), corner(row, r, j + 1),
                     corner(row, r - 1, static_cast<int>(i)), outward);
      }
      for (std::int64_t q = 0; q < inner_edges.count; ++q) {
        const int i = inner_edges.at(q, inner_size);
        const std::int64_t j = std::int64_t{i + 1} * outer_size / inner_size;
        builder->add(corner(row, r - 1, i), corner(row, r, static_cast<int>(j)),
                     corner(row, r - 1, i + 1), outward);
      }
    }
    return count;
  }

  CylinderFrame frame_;
  CylinderPlan plan_;
  double half_;
};

Mesh tessellate_cylinder(const Obstacle& cylinder, const Box3& box, double edge_length,
                         double inset, TessellationBounds& bounds) {
  const double rho = cylinder.radius - inset, half = 0.5 * cylinder.height - inset;
  bounds = {edge_length, 0};
  if (!(rho > 0 && half > 0)) return {};
  CylinderFrame frame{cylinder.center, cylinder.axis, any_perpendicular(cylinder.axis), {}};
  frame.e2 = cross(frame.axis, frame.e1);
  double length = std::max(edge_length, std::max(rho, half) * kFinestStep);
  for (;;) {
    const Box3 reach = grown(box, length);
    const CylinderPlan plan = cylinder_plan(rho, half, length);
    const CylinderMesher mesher(frame, plan, half);
    const AngularWindow window = angular_window(frame, reach);
    const std::int64_t count = mesher.visit(window, nullptr);
    if (count <= kMaxObstacleFaces) {
      bounds = {length, plan.vertex_radius - rho};
      MeshBuilder builder(reach);
      mesher.visit(window, &builder);
      return builder.take();
    }
    length *= std::sqrt(static_cast<double>(count) / kMaxObstacleFaces) * kCoarsening;
  }
}

// ---- Plane: one rectangle. ----

Mesh tessellate_plane(const Obstacle& plane, const Box3& box, double edge_length, double inset,
                      TessellationBounds& bounds) {
  bounds = {edge_length, 0};
  const Box3 reach = grown(box, edge_length);
  const Vec3 origin = sub(plane.center, scaled(plane.normal, inset));
  const Vec3 u = any_perpendicular(plane.normal), v = cross(plane.normal, u);
  double low_u = HUGE_VAL, high_u = -HUGE_VAL, low_v = HUGE_VAL, high_v = -HUGE_VAL;
  double low_n = HUGE_VAL, high_n = -HUGE_VAL;
  for (const Vec3& corner : corners(reach)) {
    const Vec3 d = sub(corner, origin);
    low_u = std::min(low_u, dot(d, u));
    high_u = std::max(high_u, dot(d, u));
    low_v = std::min(low_v, dot(d, v));
    high_v = std::max(high_v, dot(d, v));
    low_n = std::min(low_n, dot(d, plane.normal));
    high_n = std::max(high_n, dot(d, plane.normal));
  }
  if (low_n > 0 || high_n < 0) return {};  // the moved plane misses the box
  Mesh mesh;
  for (const auto& [a, b] : std::array<std::array<double, 2>, 4>{
           {{low_u, low_v}, {high_u, low_v}, {high_u, high_v}, {low_u, high_v}}}) {
    mesh.positions.push_back(add(origin, add(scaled(u, a), scaled(v, b))));
  }
  // (u, v, normal) is right-handed: counter-clockwise in (u, v) faces the normal.
  mesh.faces = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

}  // namespace

Mesh tessellate_obstacle(const Obstacle& obstacle, const Box3& box, double edge_length,
                         double inset, TessellationBounds* bounds) {
  if (obstacle.type == Obstacle::Type::Mesh) {
    throw UsageError("tessellate_obstacle: a mesh obstacle is triangles already");
  }
  if (!(std::isfinite(edge_length) && edge_length > 0)) {
    throw UsageError("tessellate_obstacle: edge length must be positive");
  }
  if (!(std::isfinite(inset) && inset >= 0)) {
    throw UsageError("tessellate_obstacle: inset must be finite and not negative");
  }
  for (int c = 0; c < 3; ++c) {
    if (!(std::isfinite(box.low[c]) && std::isfinite(box.high[c]) && box.low[c] <= box.high[c])) {
      throw UsageError("tessellate_obstacle: the box must be finite, low <= high");
    }
  }
  TessellationBounds result;
  Mesh mesh;
  switch (obstacle.type) {
    case Obstacle::Type::Sphere:
      mesh = tessellate_sphere(obstacle, box, edge_length, inset, result);
      break;
    case Obstacle::Type::Cylinder:
      mesh = tessellate_cylinder(obstacle, box, edge_length, inset, result);
      break;
    case Obstacle::Type::Plane:
      mesh = tessellate_plane(obstacle, box, edge_length, inset, result);
      break;
    case Obstacle::Type::Mesh:
      break;
  }
  if (bounds) *bounds = result;
  return mesh;
}

}  // namespace foldfill
