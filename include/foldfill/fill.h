// The one-call fill: what `foldfill fill` does to one mesh, without the
// files. It finds the boundary loops (find_boundary_loops), chooses the ones
// to fill by the CLI's rules (select_holes with a HoleSelection), fills them
// (fill_holes, Gisbert et al. 2023 section 3, or fill_holes_liepa) and marks
// the new elements (mark_new_elements). The step-by-step functions stay
// available for a program that wants to look between the steps.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/mesh.h"

namespace foldfill {

// How the chosen holes are filled.
enum class FillAlgorithm {
  Fabric,  // the fabric method and its fallbacks (fill_holes)
  Liepa,   // CGAL's smooth refine-and-fair fill, for comparison (fill_holes_liepa)
};

// What to fill and how.
struct FillRequest {
  // Which loops (holes.h): by default the loops of kind Hole.
  HoleSelection selection;
  // When above 0: fill only loops whose bounding-box diagonal is at most this
  // many mean edge lengths of the mesh (the CLI's --max-hole-diameter); it
  // replaces selection.max_hole_diameter, which is in mesh units.
  double max_hole_diameter_edges = 0;
  FillAlgorithm algorithm = FillAlgorithm::Fabric;
  // The fill's parameters, obstacles and progress callback (inpaint.h).
  // FillAlgorithm::Liepa uses only the obstacles (measured against, not
  // avoided).
  FillOptions options;
  // Names the mesh in messages: "SOURCE: loop 3: ...".
  std::string source = "mesh";
};

// The loops of a mesh and the choice of those to fill.
struct ChosenHoles {
  std::vector<BoundaryLoop> loops;  // find_boundary_loops, by id
  HoleChoice choice;                // select_holes, with the warnings below
  HoleSelection selection;          // the selection applied (the diameter in mesh units)
};

// The boundary loops of `mesh` and the ones `request.selection` picks
// (select_holes), its warnings in choice.warnings. With
// HoleSelection::Mode::KeepOpen, which goes by length alone, a warning says
// so where the default (by kind) would fill other loops. Precondition:
// `mesh` is valid (as read_mesh or validate_mesh leave it). Throws
// NonManifoldError as find_boundary_loops, UsageError and NotADiskError as
// select_holes.
ChosenHoles choose_holes(const Mesh& mesh, const FillRequest& request);

// What fill() gives: the fill's result (the output mesh and the report) and
// what was chosen.
struct FillOutput : FillResult {
  std::vector<BoundaryLoop> loops;  // the input's loops, by id
  HoleChoice choice;                // the loops filled and left open, and why
  HoleSelection selection;          // the selection applied (the diameter in mesh units)
};

// Fills the loops `chosen.choice.fill` of `mesh` (from choose_holes(mesh,
// request), a precondition) as `request` says. The result's mesh is `mesh` with the patches
// appended and its new elements marked (Mesh::vertex_hole, face_hole); its
// report has one entry per chosen loop, in order; `loops` and `choice` are
// `chosen`. A hole that cannot be filled is left open with its reason in the
// report (nothing is thrown for it); when options.progress returns false the
// fill is cancelled and report.cancelled set (fill_holes). Throws
// UsageError for contradicting options (see fill_holes).
FillOutput fill(const Mesh& mesh, ChosenHoles chosen, const FillRequest& request);

// choose_holes, then the fill above: the whole of `foldfill fill` on one
// mesh. Preconditions: `mesh` is valid (as read_mesh or validate_mesh leave
// it). Throws what those two throw.
FillOutput fill(const Mesh& mesh, const FillRequest& request = {});

// The options a fill ran with, as the report gives them (docs/report.md,
// "options"): the fill's parameters (null where the algorithm does not use
// them), "method" and the selection applied.
nlohmann::json options_json(const FillRequest& request, const HoleSelection& selection);

// The sizes the report gives under "counts".
struct ReportCounts {
  int input_vertices = 0, input_faces = 0, output_vertices = 0, output_faces = 0;
};

// The report of a fill as JSON, the CLI's report without the file names
// (docs/report.md): to_json(report) (report.h) with "foldfill_version",
// "counts", "options", "filled_loops" (the loops filled, ascending),
// "left_open_loops" (every loop still open, with its kind and why) and
// "warnings" (those of the choice; each hole's own warning is in its entry).
nlohmann::json report_json(const FillReport& report, const std::vector<BoundaryLoop>& loops,
                           const HoleChoice& choice, const nlohmann::json& options,
                           const ReportCounts& counts);
// The same for a fill of `input` by foldfill::fill.
nlohmann::json report_json(const Mesh& input, const FillOutput& result, const FillRequest& request);

// One loop as `foldfill holes --json` lists it: "id", "vertex_count",
// "length", "centroid", "bbox_diagonal", "mean_edge_length", "kind",
// "kind_reason", "explanation", "outer" (whether `choice` leaves it open),
// "turning", "curvature_density", "predicted_area" (null where infinite),
// "component_area", "hole_like", "disk", "reason", "split_at", "vertices".
nlohmann::json loop_json(const BoundaryLoop& loop, const HoleChoice& choice);

}  // namespace foldfill
