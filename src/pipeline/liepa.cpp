// The smooth baseline with CGAL (one of the few translation units that include
// CGAL's mesh processing).
#include "foldfill/liepa.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <chrono>
#include <iterator>

#include "foldfill/error.h"
#include "foldfill/marks.h"
#include "embed/triangle_geometry.h"

namespace foldfill {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

SurfaceMesh to_surface_mesh(const Mesh& mesh, const std::string& source) {
  SurfaceMesh sm;
  sm.reserve(mesh.vertex_count(), 3 * mesh.face_count() / 2, mesh.face_count());
  for (const Vec3& p : mesh.positions) sm.add_vertex(Kernel::Point_3(p[0], p[1], p[2]));
  for (const Tri& f : mesh.faces) {
    if (sm.add_face(SurfaceMesh::Vertex_index(f[0]), SurfaceMesh::Vertex_index(f[1]),
                    SurfaceMesh::Vertex_index(f[2])) == SurfaceMesh::null_face()) {
      throw NonManifoldError(source + ": CGAL cannot build a surface mesh from it");
    }
  }
  return sm;
}

// The border half-edge of `sm` from loop vertex 0 to loop vertex 1.
SurfaceMesh::Halfedge_index border_halfedge(const SurfaceMesh& sm, const BoundaryLoop& loop) {
  const SurfaceMesh::Vertex_index from(loop.vertices[0]), to(loop.vertices[1]);
  for (auto h : CGAL::halfedges_around_source(from, sm)) {
    if (sm.target(h) == to && sm.is_border(h)) return h;
  }
  throw InternalError("liepa: loop " + std::to_string(loop.id) + " has no border half-edge");
}

}  // namespace

FillResult fill_holes_liepa(const Mesh& mesh, const std::vector<BoundaryLoop>& loops,
                            const std::vector<int>& fill_ids, const std::string& source,
                            const std::vector<Obstacle>& obstacles) {
  const auto start = std::chrono::steady_clock::now();
  SurfaceMesh sm = to_surface_mesh(mesh, source);
  FillResult result{mesh, {}};
  const auto holes_start = std::chrono::steady_clock::now();
  result.report.seconds_prepare = std::chrono::duration<double>(holes_start - start).count();
  std::vector<std::vector<SurfaceMesh::Face_index>> hole_faces;
  for (int id : fill_ids) {
    const BoundaryLoop& loop = loops.at(id);
    HoleReport report;
    report.loop_id = id;
    report.method = FillMethod::Liepa;
    report.loop_vertex_count = static_cast<int>(loop.vertices.size());
    const auto hole_start = std::chrono::steady_clock::now();
    std::vector<SurfaceMesh::Face_index> faces;
    std::vector<SurfaceMesh::Vertex_index> vertices;
    const auto [fair, patch_faces, patch_vertices] = PMP::triangulate_refine_and_fair_hole(
        sm, border_halfedge(sm, loop), std::back_inserter(faces), std::back_inserter(vertices));
    (void)patch_faces;
    (void)patch_vertices;
    report.seconds.total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - hole_start).count();
    report.filled = !faces.empty();
    if (!fair)
      report.warning = source + ": loop " + std::to_string(id) +
                       ": CGAL's fairing failed; the refined patch is kept unfaired";
    if (!report.filled)
      report.reason = source + ": loop " + std::to_string(id) + ": CGAL found no triangulation";
    report.patch_vertex_count = static_cast<int>(vertices.size());
    report.patch_face_count = static_cast<int>(faces.size());
    report.length_scale = loop.mean_edge_length;
    result.report.holes.push_back(report);
    hole_faces.push_back(std::move(faces));
  }
  const auto stitch_start = std::chrono::steady_clock::now();
  result.report.seconds_holes = std::chrono::duration<double>(stitch_start - holes_start).count();
  // CGAL appends vertices and faces after the existing ones; `index` maps
  // the new ones to their place in the result.
  std::vector<int> index(sm.number_of_faces(), -1);
  for (auto v : sm.vertices()) {
    if (static_cast<int>(v.idx()) < mesh.vertex_count()) continue;
    const auto& p = sm.point(v);
    result.mesh.positions.push_back({p.x(), p.y(), p.z()});
  }
  for (auto f : sm.faces()) {
    if (static_cast<int>(f.idx()) < mesh.face_count()) continue;
    Tri t;
    int k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm))
      t[k++] = static_cast<int>(v.idx());
    if (f.idx() >= index.size()) index.resize(f.idx() + 1, -1);
    index[f.idx()] = result.mesh.face_count();
    result.mesh.faces.push_back(t);
    if (!result.mesh.face_texcoords.empty()) result.mesh.face_texcoords.push_back({-1, -1, -1});
    if (!result.mesh.face_normals.empty()) result.mesh.face_normals.push_back({-1, -1, -1});
  }
  std::vector<std::vector<int>> patch_faces(hole_faces.size());
  for (size_t h = 0; h < hole_faces.size(); ++h) {
    for (auto f : hole_faces[h])
      if (f.idx() < index.size() && index[f.idx()] >= 0) patch_faces[h].push_back(index[f.idx()]);
    std::sort(patch_faces[h].begin(), patch_faces[h].end());
    double smallest = patch_faces[h].empty() ? 0 : 180;
    for (int f : patch_faces[h]) {
      const Tri& t = result.mesh.faces[f];
      smallest = std::min(smallest, geometry::smallest_angle_deg({result.mesh.positions[t[0]],
                                                                  result.mesh.positions[t[1]],
                                                                  result.mesh.positions[t[2]]}));
    }
    result.report.holes[h].patch_min_angle_deg = smallest;
  }
  mark_new_elements(result.mesh, loops, result.report);
  const auto crossings_start = std::chrono::steady_clock::now();
  result.report.seconds_stitch =
      std::chrono::duration<double>(crossings_start - stitch_start).count();
  measure_crossings(result.mesh, patch_faces, obstacles, source, result.report);
  const auto end = std::chrono::steady_clock::now();
  result.report.seconds_crossings = std::chrono::duration<double>(end - crossings_start).count();
  result.report.seconds_total = std::chrono::duration<double>(end - start).count();
  return result;
}

}  // namespace foldfill
