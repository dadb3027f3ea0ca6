// Quality figures of a filled patch. Self-intersections and crossings use
// CGAL's exact triangle-triangle tests and surface distances CGAL's AABB tree
// (this is one of the few translation units that include CGAL).
#include "foldfill/metrics.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <unordered_map>
#include <utility>

#include "foldfill/error.h"
#include "foldfill/vec3.h"
#include "triangle_geometry.h"

namespace foldfill {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

double triangle_area(const std::vector<Vec3>& p, const Tri& f) {
  return 0.5 * norm(cross(sub(p[f[1]], p[f[0]]), sub(p[f[2]], p[f[0]])));
}

// Interior angle at corner k of face f.
double corner_angle(const std::vector<Vec3>& p, const Tri& f, int k) {
  return foldfill::corner_angle(p[f[k]], p[f[(k + 1) % 3]], p[f[(k + 2) % 3]]);
}

Vec3 face_normal(const std::vector<Vec3>& p, const Tri& f) {
  return cross(sub(p[f[1]], p[f[0]]), sub(p[f[2]], p[f[0]]));
}

// Angle between the normals of faces f and g (0 when they are coplanar and
// consistently oriented).
double normal_angle(const std::vector<Vec3>& p, const Tri& f, const Tri& g) {
  const Vec3 a = face_normal(p, f), b = face_normal(p, g);
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32 |
         static_cast<std::uint32_t>(b);
}

// (edge key, face) for every edge of every face, sorted: the faces that share
// an edge are neighbours in the list.
std::vector<std::pair<std::uint64_t, int>> sorted_edge_faces(const std::vector<Tri>& faces) {
  std::vector<std::pair<std::uint64_t, int>> entries;
  entries.reserve(3 * faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      entries.emplace_back(edge_key(faces[f][k], faces[f][(k + 1) % 3]), static_cast<int>(f));
    }
  }
  std::sort(entries.begin(), entries.end());
  return entries;
}

using Triangle = Kernel::Triangle_3;
using TriangleTree = CGAL::AABB_tree<CGAL::AABB_traits<
    Kernel, CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>>>;

Kernel::Point_3 point(const Vec3& p) { return {p[0], p[1], p[2]}; }

// Largest and mean distance from the samples of surface (positions, faces) to
// the triangles of `tree`.
std::pair<double, double> one_sided_distance(const std::vector<Vec3>& positions,
                                             const std::vector<Tri>& faces,
                                             const TriangleTree& tree) {
  std::vector<Kernel::Point_3> samples;
  std::vector<char> sampled(positions.size(), 0);
  for (const Tri& f : faces) {
    for (int v : f) {
      if (!sampled[v]) samples.push_back(point(positions[v]));
      sampled[v] = 1;
    }
    samples.push_back(
        CGAL::centroid(point(positions[f[0]]), point(positions[f[1]]), point(positions[f[2]])));
  }
  double largest = 0, sum = 0;
  for (const Kernel::Point_3& s : samples) {
    const double distance = std::sqrt(tree.squared_distance(s));
    largest = std::max(largest, distance);
    sum += distance;
  }
  return {largest, sum / samples.size()};
}

std::vector<Triangle> nondegenerate_triangles(const std::vector<Vec3>& positions,
                                              const std::vector<Tri>& faces) {
  std::vector<Triangle> triangles;
  for (const Tri& f : faces) {
    const Triangle t(point(positions[f[0]]), point(positions[f[1]]), point(positions[f[2]]));
    if (!t.is_degenerate()) triangles.push_back(t);
  }
  return triangles;
}

// The bounding box of a face; `counted`: the face is one whose pairs count.
struct FaceBox {
  std::array<double, 3> low, high;
  int face;
  bool counted;
};

bool overlap(const FaceBox& a, const FaceBox& b) {
  for (int c = 0; c < 3; ++c)
    if (a.high[c] < b.low[c] || b.high[c] < a.low[c]) return false;
  return true;
}

