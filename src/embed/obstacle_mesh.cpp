// Triangle meshes as obstacles: the nearest point through CGAL's AABB tree,
// inside and outside by CGAL's Side_of_triangle_mesh or the angle-weighted
// pseudo-normal of the nearest feature (Baerentzen and Aanaes 2005), and
// exact triangle tests (one of the few translation units that include CGAL).
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "embed/triangle_geometry.h"
#include "foldfill/error.h"
#include "foldfill/obstacles.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
using Side = CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel>;
namespace PMP = CGAL::Polygon_mesh_processing;

// Within this fraction of the bounding-box diagonal of the surface, the side
// of a point is decided by exact predicates: the pseudo-normal's sign is
// rounding noise there.
constexpr double kExactSideWithin = 1e-7;
// push_outside puts a point this fraction of the diagonal off the surface,
// and up to kPushTries times ten times farther where that is not outside.
constexpr double kPushMargin = 1e-9;
constexpr int kPushTries = 6;
// Barycentric coordinates below this: the nearest point is on an edge or a
// corner of its face (the pseudo-normal there is the edge's or the corner's).
constexpr double kOnFeature = 1e-9;

Vec3 unit_or_zero(const Vec3& a) {
  const double length = norm(a);
  return length > 0 ? Vec3{a[0] / length, a[1] / length, a[2] / length} : Vec3{0, 0, 0};
}

Point point(const Vec3& p) { return {p[0], p[1], p[2]}; }
Vec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32 |
         static_cast<std::uint32_t>(b);
}

// The nearest point of the surface to a query point, and the feature of its
// face it lies on.
struct Nearest {
  Vec3 point;
  int face;
  Vec3 pseudo_normal;  // of the face, the edge or the corner, not unit
  double distance;
  bool on_rim = false;  // the nearest point is on the boundary of an open mesh
};

}  // namespace

struct ObstacleMesh::Search {
  SurfaceMesh surface;
  std::vector<Tri> faces;  // as in `surface`, oriented outwards when closed
  std::vector<Vec3> positions;
  std::vector<Vec3> face_normals;                        // unit (0 for a degenerate face)
  std::vector<Vec3> corner_normals;                      // angle-weighted sums of the face normals
  std::unordered_map<std::uint64_t, Vec3> edge_normals;  // sums of the faces' normals
  std::unordered_map<std::uint64_t, int> edge_faces;     // faces per edge: 1 on the rim
  std::vector<char> rim_vertex;                          // on a boundary edge
  std::optional<Tree> tree;
  std::optional<Side> side;  // closed meshes only
  bool closed = false;
  std::array<double, 3> low{}, high{};
  double diagonal = 0;

  Search(const Mesh& mesh, const std::string& source);

  Nearest nearest(const Vec3& p) const;
  double signed_distance(const Vec3& p, const Nearest& n) const;
};

ObstacleMesh::Search::Search(const Mesh& mesh, const std::string& source) {
  surface.reserve(mesh.vertex_count(), 3 * mesh.face_count() / 2 + 3, mesh.face_count());
  for (const Vec3& p : mesh.positions) surface.add_vertex(point(p));
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Tri& t = mesh.faces[f];
    if (surface.add_face(SurfaceMesh::Vertex_index(t[0]), SurfaceMesh::Vertex_index(t[1]),
                         SurfaceMesh::Vertex_index(t[2])) == SurfaceMesh::null_face()) {
      throw NonManifoldError(source + ": obstacle mesh face " + std::to_string(f) +
                             " makes an edge or a vertex non-manifold, or is oriented against its "
                             "neighbours");
    }
  }
  closed = CGAL::is_closed(surface);
  if (closed) PMP::orient_to_bound_a_volume(surface);
  positions = mesh.positions;
  for (auto f : surface.faces()) {
    Tri t;
    int k = 0;
    for (auto v : CGAL::vertices_around_face(surface.halfedge(f), surface))
      t[k++] = static_cast<int>(v.idx());
    faces.push_back(t);
  }
  corner_normals.assign(positions.size(), Vec3{0, 0, 0});
  for (const Tri& t : faces) {
    const Vec3 n = unit_or_zero(
        cross(sub(positions[t[1]], positions[t[0]]), sub(positions[t[2]], positions[t[0]])));
    face_normals.push_back(n);
    for (int k = 0; k < 3; ++k) {
      const double angle =
          corner_angle(positions[t[k]], positions[t[(k + 1) % 3]], positions[t[(k + 2) % 3]]);
      corner_normals[t[k]] = add_scaled(corner_normals[t[k]], n, angle);
      Vec3& edge = edge_normals[edge_key(t[k], t[(k + 1) % 3])];
      edge = add_scaled(edge, n, 1);
      ++edge_faces[edge_key(t[k], t[(k + 1) % 3])];
    }
  }
  rim_vertex.assign(positions.size(), 0);
  for (const Tri& t : faces)
    for (int k = 0; k < 3; ++k)
      if (edge_faces.at(edge_key(t[k], t[(k + 1) % 3])) == 1)
        rim_vertex[t[k]] = rim_vertex[t[(k + 1) % 3]] = 1;
  low.fill(HUGE_VAL);
  high.fill(-HUGE_VAL);
  for (const Vec3& p : positions)
    for (int c = 0; c < 3; ++c) {
      low[c] = std::min(low[c], p[c]);
      high[c] = std::max(high[c], p[c]);
    }
  diagonal = std::hypot(high[0] - low[0], high[1] - low[1], high[2] - low[2]);
  tree.emplace(CGAL::faces(surface).first, CGAL::faces(surface).second, surface);
  tree->build();
  tree->accelerate_distance_queries();
  if (closed) side.emplace(*tree);
}

