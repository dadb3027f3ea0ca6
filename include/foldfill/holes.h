// Boundary loops of a mesh and the choice of which ones to fill.
#pragma once

#include <string>
#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

// One closed chain of boundary edges. `vertices` are input vertex indices in
// loop order, oriented so that the missing region lies to the left when the
// mesh's faces are seen counter-clockwise (the loop follows the boundary
// half-edges, opposite to the faces' own edges). A new face (a, b, c) whose
// vertices run in that order around the hole is oriented like its neighbours.
struct BoundaryLoop {
  int id = 0;                   // position in the list, loops sorted by first vertex
  std::vector<int> vertices;    // loop order, 0-based input indices
  std::vector<Vec3> positions;  // positions of `vertices`, same order (used to select near a point)
  double length = 0;            // sum of edge lengths
  Vec3 centroid{};              // mean of the loop vertices
  double bbox_diagonal = 0;     // diagonal of the loop vertices' bounding box
  double mean_edge_length = 0;
  // Total geodesic turning along the loop, sum over its vertices of (angle sum
  // of the faces at the vertex - pi), in radians. By Gauss-Bonnet it is about
  // 2 pi for a hole in nearly developable cloth (the missing piece is a disk),
  // about -2 pi for the outer edge of a sheet and about 0 for a sleeve's end.
  double turning = 0;
  // Pinched vertices where the boundary passes more than once and was split
  // into this loop and others (a hole touching the outer edge or another hole
  // at one vertex), in loop order.
  std::vector<int> split_at;
  bool is_disk = true;  // false: it touches another piece of surface at a pinched vertex
  std::string reason;   // why it is not fillable, empty when it is
};

// Finds every boundary loop of `mesh`. Throws Error(NonManifold) naming
// `source` for non-manifold edges, inconsistent orientation, or a vertex whose
// faces form more than one fan when one of the fans is closed. A vertex
// where boundary fans meet is allowed: a boundary that passes it several times
// is split there into simple loops, one per missing piece (`split_at`); loops
// of pieces of surface that meet only there are flagged `is_disk = false`.
std::vector<BoundaryLoop> find_boundary_loops(const Mesh& mesh, const std::string& source = "mesh");

// How the user picks the loops to fill.
struct HoleSelection {
  // Default: all but the `keep_open` longest loops. Auto: the loops that turn
  // like a hole (turning > pi), whatever their length.
  enum class Mode { Default, All, Ids, Near, Auto };
  Mode mode = Mode::Default;
  std::vector<int> ids;  // Mode::Ids
  Vec3 near{};           // Mode::Near: the loop closest to this point
  int keep_open = 1;     // Mode::Default: the `keep_open` longest loops stay open (2 for a tube)
};

struct HoleChoice {
  std::vector<int> fill;              // loop ids to fill, ascending
  std::vector<int> left_open;         // loop ids left open, ascending
  std::vector<std::string> warnings;  // e.g. a non-disk loop skipped by the default choice
};

// Applies `selection`. Loops the default would leave open are the `keep_open`
// longest ones (`outer`). Non-disk loops are skipped with a warning by the
// default and `all`; naming one explicitly (ids or near) throws
// Error(NotADisk). Unknown ids throw Error(Usage).
HoleChoice select_holes(const std::vector<BoundaryLoop>& loops, const HoleSelection& selection,
                        const std::string& source = "mesh");

// Ids of the loops the default selection leaves open (the `keep_open` longest).
std::vector<int> default_outer_loops(const std::vector<BoundaryLoop>& loops, int keep_open = 1);

// Whether a loop turns like the boundary of a missing disk (turning > pi).
bool turns_like_a_hole(const BoundaryLoop& loop);

}  // namespace foldfill