// The boxes of the nondegenerate faces, and how many counted faces (index >=
// counted_from) are degenerate: collinear or with a non-finite corner.
std::vector<FaceBox> face_boxes(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                                int counted_from, int& degenerate_counted) {
  const int face_count = static_cast<int>(faces.size());
  counted_from = std::clamp(counted_from, 0, face_count);
  degenerate_counted = 0;
  std::vector<FaceBox> boxes;
  boxes.reserve(faces.size());
  for (int f = 0; f < face_count; ++f) {
    const Vec3 &p = positions[faces[f][0]], &q = positions[faces[f][1]],
               &r = positions[faces[f][2]];
    if (!is_finite(p) || !is_finite(q) || !is_finite(r) ||
        CGAL::collinear(point(p), point(q), point(r))) {
      degenerate_counted += f >= counted_from;
      continue;
    }
    FaceBox box{{}, {}, f, f >= counted_from};
    for (int c = 0; c < 3; ++c) {
      box.low[c] = std::min({p[c], q[c], r[c]});
      box.high[c] = std::max({p[c], q[c], r[c]});
    }
    boxes.push_back(box);
  }
  return boxes;
}

bool share_a_vertex(const Tri& f, const Tri& g) {
  for (int v : f)
    if (v == g[0] || v == g[1] || v == g[2]) return true;
  return false;
}

// A uniform grid of cubic cells over boxes, about as wide as most boxes (see
// the constants), so that a cell holds few boxes and a box overlaps few cells.
class BoxGrid {
 public:
  explicit BoxGrid(const std::vector<FaceBox>& boxes) {
    origin_.fill(std::numeric_limits<double>::infinity());
    std::array<double, 3> span{0, 0, 0};
    std::vector<double> extents;
    extents.reserve(boxes.size());
    for (const FaceBox& box : boxes)
      for (int c = 0; c < 3; ++c) origin_[c] = std::min(origin_[c], box.low[c]);
    for (const FaceBox& box : boxes) {
      double extent = 0;
      for (int c = 0; c < 3; ++c) {
        span[c] = std::max(span[c], box.high[c] - origin_[c]);
        extent = std::max(extent, box.high[c] - box.low[c]);
      }
      extents.push_back(extent);
    }
    if (extents.empty()) return;
    const auto typical =
        extents.begin() + static_cast<std::ptrdiff_t>(kTypicalQuantile * (extents.size() - 1));
    std::nth_element(extents.begin(), typical, extents.end());
    const double widest = *std::max_element(typical, extents.end());
    width_ = std::max(kTypicalWidth * *typical, widest / kMostCellsPerAxis);
    if (!(width_ > 0)) return;  // only point boxes (no nondegenerate face): no cell
    if (!std::isfinite(span[0] + span[1] + span[2] + width_)) {
      size_ = {1, 1, 1};  // coordinates too far apart to subtract: one cell for all
      return;
    }
    const double most_cells = kMaxCellsPerBox * static_cast<double>(boxes.size()) + 64;
    while (true) {
      double cells = 1;
      for (int c = 0; c < 3; ++c) cells *= std::floor(span[c] / width_) + 1;
      if (cells <= most_cells) break;
      width_ *= std::cbrt(cells / most_cells) * (1 + 1e-9);
    }
    per_width_ = 1 / width_;
    for (int c = 0; c < 3; ++c) size_[c] = static_cast<int>(span[c] * per_width_) + 1;
  }

  int cell_count() const { return size_[0] * size_[1] * size_[2]; }
  // The cell of the point `corner` (any point of the boxes' hull).
  int cell(const std::array<double, 3>& corner) const {
    return (index(corner[2], 2) * size_[1] + index(corner[1], 1)) * size_[0] + index(corner[0], 0);
  }
  // Calls add(cell) for every cell that `box` overlaps.
  template <typename Add>
  void cells_of(const FaceBox& box, Add add) const {
    for (int k = index(box.low[2], 2); k <= index(box.high[2], 2); ++k)
      for (int j = index(box.low[1], 1); j <= index(box.high[1], 1); ++j)
        for (int i = index(box.low[0], 0); i <= index(box.high[0], 0); ++i)
          add((k * size_[1] + j) * size_[0] + i);
  }

 private:
  // Monotone in x, so that a box's cells hold every point of it.
  int index(double x, int c) const {
    const double at = (x - origin_[c]) * per_width_;
    return at < size_[c] - 1 ? static_cast<int>(at) : size_[c] - 1;  // NaN: the last
  }

