// Exactly developable meshes generated in code, with their flat coordinates:
// the built-in demo and the ground truth of many tests (the paper assumes
// developable cloth, section 3.1). The generators are deterministic and throw
// nothing.
#pragma once

#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

// A grid of `columns` x `rows` vertices (vertex (i, j) at j * columns + i),
// each cell split into two triangles counter-clockwise in (i, j), with
// alternating diagonals; `wrap_columns` joins column columns - 1 to column 0,
// `wrap_rows` row rows - 1 to row 0 (tubes and tori).
std::vector<Tri> grid_triangles(int columns, int rows, bool wrap_columns = false,
                                bool wrap_rows = false);

// A mesh together with the flat (developed) position of every vertex: the map
// from `flat` to `mesh.positions` is an isometry.
struct DevelopableMesh {
  Mesh mesh;
  std::vector<Vec2> flat;
};

// A sheet bent along rulings parallel to y: its cross-section is the curve
// z = amplitude * sin(2 pi folds x / width) for x in [0, width], so `folds`
// sinusoidal folds run across it; y spans [0, height]. Triangulated on a grid
// with about `edge_length` spacing (equal arc length steps across the folds).
// Its flat width is the curve's length. Exactly developable.
struct FoldedSheetOptions {
  double width = 4, height = 3, edge_length = 0.05;
  double amplitude = 0.25;
  int folds = 3;
};
DevelopableMesh make_folded_sheet(const FoldedSheetOptions& options = {});

// A sheet whose cross-section in the xz plane is the polyline `profile`
// (points (x, z), a column of vertices each), extruded along y over [0,
// height] with rows about `edge_length` apart. The flat u is the arc length
// along the profile: exactly developable. The profile may fold back over
// itself (layers of cloth above one another) as long as it does not cross
// itself.
DevelopableMesh make_profile_sheet(const std::vector<Vec2>& profile, double height,
                                   double edge_length);

// The profile of a sheet folded over itself: the lower layer from (length, 0)
// to (0, 0) at z = 0, a half circle of diameter `gap` up to (0, gap), and the
// upper layer back to (length, gap); points about `edge_length` apart.
std::vector<Vec2> u_fold_profile(double length, double gap, double edge_length);

// A section of a cylinder of `radius`, spanning `angle` radians and `height`.
DevelopableMesh make_cylinder_section(double radius, double angle, double height,
                                      double edge_length);

// A section of a cone with apex at the origin, axis z, half-angle
// `half_angle`, between distances r0 < r1 from the apex along the surface,
// spanning `angle` radians around the axis.
DevelopableMesh make_cone_section(double half_angle, double r0, double r1, double angle,
                                  double edge_length);

// Removes the faces whose flat centroid lies within `radius` of `center`
// (flat coordinates), and more faces where needed so that the hole's boundary
// is a simple loop; unreferenced vertices are dropped and the rest keep their
// relative order. Returns the cut mesh and the flat area removed.
struct CutMesh {
  DevelopableMesh cut;
  double removed_area = 0;  // flat area of the removed faces
  int removed_faces = 0;
};
CutMesh cut_disk_hole(const DevelopableMesh& input, Vec2 center, double radius);

}  // namespace foldfill
