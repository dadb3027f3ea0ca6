// Quality figures of a filled patch: among them the paper's (section 4.3:
// the Gaussian curvature's mean and variance, the edge length error;
// METHOD.md 3). The functions throw nothing unless they say so.
#pragma once

#include <array>
#include <memory>
#include <utility>
#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

struct CurvatureStats {
  double mean_abs = 0;  // mean |K| over the interior vertices (angle defect / area)
  double variance = 0;  // variance of K over the same
};

// Gaussian curvature (angle defect divided by a third of the incident area)
// at `vertices` of the mesh (positions, faces); each must be interior.
CurvatureStats gaussian_curvature_stats(const std::vector<Vec3>& positions,
                                        const std::vector<Tri>& faces,
                                        const std::vector<int>& vertices);

// Number of pairs of triangles among `faces` that intersect (CGAL's exact
// test: neighbours that only share their common vertex or edge do not count),
// counting only pairs with at least one face of index >= `counted_from`; a
// degenerate face among those counts once. The count of CGAL's
// Polygon_mesh_processing::self_intersections over all faces, without its
// tests of pairs that are not counted.
int count_self_intersections(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                             int counted_from = 0);

// Whether a face of [counted_from, counted_to) is degenerate (collinear or
// with a non-finite corner) or one of `pairs` (indices into `faces`, each
// with a counted face) intersects by the rules of count_self_intersections,
// pairs with a degenerate face left out. Given every pair of faces whose
// closed boxes overlap, one of them counted, the same as a non-zero count
// of count_subset_crossings over the counted faces.
bool any_crossing(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                  int counted_from, int counted_to, const std::vector<std::array<int, 2>>& pairs);

// The pairs among `pairs` (as for any_crossing) that intersect by the rules
// of count_self_intersections, pairs with a degenerate face left out: each
// with its counted face first (the lower index first where both are
// counted), sorted.
std::vector<std::pair<int, int>> intersecting_pairs(const std::vector<Vec3>& positions,
                                                    const std::vector<Tri>& faces, int counted_from,
                                                    int counted_to,
                                                    const std::vector<std::array<int, 2>>& pairs);

// The intersecting pairs of faces with at least one face in `subset` (by the
// rules of count_self_intersections; a degenerate face of `subset` counts
// once, among `within`), and the distance from `subset` to the faces near it.
struct SubsetCrossings {
  int within = 0;       // pairs of faces both in `subset`
  int with_others = 0;  // pairs of a face of `subset` and one not in it
  // The smallest distance between a face of `subset` and a face that shares
  // no vertex with it (0 where such faces intersect), or `reach` when none is
  // nearer than that. Degenerate faces have no distance.
  double min_distance = 0;
  int faces_examined = 0;  // faces tested: those near `subset`, `subset`'s own included
};
// `subset`: indices into `faces`, ascending. Only the faces whose bounding
// boxes come within `reach` (>= 0) of the bounding box of `subset` are
// looked at: those of `nearby` when given (ascending, from faces_near_boxes:
// a superset of them), or else found in one pass over `faces`. The pairs
// are found through a grid over those faces alone, as in
// count_self_intersections, so that the work follows the size of `subset`
// and of its neighbourhood, not the mesh's.
SubsetCrossings count_subset_crossings(const std::vector<Vec3>& positions,
                                       const std::vector<Tri>& faces,
                                       const std::vector<int>& subset, double reach,
                                       const std::vector<int>* nearby = nullptr);

// The bounding box of the faces `subset` of `faces`, grown by `margin` on every side.
Box3 bounding_box(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                  const std::vector<int>& subset, double margin);
// For each box, the faces whose bounding boxes overlap it (closed boxes),
// ascending: one pass over `faces`, each looked up in a grid over the boxes.
std::vector<std::vector<int>> faces_near_boxes(const std::vector<Vec3>& positions,
                                               const std::vector<Tri>& faces,
                                               const std::vector<Box3>& boxes);

// Whether two faces that share no vertex intersect, one of them of index >=
// `counted_from`: the surface passes through itself (by the test of
// count_self_intersections; degenerate faces and neighbours folded onto each
// other do not count). Stops at the first such pair, and tests no
// neighbours, the most of count_self_intersections's pairs.
bool passes_through_itself(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                           int counted_from = 0);

// The summed area of `faces`.
double total_area(const std::vector<Vec3>& positions, const std::vector<Tri>& faces);

// RMS of (|e| / l - 1) over `edges` with rest lengths.
double rms_relative_edge_error(const std::vector<Vec3>& positions,
                               const std::vector<std::array<int, 2>>& edges,
                               const std::vector<double>& rest_lengths);

// Two-sided distance between two triangle surfaces A and B, measured from
// samples (the vertices of the faces and the face centroids) of each surface
// to the other surface's triangles (exact point-to-triangle distances through
// an AABB tree). Degenerate triangles are not distance targets. Throws
// UsageError when either surface has no non-degenerate triangle.
struct SurfaceDistance {
  double hausdorff = 0;  // largest sample distance, both directions
  double mean = 0;       // average of the two one-sided mean sample distances
};
SurfaceDistance surface_distance(const std::vector<Vec3>& positions_a,
                                 const std::vector<Tri>& faces_a,
                                 const std::vector<Vec3>& positions_b,
                                 const std::vector<Tri>& faces_b);

// Unsigned dihedral angle (radians; 0 where the surface is flat, pi where it
// folds back onto itself) across each of `edges`, between the normals of the
// two faces of `faces` that share it. Throws UsageError for an edge that is
// not shared by exactly two faces.
std::vector<double> dihedral_angles(const std::vector<Vec3>& positions,
                                    const std::vector<Tri>& faces,
                                    const std::vector<std::array<int, 2>>& edges);

// Mean |mean curvature| over the cells of `vertices` (each must be interior):
// sum of |H_v| A_v over sum of A_v, with the cotan Laplacian (Meyer et al.
// 2003) projected on the vertex normal, |H_v| A_v = |n_v . sum_j (cot a_ij +
// cot b_ij) (x_j - x_i)| / 4, and A_v a third of the incident area. Little
// biased by the triangulation (the dihedral-angle sum over edges is not: on
// a cylinder it grows with edges across the rulings). A cylinder of radius r
// gives 1 / (2 r). 0 for no vertices.
double mean_abs_mean_curvature(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                               const std::vector<int>& vertices);

// The corner angles of a triangulation (the flat patch's, or the new faces'
// in 3D).
struct TriangleQuality {
  double min_angle_deg = 0;      // smallest corner angle of all faces
  double share_below_20deg = 0;  // share of faces with a corner angle under 20 degrees
};
TriangleQuality triangle_quality(const std::vector<Vec3>& positions, const std::vector<Tri>& faces);

// The vertices at most `rings` edges away from `seeds` along the edges of
// `faces`, seeds excluded, ascending. Throws UsageError for a seed and
// BadFaceError for a face index outside [0, vertex_count).
std::vector<int> vertices_within_rings(int vertex_count, const std::vector<Tri>& faces,
                                       const std::vector<int>& seeds, int rings);

}  // namespace foldfill
