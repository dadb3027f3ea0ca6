// Meshing the flat hole polygon: a constrained Delaunay refinement in 2D whose
// interior vertex spacing follows the boundary edge lengths.
#pragma once

#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

struct TriangulateOptions {
  // Interior edge length = length-weighted mean boundary edge length
  // (sum l^2 / sum l) / density. 1 matches the boundary; 2 gives about four
  // times as many triangles.
  double density = 1.0;
};

// The flat patch. Vertices [0, boundary_count) are the polygon's vertices in
// the given order (no Steiner point is put on the boundary, so the patch
// stitches into the hole exactly); interior vertices follow.
struct FlatPatch {
  std::vector<Vec2> uv;
  std::vector<Tri> faces;  // counter-clockwise in the plane
  int boundary_count = 0;
  double area = 0;
  double min_angle_deg = 0;      // smallest triangle angle
  double share_below_20deg = 0;  // share of triangles with an angle under 20 degrees
};

// Triangulates the counter-clockwise simple polygon `polygon`, the flat hole
// of the strip's flattening (paper section 3.2, CGAL's refinement; METHOD.md
// 1). Throws UsageError for a density that is not positive, FillFailedError
// when the polygon has fewer than 3 vertices or a non-finite coordinate, is
// not simple or not counter-clockwise, or would give too many triangles, and
// InternalError when the triangulation loses a polygon edge.
FlatPatch triangulate_hole(const std::vector<Vec2>& polygon,
                           const TriangulateOptions& options = {});

}  // namespace foldfill