  // Cells 1.25 times as wide as the box extent (largest side) that 90% of
  // the boxes do not exceed: a few long faces (a strip's faces can be several
  // times longer than the patch's) would otherwise make the cells, and the
  // pairs tested in them, several times too many. The best of the widths
  // tried on the reference cases.
  static constexpr double kTypicalQuantile = 0.9, kTypicalWidth = 1.25;
  // ... but no box overlaps more than 5 cells per axis,
  static constexpr double kMostCellsPerAxis = 4;
  // and there are at most this many cells per box, all told.
  static constexpr double kMaxCellsPerBox = 16;
  std::array<double, 3> origin_{};
  double width_ = 0, per_width_ = 0;
  std::array<int, 3> size_{0, 0, 0};
};

// Calls visit(f, g) once for every pair of faces whose (closed) boxes overlap
// and one of which is counted, until it returns false. Each box is entered in
// the cells of a BoxGrid it overlaps (a counting sort by cell), and a pair is
// visited in the one cell that holds the low corner of the boxes'
// intersection, which both boxes overlap. A fill's faces are all of about one
// size, so that a cell holds few boxes, and this grid finds the pairs in
// less time than CGAL's box_self_intersection_d (a segment tree), which is
// made for boxes of any sizes (docs/benchmarks.md).
template <typename Visit>
void for_each_overlapping_pair(const std::vector<FaceBox>& boxes, Visit visit) {
  const BoxGrid grid(boxes);
  const int cells = grid.cell_count();
  if (cells == 0) return;
  std::vector<int> start(cells + 1, 0);  // boxes of cell c: members[start[c], start[c + 1])
  for (const FaceBox& box : boxes) grid.cells_of(box, [&](int c) { ++start[c + 1]; });
  for (int c = 0; c < cells; ++c) start[c + 1] += start[c];
  std::vector<int> members(start.back()), next(start.begin(), start.end() - 1);
  for (int b = 0; b < static_cast<int>(boxes.size()); ++b)
    grid.cells_of(boxes[b], [&](int c) { members[next[c]++] = b; });

  for (int c = 0; c < cells; ++c) {
    for (int p = start[c]; p < start[c + 1]; ++p) {
      const FaceBox& a = boxes[members[p]];
      for (int q = p + 1; q < start[c + 1]; ++q) {
        const FaceBox& b = boxes[members[q]];
        if (!(a.counted || b.counted) || !overlap(a, b)) continue;
        const std::array<double, 3> corner{std::max(a.low[0], b.low[0]),
                                           std::max(a.low[1], b.low[1]),
                                           std::max(a.low[2], b.low[2])};
        if (grid.cell(corner) == c && !visit(a.face, b.face)) return;
      }
    }
  }
}

// Whether the nondegenerate faces f and g of a manifold mesh intersect, by
// PMP::self_intersections's rules (internal::do_faces_intersect), in terms
// of vertex indices: faces sharing an edge intersect only when they are
// coplanar and overlap (their third vertices on the same side of the edge);
// faces sharing a vertex only when the edge of one opposite that vertex meets
// the other; other faces when their triangles meet.
bool faces_intersect(const std::vector<Vec3>& positions, const Tri& f, const Tri& g) {
  auto has = [](const Tri& t, int v) { return t[0] == v || t[1] == v || t[2] == v; };
  int shared = 0, f_shared = 0, f_own = 0, g_shared = 0, g_own = 0;  // corners
  for (int k = 0; k < 3; ++k) {
    if (has(g, f[k])) {
      ++shared;
      f_shared = k;
    } else {
      f_own = k;
    }
    (has(f, g[k]) ? g_shared : g_own) = k;
  }
  auto corner = [&](const Tri& t, int k) { return point(positions[t[k % 3]]); };
  if (shared == 3) {
    throw InternalError("self-intersection test: the faces do not form a manifold");
  }
  if (shared == 2) {
    const Kernel::Point_3 a = corner(f, f_own + 1), b = corner(f, f_own + 2),
                          f_third = corner(f, f_own), g_third = corner(g, g_own);
    return CGAL::coplanar(a, b, f_third, g_third) &&
           CGAL::coplanar_orientation(a, b, f_third, g_third) == CGAL::POSITIVE;
  }
  const Triangle f_triangle(corner(f, 0), corner(f, 1), corner(f, 2)),
      g_triangle(corner(g, 0), corner(g, 1), corner(g, 2));
  if (shared == 0) return CGAL::do_intersect(f_triangle, g_triangle);
  const Kernel::Segment_3 f_opposite(corner(f, f_shared + 1), corner(f, f_shared + 2)),
      g_opposite(corner(g, g_shared + 1), corner(g, g_shared + 2));
  return CGAL::do_intersect(f_triangle, g_opposite) || CGAL::do_intersect(g_triangle, f_opposite);
}

