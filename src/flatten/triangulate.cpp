// Meshing the flat hole polygon (see triangulate.h). A hexagonal lattice at the
// target spacing, clipped to the polygon and kept away from its edges, gives
// the interior points; a constrained Delaunay triangulation of polygon and
// points (CGAL, exact predicates) connects them; a few rounds of optimal
// Delaunay (ODT) smoothing of the interior points, each followed by a new
// triangulation, even the triangles out. The polygon's edges are constraints
// and no point is ever put on them, so the boundary stays exactly the input.
#include "foldfill/triangulate.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "foldfill/box_tree.h"
#include "foldfill/error.h"
#include "foldfill/topology.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_2;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using FaceBase =
    CGAL::Triangulation_face_base_with_info_2<bool, Kernel,
                                              CGAL::Constrained_triangulation_face_base_2<Kernel>>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<
    Kernel, CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>,
    CGAL::No_constraint_intersection_tag>;

const char* const kSource = "triangulate_hole";

// Lattice points closer than this many target edge lengths to the polygon are
// dropped: the triangles between them and the boundary would be slivers.
constexpr double kBoundaryMargin = 0.55;
// Smoothing rounds; the angles hardly improve after three or four.
constexpr int kSmoothingRounds = 4;
// A patch larger than this is a wrong density or a wrong scale, not a hole.
constexpr double kMaxInteriorVertices = 2e7;

std::vector<Point> to_points(const std::vector<Vec2>& uv) {
  std::vector<Point> points;
  points.reserve(uv.size());
  for (const Vec2& p : uv) points.emplace_back(p[0], p[1]);
  return points;
}

// Throws unless `polygon` is a simple counter-clockwise polygon with finite
// coordinates (decided with exact predicates).
void check_polygon(const std::vector<Vec2>& polygon) {
  if (polygon.size() < 3)
    throw FillFailedError(std::string(kSource) + ": the hole polygon has " +
                          std::to_string(polygon.size()) + " vertices, at least 3 are needed");
  for (const Vec2& p : polygon)
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]))
      throw FillFailedError(std::string(kSource) +
                            ": the hole polygon has a non-finite coordinate");
  const std::vector<Point> points = to_points(polygon);
  if (!CGAL::is_simple_2(points.begin(), points.end(), Kernel()))
    throw FillFailedError(std::string(kSource) +
                          ": the hole polygon is not simple (it crosses or "
                          "touches itself)");
  if (CGAL::orientation_2(points.begin(), points.end(), Kernel()) != CGAL::COUNTERCLOCKWISE)
    throw FillFailedError(std::string(kSource) +
                          ": the hole polygon is clockwise, counter-clockwise "
                          "is expected");
}

// The length-weighted mean edge length, sum l^2 / sum l: the mean for even
// edges, but unmoved when a few edges are split into many tiny ones (a plain
// mean would then shrink the spacing and blow up the patch).
double mean_edge_length(const std::vector<Vec2>& polygon) {
  double sum = 0, sum_squares = 0;
  for (size_t k = 0; k < polygon.size(); ++k) {
    const double l = distance(polygon[k], polygon[(k + 1) % polygon.size()]);
    sum += l;
    sum_squares += l * l;
  }
  return sum_squares / sum;
}

double polygon_area(const std::vector<Vec2>& polygon) {
  double twice_area = 0;
  for (size_t k = 0; k < polygon.size(); ++k) {
    const Vec2& a = polygon[k];
    const Vec2& b = polygon[(k + 1) % polygon.size()];
    twice_area += a[0] * b[1] - a[1] * b[0];
  }
  return 0.5 * twice_area;
}

struct Box {
  Vec2 min{}, max{};
};

Box bounding_box(const std::vector<Vec2>& points) {
  Box box{points[0], points[0]};
  for (const Vec2& p : points)
    for (int d = 0; d < 2; ++d) {
      box.min[d] = std::min(box.min[d], p[d]);
      box.max[d] = std::max(box.max[d], p[d]);
    }
  return box;
}

