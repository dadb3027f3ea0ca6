// The fill report as JSON (docs/report.md). Energies are those of the
// normalised problem (unit length = the hole's mean loop edge length), so runs
// at any scale and with either solver compare.
#include "foldfill/report.h"

#include <algorithm>
#include <cmath>

namespace foldfill {
namespace {

nlohmann::json to_json(const EnergyTerms& e) {
  return {{"isometric", e.isometric},
          {"bending", e.bending},
          {"repulsion", e.repulsion},
          {"total", e.total}};
}

// `value` where it was measured, else null.
nlohmann::json measured(bool is_measured, nlohmann::json value) {
  return is_measured ? std::move(value) : nlohmann::json(nullptr);
}

nlohmann::json finite_or_null(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

}  // namespace

const char* version() { return FOLDFILL_VERSION; }

const char* to_string(HoleStatus status) {
  switch (status) {
    case HoleStatus::Filled:
      return "filled";
    case HoleStatus::Failed:
      return "failed";
    case HoleStatus::Cancelled:
      return "cancelled";
  }
  return "failed";
}

const char* to_string(BendingModel bending) {
  return bending == BendingModel::TwoRing ? "two-ring" : "quadratic";
}

const char* to_string(SolverKind kind) {
  return kind == SolverKind::GradientDescent ? "gd" : "fast";
}

nlohmann::json to_json(const HoleReport& hole) {
  const bool filled = hole.filled;
  const bool fabric =
      filled && (hole.method == FillMethod::Fabric || hole.method == FillMethod::FabricRepaired);
  const Flattening& fit = hole.flattening_fit;
  return {
      {"loop_id", hole.loop_id},
      {"status", to_string(hole.status())},
      {"filled", filled},
      {"reason", measured(!filled, hole.reason)},
      {"warning", measured(!hole.warning.empty(), hole.warning)},
      {"method", measured(filled, to_string(hole.method))},
      {"fallback_reasons", hole.fallback_reasons},
      {"loop_vertex_count", hole.loop_vertex_count},
      {"patch_vertex_count", measured(filled, hole.patch_vertex_count)},
      {"patch_face_count", measured(filled, hole.patch_face_count)},
      {"new_vertices", measured(filled, {hole.new_vertices.first, hole.new_vertices.end})},
      {"new_faces", measured(filled, {hole.new_faces.first, hole.new_faces.end})},
      {"patch_area", measured(filled, hole.patch_area)},
      {"flat_area", measured(fabric, hole.flat_area)},
      {"area_ratio_to_flat", measured(fabric, hole.area_ratio_to_flat)},
      {"patch_min_angle_deg", measured(filled, hole.patch_min_angle_deg)},
      {"crossings", measured(filled, {{"patch_patch", hole.crossings.patch_patch},
                                      {"patch_mesh", hole.crossings.patch_mesh},
                                      {"patch_obstacles", hole.crossings.patch_obstacles}})},
      {"self_intersections", measured(filled, hole.self_intersections)},
      {"min_distance", measured(filled, hole.min_distance)},
      {"length_scale", measured(filled, hole.length_scale)},
      {"seconds",
       {{"flatten", measured(fabric, hole.seconds.flatten)},
        {"triangulate", measured(fabric, hole.seconds.triangulate)},
        {"arap", measured(fabric, hole.seconds.arap)},
        {"optimize", measured(fabric, hole.seconds.optimize)},
        {"total", measured(filled, hole.seconds.total)}}},
      {"iterations", measured(fabric, hole.iterations)},
      {"stop_reason", measured(fabric, to_string(hole.stop_reason))},
      {"start", measured(fabric, to_string(hole.start))},
      {"start_blend", measured(fabric, hole.start_blend)},
      {"folds_first", measured(fabric, to_string(hole.folds_first))},
      {"unguarded_coarse_levels", measured(fabric, hole.unguarded_coarse_levels)},
      {"lambda", measured(fabric, hole.lambda)},
      {"repulsion", measured(fabric, hole.repulsion)},
      {"obstacle_allowance", measured(fabric, hole.obstacle_allowance)},
      {"flattening", measured(fabric, {{"edge_length_rms_rel", fit.edge_length_rms_rel},
                                       {"edge_length_max_rel", fit.edge_length_max_rel},
                                       {"angle_sum_rms", fit.angle_sum_rms},
                                       {"angle_sum_max", fit.angle_sum_max},
                                       {"flipped_triangles", fit.flipped_triangles},
                                       {"simple_polygon", fit.simple_polygon}})},
      {"triangulation", measured(fabric, {{"min_angle_deg", hole.min_angle_deg},
                                          {"share_below_20deg", hole.share_below_20deg}})},
      {"energy", measured(fabric, {{"after_arap", to_json(hole.energy_after_arap)},
                                   {"final", to_json(hole.energy_final)}})},
      {"gaussian_curvature", measured(fabric, {{"after_arap",
                                                {{"mean_abs", hole.gaussian_mean_abs_after_arap},
                                                 {"variance", hole.gaussian_variance_after_arap}}},
                                               {"final",
                                                {{"mean_abs", hole.gaussian_mean_abs_final},
                                                 {"variance", hole.gaussian_variance_final}}}})},
      {"edge_length_rms_rel", measured(fabric, {{"after_arap", hole.edge_length_rms_rel_after_arap},
                                                {"final", hole.edge_length_rms_rel_final}})},
  };
}

nlohmann::json to_json(const FillReport& report) {
  nlohmann::json holes = nlohmann::json::array();
  for (const HoleReport& hole : report.holes) holes.push_back(to_json(hole));
  return {{"holes", holes},
          {"cancelled", report.cancelled},
          {"seconds",
           {{"prepare", report.seconds_prepare},
            {"holes", report.seconds_holes},
            {"stitch", report.seconds_stitch},
            {"crossings", report.seconds_crossings}}},
          {"seconds_total", report.seconds_total}};
}

nlohmann::json to_json(const FillOptions& options) {
  EnergyOptions energy = options.energy;
  SolverOptions solver = options.solver;
  // The prototype's weights for an unknown length scale: what depends on it
  // comes out as NaN, written as null.
  if (options.prototype) apply_prototype_weights(*options.prototype, std::nan(""), energy, solver);
  const bool fast = solver.kind == SolverKind::Fast;
  const FallbackOptions& fallback = options.fallback;
  nlohmann::json prototype = nullptr;
  if (options.prototype) {
    const PrototypeWeights& w = *options.prototype;
    prototype = {{"alpha", w.alpha}, {"beta", w.beta}, {"mu", w.mu}, {"step", w.step}};
  }
  return {
      {"lambda", finite_or_null(energy.lambda)},
      {"repulsion", finite_or_null(energy.repulsion)},
      {"bending", to_string(energy.bending)},
      {"shrink", options.arap.shrink},
      {"density", options.triangulate.density},
      {"thickness", options.contact.thickness},
      {"solver", to_string(solver.kind)},
      {"step", measured(!fast, finite_or_null(solver.step))},
      {"max_iterations", solver.max_iterations},
      {"time_limit", solver.time_limit_seconds},
      {"coarse_start", measured(fast, options.multilevel.min_patch_vertices)},
      {"stiff_start_lambda", measured(fast, options.stiff_start_lambda)},
      {"unguarded_folds_first", measured(fast, options.unguarded_folds_first)},
      {"prototype", prototype},
      {"fallback",
       {{"enabled", fallback.enabled},
        {"max_developability_ratio", fallback.max_developability_ratio},
        {"min_angle_deg", fallback.min_angle_deg}}},
      {"obstacles", options.obstacles.size()},
  };
}

std::vector<int> filled_loops(const FillReport& report) {
  std::vector<int> ids;
  for (const HoleReport& hole : report.holes)
    if (hole.filled) ids.push_back(hole.loop_id);
  std::sort(ids.begin(), ids.end());
  return ids;
}

nlohmann::json left_open_loops(const std::vector<BoundaryLoop>& loops, const HoleChoice& choice,
                               const FillReport& report) {
  std::vector<std::pair<int, std::string>> open;
  for (int id : choice.left_open) open.emplace_back(id, json_name(choice.reasons.at(id)));
  for (const HoleReport& hole : report.holes)
    if (!hole.filled) open.emplace_back(hole.loop_id, to_string(hole.status()));
  std::sort(open.begin(), open.end());
  nlohmann::json entries = nlohmann::json::array();
  for (const auto& [id, reason] : open)
    entries.push_back(
        {{"loop_id", id}, {"kind", json_name(loops.at(id).kind)}, {"reason", reason}});
  return entries;
}

}  // namespace foldfill