Nearest ObstacleMesh::Search::nearest(const Vec3& p) const {
  const auto [q, primitive] = tree->closest_point_and_primitive(point(p));
  Nearest n;
  n.point = vec(q);
  n.face = static_cast<int>(primitive.idx());
  n.distance = norm(sub(p, n.point));
  // Barycentric coordinates of the nearest point in its face.
  const Tri& t = faces[n.face];
  const Vec3 ab = sub(positions[t[1]], positions[t[0]]), ac = sub(positions[t[2]], positions[t[0]]),
             aq = sub(n.point, positions[t[0]]);
  const double d00 = dot(ab, ab), d01 = dot(ab, ac), d11 = dot(ac, ac), d20 = dot(aq, ab),
               d21 = dot(aq, ac), denominator = d00 * d11 - d01 * d01;
  n.pseudo_normal = face_normals[n.face];
  if (!(denominator > 0)) return n;
  const double v = (d11 * d20 - d01 * d21) / denominator, w = (d00 * d21 - d01 * d20) / denominator;
  const std::array<double, 3> weight{1 - v - w, v, w};
  int small = 0, last_large = 0, last_small = 0;
  for (int k = 0; k < 3; ++k) {
    if (weight[k] < kOnFeature) {
      ++small;
      last_small = k;
    } else {
      last_large = k;
    }
  }
  if (small == 1) {  // on the edge opposite corner last_small
    const std::uint64_t key = edge_key(t[(last_small + 1) % 3], t[(last_small + 2) % 3]);
    n.pseudo_normal = edge_normals.at(key);
    n.on_rim = edge_faces.at(key) == 1;
  } else if (small >= 2) {  // at corner last_large
    n.pseudo_normal = corner_normals[t[last_large]];
    n.on_rim = rim_vertex[t[last_large]] != 0;
  }
  return n;
}

double ObstacleMesh::Search::signed_distance(const Vec3& p, const Nearest& n) const {
  // An open mesh has an inside only behind it: a point whose nearest point is
  // on its rim lies beside the surface, not under it (else one far-off
  // triangle would put half of space inside).
  if (!closed && n.on_rim) return n.distance;
  if (n.distance > kExactSideWithin * diagonal) {
    return dot(sub(p, n.point), n.pseudo_normal) < 0 ? -n.distance : n.distance;
  }
  if (closed) {
    switch ((*side)(point(p))) {
      case CGAL::ON_BOUNDED_SIDE:
        return -n.distance;
      case CGAL::ON_BOUNDARY:
        return 0;
      case CGAL::ON_UNBOUNDED_SIDE:
        return n.distance;
    }
  }
  const Tri& t = faces[n.face];
  switch (CGAL::orientation(point(positions[t[0]]), point(positions[t[1]]), point(positions[t[2]]),
                            point(p))) {
    case CGAL::NEGATIVE:
      return -n.distance;
    case CGAL::ZERO:
      return 0;
    case CGAL::POSITIVE:
      return n.distance;
  }
  return n.distance;
}