// The box of a face; false when a corner is not finite.
bool face_box(const std::vector<Vec3>& positions, const Tri& f, Box3& box) {
  const Vec3 &p = positions[f[0]], &q = positions[f[1]], &r = positions[f[2]];
  if (!is_finite(p) || !is_finite(q) || !is_finite(r)) return false;
  for (int c = 0; c < 3; ++c) {
    box.low[c] = std::min({p[c], q[c], r[c]});
    box.high[c] = std::max({p[c], q[c], r[c]});
  }
  return true;
}

// The distance between two boxes: a lower bound of that of what they hold.
double box_gap(const FaceBox& a, const FaceBox& b) {
  double squared = 0;
  for (int c = 0; c < 3; ++c) {
    const double gap = std::max({a.low[c] - b.high[c], b.low[c] - a.high[c], 0.0});
    squared += gap * gap;
  }
  return std::sqrt(squared);
}

geometry::Triangle corners(const std::vector<Vec3>& positions, const Tri& f) {
  return {positions[f[0]], positions[f[1]], positions[f[2]]};
}

}  // namespace

CurvatureStats gaussian_curvature_stats(const std::vector<Vec3>& positions,
                                        const std::vector<Tri>& faces,
                                        const std::vector<int>& vertices) {
  std::vector<double> angle_sum(positions.size(), 0.0), area(positions.size(), 0.0);
  for (const Tri& f : faces) {
    const double third = triangle_area(positions, f) / 3;
    for (int k = 0; k < 3; ++k) {
      angle_sum[f[k]] += corner_angle(positions, f, k);
      area[f[k]] += third;
    }
  }
  CurvatureStats stats;
  if (vertices.empty()) return stats;
  std::vector<double> curvature;
  curvature.reserve(vertices.size());
  for (int v : vertices) curvature.push_back(area[v] > 0 ? (2 * M_PI - angle_sum[v]) / area[v] : 0);
  double sum = 0, sum_abs = 0;
  for (double k : curvature) {
    sum += k;
    sum_abs += std::abs(k);
  }
  const double mean = sum / curvature.size();
  double squares = 0;
  for (double k : curvature) squares += (k - mean) * (k - mean);
  stats.mean_abs = sum_abs / curvature.size();
  stats.variance = squares / curvature.size();
  return stats;
}

// The pairs PMP::self_intersections would find on the mesh, without building
// it (the faces must form a manifold, as a fill's domain does; only a face
// given twice is caught), and only those with a counted face: the strip's own
// pairs are never looked at. PMP::self_intersections reports a degenerate
// face as intersecting itself and tests it against no other; a face with a
// non-finite corner is taken as degenerate.
int count_self_intersections(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                             int counted_from) {
  int count = 0;
  const std::vector<FaceBox> boxes = face_boxes(positions, faces, counted_from, count);
  for_each_overlapping_pair(boxes, [&](int f, int g) {
    count += faces_intersect(positions, faces[f], faces[g]);
    return true;
  });
  return count;
}

bool passes_through_itself(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                           int counted_from) {
  int degenerate = 0;
  const std::vector<FaceBox> boxes = face_boxes(positions, faces, counted_from, degenerate);
  bool found = false;
  for_each_overlapping_pair(boxes, [&](int f, int g) {
    found = !share_a_vertex(faces[f], faces[g]) && faces_intersect(positions, faces[f], faces[g]);
    return !found;
  });
  return found;
}

double total_area(const std::vector<Vec3>& positions, const std::vector<Tri>& faces) {
  double area = 0;
  for (const Tri& f : faces) area += triangle_area(positions, f);
  return area;
}

double rms_relative_edge_error(const std::vector<Vec3>& positions,
                               const std::vector<std::array<int, 2>>& edges,
                               const std::vector<double>& rest_lengths) {
  if (edges.empty()) return 0;
  double squares = 0;
  for (size_t e = 0; e < edges.size(); ++e) {
    const double ratio =
        norm(sub(positions[edges[e][0]], positions[edges[e][1]])) / rest_lengths[e];
    squares += (ratio - 1) * (ratio - 1);
  }
  return std::sqrt(squares / edges.size());
}

