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
#include <utility>

#include "embed/triangle_geometry.h"
#include "foldfill/box_tree.h"
#include "foldfill/error.h"
#include "foldfill/topology.h"
#include "foldfill/vec3.h"

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
  Box box;
  int face;
  bool counted;
};

// The boxes of the nondegenerate faces, and how many counted faces (index in
// [counted_from, counted_to)) are degenerate: collinear or with a non-finite
// corner.
std::vector<FaceBox> face_boxes(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                                int counted_from, int& degenerate_counted,
                                int counted_to = std::numeric_limits<int>::max()) {
  const int face_count = static_cast<int>(faces.size());
  counted_from = std::clamp(counted_from, 0, face_count);
  counted_to = std::clamp(counted_to, counted_from, face_count);
  degenerate_counted = 0;
  std::vector<FaceBox> boxes;
  boxes.reserve(faces.size());
  for (int f = 0; f < face_count; ++f) {
    const Vec3 &p = positions[faces[f][0]], &q = positions[faces[f][1]],
               &r = positions[faces[f][2]];
    if (!is_finite(p) || !is_finite(q) || !is_finite(r) ||
        CGAL::collinear(point(p), point(q), point(r))) {
      degenerate_counted += f >= counted_from && f < counted_to;
      continue;
    }
    FaceBox box{{}, f, f >= counted_from && f < counted_to};
    for (int c = 0; c < 3; ++c) {
      box.box.low[c] = std::min({p[c], q[c], r[c]});
      box.box.high[c] = std::max({p[c], q[c], r[c]});
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

// Calls visit(f, g) once for every pair of faces whose (closed) boxes overlap
// and one of which is counted, until it returns false. The pairs come from
// the shared box tree (foldfill/box_tree.h): the counted boxes against
// themselves, then against the others, so that the pairs of two faces that
// are not counted (the strip's, the rest of the mesh's) are never looked at.
template <typename Visit>
void for_each_overlapping_pair(const std::vector<FaceBox>& boxes, Visit visit) {
  std::vector<Box> counted, others;
  std::vector<int> counted_id, other_id;  // indices into `boxes`
  for (int b = 0; b < static_cast<int>(boxes.size()); ++b) {
    (boxes[b].counted ? counted : others).push_back(boxes[b].box);
    (boxes[b].counted ? counted_id : other_id).push_back(b);
  }
  if (counted.empty()) return;
  const BoxTree counted_tree(counted);
  bool go_on = true;
  counted_tree.for_each_meeting_pair(0.0, [&](int i, int j) {
    if (go_on) go_on = visit(boxes[counted_id[i]].face, boxes[counted_id[j]].face);
  });
  if (!go_on || others.empty()) return;
  const BoxTree other_tree(others);
  counted_tree.for_each_meeting_pair(other_tree, 0.0, [&](int i, int j) {
    if (go_on) go_on = visit(boxes[counted_id[i]].face, boxes[other_id[j]].face);
  });
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
    const double gap = std::max({a.box.low[c] - b.box.high[c], b.box.low[c] - a.box.high[c], 0.0});
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

namespace {

// Whether a face is degenerate (collinear or with a non-finite corner),
// found when first asked.
class DegenerateFaces {
 public:
  DegenerateFaces(const std::vector<Vec3>& positions, const std::vector<Tri>& faces)
      : positions_(positions), faces_(faces), state_(faces.size(), 0) {}
  bool operator()(int f) {
    if (state_[f] == 0) {
      const Vec3 &p = positions_[faces_[f][0]], &q = positions_[faces_[f][1]],
                 &r = positions_[faces_[f][2]];
      state_[f] = !is_finite(p) || !is_finite(q) || !is_finite(r) ||
                          CGAL::collinear(point(p), point(q), point(r))
                      ? 2
                      : 1;
    }
    return state_[f] == 2;
  }

 private:
  const std::vector<Vec3>& positions_;
  const std::vector<Tri>& faces_;
  std::vector<unsigned char> state_;  // 0 not asked yet, 1 proper, 2 degenerate
};

}  // namespace

bool any_crossing(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                  int counted_from, int counted_to, const std::vector<std::array<int, 2>>& pairs) {
  DegenerateFaces degenerate(positions, faces);
  for (int f = counted_from; f < counted_to; ++f)
    if (degenerate(f)) return true;
  for (const auto& [f, g] : pairs)
    if (!degenerate(f) && !degenerate(g) && faces_intersect(positions, faces[f], faces[g]))
      return true;
  return false;
}

std::vector<std::pair<int, int>> intersecting_pairs(const std::vector<Vec3>& positions,
                                                    const std::vector<Tri>& faces, int counted_from,
                                                    int counted_to,
                                                    const std::vector<std::array<int, 2>>& pairs) {
  DegenerateFaces degenerate(positions, faces);
  const auto counted = [&](int f) { return f >= counted_from && f < counted_to; };
  std::vector<std::pair<int, int>> found;
  for (auto [f, g] : pairs) {
    if (degenerate(f) || degenerate(g) || !faces_intersect(positions, faces[f], faces[g])) continue;
    if (!counted(f) || (counted(g) && g < f)) std::swap(f, g);
    found.emplace_back(f, g);
  }
  std::sort(found.begin(), found.end());
  return found;
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
  int vertex_count = 0;
  for (const Tri& f : faces)
    for (int v : f) vertex_count = std::max(vertex_count, v + 1);
  const VertexFaces around = build_vertex_faces(faces, vertex_count, "dihedral angle");
  std::vector<double> angles;
  angles.reserve(edges.size());
  for (const auto& [a, b] : edges) {
    int shared[3], count = 0;  // the faces of edge a-b, ascending
    if (a >= 0 && a < vertex_count && b >= 0 && b < vertex_count && a != b) {
      for (int k = around.start[a]; k < around.start[a + 1] && count < 3; ++k) {
        const Tri& f = faces[around.faces[k]];
        if (f[0] == b || f[1] == b || f[2] == b) shared[count++] = around.faces[k];
      }
    }
    if (count != 2) {
      throw UsageError("dihedral angle: edge " + std::to_string(a) + "-" + std::to_string(b) +
                       " is not shared by two faces");
    }
    angles.push_back(normal_angle(positions, faces[shared[0]], faces[shared[1]]));
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
  const VertexFaces vertex_faces = build_vertex_faces(faces, vertex_count, "rings");
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
      for (int k = vertex_faces.start[v]; k < vertex_faces.start[v + 1]; ++k) {
        for (int w : faces[vertex_faces.faces[k]]) {
          if (distance[w] >= 0) continue;
          distance[w] = ring;
          next.push_back(w);
        }
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
  const BoxTree tree(boxes);  // an empty or non-finite box meets nothing
  // The box of all the boxes: most faces of a large mesh lie beyond it along
  // some axis, which three comparisons per axis tell.
  Box3 all{{HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
  for (const Box3& b : boxes) {
    if (is_empty(b)) continue;
    for (int c = 0; c < 3; ++c) {
      all.low[c] = std::min(all.low[c], b.low[c]);
      all.high[c] = std::max(all.high[c], b.high[c]);
    }
  }
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    const Vec3 &p = positions[faces[f][0]], &q = positions[faces[f][1]],
               &r = positions[faces[f][2]];
    bool beyond = false;
    for (int c = 0; c < 3; ++c)
      beyond |= (p[c] < all.low[c] && q[c] < all.low[c] && r[c] < all.low[c]) |
                (p[c] > all.high[c] && q[c] > all.high[c] && r[c] > all.high[c]);
    if (beyond) continue;
    Box3 box;
    if (!face_box(positions, faces[f], box)) continue;
    tree.for_each_meeting(box, 0.0, [&](int b) { near[b].push_back(f); });
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
    FaceBox face{box, static_cast<int>(boxes.size()), counted};
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
      face.box.low[c] -= 0.5 * reach;
      face.box.high[c] += 0.5 * reach;
    }
    grown.push_back(face);
  }
  double& best = result.min_distance;
  // The pairs that may be nearer than the reach, with a lower bound on
  // their distance: measured afterwards nearest bound first, until the
  // bound passes the least distance found (branch and bound).
  struct Bounded {
    double bound;
    int i, j;
  };
  std::vector<Bounded> near;
  for_each_overlapping_pair(grown, [&](int i, int j) {
    const int f = face_of[i], g = face_of[j];
    const bool intersect =
        overlap(boxes[i].box, boxes[j].box) && faces_intersect(positions, faces[f], faces[g]);
    if (intersect) ++(boxes[i].counted && boxes[j].counted ? result.within : result.with_others);
    if (best > 0 && !share_a_vertex(faces[f], faces[g])) {
      if (intersect) {
        best = 0;
      } else {
        const double bound = std::max(box_gap(boxes[i], boxes[j]),
                                      norm(sub(centroid[i], centroid[j])) - spread[i] - spread[j]);
        if (bound < best) near.push_back({bound, i, j});
      }
    }
    return true;
  });
  if (!(best > 0)) return result;
  std::sort(near.begin(), near.end(), [](const Bounded& a, const Bounded& b) {
    return a.bound < b.bound || (a.bound == b.bound && (a.i < b.i || (a.i == b.i && a.j < b.j)));
  });
  for (const Bounded& pair : near) {
    if (!(pair.bound < best)) break;
    best = std::min(
        best, geometry::disjoint_triangle_distance(corners(positions, faces[face_of[pair.i]]),
                                                   corners(positions, faces[face_of[pair.j]])));
  }
  return result;
}

}  // namespace foldfill
