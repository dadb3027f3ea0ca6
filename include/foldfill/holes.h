// Boundary loops of a mesh, what each one is (a hole, an outer edge, a tube's
// end), and the choice of which ones to fill.
//
// Telling holes from edges. Every loop gets a kind from what can be measured
// around it, whatever its length (a hole may be longer than the cloth's edge):
//  1. `turning`, the loop's total geodesic turning. By Gauss-Bonnet it is
//     2 pi - (the Gaussian curvature of the missing piece) for a hole: about
//     +2 pi in nearly developable cloth, while a sheet's outer edge turns by
//     about -2 pi and a tube's end by about 0. Above `hole_turning` (pi):
//     a hole ("turns like a hole").
//  2. Otherwise the loop may still bound a missing cap of a curved surface (a
//     65-degree cap cut from a sphere turns by only 139 degrees). The
//     curvature density around it, K_near = (sum of the angle defects
//     2 pi - angle sum of the interior vertices within a band about the loop)
//     / (their area), predicts the missing area A = (2 pi - turning) / K_near
//     (Gauss-Bonnet, assuming the missing piece is curved like its
//     surroundings). Angle-defect sums are boundary quantities, so noise in
//     the vertices mostly cancels. When K_near > 0 and A is smaller than the
//     area of the loop's connected piece of surface, the loop closes the
//     smaller part of the surface: a hole ("closes the surrounding
//     curvature"). A dome's rim is not: the rest of its sphere is larger
//     than the dome.
//  3. Otherwise it is left open: an outer edge when it turns by less than
//     `edge_turning` (-pi/2), else a tube's end (a sleeve's ends, the rim of
//     a bowl about as deep as a hemisphere).
// A loop that is not a disk boundary (two pieces of surface meeting at one
// vertex) is of kind NotADisk, whatever it turns by. Each connected piece of
// surface is judged on its own.
#pragma once

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

// What a boundary loop is.
enum class LoopKind {
  Hole,       // the boundary of a missing piece: filled by default
  OuterEdge,  // a sheet's outer edge: left open
  TubeEnd,    // a tube's or sleeve's end: left open
  NotADisk,   // touches another piece of surface at a vertex: left open, with a warning
};

// Why a loop is of its kind (section above).
enum class LoopKindReason {
  TurnsLikeAHole,       // turning > hole_turning
  ClosesTheCurvature,   // the surrounding curvature closes it with less than the surface present
  TurnsLikeAnEdge,      // turning < edge_turning, and it does not close the curvature
  TurnsLikeATubeEnd,    // turning in [edge_turning, hole_turning], not closing the curvature
  TouchesAnotherPiece,  // not a disk boundary
};

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

  // What the loop is (classify_loops).
  LoopKind kind = LoopKind::Hole;
  LoopKindReason kind_reason = LoopKindReason::TurnsLikeAHole;
  // The curvature density K_near around the loop (1 / length^2; 0 where no
  // interior vertex lies in the band), the missing area it predicts
  // ((2 pi - turning) / K_near, infinity unless K_near > 0) and the area of
  // the loop's connected piece of surface.
  double curvature_density = 0;
  double predicted_area = std::numeric_limits<double>::infinity();
  double component_area = 0;
};

// Finds every boundary loop of `mesh`. Throws NonManifoldError naming
// `source` for non-manifold edges, inconsistent orientation, or a vertex whose
// faces form more than one fan when one of the fans is closed. A vertex
// where boundary fans meet is allowed: a boundary that passes it several times
// is split there into simple loops, one per missing piece (`split_at`); loops
// of pieces of surface that meet only there are flagged `is_disk = false`.
// Each loop is classified with the default ClassifyOptions. Precondition:
// `mesh` is valid (validate_mesh); BadFaceError otherwise.
std::vector<BoundaryLoop> find_boundary_loops(const Mesh& mesh, const std::string& source = "mesh");

// The thresholds of the classification (section at the top).
struct ClassifyOptions {
  double hole_turning = M_PI;       // turning above this: a hole
  double edge_turning = -M_PI / 2;  // turning below this, not a hole: an outer edge
  // K_near is measured over the interior vertices within `band` times the
  // loop's bounding-box diagonal of it (along the edges), and at least
  // `band_edges` of its mean edge lengths.
  double band = 0.25;
  double band_edges = 3;
};