SurfaceDistance surface_distance(const std::vector<Vec3>& positions_a,
                                 const std::vector<Tri>& faces_a,
                                 const std::vector<Vec3>& positions_b,
                                 const std::vector<Tri>& faces_b) {
  const std::vector<Triangle> triangles_a = nondegenerate_triangles(positions_a, faces_a);
  const std::vector<Triangle> triangles_b = nondegenerate_triangles(positions_b, faces_b);
  if (triangles_a.empty() || triangles_b.empty()) {
    throw UsageError("surface distance: a surface has no non-degenerate triangle");
  }
  const TriangleTree tree_a(triangles_a.begin(), triangles_a.end());
  const TriangleTree tree_b(triangles_b.begin(), triangles_b.end());
  const auto [largest_ab, mean_ab] = one_sided_distance(positions_a, faces_a, tree_b);
  const auto [largest_ba, mean_ba] = one_sided_distance(positions_b, faces_b, tree_a);
  return {std::max(largest_ab, largest_ba), 0.5 * (mean_ab + mean_ba)};
}

std::vector<double> dihedral_angles(const std::vector<Vec3>& positions,
                                    const std::vector<Tri>& faces,
                                    const std::vector<std::array<int, 2>>& edges) {
  const auto edge_faces = sorted_edge_faces(faces);
  std::vector<double> angles;
  angles.reserve(edges.size());
  for (const auto& [a, b] : edges) {
    const std::uint64_t key = edge_key(a, b);
    const auto first =
        std::lower_bound(edge_faces.begin(), edge_faces.end(), std::make_pair(key, -1));
    if (std::distance(first, edge_faces.end()) < 2 || first[0].first != key ||
        first[1].first != key || (first + 2 != edge_faces.end() && first[2].first == key)) {
      throw UsageError("dihedral angle: edge " + std::to_string(a) + "-" + std::to_string(b) +
                       " is not shared by two faces");
    }
    angles.push_back(normal_angle(positions, faces[first[0].second], faces[first[1].second]));
  }
  return angles;
}

double mean_abs_mean_curvature(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                               const std::vector<int>& vertices) {
  std::vector<Vec3> laplacian(positions.size(), Vec3{0, 0, 0}),
      normal(positions.size(), Vec3{0, 0, 0});
  std::vector<double> area(positions.size(), 0.0);
  for (const Tri& f : faces) {
    const Vec3 n = face_normal(positions, f);
    const double double_area = norm(n);
    if (!(double_area > 0)) continue;  // a degenerate face has no cotangents
    for (int k = 0; k < 3; ++k) {
      const int i = f[(k + 1) % 3], j = f[(k + 2) % 3];
      const double cot_k =
          dot(sub(positions[i], positions[f[k]]), sub(positions[j], positions[f[k]])) / double_area;
      const Vec3 e = sub(positions[j], positions[i]);
      for (int c = 0; c < 3; ++c) {
        laplacian[i][c] += cot_k * e[c];
        laplacian[j][c] -= cot_k * e[c];
        normal[f[k]][c] += n[c];
      }
      area[f[k]] += double_area / 6;
    }
  }
  double integral = 0, total = 0;
  for (int v : vertices) {
    const double length = norm(normal[v]);
    if (length > 0) integral += std::abs(dot(laplacian[v], normal[v])) / (4 * length);
    total += area[v];
  }
  return total > 0 ? integral / total : 0;
}

TriangleQuality triangle_quality(const std::vector<Vec3>& positions,
                                 const std::vector<Tri>& faces) {
  TriangleQuality quality;
  if (faces.empty()) return quality;
  const double twenty_degrees = 20 * M_PI / 180;
  double smallest = M_PI;
  int below = 0;
  for (const Tri& f : faces) {
    const double angle = std::min({corner_angle(positions, f, 0), corner_angle(positions, f, 1),
                                   corner_angle(positions, f, 2)});
    smallest = std::min(smallest, angle);
    below += angle < twenty_degrees;
  }
  quality.min_angle_deg = smallest * 180 / M_PI;
  quality.share_below_20deg = static_cast<double>(below) / faces.size();
  return quality;
}