double point_segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const double ex = b[0] - a[0], ey = b[1] - a[1];
  const double length2 = ex * ex + ey * ey;
  double t = length2 > 0 ? ((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / length2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p[0] - a[0] - t * ex, p[1] - a[1] - t * ey);
}

// The zone where interior points must not go: within kBoundaryMargin times
// max(spacing, edge length) of a polygon edge. A point closer to an edge than
// that would make a sliver with it, and since edges longer than the spacing
// cannot be split, their triangles need their apex further out. The edges'
// boxes, grown by their radii, are held in the shared box tree, so that a
// query looks only at the edges whose zone may hold the point.
class KeepOutZone {
 public:
  KeepOutZone(const std::vector<Vec2>& polygon, double spacing)
      : polygon_(polygon), spacing_(spacing) {
    const int n = static_cast<int>(polygon.size());
    std::vector<Box3> boxes(n);
    for (int e = 0; e < n; ++e) {
      const Vec2 &a = polygon[e], &b = polygon[(e + 1) % n];
      const double r = radius(e);
      boxes[e].low = {std::min(a[0], b[0]) - r, std::min(a[1], b[1]) - r, 0};
      boxes[e].high = {std::max(a[0], b[0]) + r, std::max(a[1], b[1]) + r, 0};
    }
    edges_.build(boxes);
  }

  bool contains(const Vec2& p) const {
    const int n = static_cast<int>(polygon_.size());
    bool inside = false;
    edges_.for_each_meeting(Box3{{p[0], p[1], 0}, {p[0], p[1], 0}}, 0.0, [&](int e) {
      if (!inside && point_segment_distance(p, polygon_[e], polygon_[(e + 1) % n]) < radius(e))
        inside = true;
    });
    return inside;
  }

 private:
  double radius(int e) const {
    const int n = static_cast<int>(polygon_.size());
    return kBoundaryMargin * std::max(spacing_, distance(polygon_[e], polygon_[(e + 1) % n]));
  }

  const std::vector<Vec2>& polygon_;
  double spacing_;
  BoxTree edges_;
};

// The points of a hexagonal lattice of spacing `spacing` inside the polygon
// and outside the keep-out zone, row by row. Each lattice row is clipped by
// the crossings of the polygon edges with it (edges bucketed by the rows they
// span, half-open so that a vertex on a row counts once).
std::vector<Vec2> interior_lattice(const std::vector<Vec2>& polygon, double spacing,
                                   const KeepOutZone& keep_out) {
  const Box box = bounding_box(polygon);
  const double row_step = spacing * std::sqrt(3.0) / 2;
  const int rows = static_cast<int>((box.max[1] - box.min[1]) / row_step) + 1;
  const auto row_y = [&](int j) { return box.min[1] + (j + 0.5) * row_step; };
  // A row at or just below height y; the crossing test below settles it.
  const auto row_near = [&](double y) {
    return std::clamp(static_cast<int>(std::floor((y - box.min[1]) / row_step - 0.5)), 0, rows);
  };

  const int n = static_cast<int>(polygon.size());
  std::vector<int> offsets(rows + 1, 0);
  const auto for_each_crossing = [&](auto&& visit) {
    for (int e = 0; e < n; ++e) {
      const Vec2& a = polygon[e];
      const Vec2& b = polygon[(e + 1) % n];
      if (a[1] == b[1]) continue;
      const double low = std::min(a[1], b[1]), high = std::max(a[1], b[1]);
      for (int j = row_near(low); j < rows && row_y(j) < high; ++j) {
        if (row_y(j) < low) continue;
        visit(j, a[0] + (row_y(j) - a[1]) * (b[0] - a[0]) / (b[1] - a[1]));
      }
    }
  };
  for_each_crossing([&](int j, double) { ++offsets[j + 1]; });
  for (int j = 0; j < rows; ++j) offsets[j + 1] += offsets[j];
  std::vector<double> crossings(offsets[rows]);
  std::vector<int> filled(offsets.begin(), offsets.end() - 1);
  for_each_crossing([&](int j, double x) { crossings[filled[j]++] = x; });

  std::vector<Vec2> points;
  for (int j = 0; j < rows; ++j) {
    std::sort(crossings.begin() + offsets[j], crossings.begin() + offsets[j + 1]);
    const double shift = (j % 2) * 0.5 * spacing;
    for (int k = offsets[j]; k + 1 < offsets[j + 1]; k += 2) {
      const double from = crossings[k], to = crossings[k + 1];
      const auto first = static_cast<long long>(std::ceil((from - box.min[0] - shift) / spacing));
      for (long long i = first;; ++i) {
        const Vec2 p{box.min[0] + shift + static_cast<double>(i) * spacing, row_y(j)};
        if (p[0] > to) break;
        if (!keep_out.contains(p)) points.push_back(p);
      }
    }
  }
  return points;
}

