// The whole fill: per selected hole, flatten -> triangulate -> embed (a
// start that crosses nothing, then one minimisation that keeps it so) ->
// stitch.
#pragma once

#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "foldfill/arap.h"
#include "foldfill/contact.h"
#include "foldfill/energy.h"
#include "foldfill/holes.h"
#include "foldfill/mesh.h"
#include "foldfill/multilevel.h"
#include "foldfill/obstacles.h"
#include "foldfill/solver.h"
#include "foldfill/triangulate.h"
#include "foldfill/untangle.h"

namespace foldfill {

// The prototype's weights, in the mesh's own units: its gradient step was
// x -= step * (alpha grad E_I + 0.001 beta grad E_B + mu grad E_C). With h the
// hole's length scale, that is our normalised energy with lambda =
// 0.001 beta / (alpha h^2), repulsion = mu / alpha, and a normalised step of
// step * alpha (see README, "Parameters").
struct PrototypeWeights {
  double alpha = 0.1, beta = 0.003, mu = 0.01, step = 0.5;
};

// Sets energy.lambda (by energy.bending), energy.repulsion and solver.step
// from `weights` for a hole of length scale `length_scale` (the mapping above).
void apply_prototype_weights(const PrototypeWeights& weights, double length_scale,
                             EnergyOptions& energy, SolverOptions& solver);

// How a hole was closed: the fabric method where it applies, then the
// fallback chain (see fill_holes).
enum class FillMethod {
  Fabric,          // the fabric method of Gisbert et al. 2023
  FabricRepaired,  // the same from a repaired flattening (flatten_strip_repaired)
  Smooth,          // refined and faired with continuous curvature (smooth_fill.h)
  Liepa,           // refined and faired with continuous tangents: CGAL's refine-and-fair fill
  Triangulation,   // the loop's minimal-area triangulation alone
};

// "fabric", "fabric-repaired", "smooth", "liepa", "triangulation".
const char* to_string(FillMethod method);

struct FallbackOptions {
  // false: a hole the fabric method cannot fill stays open with its reason.
  bool enabled = true;
  // Where the surroundings are far from developable (a dome, a curved
  // statue, however small the hole: Developability::ratio above this; 1 on
  // a sphere, 0 on cloth however it folds, under 0.05 on every simulated
  // cloth case) the hole is filled smooth, not flattened: there is no flat
  // piece of cloth to put back.
  double max_developability_ratio = 0.25;
  // A smooth patch with a triangle angle below this (degrees) is passed to
  // the next step of the chain (the last step keeps it unless it has zero
  // area); a fabric patch only when it has a face of zero area.
  double min_angle_deg = 1;
};

// How a patch's start is made one that crosses nothing (normalised units:
// the hole's length scale).
struct StartOptions {
  // How far outside an obstacle start vertices in or near it are put: a face
  // between such vertices stays outside a curved obstacle unless its radius is
  // under a quarter of an edge.
  double obstacle_clearance = 0.25;
  // Bisections of the way from the ARAP start towards the membrane, for the
  // first point of it that crosses nothing.
  int membrane_bisections = 6;
  // Where the ARAP start and the membrane both cross something: how the ARAP
  // start is untangled (untangle.h) into one that does not.
  UntangleOptions untangle;
};

struct FillOptions {
  TriangulateOptions triangulate;
  ArapOptions arap;
  EnergyOptions energy;
  SolverOptions solver;
  // The barrier and step bound that keep the patch from crossing itself, the
  // mesh and the obstacles (contact.h).
  ContactOptions contact;
  std::vector<Obstacle> obstacles;  // in the mesh's units
  // With the fast solver, large patches start from a coarser fill of the same
  // hole instead of ARAP (see multilevel.h); `arap` then places the coarsest
  // level. Gradient descent always starts from ARAP, as in the paper.
  MultilevelOptions multilevel;
  // How a start that crosses nothing is found (README, "Never through the cloth").
  StartOptions start;
  // With the fast solver, a patch (or its coarsest level) whose bending
  // weight is below this is first minimised with this weight, then with its
  // own from there: the large folds form first (0: never).
  double stiff_start_lambda = 0.1;
  // The folds-first pass is first run kept out of the analytic obstacles
  // only (PatchContact::Scope::ObstaclesOnly: the patch may cross itself,
  // its strip and the rest of the mesh): where its end crosses and touches
  // nothing (the exact test of a start, cleared of the obstacles where it
  // needs to be), the guarded minimisation with the weight asked for starts
  // there; otherwise the pass is run again from the same start, guarded.
  // Like ARAP, the pass is then a way to a start, checked as every start is;
  // the minimisation that gives the fill stays guarded at every step.
  // false: always guarded.
  bool unguarded_folds_first = true;
  // The prototype's weights in the mesh's units, mapped per hole onto
  // energy.lambda, energy.repulsion and solver.step; those must then be left
  // at their defaults (fill_holes throws UsageError otherwise).
  std::optional<PrototypeWeights> prototype;
  FallbackOptions fallback;
  bool keep_flat = false;  // keep the flat strip and patch in the report
  // Called per hole and iteration with (loop id, progress), from the threads
  // that fill the holes; false cancels the whole fill (see fill_holes).
  std::function<bool(int, const SolverProgress&)> progress;
};

struct StageSeconds {
  double flatten = 0, triangulate = 0, arap = 0, optimize = 0, total = 0;
};

// How a hole's patch crosses the rest of the output, counted on the output
// with exact predicates (see measure_crossings).
struct Crossings {
  int patch_patch = 0;      // pairs of intersecting triangles both new faces of this hole
  int patch_mesh = 0;       // pairs of a new face and another face of the output that intersect
  int patch_obstacles = 0;  // new faces that cross into an obstacle
  int total() const { return patch_patch + patch_mesh + patch_obstacles; }
};

// Where a patch's minimisation started from.
enum class StartKind {
  Arap,          // the ARAP start of section 3.3
  CoarseLevels,  // the minimised coarser levels, interpolated (multilevel.h)
  // Part of the way from the membrane (membrane_embed) to the ARAP start:
  // the ARAP start crossed something, the membrane did not.
  TowardsMembrane,
  // The ARAP start and the membrane crossed something: the ARAP start
  // untangled (pipeline/untangle.h: its crossing curves shrunk until none is left).
  Untangled,
  // The coarsest level's ARAP start and its membrane crossed something: that
  // start untangled, then the coarser levels as for CoarseLevels. Untangling
  // the coarsest level is cheaper than untangling the patch, and where the
  // patch's own untangling stalls among many small triangles it often gets
  // through.
  CoarseLevelsUntangled,
  // No start that crosses nothing was found: the patch was minimised without
  // the contact's guarantee (its crossings are in the report).
  Unguarded,
};

// "arap", "coarse_levels", "towards_membrane", "untangled",
// "coarse_levels_untangled", "unguarded".
const char* to_string(StartKind start);

// How the folds-first pass (FillOptions::stiff_start_lambda) ran: the
// patch's, or where the patch started from its coarse levels, the coarsest
// level's.
enum class FoldsFirstPass {
  None,  // none ran (the bending weight is not below stiff_start_lambda, gradient descent)
  // Kept out of the analytic obstacles only, its end a clean start
  // (FillOptions::unguarded_folds_first); or without any contact, where the
  // patch is minimised unguarded (StartKind::Unguarded).
  Unguarded,
  Guarded,  // with the contact's barrier and step bound
};

// "none", "unguarded", "guarded".
const char* to_string(FoldsFirstPass pass);

// What became of a hole chosen for filling.
enum class HoleStatus {
  Filled,     // a patch closes it
  Failed,     // no method could fill it: left open, with the reason
  Cancelled,  // the fill was cancelled (FillOptions::progress) before it was done: left open
};

// "filled", "failed", "cancelled".
const char* to_string(HoleStatus status);

// The indices [first, end) of a run of vertices or faces.
struct IndexRange {
  int first = 0, end = 0;
  int size() const { return end - first; }
};

struct HoleReport {
  int loop_id = 0;
  bool filled = false;
  // Set on a hole left open because the fill was being cancelled.
  bool cancelled = false;
  std::string reason;  // why it was not filled
  FillMethod method = FillMethod::Fabric;
  // Why each step of the chain before `method` was passed over, in order
  // ("STEP: reason"); empty when the first choice filled the hole.
  std::vector<std::string> fallback_reasons;
  int loop_vertex_count = 0;
  int patch_vertex_count = 0;  // new (interior) vertices
  int patch_face_count = 0;
  // Where the new vertices and faces are in the output (mark_new_elements,
  // foldfill/marks.h); empty when the hole was not filled.
  IndexRange new_vertices, new_faces;
  int iterations = 0;  // of the minimisation of the patch (not of its coarser levels)
  StopReason stop_reason = StopReason::Converged;
  StartKind start = StartKind::Arap;
  // How far the start is from the ARAP start towards the membrane (0: it is
  // the ARAP start; 1: the membrane) with StartKind::TowardsMembrane.
  double start_blend = 0;
  FoldsFirstPass folds_first = FoldsFirstPass::None;
  // How many coarse levels were minimised kept out of the analytic obstacles
  // only, their ends checked (MultilevelOptions::unguarded_first).
  int unguarded_coarse_levels = 0;
  // Set when the patch was kept but the minimisation did not end normally (it
  // diverged: the lowest-energy state seen was kept; a time limit stopped it),
  // or when the fill crosses itself, the rest of the mesh or an obstacle.
  std::string warning;
  StageSeconds seconds;
  Flattening flattening_fit;                        // uv left empty
  double min_angle_deg = 0, share_below_20deg = 0;  // of the flat patch (fabric methods)
  double patch_min_angle_deg = 0;  // the smallest angle of the new faces in 3D, any method
  EnergyTerms energy_after_arap, energy_final;
  double gaussian_mean_abs_after_arap = 0, gaussian_variance_after_arap = 0;
  double gaussian_mean_abs_final = 0, gaussian_variance_final = 0;
  double edge_length_rms_rel_after_arap = 0, edge_length_rms_rel_final = 0;
  // Measured on the output, after stitching (see measure_crossings).
  Crossings crossings;
  int self_intersections = 0;  // crossings.total()
  // The smallest distance, in units of length_scale, from the hole's new faces
  // to the faces of the output that share no vertex with them and to the
  // obstacles: 0 where they touch or cross; at most kCrossingReach (nothing
  // nearer).
  double min_distance = 0;
  // How deep (in units of length_scale) the patch may reach into an
  // analytic obstacle: as deep as the strip around the hole already does,
  // plus the gap of the obstacle's triangulation the contact sees.
  double obstacle_allowance = 0;
  double repulsion = 0;           // the repulsion weight the patch was minimised with
  double lambda = 0;              // the bending weight the patch was minimised with
  double flat_area = 0;           // area of the flat patch (mesh units)
  double patch_area = 0;          // area of the new faces in the output (mesh units), any method
  double area_ratio_to_flat = 0;  // 3D patch area / flat patch area
  double length_scale = 0;        // the hole's unit (mean loop edge length)
  Mesh flat_strip, flat_patch;    // z = 0; only with FillOptions::keep_flat

