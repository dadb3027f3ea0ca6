// Quality figures of a filled patch.
#pragma once

#include <array>
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
// counting only pairs with at least one face of index >= `counted_from`.
int count_self_intersections(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                             int counted_from = 0);

double total_area(const std::vector<Vec3>& positions, const std::vector<Tri>& faces);

// RMS of (|e| / l - 1) over `edges` with rest lengths.
double rms_relative_edge_error(const std::vector<Vec3>& positions,
                               const std::vector<std::array<int, 2>>& edges,
                               const std::vector<double>& rest_lengths);

}  // namespace foldfill
