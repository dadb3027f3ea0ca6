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
  chosen.selection = selection;
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
  result.selection = chosen.selection;
  return result;
}

FillOutput fill(const Mesh& mesh, const FillRequest& request) {
  return fill(mesh, choose_holes(mesh, request), request);
}

namespace {

const char* selection_mode_name(HoleSelection::Mode mode) {
  switch (mode) {
    case HoleSelection::Mode::Default:
      return "default";
    case HoleSelection::Mode::All:
      return "all";
    case HoleSelection::Mode::Ids:
      return "ids";
    case HoleSelection::Mode::Near:
      return "near";
    case HoleSelection::Mode::KeepOpen:
      return "keep_open";
  }
  return "default";
}

nlohmann::json positive_or_null(double value) {
  return value > 0 ? nlohmann::json(value) : nlohmann::json(nullptr);
}

}  // namespace

nlohmann::json options_json(const FillRequest& request, const HoleSelection& selection) {
  nlohmann::json options = to_json(request.options);
  const bool liepa = request.algorithm == FillAlgorithm::Liepa;
  if (liepa)
    for (auto item : options.items())
      if (item.key() != "obstacles") item.value() = nullptr;
  options["method"] = liepa ? "liepa" : "foldfill";
  const bool keep_open = selection.mode == HoleSelection::Mode::KeepOpen;
  nlohmann::json near = nlohmann::json::array();
  for (const Vec3& point : selection.near) near.push_back(point);
  options["selection"] = {
      {"mode", selection_mode_name(selection.mode)},
      {"holes", selection.ids},
      {"near", near},
      {"keep_open", keep_open ? nlohmann::json(selection.keep_open) : nlohmann::json(nullptr)},
      {"max_hole_size", positive_or_null(selection.max_hole_size)},
      {"max_hole_diameter", positive_or_null(selection.max_hole_diameter)},
  };
  return options;
}

nlohmann::json report_json(const FillReport& fill_report, const std::vector<BoundaryLoop>& loops,
                           const HoleChoice& choice, const nlohmann::json& options,
                           const ReportCounts& counts) {
  nlohmann::json report = to_json(fill_report);
  report["foldfill_version"] = version();
  report["counts"] = {{"input_vertices", counts.input_vertices},
                      {"input_faces", counts.input_faces},
                      {"boundary_loops", loops.size()},
                      {"output_vertices", counts.output_vertices},
                      {"output_faces", counts.output_faces}};
  report["options"] = options;
  report["filled_loops"] = filled_loops(fill_report);
  report["left_open_loops"] = left_open_loops(loops, choice, fill_report);
  report["warnings"] = choice.warnings;
  return report;
}

nlohmann::json report_json(const Mesh& input, const FillOutput& result,
                           const FillRequest& request) {
  return report_json(result.report, result.loops, result.choice,
                     options_json(request, result.selection),
                     {input.vertex_count(), input.face_count(), result.mesh.vertex_count(),
                      result.mesh.face_count()});
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
