#include "foldfill/fill.h"

#include <algorithm>
#include <cmath>

#include "foldfill/liepa.h"
#include "foldfill/report.h"

namespace foldfill {
namespace {

// A JSON number, or null where it is infinite (no curvature to predict from).
nlohmann::json finite_or_null(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

std::string join_ids(const std::vector<int>& ids) {
  std::string text;
  for (int id : ids) text += (text.empty() ? "" : ", ") + std::to_string(id);
  return text.empty() ? "none" : text;
}

}  // namespace

ChosenHoles choose_holes(const Mesh& mesh, const FillRequest& request) {
  ChosenHoles chosen;
  chosen.loops = find_boundary_loops(mesh, request.source);
  HoleSelection selection = request.selection;
  if (request.max_hole_diameter_edges > 0) {
    selection.max_hole_diameter = request.max_hole_diameter_edges * mean_edge_length(mesh);
  }
  chosen.choice = select_holes(chosen.loops, selection, request.source);
  // KeepOpen goes by length alone; say so when the classifier tells another
  // story (a hole longer than the cloth's edge, a sleeve's ends).
  if (selection.mode == HoleSelection::Mode::KeepOpen) {
    HoleSelection by_kind = selection;
    by_kind.mode = HoleSelection::Mode::Default;
    const std::vector<int> holes = select_holes(chosen.loops, by_kind, request.source).fill;
    if (holes != chosen.choice.fill) {
      chosen.choice.warnings.push_back(
          request.source + ": --keep-open " + std::to_string(selection.keep_open) +
          " fills other loops than the default, which fills the holes (" + join_ids(holes) +
          "; see `foldfill holes`)");
    }
  }
  return chosen;
}

FillOutput fill(const Mesh& mesh, ChosenHoles chosen, const FillRequest& request) {
  FillOutput result;
  static_cast<FillResult&>(result) =
      request.algorithm == FillAlgorithm::Liepa
          ? fill_holes_liepa(mesh, chosen.loops, chosen.choice.fill, request.source,
                             request.options.obstacles)
          : fill_holes(mesh, chosen.loops, chosen.choice.fill, request.options, request.source);
  result.loops = std::move(chosen.loops);
  result.choice = std::move(chosen.choice);
  return result;
}

FillOutput fill(const Mesh& mesh, const FillRequest& request) {
  return fill(mesh, choose_holes(mesh, request), request);
}

nlohmann::json report_json(const FillReport& fill_report, const HoleChoice& choice) {
  nlohmann::json report = to_json(fill_report);
  report["filled_loops"] = choice.fill;
  report["left_open_loops"] = choice.left_open;
  report["warnings"] = choice.warnings;
  return report;
}

nlohmann::json loop_json(const BoundaryLoop& loop, const HoleChoice& choice) {
  const bool outer = !std::binary_search(choice.fill.begin(), choice.fill.end(), loop.id);
  return {{"id", loop.id},
          {"vertex_count", loop.vertices.size()},
          {"length", loop.length},
          {"centroid", loop.centroid},
          {"bbox_diagonal", loop.bbox_diagonal},
          {"mean_edge_length", loop.mean_edge_length},
          {"kind", json_name(loop.kind)},
          {"kind_reason", json_name(loop.kind_reason)},
          {"explanation", explain_kind(loop)},
          {"outer", outer},
          {"turning", loop.turning},
          {"curvature_density", loop.curvature_density},
          {"predicted_area", finite_or_null(loop.predicted_area)},
          {"component_area", loop.component_area},
          {"hole_like", turns_like_a_hole(loop)},
          {"disk", loop.is_disk},
          {"reason", loop.reason},
          {"split_at", loop.split_at},
          {"vertices", loop.vertices}};
}

}  // namespace foldfill