std::vector<int> vertices_within_rings(int vertex_count, const std::vector<Tri>& faces,
                                       const std::vector<int>& seeds, int rings) {
  // Vertex adjacency in compressed rows (both directions of every face edge).
  std::vector<int> start(vertex_count + 1, 0);
  for (const Tri& f : faces) {
    for (int v : f) {
      if (v < 0 || v >= vertex_count) {
        throw UsageError("rings: vertex index " + std::to_string(v) + " out of range");
      }
      start[v + 1] += 2;
    }
  }
  for (int v = 0; v < vertex_count; ++v) start[v + 1] += start[v];
  std::vector<int> neighbours(start.back()), next_slot(start.begin(), start.end() - 1);
  for (const Tri& f : faces) {
    for (int k = 0; k < 3; ++k) {
      neighbours[next_slot[f[k]]++] = f[(k + 1) % 3];
      neighbours[next_slot[f[k]]++] = f[(k + 2) % 3];
    }
  }
  std::vector<int> distance(vertex_count, -1), frontier;
  for (int s : seeds) {
    if (s < 0 || s >= vertex_count) {
      throw UsageError("rings: seed " + std::to_string(s) + " out of range");
    }
    if (distance[s] < 0) frontier.push_back(s);
    distance[s] = 0;
  }
  std::vector<int> reached;
  for (int ring = 1; ring <= rings && !frontier.empty(); ++ring) {
    std::vector<int> next;
    for (int v : frontier) {
      for (int i = start[v]; i < start[v + 1]; ++i) {
        if (distance[neighbours[i]] >= 0) continue;
        distance[neighbours[i]] = ring;
        next.push_back(neighbours[i]);
      }
    }
    reached.insert(reached.end(), next.begin(), next.end());
    frontier = std::move(next);
  }
  std::sort(reached.begin(), reached.end());
  return reached;
}

}  // namespace foldfill

namespace foldfill {

Box3 bounding_box(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                  const std::vector<int>& subset, double margin) {
  Box3 box;
  box.low.fill(HUGE_VAL);
  box.high.fill(-HUGE_VAL);
  for (int f : subset) {
    Box3 face;
    if (!face_box(positions, faces[f], face)) continue;
    for (int c = 0; c < 3; ++c) {
      box.low[c] = std::min(box.low[c], face.low[c] - margin);
      box.high[c] = std::max(box.high[c], face.high[c] + margin);
    }
  }
  return box;
}

std::vector<std::vector<int>> faces_near_boxes(const std::vector<Vec3>& positions,
                                               const std::vector<Tri>& faces,
                                               const std::vector<Box3>& boxes) {
  std::vector<std::vector<int>> near(boxes.size());
  // Cells as wide as the widest box, so that a box is in at most 8 of them.
  Box3 all;
  all.low.fill(HUGE_VAL);
  all.high.fill(-HUGE_VAL);
  double width = 0;
  for (const Box3& box : boxes) {
    for (int c = 0; c < 3; ++c) {
      if (!(box.low[c] <= box.high[c])) continue;
      all.low[c] = std::min(all.low[c], box.low[c]);
      all.high[c] = std::max(all.high[c], box.high[c]);
      width = std::max(width, box.high[c] - box.low[c]);
    }
  }
  if (!(all.low[0] <= all.high[0] && all.low[1] <= all.high[1] && all.low[2] <= all.high[2]))
    return near;  // no box holds anything
  if (!(width > 0) || !std::isfinite(width)) width = 1;
  const auto index = [&](double x, int c) {
    return static_cast<std::int64_t>(
        std::floor((std::clamp(x, all.low[c], all.high[c]) - all.low[c]) / width));
  };
  const auto key = [](std::int64_t i, std::int64_t j, std::int64_t k) {
    return static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ull ^
           static_cast<std::uint64_t>(j) * 0xC2B2AE3D27D4EB4Full ^
           static_cast<std::uint64_t>(k) * 0x165667B19E3779F9ull;
  };
  std::unordered_map<std::uint64_t, std::vector<int>> cells;
  for (int b = 0; b < static_cast<int>(boxes.size()); ++b) {
    const Box3& box = boxes[b];
    if (!(box.low[0] <= box.high[0] && box.low[1] <= box.high[1] && box.low[2] <= box.high[2]))
      continue;
    for (auto k = index(box.low[2], 2); k <= index(box.high[2], 2); ++k)
      for (auto j = index(box.low[1], 1); j <= index(box.high[1], 1); ++j)
        for (auto i = index(box.low[0], 0); i <= index(box.high[0], 0); ++i)
          cells[key(i, j, k)].push_back(b);
  }
  // A face that spans more cells than this is tested against every box.
  constexpr std::int64_t kMostCellsPerFace = 64;
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    Box3 box;
    if (!face_box(positions, faces[f], box) || !overlap(box, all)) continue;
    const auto add = [&](int b) {
      if (overlap(box, boxes[b]) && (near[b].empty() || near[b].back() != f)) near[b].push_back(f);
    };
    std::array<std::int64_t, 3> from, to;
    for (int c = 0; c < 3; ++c) {
      from[c] = index(box.low[c], c);
      to[c] = index(box.high[c], c);
    }
    if ((to[0] - from[0] + 1) * (to[1] - from[1] + 1) * (to[2] - from[2] + 1) > kMostCellsPerFace) {
      for (int b = 0; b < static_cast<int>(boxes.size()); ++b) add(b);
      continue;
    }
    for (auto k = from[2]; k <= to[2]; ++k)
      for (auto j = from[1]; j <= to[1]; ++j)
        for (auto i = from[0]; i <= to[0]; ++i) {
          const auto cell = cells.find(key(i, j, k));
          if (cell == cells.end()) continue;
          for (int b : cell->second) add(b);
        }
  }
  return near;
}

