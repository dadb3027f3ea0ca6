// Quality figures of a filled patch. Self-intersections use CGAL's exact
// triangle-triangle tests (this is one of the few translation units that
// include CGAL).
#include "foldfill/metrics.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <iterator>

#include "foldfill/error.h"

namespace foldfill {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

double triangle_area(const std::vector<Vec3>& p, const Tri& f) {
  return 0.5 * norm(cross(sub(p[f[1]], p[f[0]]), sub(p[f[2]], p[f[0]])));
}

// Interior angle at corner k of face f.
double corner_angle(const std::vector<Vec3>& p, const Tri& f, int k) {
  const Vec3 a = sub(p[f[(k + 1) % 3]], p[f[k]]), b = sub(p[f[(k + 2) % 3]], p[f[k]]);
  return std::atan2(norm(cross(a, b)), dot(a, b));
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

int count_self_intersections(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                             int counted_from) {
  SurfaceMesh mesh;
  std::vector<SurfaceMesh::Vertex_index> vertex(positions.size());
  for (size_t v = 0; v < positions.size(); ++v) {
    vertex[v] = mesh.add_vertex(Kernel::Point_3(positions[v][0], positions[v][1], positions[v][2]));
  }
  std::vector<int> face_index;  // CGAL face -> our face
  for (size_t f = 0; f < faces.size(); ++f) {
    const auto added = mesh.add_face(vertex[faces[f][0]], vertex[faces[f][1]], vertex[faces[f][2]]);
    if (added == SurfaceMesh::null_face()) {
      throw Error(ErrorKind::Internal, "self-intersection test: the faces do not form a manifold");
    }
    face_index.push_back(static_cast<int>(f));
  }
  std::vector<std::pair<SurfaceMesh::Face_index, SurfaceMesh::Face_index>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(mesh, std::back_inserter(pairs));
  int count = 0;
  for (const auto& [a, b] : pairs) {
    count += face_index[a.idx()] >= counted_from || face_index[b.idx()] >= counted_from;
  }
  return count;
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

}  // namespace foldfill