// Each face from its smallest vertex, the faces sorted.
void sort_canonically(std::vector<Tri>& faces) {
  for (Tri& f : faces) std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
  std::sort(faces.begin(), faces.end());
}

// The constrained Delaunay triangulation of polygon + interior points
// (uv[0, boundary_count) is the polygon), faces inside the polygon only,
// counter-clockwise, in a canonical order.
std::vector<Tri> constrained_delaunay(const std::vector<Vec2>& uv, int boundary_count) {
  Cdt cdt;
  std::vector<std::pair<Point, int>> boundary, interior;
  for (int i = 0; i < static_cast<int>(uv.size()); ++i)
    (i < boundary_count ? boundary : interior).emplace_back(Point(uv[i][0], uv[i][1]), i);
  cdt.insert(boundary.begin(), boundary.end());
  std::vector<Cdt::Vertex_handle> handles(boundary_count);
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
    handles[v->info()] = v;
  for (int k = 0; k < boundary_count; ++k)
    cdt.insert_constraint(handles[k], handles[(k + 1) % boundary_count]);
  cdt.insert(interior.begin(), interior.end());
  if (cdt.number_of_vertices() != uv.size())
    throw InternalError(std::string(kSource) + ": the triangulation lost or added vertices");

  // The inside: flood from the faces left of the polygon's edges, stopping at
  // constraints (the polygon's edges are the only ones).
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = false;
  std::vector<Cdt::Face_handle> stack;
  for (int k = 0; k < boundary_count; ++k) {
    Cdt::Face_handle face;
    int opposite = 0;
    const auto from = handles[k], to = handles[(k + 1) % boundary_count];
    if (!cdt.is_edge(from, to, face, opposite))
      throw InternalError(std::string(kSource) + ": a polygon edge went missing");
    if (face->vertex(Cdt::ccw(opposite)) != from) face = face->neighbor(opposite);
    stack.push_back(face);
  }
  std::vector<Tri> faces;
  while (!stack.empty()) {
    const Cdt::Face_handle face = stack.back();
    stack.pop_back();
    if (face->info()) continue;
    face->info() = true;
    faces.push_back({face->vertex(0)->info(), face->vertex(1)->info(), face->vertex(2)->info()});
    for (int i = 0; i < 3; ++i)
      if (!face->is_constrained(i) && !face->neighbor(i)->info())
        stack.push_back(face->neighbor(i));
  }
  sort_canonically(faces);
  return faces;
}

// Across which face each edge of each face lies: neighbour[3 f + k] is the
// face across the edge opposite corner k of face f, -1 on the polygon.
std::vector<int> face_neighbours(const std::vector<Tri>& faces) {
  std::vector<std::pair<std::uint64_t, int>> edges;  // (edge key, 3 f + k)
  edges.reserve(3 * faces.size());
  for (int f = 0; f < static_cast<int>(faces.size()); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto [a, b] = std::minmax(faces[f][(k + 1) % 3], faces[f][(k + 2) % 3]);
      edges.emplace_back(static_cast<std::uint64_t>(a) << 32 | static_cast<std::uint32_t>(b),
                         3 * f + k);
    }
  std::sort(edges.begin(), edges.end());
  std::vector<int> neighbour(3 * faces.size(), -1);
  for (size_t e = 0; e + 1 < edges.size(); ++e)
    if (edges[e].first == edges[e + 1].first) {
      neighbour[edges[e].second] = edges[e + 1].second / 3;
      neighbour[edges[e + 1].second] = edges[e].second / 3;
    }
  return neighbour;
}