SubsetCrossings count_subset_crossings(const std::vector<Vec3>& positions,
                                       const std::vector<Tri>& faces,
                                       const std::vector<int>& subset, double reach,
                                       const std::vector<int>* nearby) {
  SubsetCrossings result;
  result.min_distance = reach;
  if (subset.empty()) return result;
  std::vector<int> found;
  if (!nearby) {
    found = faces_near_boxes(positions, faces, {bounding_box(positions, faces, subset, reach)})[0];
    nearby = &found;
  }
  std::vector<int> local;  // the faces looked at: `subset` and those near it
  local.reserve(nearby->size() + subset.size());
  std::set_union(nearby->begin(), nearby->end(), subset.begin(), subset.end(),
                 std::back_inserter(local));
  result.faces_examined = static_cast<int>(local.size());

  // The boxes of the nondegenerate faces, as face_boxes makes them, and the
  // same grown by half the reach: those of two faces within `reach` of each
  // other overlap.
  std::vector<FaceBox> boxes, grown;
  std::vector<int> face_of;  // of each box
  // The centroid of each box's face and the largest distance of a corner
  // from it: what bounds the distance of two faces below, with box_gap.
  std::vector<Vec3> centroid;
  std::vector<double> spread;
  boxes.reserve(local.size());
  grown.reserve(local.size());
  face_of.reserve(local.size());
  for (size_t i = 0, s = 0; i < local.size(); ++i) {
    const int f = local[i];
    while (s < subset.size() && subset[s] < f) ++s;
    const bool counted = s < subset.size() && subset[s] == f;
    const Tri& t = faces[f];
    Box3 box;
    if (!face_box(positions, t, box) ||
        CGAL::collinear(point(positions[t[0]]), point(positions[t[1]]), point(positions[t[2]]))) {
      result.within += counted;
      continue;
    }
    FaceBox face{box.low, box.high, static_cast<int>(boxes.size()), counted};
    boxes.push_back(face);
    face_of.push_back(f);
    const geometry::Triangle corner = corners(positions, t);
    Vec3 middle;
    for (int c = 0; c < 3; ++c) middle[c] = (corner[0][c] + corner[1][c] + corner[2][c]) / 3;
    double farthest = 0;
    for (const Vec3& p : corner) farthest = std::max(farthest, norm(sub(p, middle)));
    centroid.push_back(middle);
    spread.push_back(farthest);
    for (int c = 0; c < 3; ++c) {
      face.low[c] -= 0.5 * reach;
      face.high[c] += 0.5 * reach;
    }
    grown.push_back(face);
  }
  double& best = result.min_distance;
  for_each_overlapping_pair(grown, [&](int i, int j) {
    const int f = face_of[i], g = face_of[j];
    const bool intersect =
        overlap(boxes[i], boxes[j]) && faces_intersect(positions, faces[f], faces[g]);
    if (intersect) ++(boxes[i].counted && boxes[j].counted ? result.within : result.with_others);
    if (best > 0 && !share_a_vertex(faces[f], faces[g])) {
      if (intersect) {
        best = 0;
      } else if (box_gap(boxes[i], boxes[j]) < best &&
                 norm(sub(centroid[i], centroid[j])) - spread[i] - spread[j] < best) {
        best = std::min(best, geometry::disjoint_triangle_distance(corners(positions, faces[f]),
                                                                   corners(positions, faces[g])));
      }
    }
    return true;
  });
  return result;
}

}  // namespace foldfill