// Sets the kind, its reason and the curvature figures of each of `loops`, the
// loops of `mesh` as find_boundary_loops gives them (a precondition). Not in
// the paper, which is given its hole (section 3.1).
void classify_loops(const Mesh& mesh, std::vector<BoundaryLoop>& loops,
                    const ClassifyOptions& options = {});

// "hole", "outer edge", "tube end", "not a disk".
const char* to_string(LoopKind kind);
// An identifier for JSON: "hole", "outer_edge", "tube_end", "not_a_disk".
const char* json_name(LoopKind kind);
// An identifier for JSON: "turns_like_a_hole", "closes_the_curvature", ...
const char* json_name(LoopKindReason reason);
// One sentence (without a capital or a full stop) on why `loop` is of its
// kind, with the figures: "turns by 139 degrees, and the surrounding
// curvature (K 1.01) closes it with an area of 3.8, less than the 8.3 present".
std::string explain_kind(const BoundaryLoop& loop);

// How the user picks the loops to fill.
struct HoleSelection {
  // Default and All: the loops of kind Hole (All says so explicitly; both
  // skip non-disk loops with a warning). Ids and Near: the loops named, each
  // point of `near` naming its nearest loop (both may be given: every loop
  // named), whatever their kind. KeepOpen: all but the `keep_open` longest
  // loops (2 for a tube), whatever their kind.
  enum class Mode { Default, All, Ids, Near, KeepOpen };
  Mode mode = Mode::Default;
  std::vector<int> ids;    // Mode::Ids (and Mode::Near, added to the points' loops)
  std::vector<Vec3> near;  // Mode::Near: each picks the loop closest to it
  int keep_open = 1;       // Mode::KeepOpen
  // Filters on top of every mode (0: none): only loops with at most
  // `max_hole_size` boundary edges, whose bounding-box diagonal is at most
  // `max_hole_diameter` (mesh units).
  int max_hole_size = 0;
  double max_hole_diameter = 0;
};

// Why a selection fills a loop or leaves it open.
enum class ChoiceReason {
  IsAHole,       // filled: of kind Hole (Default, All)
  Named,         // filled: named by id or near a point
  NotLongest,    // filled: not among the `keep_open` longest (KeepOpen)
  NotAHole,      // open: an outer edge or a tube's end (Default, All)
  NotADisk,      // open: not a disk boundary (Default, All, KeepOpen; with a warning)
  NotNamed,      // open: not named (Ids, Near)
  Longest,       // open: among the `keep_open` longest (KeepOpen)
  TooManyEdges,  // open: more boundary edges than max_hole_size
  TooWide,       // open: bounding-box diagonal above max_hole_diameter
};

// A few words: "a hole", "named", "not among the longest", "not a hole",
// "not a disk boundary", "not named", "among the longest", "too many edges",
// "too wide".
const char* to_string(ChoiceReason reason);
// An identifier for JSON: "is_a_hole", "named", "not_longest", "not_a_hole",
// "not_a_disk", "not_named", "longest", "too_many_edges", "too_wide".
const char* json_name(ChoiceReason reason);

struct HoleChoice {
  std::vector<int> fill;              // loop ids to fill, ascending
  std::vector<int> left_open;         // loop ids left open, ascending
  std::vector<ChoiceReason> reasons;  // per loop id
  std::vector<std::string> warnings;  // e.g. a non-disk loop skipped by the default choice
};

// Applies `selection`. Non-disk loops are skipped with a warning by Default,
// All and KeepOpen; naming one explicitly (ids or near) throws
// NotADiskError. Unknown ids throw UsageError, and so does a point of
// `near` farther from every loop than that loop's bounding-box diagonal (the
// message names the nearest loop).
HoleChoice select_holes(const std::vector<BoundaryLoop>& loops, const HoleSelection& selection,
                        const std::string& source = "mesh");

// Ids of the `count` longest loops, ascending (equal lengths: the lower id).
std::vector<int> longest_loops(const std::vector<BoundaryLoop>& loops, int count = 1);

// Whether a loop turns like the boundary of a missing disk (turning > pi).
bool turns_like_a_hole(const BoundaryLoop& loop);

// The mean length of the mesh's edges (each edge counted once; 0 without faces).
double mean_edge_length(const Mesh& mesh);

}  // namespace foldfill
