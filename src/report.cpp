// The fill report as JSON. Energies are those of the normalised problem (unit
// length = the hole's mean loop edge length), so runs at any scale and with
// either solver compare.
#include "foldfill/report.h"

namespace foldfill {
namespace {

nlohmann::json to_json(const EnergyTerms& e) {
  return {{"isometric", e.isometric},
          {"bending", e.bending},
          {"repulsion", e.repulsion},
          {"total", e.total}};
}

}  // namespace

nlohmann::json to_json(const HoleReport& hole) {
  nlohmann::json j = {{"loop_id", hole.loop_id},
                      {"filled", hole.filled},
                      {"loop_vertex_count", hole.loop_vertex_count},
                      {"fallback_reasons", hole.fallback_reasons}};
  if (!hole.filled) {
    j["reason"] = hole.reason;
    return j;
  }
  if (!hole.warning.empty()) j["warning"] = hole.warning;
  j.update({
      {"method", to_string(hole.method)},
      {"patch_vertex_count", hole.patch_vertex_count},
      {"patch_face_count", hole.patch_face_count},
      {"patch_min_angle_deg", hole.patch_min_angle_deg},
      {"new_vertices", {hole.new_vertices.first, hole.new_vertices.end}},
      {"new_faces", {hole.new_faces.first, hole.new_faces.end}},
      {"crossings",
       {{"patch_patch", hole.crossings.patch_patch},
        {"patch_mesh", hole.crossings.patch_mesh},
        {"patch_obstacles", hole.crossings.patch_obstacles}}},
      {"min_distance", hole.min_distance},
      {"self_intersections", hole.self_intersections},
      {"length_scale", hole.length_scale},
      {"seconds", {{"total", hole.seconds.total}}},
  });
  if (hole.method != FillMethod::Fabric && hole.method != FillMethod::FabricRepaired) {
    // The fabric method's figures were not measured: null, not zero.
    for (const char* key :
         {"iterations", "stop_reason", "start", "start_blend", "flattening", "triangulation",
          "energy", "gaussian_curvature", "edge_length_rms_rel", "repulsion", "lambda",
          "obstacle_allowance", "flat_area", "area_ratio_to_flat"})
      j[key] = nullptr;
    return j;
  }
  const Flattening& fit = hole.flattening_fit;
  j.update({
      {"iterations", hole.iterations},
      {"stop_reason", to_string(hole.stop_reason)},
      {"start", to_string(hole.start)},
      {"start_blend", hole.start_blend},
      {"seconds",
       {{"flatten", hole.seconds.flatten},
        {"triangulate", hole.seconds.triangulate},
        {"arap", hole.seconds.arap},
        {"optimize", hole.seconds.optimize},
        {"total", hole.seconds.total}}},
      {"flattening",
       {{"edge_length_rms_rel", fit.edge_length_rms_rel},
        {"edge_length_max_rel", fit.edge_length_max_rel},
        {"angle_sum_rms", fit.angle_sum_rms},
        {"angle_sum_max", fit.angle_sum_max},
        {"flipped_triangles", fit.flipped_triangles},
        {"simple_polygon", fit.simple_polygon}}},
      {"triangulation",
       {{"min_angle_deg", hole.min_angle_deg}, {"share_below_20deg", hole.share_below_20deg}}},
      {"energy",
       {{"after_arap", to_json(hole.energy_after_arap)}, {"final", to_json(hole.energy_final)}}},
      {"gaussian_curvature",
       {{"after_arap",
         {{"mean_abs", hole.gaussian_mean_abs_after_arap},
          {"variance", hole.gaussian_variance_after_arap}}},
        {"final",
         {{"mean_abs", hole.gaussian_mean_abs_final},
          {"variance", hole.gaussian_variance_final}}}}},
      {"edge_length_rms_rel",
       {{"after_arap", hole.edge_length_rms_rel_after_arap},
        {"final", hole.edge_length_rms_rel_final}}},
      {"repulsion", hole.repulsion},
      {"lambda", hole.lambda},
      {"obstacle_allowance", hole.obstacle_allowance},
      {"flat_area", hole.flat_area},
      {"area_ratio_to_flat", hole.area_ratio_to_flat},
  });
  return j;
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

}  // namespace foldfill
