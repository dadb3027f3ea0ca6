// The fallback chain's smooth fills with CGAL (one of the few translation
// units that include CGAL's mesh processing). Only the hole's neighbourhood is
// handed to CGAL, so the cost follows the hole, not the mesh.
#include "foldfill/smooth_fill.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <iterator>

#include "foldfill/error.h"

namespace foldfill {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

// The faces within `rings` rings of the loop, with local vertex numbers:
// the loop first, in loop order, then the others as they are reached.
struct Neighbourhood {
  std::vector<int> to_input;  // local vertex -> input vertex
  std::vector<Tri> faces;     // local indices, input orientation
};

Neighbourhood collect_neighbourhood(const Mesh& mesh, const VertexFaces& vertex_faces,
                                    const BoundaryLoop& loop, int rings) {
  Neighbourhood around;
  std::vector<int> local(mesh.vertex_count(), -1);
  std::vector<char> face_taken(mesh.face_count(), 0);
  for (int v : loop.vertices) {
    local[v] = static_cast<int>(around.to_input.size());
    around.to_input.push_back(v);
  }
  size_t ring_begin = 0, ring_end = around.to_input.size();
  for (int ring = 0; ring < rings; ++ring) {
    for (size_t i = ring_begin; i < ring_end; ++i) {
      const int v = around.to_input[i];
      for (int k = vertex_faces.start[v]; k < vertex_faces.start[v + 1]; ++k) {
        const int f = vertex_faces.faces[k];
        if (face_taken[f]) continue;
        face_taken[f] = 1;
        Tri t;
        for (int c = 0; c < 3; ++c) {
          const int w = mesh.faces[f][c];
          if (local[w] < 0) {
            local[w] = static_cast<int>(around.to_input.size());
            around.to_input.push_back(w);
          }
          t[c] = local[w];
        }
        around.faces.push_back(t);
      }
    }
    ring_begin = ring_end;
    ring_end = around.to_input.size();
  }
  return around;
}

}  // namespace

SmoothPatch fill_hole_smooth(const Mesh& mesh, const VertexFaces& vertex_faces,
                             const BoundaryLoop& loop, SmoothFairing fairing,
                             const std::string& source, int rings) {
  const std::string where = source + ": loop " + std::to_string(loop.id);
  const int loop_size = static_cast<int>(loop.vertices.size());
  if (loop_size < 3) throw Error(ErrorKind::NotADisk, where + ": it has fewer than 3 vertices");
  const int continuity = fairing == SmoothFairing::Curvature ? 2 : 1;
  const Neighbourhood around =
      collect_neighbourhood(mesh, vertex_faces, loop, std::max(rings, continuity + 1));

  SurfaceMesh sm;
  sm.reserve(around.to_input.size(), 3 * around.faces.size() / 2 + loop_size, around.faces.size());
  for (int v : around.to_input) {
    const Vec3& p = mesh.positions[v];
    sm.add_vertex(Kernel::Point_3(p[0], p[1], p[2]));
  }
  for (const Tri& f : around.faces) {
    const auto added = sm.add_face(SurfaceMesh::Vertex_index(f[0]), SurfaceMesh::Vertex_index(f[1]),
                                   SurfaceMesh::Vertex_index(f[2]));
    // A face at the outer edge of the neighbourhood may pinch it there; the
    // faces at the loop must all be there.
    if (added == SurfaceMesh::null_face() &&
        (f[0] < loop_size || f[1] < loop_size || f[2] < loop_size))
      throw Error(ErrorKind::NotADisk, where +
                                           ": the faces around it do not form a surface CGAL "
                                           "can hold");
  }

  SurfaceMesh::Halfedge_index border;
  bool found = false;
  for (auto h : CGAL::halfedges_around_source(SurfaceMesh::Vertex_index(0), sm))
    if (sm.target(h) == SurfaceMesh::Vertex_index(1) && sm.is_border(h)) {
      border = h;
      found = true;
      break;
    }
  if (!found) throw Error(ErrorKind::NotADisk, where + ": it is not a border of its neighbourhood");

  const size_t region_vertices = around.to_input.size();
  std::vector<SurfaceMesh::Face_index> faces;
  std::vector<SurfaceMesh::Vertex_index> vertices;
  SmoothPatch patch;
  if (fairing == SmoothFairing::Triangulation) {
    PMP::triangulate_hole(sm, border, std::back_inserter(faces));
    patch.faired = false;
  } else {
    const auto result = PMP::triangulate_refine_and_fair_hole(
        sm, border, std::back_inserter(faces), std::back_inserter(vertices),
        CGAL::parameters::fairing_continuity(static_cast<unsigned>(continuity)));
    patch.faired = std::get<0>(result);
  }
  if (faces.empty()) throw Error(ErrorKind::FillFailed, where + ": CGAL found no triangulation");

  // New vertices in index order, after the loop.
  std::vector<int> patch_index(sm.number_of_vertices(), -1);
  for (int k = 0; k < loop_size; ++k) patch_index[k] = k;
  for (auto v : sm.vertices()) {
    if (v.idx() < region_vertices) continue;
    patch_index[v.idx()] = loop_size + static_cast<int>(patch.new_positions.size());
    const auto& p = sm.point(v);
    patch.new_positions.push_back({p.x(), p.y(), p.z()});
  }
  std::sort(faces.begin(), faces.end());
  for (auto f : faces) {
    Tri t;
    int k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      const int index = v.idx() < patch_index.size() ? patch_index[v.idx()] : -1;
      if (index < 0 || k >= 3)
        throw Error(ErrorKind::Internal, where + ": CGAL's patch uses a vertex off the loop");
      t[k++] = index;
    }
    patch.faces.push_back(t);
  }
  return patch;
}

}  // namespace foldfill
