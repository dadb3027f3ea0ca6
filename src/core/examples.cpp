// Exactly developable example meshes. Every mesh here is a grid of planar
// quads (a general cylinder's quads are rectangles, a cone's are trapezoids in
// the plane of two rulings), each split into two triangles, so the triangle
// mesh itself, not only the smooth surface it samples, is isometric to its
// flat grid: flattening tests can demand exact figures.
#include "foldfill/examples.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "foldfill/topology.h"

namespace foldfill {
namespace {

constexpr double kPi = 3.14159265358979323846;

double distance(const Vec3& a, const Vec3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

// A grid of `columns` x `rows` vertices, vertex (i, j) at index j * columns + i,
// split into triangles with alternating diagonals (no preferred direction).
int segments_for(double length, double edge_length) {
  return std::max(1, static_cast<int>(std::lround(length / edge_length)));
}

// Points of a planar curve (x, z) sampled by `count` parameters, extruded along
// y over `height`; flat u is the cumulative chord length, so every grid quad is
// a rectangle of the same size in 3D and in the plane.
DevelopableMesh extrude_curve(const std::vector<std::array<double, 2>>& curve, double height,
                              double edge_length) {
  const int columns = static_cast<int>(curve.size());
  const int rows = segments_for(height, edge_length) + 1;
  std::vector<double> u(columns, 0.0);
  for (int i = 1; i < columns; ++i) {
    u[i] = u[i - 1] + std::hypot(curve[i][0] - curve[i - 1][0], curve[i][1] - curve[i - 1][1]);
  }
  DevelopableMesh result;
  for (int j = 0; j < rows; ++j) {
    const double y = height * j / (rows - 1);
    for (int i = 0; i < columns; ++i) {
      result.mesh.positions.push_back({curve[i][0], y, curve[i][1]});
      result.flat.push_back({u[i], y});
    }
  }
  result.mesh.faces = grid_triangles(columns, rows);
  return result;
}

// Cumulative arc length of a curve given by its speed on a table of `size`
// equal parameter steps over [0, t_end] (Simpson's rule per step).
template <class Speed>
std::vector<double> arc_length_table(Speed speed, double t_end, int size) {
  std::vector<double> arc(size + 1, 0.0);
  const double dt = t_end / size;
  for (int k = 0; k < size; ++k) {
    const double t = k * dt;
    arc[k + 1] = arc[k] + dt / 6 * (speed(t) + 4 * speed(t + dt / 2) + speed(t + dt));
  }
  return arc;
}

// Parameters 0 = t_0 < ... < t_n = t_end equally spaced in arc length.
std::vector<double> arc_length_samples(const std::vector<double>& arc, double t_end, int segments) {
  const int size = static_cast<int>(arc.size()) - 1;
  std::vector<double> samples(segments + 1, 0.0);
  int k = 0;
  for (int i = 1; i < segments; ++i) {
    const double target = arc.back() * i / segments;
    while (k + 1 < size && arc[k + 1] < target) ++k;
    const double share = (target - arc[k]) / (arc[k + 1] - arc[k]);
    samples[i] = (k + share) * t_end / size;
  }
  samples.back() = t_end;
  return samples;
}

}  // namespace

DevelopableMesh make_folded_sheet(const FoldedSheetOptions& options) {
  const double wave = 2 * kPi * options.folds / options.width;
  const double slope = options.amplitude * wave;
  auto speed = [&](double t) { return std::hypot(1.0, slope * std::cos(wave * t)); };
  const std::vector<double> arc = arc_length_table(speed, options.width, 16384);
  const int segments = segments_for(arc.back(), options.edge_length);
  std::vector<std::array<double, 2>> curve;
  for (double t : arc_length_samples(arc, options.width, segments)) {
    curve.push_back({t, options.amplitude * std::sin(wave * t)});
  }
  return extrude_curve(curve, options.height, options.edge_length);
}

DevelopableMesh make_profile_sheet(const std::vector<Vec2>& profile, double height,
                                   double edge_length) {
  return extrude_curve({profile.begin(), profile.end()}, height, edge_length);
}

std::vector<Vec2> u_fold_profile(double length, double gap, double edge_length) {
  std::vector<Vec2> profile;
  const int straight = segments_for(length, edge_length);
  const int bend = std::max(2, segments_for(kPi * gap / 2, edge_length));
  for (int i = 0; i < straight; ++i) profile.push_back({length * (1 - double(i) / straight), 0});
  for (int i = 0; i < bend; ++i) {
    const double angle = kPi * i / bend;  // from the bottom of the circle, turning up
    profile.push_back({-0.5 * gap * std::sin(angle), 0.5 * gap * (1 - std::cos(angle))});
  }
  for (int i = 0; i <= straight; ++i) profile.push_back({length * double(i) / straight, gap});
  return profile;
}

DevelopableMesh make_cylinder_section(double radius, double angle, double height,
                                      double edge_length) {
  const int segments = segments_for(radius * angle, edge_length);
  std::vector<std::array<double, 2>> curve;
  for (int i = 0; i <= segments; ++i) {
    const double theta = angle * i / segments;
    curve.push_back({radius * std::sin(theta), radius * (1 - std::cos(theta))});
  }
  return extrude_curve(curve, height, edge_length);
}

DevelopableMesh make_cone_section(double half_angle, double r0, double r1, double angle,
                                  double edge_length) {
  const double ring_radius = r1 * std::sin(half_angle);
  const int columns = segments_for(ring_radius * angle, edge_length) + 1;
  const int rows = segments_for(r1 - r0, edge_length) + 1;
  // Unit rulings; the flat angle between neighbouring rulings is their 3D angle,
  // so each quad (a trapezoid in the plane of two rulings) develops exactly.
  std::vector<Vec3> ruling(columns);
  std::vector<double> flat_angle(columns, 0.0);
  for (int i = 0; i < columns; ++i) {
    const double theta = angle * i / (columns - 1);
    ruling[i] = {std::sin(half_angle) * std::cos(theta), std::sin(half_angle) * std::sin(theta),
                 std::cos(half_angle)};
    if (i > 0)
      flat_angle[i] = flat_angle[i - 1] + 2 * std::asin(distance(ruling[i], ruling[i - 1]) / 2);
  }
  DevelopableMesh result;
  for (int j = 0; j < rows; ++j) {
    const double r = r0 + (r1 - r0) * j / (rows - 1);
    for (int i = 0; i < columns; ++i) {
      result.mesh.positions.push_back({r * ruling[i][0], r * ruling[i][1], r * ruling[i][2]});
      // Mirrored (angle decreasing with i) so that the grid's faces are
      // counter-clockwise in the plane.
      result.flat.push_back({r * std::cos(flat_angle[i]), -r * std::sin(flat_angle[i])});
    }
  }
  result.mesh.faces = grid_triangles(columns, rows);
  return result;
}

namespace {

double flat_area(const std::vector<Vec2>& flat, const Tri& f) {
  const Vec2 &a = flat[f[0]], &b = flat[f[1]], &c = flat[f[2]];
  return 0.5 * std::abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
}

// Whether the kept faces around `vertex` form more than one fan (faces are
// joined when they share an edge through the vertex).
bool is_pinched(int vertex, const std::vector<int>& kept_faces, const std::vector<Tri>& faces) {
  std::vector<int> fan(kept_faces.size());
  std::iota(fan.begin(), fan.end(), 0);
  auto root = [&](int k) {
    while (fan[k] != k) k = fan[k] = fan[fan[k]];
    return k;
  };
  for (size_t a = 0; a < kept_faces.size(); ++a) {
    for (size_t b = a + 1; b < kept_faces.size(); ++b) {
      int shared = 0;
      for (int x : faces[kept_faces[a]]) {
        for (int y : faces[kept_faces[b]]) shared += (x == y && x != vertex);
      }
      if (shared > 0) fan[root(static_cast<int>(a))] = root(static_cast<int>(b));
    }
  }
  int fans = 0;
  for (size_t k = 0; k < kept_faces.size(); ++k)
    fans += (root(static_cast<int>(k)) == static_cast<int>(k));
  return fans > 1;
}

}  // namespace

CutMesh cut_disk_hole(const DevelopableMesh& input, Vec2 center, double radius) {
  const std::vector<Tri>& faces = input.mesh.faces;
  std::vector<char> removed(faces.size(), 0);
  for (size_t f = 0; f < faces.size(); ++f) {
    double cx = 0, cy = 0;
    for (int v : faces[f]) {
      cx += input.flat[v][0] / 3;
      cy += input.flat[v][1] / 3;
    }
    removed[f] = std::hypot(cx - center[0], cy - center[1]) < radius;
  }
  // Grow the hole at vertices where the kept faces form several fans (the
  // hole's boundary would touch itself there) until there is none.
  const VertexFaces vertex_faces =
      build_vertex_faces(faces, static_cast<int>(input.flat.size()), "example");
  for (bool changed = true; changed;) {
    changed = false;
    for (int v = 0; v < vertex_faces.vertex_count(); ++v) {
      std::vector<int> kept;
      bool touches_hole = false;
      for (int k = vertex_faces.start[v]; k < vertex_faces.start[v + 1]; ++k) {
        const int f = vertex_faces.faces[k];
        if (removed[f]) {
          touches_hole = true;
        } else {
          kept.push_back(f);
        }
      }
      if (!touches_hole || !is_pinched(static_cast<int>(v), kept, faces)) continue;
      for (int f : kept) removed[f] = 1;
      changed = true;
    }
  }
  CutMesh result;
  std::vector<int> new_index(input.flat.size(), -1);
  for (size_t f = 0; f < faces.size(); ++f) {
    if (removed[f]) {
      result.removed_area += flat_area(input.flat, faces[f]);
      ++result.removed_faces;
      continue;
    }
    for (int v : faces[f]) new_index[v] = 0;
  }
  for (size_t v = 0; v < new_index.size(); ++v) {
    if (new_index[v] < 0) continue;
    new_index[v] = static_cast<int>(result.cut.flat.size());
    result.cut.mesh.positions.push_back(input.mesh.positions[v]);
    result.cut.flat.push_back(input.flat[v]);
  }
  for (size_t f = 0; f < faces.size(); ++f) {
    if (!removed[f]) {
      result.cut.mesh.faces.push_back(
          {new_index[faces[f][0]], new_index[faces[f][1]], new_index[faces[f][2]]});
    }
  }
  return result;
}

std::vector<Tri> grid_triangles(int columns, int rows, bool wrap_columns, bool wrap_rows) {
  std::vector<Tri> faces;
  const int cell_columns = wrap_columns ? columns : columns - 1;
  const int cell_rows = wrap_rows ? rows : rows - 1;
  for (int j = 0; j < cell_rows; ++j) {
    for (int i = 0; i < cell_columns; ++i) {
      const int i1 = (i + 1) % columns, j1 = (j + 1) % rows;
      const int a = j * columns + i, b = j * columns + i1, c = j1 * columns + i1,
                d = j1 * columns + i;
      if ((i + j) % 2 == 0) {
        faces.push_back({a, b, c});
        faces.push_back({a, c, d});
      } else {
        faces.push_back({a, b, d});
        faces.push_back({b, c, d});
      }
    }
  }
  return faces;
}

}  // namespace foldfill