  HoleStatus status() const {
    return filled ? HoleStatus::Filled : cancelled ? HoleStatus::Cancelled : HoleStatus::Failed;
  }
};

struct FillReport {
  std::vector<HoleReport> holes;
  bool cancelled = false;        // the progress callback returned false
  double seconds_prepare = 0;    // the mesh's vertex-face incidence, built once for all holes
  double seconds_holes = 0;      // wall time of filling the holes (in parallel)
  double seconds_stitch = 0;     // appending the patches to the mesh
  double seconds_crossings = 0;  // measuring the crossings of the output
  double seconds_total = 0;
};

// The output's new elements are marked (Mesh::vertex_hole, face_hole), the
// carried per-element data has values for them and each filled hole's report
// says where they are (see mark_new_elements).
struct FillResult {
  Mesh mesh;  // the input with new vertices and faces appended
  FillReport report;
};

// Fills the loops `fill_ids` of `loops`. Preconditions: `mesh` is valid
// (validate_mesh) and `loops` is find_boundary_loops(mesh).
//
// Per hole (Gisbert et al. 2023, section 3): plan (the strip, its LSCM
// flattening, the flat patch, the normalised domain), start (ARAP from the
// shrunk rest shape, or the hole's coarser levels, each minimised and
// interpolated onto the next), one minimisation of the fabric energy, then
// the measurements of the report. The patch must not cross anything: itself,
// its strip, the rest of the mesh within its reach (other layers of the
// cloth, other parts of the garment), the obstacles. Every minimisation
// starts from a state that crosses nothing, checked with exact predicates
// (where the ARAP start does cross something, the start is moved towards the
// membrane until it does not), and keeps it so by the contact's barrier and
// step bound (contact.h). The output's crossings are then counted on the
// whole output (measure_crossings): 0 unless no clean start was found
// (StartKind::Unguarded, with a warning).
//
// Holes whose reach (a box around the loop that the patch cannot leave)
// overlaps another's are filled one after the other, in the order of
// `fill_ids`, each seeing the patches of the ones before; the others in
// parallel. The result does not depend on the thread count (unless a time
// limit stops a minimisation). The work per hole follows the size of the
// hole, its patch and its surroundings, not the mesh's.
//
// A hole that cannot be filled is left open and reported with its reason,
// "SOURCE: loop ID: problem": a loop that is not a disk boundary or whose
// strip is not an annulus, a flattening or triangulation that fails, a patch
// with non-finite positions. `mesh`'s own vertices and faces come out
// unchanged, the patches' are appended in the order of `fill_ids`.
//
// Limits: options.solver.max_iterations bounds each minimisation of a hole;
// options.solver.time_limit_seconds the hole's fill, counted from its start:
// flattening and triangulation run to their end, the start (ARAP, coarse
// levels) and the minimisation stop when it passes (see Budget), and the hole
// keeps the state reached (stop reason TimeLimit). When the progress callback
// returns false, the fill is cancelled: the holes being minimised then and
// the ones not started are left open with the reason "cancelled",
// report.cancelled is set, and holes already finished stay filled. A
// minimisation that diverges keeps its lowest-energy state, with
// HoleReport::warning saying so. Throws UsageError for an id not in `loops`
// and for options that contradict each other (prototype weights with lambda,
// repulsion or the descent step set too).
FillResult fill_holes(const Mesh& mesh, const std::vector<BoundaryLoop>& loops,
                      const std::vector<int>& fill_ids, const FillOptions& options = {},
                      const std::string& source = "mesh");
// The same, stitching into `mesh` itself instead of a copy (a large mesh is
// then held once).
FillResult fill_holes(Mesh&& mesh, const std::vector<BoundaryLoop>& loops,
                      const std::vector<int>& fill_ids, const FillOptions& options = {},
                      const std::string& source = "mesh");

// How far from the patch HoleReport::min_distance looks, in units of the
// hole's length scale: the faces of the output that come nearer to the
// patch's bounding box than this are the only ones looked at.
constexpr double kCrossingReach = 1;
// A sphere, cylinder or plane is crossed where a face reaches inside it
// deeper than this, in units of the hole's length scale: the rounding of the
// vertices the solver leaves on its surface is not a crossing.
constexpr double kObstacleTolerance = 1e-9;

// Not in the paper (its section 3.4 counts on the repulsion; METHOD.md 3).
// Measures the crossings and min_distance of each filled hole of `report` on
// the output `mesh`, whose faces `patch_faces[k]` (ascending) are the new
// faces of report.holes[k]; sets self_intersections to their total and, where
// it is not 0, adds to the hole's warning "SOURCE: loop ID: the fill crosses
// itself, the rest of the mesh and an obstacle (patch_patch 1, patch_mesh 10,
// patch_obstacles 2)" (naming the counts that are not 0). patch_mesh counts
// the pairs of a new face and any other face of `mesh` (faces of the input
// anywhere, the strip around the hole, the other holes' patches) that
// intersect by the rules of count_self_intersections: faces that share a
// vertex or an edge only when they intersect beyond it. patch_obstacles
// counts the new faces that cross into an obstacle (see crosses(), with
// the larger of kObstacleTolerance and the hole's obstacle_allowance times the
// length scale: a mesh obstacle is crossed at any depth). The work follows the holes: one
// pass over the faces finds those near each patch, and the pairs are found in
// a grid over those alone (count_subset_crossings). Holes are measured in
// parallel; the result does not depend on the thread count.
void measure_crossings(const Mesh& mesh, const std::vector<std::vector<int>>& patch_faces,
                       const std::vector<Obstacle>& obstacles, const std::string& source,
                       FillReport& report);

}  // namespace foldfill
