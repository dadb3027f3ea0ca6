// The fallback chain's smooth fills with CGAL (one of the few translation
// units that include CGAL's mesh processing). Only the hole's neighbourhood is
// handed to CGAL, so the cost follows the hole, not the mesh.
#include "foldfill/smooth_fill.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <unordered_map>
#include <unordered_set>

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
  // Hash maps, so that the cost follows the neighbourhood, not the mesh.
  std::unordered_map<int, int> local;
  std::unordered_set<int> face_taken;
  for (int v : loop.vertices) {
    local.emplace(v, static_cast<int>(around.to_input.size()));
    around.to_input.push_back(v);
  }
  size_t ring_begin = 0, ring_end = around.to_input.size();
  for (int ring = 0; ring < rings; ++ring) {
    for (size_t i = ring_begin; i < ring_end; ++i) {
      const int v = around.to_input[i];
      for (int k = vertex_faces.start[v]; k < vertex_faces.start[v + 1]; ++k) {
        const int f = vertex_faces.faces[k];
        if (!face_taken.insert(f).second) continue;
        Tri t;
        for (int c = 0; c < 3; ++c) {
          const int w = mesh.faces[f][c];
          const auto [it, added] = local.emplace(w, static_cast<int>(around.to_input.size()));
          if (added) around.to_input.push_back(w);
          t[c] = it->second;
        }
        around.faces.push_back(t);
      }
    }
    ring_begin = ring_end;
    ring_end = around.to_input.size();
  }
  return around;
}

double cotangent(const Kernel::Point_3& a, const Kernel::Point_3& b, const Kernel::Point_3& c) {
  // At a, between a->b and a->c.
  const Kernel::Vector_3 u = b - a, w = c - a;
  const double sine = std::sqrt(CGAL::cross_product(u, w).squared_length());
  return sine > 0 ? (u * w) / sine : 0;
}

// Moves the vertices of `sm` from `first_free` on so that the `power`-th
// power of the Laplace-Beltrami operator (cotangent weights over a third of
// the faces' area) vanishes there: the membrane (1), thin plate (2) or the
// curvature-continuous surface (3) over the fixed vertices around them
// (Botsch and Kobbelt 2004). The operator's power is a product of sparse
// matrices, so every entry is computed once. Returns false, the positions
// left as they were, when the system cannot be solved.
bool fair(SurfaceMesh& sm, size_t first_free, int power) {
  const Eigen::Index n = static_cast<Eigen::Index>(sm.number_of_vertices());
  const Eigen::Index free = n - static_cast<Eigen::Index>(first_free);
  if (free <= 0) return true;
  // Cotangents clamped so that the weights stay positive and bounded.
  constexpr double kLowest = 1e-3, kHighest = 1e3;
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd area = Eigen::VectorXd::Zero(n);
  for (auto f : sm.faces()) {
    std::array<SurfaceMesh::Vertex_index, 3> v;
    int k = 0;
    for (auto w : CGAL::vertices_around_face(sm.halfedge(f), sm)) v[k++] = w;
    const auto& p0 = sm.point(v[0]);
    const auto& p1 = sm.point(v[1]);
    const auto& p2 = sm.point(v[2]);
    const double third = std::sqrt(CGAL::cross_product(p1 - p0, p2 - p0).squared_length()) / 6;
    for (int c = 0; c < 3; ++c) {
      area[v[c].idx()] += third;
      // The edge opposite corner c, weighted by half its cotangent.
      const auto i = v[(c + 1) % 3].idx(), j = v[(c + 2) % 3].idx();
      const double w = 0.5 * std::clamp(cotangent(sm.point(v[c]), sm.point(v[(c + 1) % 3]),
                                                  sm.point(v[(c + 2) % 3])),
                                        kLowest, kHighest);
      entries.emplace_back(i, j, w);
      entries.emplace_back(j, i, w);
      entries.emplace_back(i, i, -w);
      entries.emplace_back(j, j, -w);
    }
  }
  Eigen::SparseMatrix<double> laplace(n, n);
  laplace.setFromTriplets(entries.begin(), entries.end());
  for (Eigen::Index v = 0; v < n; ++v)
    if (!(area[v] > 0)) return false;
  const Eigen::SparseMatrix<double> operator_ = area.cwiseInverse().asDiagonal() * laplace;
  Eigen::SparseMatrix<double> rows = operator_.bottomRows(free);
  for (int k = 1; k < power; ++k) rows = Eigen::SparseMatrix<double>(rows * operator_);
  const Eigen::SparseMatrix<double> unknown = rows.rightCols(free);
  const Eigen::SparseMatrix<double> known = rows.leftCols(n - free);
  Eigen::MatrixXd fixed(n - free, 3);
  for (Eigen::Index v = 0; v < n - free; ++v) {
    const auto& p = sm.point(SurfaceMesh::Vertex_index(static_cast<std::uint32_t>(v)));
    fixed.row(v) << p.x(), p.y(), p.z();
  }
  Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
  solver.compute(unknown);
  if (solver.info() != Eigen::Success) return false;
  const Eigen::MatrixXd rhs = -(known * fixed);
  const Eigen::MatrixXd x = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !x.allFinite()) return false;
  for (Eigen::Index k = 0; k < free; ++k)
    sm.point(SurfaceMesh::Vertex_index(static_cast<std::uint32_t>(n - free + k))) =
        Kernel::Point_3(x(k, 0), x(k, 1), x(k, 2));
  return true;
}

}  // namespace

SmoothPatch fill_hole_smooth(const Mesh& mesh, const VertexFaces& vertex_faces,
                             const BoundaryLoop& loop, SmoothFairing fairing,
                             const std::string& source, int rings) {
  const std::string where = source + ": loop " + std::to_string(loop.id);
  const int loop_size = static_cast<int>(loop.vertices.size());
  if (loop_size < 3) throw NotADiskError(where + ": it has fewer than 3 vertices");
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
      throw NotADiskError(where +
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
  if (!found) throw NotADiskError(where + ": it is not a border of its neighbourhood");

  const size_t region_vertices = around.to_input.size();
  std::vector<SurfaceMesh::Face_index> faces;
  std::vector<SurfaceMesh::Vertex_index> vertices;
  SmoothPatch patch;
  if (fairing == SmoothFairing::Triangulation) {
    PMP::triangulate_hole(sm, border, std::back_inserter(faces));
    patch.faired = false;
  } else {
    PMP::triangulate_and_refine_hole(sm, border, std::back_inserter(faces),
                                     std::back_inserter(vertices));
    patch.faired = fair(sm, region_vertices, continuity + 1);
  }
  if (faces.empty()) throw FillFailedError(where + ": CGAL found no triangulation");

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
        throw InternalError(where + ": CGAL's patch uses a vertex off the loop");
      t[k++] = index;
    }
    patch.faces.push_back(t);
  }
  return patch;
}

}  // namespace foldfill
