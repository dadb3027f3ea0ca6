// The whole fill of section 3 of Gisbert et al. 2023, hole by hole: flatten
// the strip, mesh the flat patch, place it with ARAP from a shrunk rest shape,
// minimise the fabric energy, then stitch the new vertices and faces.
#include "foldfill/inpaint.h"

#include <chrono>
#include <exception>
#include <optional>

#include "foldfill/domain.h"
#include "foldfill/error.h"
#include "foldfill/flatten.h"
#include "foldfill/metrics.h"

namespace foldfill {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kRepulsionRetries = 2;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// A filled hole before stitching: the patch in the mesh's units.
struct HolePatch {
  std::vector<Vec3> new_positions;  // the patch's interior vertices
  std::vector<Tri> faces;  // < loop_size: loop vertex k; else new vertex (index - loop_size)
  std::vector<int> loop;   // input indices of the loop vertices
  HoleReport report;
};

std::vector<int> free_vertices(const EmbedDomain& domain) {
  std::vector<int> vertices;
  for (int v = domain.fixed_count; v < domain.vertex_count(); ++v) vertices.push_back(v);
  return vertices;
}

// The quality figures of one state of the patch (normalised positions).
struct PatchState {
  EnergyTerms energy;
  CurvatureStats curvature;
  double edge_length_rms_rel = 0;
};

PatchState measure(const FabricEnergy& energy, const std::vector<Vec3>& positions) {
  const EmbedDomain& domain = energy.domain();
  PatchState state;
  state.energy = energy.evaluate(energy.variables(positions));
  state.curvature = gaussian_curvature_stats(positions, domain.faces, free_vertices(domain));
  std::vector<std::array<int, 2>> edges;
  std::vector<double> rest;
  for (const FabricEnergy::Spring& s : energy.springs()) {
    edges.push_back({s.i, s.j});
    rest.push_back(s.rest_length);
  }
  state.edge_length_rms_rel = rms_relative_edge_error(positions, edges, rest);
  return state;
}

std::vector<Tri> patch_faces(const EmbedDomain& domain) {
  return {domain.faces.begin() + domain.strip_face_count, domain.faces.end()};
}

void apply_prototype_weights(const PrototypeWeights& w, double length_scale, EnergyOptions& energy,
                             SolverOptions& solver) {
  // The quadratic bending energy is scale-free and the prototype scaled its
  // gradient by 0.001; two-ring springs scale like the edge springs (length^2)
  // and were not scaled.
  energy.lambda = energy.bending == BendingModel::TwoRing
                      ? w.beta / w.alpha
                      : 0.001 * w.beta / (w.alpha * length_scale * length_scale);
  energy.repulsion = w.mu / w.alpha;
  solver.step = w.step * w.alpha;
}

Mesh flat_mesh(const std::vector<Vec2>& uv, const std::vector<Tri>& faces) {
  Mesh mesh;
  for (const Vec2& p : uv) mesh.positions.push_back({p[0], p[1], 0});
  mesh.faces = faces;
  return mesh;
}

HolePatch fill_one_hole(const Mesh& mesh, const BoundaryLoop& loop, const FillOptions& options,
                        const std::string& source) {
  HolePatch result;
  HoleReport& report = result.report;
  report.loop_id = loop.id;
  report.loop_vertex_count = static_cast<int>(loop.vertices.size());
  result.loop = loop.vertices;
  const auto start = Clock::now();

  const std::string hole_source = source + ": loop " + std::to_string(loop.id);
  const Strip strip = extract_strip(mesh, loop, hole_source);
  Flattening flat = flatten_strip(strip, hole_source);
  report.seconds.flatten = seconds_since(start);

  auto stage = Clock::now();
  const FlatPatch patch = triangulate_hole(hole_polygon(strip, flat), options.triangulate);
  report.seconds.triangulate = seconds_since(stage);
  report.min_angle_deg = patch.min_angle_deg;
  report.share_below_20deg = patch.share_below_20deg;
  report.flat_area = patch.area;
  if (options.keep_flat) {
    report.flat_strip = flat_mesh(flat.uv, strip.faces);
    report.flat_patch = flat_mesh(patch.uv, patch.faces);
  }

  stage = Clock::now();
  const EmbedDomain domain = make_embed_domain(strip, flat, patch);
  const std::vector<Vec3> initial = arap_embed(domain, options.arap);
  report.seconds.arap = seconds_since(stage);
  report.length_scale = domain.length_scale;

  stage = Clock::now();
  EnergyOptions energy_options = options.energy;
  SolverOptions solver = options.solver;
  if (options.prototype)
    apply_prototype_weights(*options.prototype, domain.length_scale, energy_options, solver);
  std::vector<Obstacle> obstacles;
  for (const Obstacle& o : options.obstacles) {
    obstacles.push_back(normalized(o, domain.origin, domain.length_scale));
  }
  if (options.progress) {
    solver.progress = [&](const SolverProgress& p) { return options.progress(loop.id, p); };
  }
  // Vertex repulsion prevents most self-intersections, but a fold under
  // pressure can slip through between vertices. When the result intersects
  // itself, minimise again from the ARAP state with ten times the repulsion.
  std::optional<FabricEnergy> energy;
  SolverResult solved;
  for (int attempt = 0;; ++attempt) {
    energy.emplace(domain, energy_options);
    solved = minimize_energy(*energy, obstacles, initial, solver);
    report.iterations += solved.iterations;
    report.self_intersections =
        count_self_intersections(solved.positions, domain.faces, domain.strip_face_count);
    if (report.self_intersections == 0 || attempt == kRepulsionRetries ||
        solved.stop_reason == "cancelled") {
      break;
    }
    energy_options.repulsion = std::max(10 * energy_options.repulsion, 1.0);
  }
  report.repulsion = energy_options.repulsion;
  report.seconds.optimize = seconds_since(stage);
  report.stop_reason = solved.stop_reason;

  const PatchState after_arap = measure(*energy, initial);
  const PatchState final_state = measure(*energy, solved.positions);
  report.energy_after_arap = after_arap.energy;
  report.energy_final = final_state.energy;
  report.gaussian_mean_abs_after_arap = after_arap.curvature.mean_abs;
  report.gaussian_variance_after_arap = after_arap.curvature.variance;
  report.gaussian_mean_abs_final = final_state.curvature.mean_abs;
  report.gaussian_variance_final = final_state.curvature.variance;
  report.edge_length_rms_rel_after_arap = after_arap.edge_length_rms_rel;
  report.edge_length_rms_rel_final = final_state.edge_length_rms_rel;
  const double scale2 = domain.length_scale * domain.length_scale;
  report.area_ratio_to_flat =
      total_area(solved.positions, patch_faces(domain)) * scale2 / patch.area;

  // Back to the mesh's units. Patch vertex k < loop_size is loop vertex k;
  // the domain's free vertices are the patch's interior vertices, in order.
  for (int v = domain.fixed_count; v < domain.vertex_count(); ++v) {
    const Vec3& x = solved.positions[v];
    result.new_positions.push_back({domain.origin[0] + domain.length_scale * x[0],
                                    domain.origin[1] + domain.length_scale * x[1],
                                    domain.origin[2] + domain.length_scale * x[2]});
  }
  result.faces = patch.faces;
  report.patch_vertex_count = static_cast<int>(result.new_positions.size());
  report.patch_face_count = static_cast<int>(result.faces.size());
  report.flattening_fit = std::move(flat);
  report.flattening_fit.uv.clear();
  report.filled = true;
  report.seconds.total = seconds_since(start);
  return result;
}

// Appends a filled hole's vertices and faces to `mesh`.
void stitch(const HolePatch& patch, Mesh& mesh) {
  const int loop_size = static_cast<int>(patch.loop.size());
  const int first_new = mesh.vertex_count();
  mesh.positions.insert(mesh.positions.end(), patch.new_positions.begin(),
                        patch.new_positions.end());
  for (const Tri& f : patch.faces) {
    Tri t;
    for (int k = 0; k < 3; ++k)
      t[k] = f[k] < loop_size ? patch.loop[f[k]] : first_new + f[k] - loop_size;
    mesh.faces.push_back(t);
    if (!mesh.face_texcoords.empty()) mesh.face_texcoords.push_back({-1, -1, -1});
    if (!mesh.face_normals.empty()) mesh.face_normals.push_back({-1, -1, -1});
  }
}

}  // namespace

FillResult fill_holes(const Mesh& mesh, const std::vector<BoundaryLoop>& loops,
                      const std::vector<int>& fill_ids, const FillOptions& options,
                      const std::string& source) {
  const auto start = Clock::now();
  std::vector<HolePatch> patches(fill_ids.size());
  // Holes are independent: fill them in parallel, stitch them in order, so the
  // output does not depend on the thread count.
#pragma omp parallel for schedule(dynamic, 1)
  for (int h = 0; h < static_cast<int>(fill_ids.size()); ++h) {
    const BoundaryLoop& loop = loops.at(fill_ids[h]);
    try {
      patches[h] = fill_one_hole(mesh, loop, options, source);
    } catch (const std::exception& e) {
      patches[h] = HolePatch{};
      patches[h].report.loop_id = loop.id;
      patches[h].report.loop_vertex_count = static_cast<int>(loop.vertices.size());
      patches[h].report.reason = e.what();
    }
  }
  FillResult result{mesh, {}};
  for (const HolePatch& patch : patches) {
    if (patch.report.filled) stitch(patch, result.mesh);
    result.report.holes.push_back(patch.report);
  }
  result.report.seconds_total = seconds_since(start);
  return result;
}

}  // namespace foldfill