// The constrained Delaunay triangulation of the points of a triangulation
// (counter-clockwise `faces` inside the polygon) by Lawson's edge flips, in a
// canonical order. After a smoothing round, which keeps every triangle
// counter-clockwise, a few edges need flipping: much cheaper than a new
// triangulation, and the same triangulation (exact predicates; it is unique
// unless four points lie exactly on an empty circle).
std::vector<Tri> flip_to_delaunay(const std::vector<Vec2>& uv, std::vector<Tri> faces) {
  const auto in_circle = Kernel().side_of_oriented_circle_2_object();
  const auto point = [&](int v) { return Point(uv[v][0], uv[v][1]); };
  std::vector<int> neighbour = face_neighbours(faces);
  // The corner of face g opposite its edge shared with face f.
  const auto corner_facing = [&](int g, int f) {
    for (int m = 0; m < 3; ++m)
      if (neighbour[3 * g + m] == f) return m;
    throw InternalError(std::string(kSource) + ": broken face adjacency");
  };
  const auto replace_neighbour = [&](int face, int from, int to) {
    if (face >= 0) neighbour[3 * face + corner_facing(face, from)] = to;
  };
  std::vector<int> pending(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) pending[f] = static_cast<int>(f);
  while (!pending.empty()) {
    const int f = pending.back();
    pending.pop_back();
    for (int k = 0; k < 3; ++k) {
      const int g = neighbour[3 * f + k];
      if (g < 0) continue;
      const int m = corner_facing(g, f);
      // f = (a, b, c) from corner k, g = (d, c, b) from corner m.
      const int a = faces[f][k], b = faces[f][(k + 1) % 3], c = faces[f][(k + 2) % 3];
      const int d = faces[g][m];
      if (in_circle(point(a), point(b), point(c), point(d)) != CGAL::ON_POSITIVE_SIDE) continue;
      const int across_ca = neighbour[3 * f + (k + 1) % 3],
                across_ab = neighbour[3 * f + (k + 2) % 3];
      const int across_bd = neighbour[3 * g + (m + 1) % 3],
                across_dc = neighbour[3 * g + (m + 2) % 3];
      faces[f] = {a, b, d};
      faces[g] = {a, d, c};
      neighbour[3 * f] = across_bd;
      neighbour[3 * f + 1] = g;
      neighbour[3 * f + 2] = across_ab;
      neighbour[3 * g] = across_dc;
      neighbour[3 * g + 1] = across_ca;
      neighbour[3 * g + 2] = f;
      replace_neighbour(across_bd, g, f);
      replace_neighbour(across_ca, f, g);
      pending.push_back(f);
      pending.push_back(g);
      break;
    }
  }
  sort_canonically(faces);
  return faces;
}

Vec2 circumcenter(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double bx = b[0] - a[0], by = b[1] - a[1], cx = c[0] - a[0], cy = c[1] - a[1];
  const double d = 2 * (bx * cy - by * cx);
  const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  return {a[0] + (cy * b2 - by * c2) / d, a[1] + (bx * c2 - cx * b2) / d};
}

// Whether every face around `v` stays counter-clockwise, by a margin, with v at p.
bool star_stays_valid(const std::vector<Vec2>& uv, const std::vector<Tri>& faces,
                      const VertexFaces& star, int v, const Vec2& p, double min_twice_area) {
  for (int k = star.start[v]; k < star.start[v + 1]; ++k) {
    Vec2 corner[3];
    for (int i = 0; i < 3; ++i)
      corner[i] = faces[star.faces[k]][i] == v ? p : uv[faces[star.faces[k]][i]];
    if (cross(corner[0], corner[1], corner[2]) <= min_twice_area) return false;
  }
  return true;
}