ObstacleMesh::ObstacleMesh(Mesh mesh, std::string source)
    : mesh_(std::move(mesh)), source_(std::move(source)) {
  auto search = std::make_unique<Search>(mesh_, source_);
  mesh_.faces = search->faces;
  mesh_.texcoords.clear();
  mesh_.normals.clear();
  mesh_.face_texcoords.clear();
  mesh_.face_normals.clear();
  search_ = std::move(search);
}

ObstacleMesh::~ObstacleMesh() = default;

bool ObstacleMesh::closed() const { return search_->closed; }

double ObstacleMesh::signed_distance(const Vec3& p) const {
  return search_->signed_distance(p, search_->nearest(p));
}

Vec3 ObstacleMesh::outward_normal(const Vec3& p) const {
  const Nearest n = search_->nearest(p);
  if (n.distance > kExactSideWithin * search_->diagonal) {
    const double sign = search_->signed_distance(p, n) < 0 ? -1 : 1;
    const Vec3 away = sub(p, n.point);
    return {sign * away[0] / n.distance, sign * away[1] / n.distance, sign * away[2] / n.distance};
  }
  return unit_or_zero(n.pseudo_normal);
}

bool ObstacleMesh::farther_than(const Vec3& p, double gap) const {
  // Only a closed mesh has its whole inside within its bounding box; the
  // thresholds are grown by a hair, so that rounding here and in
  // signed_distance cannot disagree.
  if (!search_->closed) return false;
  double squared = 0;
  for (int c = 0; c < 3; ++c) {
    const double outside = std::max({search_->low[c] - p[c], p[c] - search_->high[c], 0.0});
    squared += outside * outside;
  }
  const double reach = (1 + 1e-6) * gap + 1e-12 * search_->diagonal;
  return squared > reach * reach;
}

bool ObstacleMesh::push_outside(Vec3& p) const {
  const Nearest n = search_->nearest(p);
  if (search_->signed_distance(p, n) > 0) return false;
  // Away from the surface along the way from p to its nearest point, or along
  // the pseudo-normal where p is (about) on the surface.
  Vec3 direction = n.distance > kExactSideWithin * search_->diagonal
                       ? unit_or_zero(sub(n.point, p))
                       : unit_or_zero(n.pseudo_normal);
  double margin = kPushMargin * search_->diagonal;
  Vec3 moved = n.point;
  for (int attempt = 0; attempt < kPushTries; ++attempt, margin *= 10) {
    moved = add_scaled(n.point, direction, margin);
    if (signed_distance(moved) > 0) break;
    direction = unit_or_zero(n.pseudo_normal);
  }
  p = moved;
  return true;
}

bool ObstacleMesh::crosses(const std::array<Vec3, 3>& triangle) const {
  const Kernel::Triangle_3 t(point(triangle[0]), point(triangle[1]), point(triangle[2]));
  if (!t.is_degenerate() && search_->tree->do_intersect(t)) return true;
  if (!search_->closed) return false;
  return std::any_of(triangle.begin(), triangle.end(), [&](const Vec3& corner) {
    return (*search_->side)(point(corner)) == CGAL::ON_BOUNDED_SIDE;
  });
}

double ObstacleMesh::distance(const std::array<Vec3, 3>& triangle, double limit) const {
  if (crosses(triangle)) return 0;
  std::array<double, 3> low, high;
  for (int c = 0; c < 3; ++c) {
    low[c] = std::min({triangle[0][c], triangle[1][c], triangle[2][c]}) - limit;
    high[c] = std::max({triangle[0][c], triangle[1][c], triangle[2][c]}) + limit;
  }
  std::vector<Primitive::Id> near;
  search_->tree->all_intersected_primitives(
      CGAL::Bbox_3(low[0], low[1], low[2], high[0], high[1], high[2]), std::back_inserter(near));
  double best = limit;
  for (const Primitive::Id& f : near) {
    const Tri& t = search_->faces[f.idx()];
    const geometry::Triangle other{search_->positions[t[0]], search_->positions[t[1]],
                                   search_->positions[t[2]]};
    best = std::min(best, geometry::disjoint_triangle_distance(triangle, other));
  }
  return best;
}

Obstacle mesh_obstacle(Mesh mesh, const std::string& source) {
  Obstacle obstacle;
  obstacle.type = Obstacle::Type::Mesh;
  obstacle.mesh = std::make_shared<const ObstacleMesh>(std::move(mesh), source);
  return obstacle;
}

}  // namespace foldfill