// One round of ODT smoothing (Chen & Xu 2004), in place, vertex after vertex:
// each interior vertex moves towards the area-weighted mean of the
// circumcentres of its triangles, by the largest of a full, half or quarter
// step that keeps its triangles counter-clockwise (so it stays inside the
// polygon) and keeps it out of the boundary's keep-out zone.
void smooth_interior(std::vector<Vec2>& uv, const std::vector<Tri>& faces, int boundary_count,
                     double spacing, const KeepOutZone& keep_out) {
  const int vertex_count = static_cast<int>(uv.size());
  const VertexFaces star = build_vertex_faces(faces, vertex_count);
  const double min_twice_area = 1e-3 * spacing * spacing;
  for (int v = boundary_count; v < vertex_count; ++v) {
    double weight = 0;
    Vec2 target{0, 0};
    for (int k = star.start[v]; k < star.start[v + 1]; ++k) {
      const Tri& f = faces[star.faces[k]];
      const Vec2 &a = uv[f[0]], &b = uv[f[1]], &c = uv[f[2]];
      const Vec2 centre = circumcenter(a, b, c);
      const double area = 0.5 * cross(a, b, c);
      weight += area;
      target[0] += area * centre[0];
      target[1] += area * centre[1];
    }
    if (weight <= 0) continue;
    const Vec2 step{target[0] / weight - uv[v][0], target[1] / weight - uv[v][1]};
    for (double fraction = 1; fraction >= 0.25; fraction *= 0.5) {
      const Vec2 p{uv[v][0] + fraction * step[0], uv[v][1] + fraction * step[1]};
      if (!keep_out.contains(p) && star_stays_valid(uv, faces, star, v, p, min_twice_area)) {
        uv[v] = p;
        break;
      }
    }
  }
}

void measure_quality(FlatPatch& patch) {
  const double degree = std::acos(-1.0) / 180;
  patch.area = 0;
  patch.min_angle_deg = 180;
  int below_20 = 0;
  for (const Tri& f : patch.faces) {
    const Vec2 &a = patch.uv[f[0]], &b = patch.uv[f[1]], &c = patch.uv[f[2]];
    patch.area += 0.5 * cross(a, b, c);
    const double smallest =
        std::min({corner_angle(a, b, c), corner_angle(b, c, a), corner_angle(c, a, b)}) / degree;
    patch.min_angle_deg = std::min(patch.min_angle_deg, smallest);
    below_20 += smallest < 20;
  }
  patch.share_below_20deg =
      patch.faces.empty() ? 0 : static_cast<double>(below_20) / patch.faces.size();
}

}  // namespace

FlatPatch triangulate_hole(const std::vector<Vec2>& polygon, const TriangulateOptions& options) {
  if (!(options.density > 0) || !std::isfinite(options.density))
    throw UsageError(std::string(kSource) + ": the density must be positive, not " +
                     std::to_string(options.density));
  check_polygon(polygon);
  const double spacing = mean_edge_length(polygon) / options.density;
  const double expected_interior = polygon_area(polygon) / (spacing * spacing * std::sqrt(3.0) / 2);
  if (expected_interior > kMaxInteriorVertices)
    throw FillFailedError(std::string(kSource) + ": the patch would have about " +
                          std::to_string(static_cast<long long>(expected_interior)) +
                          " interior vertices, too many (is the density right?)");

  FlatPatch patch;
  patch.boundary_count = static_cast<int>(polygon.size());
  patch.uv = polygon;
  const KeepOutZone keep_out(polygon, spacing);
  const std::vector<Vec2> interior = interior_lattice(polygon, spacing, keep_out);
  patch.uv.insert(patch.uv.end(), interior.begin(), interior.end());
  patch.faces = constrained_delaunay(patch.uv, patch.boundary_count);
  if (!interior.empty())
    for (int round = 0; round < kSmoothingRounds; ++round) {
      smooth_interior(patch.uv, patch.faces, patch.boundary_count, spacing, keep_out);
      patch.faces = flip_to_delaunay(patch.uv, std::move(patch.faces));
    }
  measure_quality(patch);
  return patch;
}

}  // namespace foldfill
