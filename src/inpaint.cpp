// The whole fill of section 3 of Gisbert et al. 2023, hole by hole: flatten
// the strip, mesh the flat patch, place it with ARAP from a shrunk rest shape,
// minimise the fabric energy, then stitch the new vertices and faces.
#include "foldfill/inpaint.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <optional>

#include "foldfill/domain.h"
#include "foldfill/error.h"
#include "foldfill/flatten.h"
#include "foldfill/metrics.h"
#include "foldfill/multilevel.h"
#include "foldfill/topology.h"

namespace foldfill {
namespace {

using Clock = std::chrono::steady_clock;

// Retries of a self-intersecting patch (see minimise_patch): the bending
// weight grows kStiffening times per step, to at least kSmallestStiffenedLambda
// (so that a weight of 0 grows too). The reference contour example untangles
// from about 0.1 on, but where it does is chaotic: the reference curtain with
// c 0.3, repulsion 3 and lambda 1e-4 still intersects at 1e-4 * 10^3 and not
// at 1 (docs/quality.md, "Tuning the defaults"). Four steps reach 1 from 1e-4.
constexpr int kStiffeningSteps = 4;
constexpr double kStiffening = 10;
constexpr double kSmallestStiffenedLambda = 1e-3;

// A watched minimisation (see RetryRules) is looked at after this many
// iterations, and given up at once when the patch passes through itself
// there (see minimise_patch).
constexpr int kPassThroughCheck = 8;

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

// What every hole of one fill shares: the mesh, its vertex-face incidence,
// the options, and the flag that cancels the whole fill.
struct FillContext {
  const Mesh& mesh;
  const VertexFaces& vertex_faces;
  const FillOptions& options;
  const std::string& source;
  std::atomic<bool>& cancelled;
};

std::string hole_source(const std::string& source, int loop_id) {
  return source + ": loop " + std::to_string(loop_id);
}

void throw_if_cancelled(const FillContext& context, const std::string& where) {
  if (context.cancelled.load(std::memory_order_relaxed))
    throw Error(ErrorKind::FillFailed, where + ": cancelled");
}

// The minimised patch and the energy it was minimised with.
struct Minimised {
  std::optional<FabricEnergy> energy;
  SolverResult solved;
  // Intersecting triangle pairs, not counted (0) in a minimisation abandoned
  // because it passed through itself: it has some (see count_if_abandoned).
  int self_intersections = 0;
  bool tangled() const { return self_intersections > 0 || solved.stop_reason == "abandoned"; }
};

// The intersecting pairs of a minimised patch (none among the strip's faces).
int patch_pairs(const Minimised& minimised, const EmbedDomain& domain) {
  return count_self_intersections(minimised.solved.positions, domain.faces,
                                  domain.strip_face_count);
}

// One minimisation from `start`.
Minimised minimise_once(const EmbedDomain& domain, const std::vector<Vec3>& start,
                        const EnergyOptions& energy_options, const SolverOptions& solver,
                        const std::vector<Obstacle>& obstacles, const Budget& budget,
                        HoleReport& report) {
  Minimised result;
  result.energy.emplace(domain, energy_options);
  result.solved = minimize_energy(*result.energy, obstacles, start, solver, budget);
  report.iterations += result.solved.iterations;
  if (result.solved.stop_reason != "abandoned")
    result.self_intersections = patch_pairs(result, domain);
  return result;
}

// Counts the pairs of an abandoned minimisation that is kept after all.
Minimised count_if_abandoned(Minimised result, const EmbedDomain& domain) {
  if (result.solved.stop_reason == "abandoned")
    result.self_intersections = patch_pairs(result, domain);
  return result;
}

// How minimise_patch retries a self-intersecting patch: at most
// `stiffening_steps` stiffer minimisations, and which minimisations are given
// up early when the patch passes through itself (kPassThroughCheck): only one
// at a weak repulsion, or every one.
struct RetryRules {
  int stiffening_steps = kStiffeningSteps;
  bool watch_every_attempt = false;
};

// Minimises the fabric energy from `initial`. Vertex repulsion prevents most
// self-intersections, but at a small bending weight a large patch can crumple
// so fast that a fold slips through between vertices, and more repulsion does
// not stop that. So when the result intersects itself: a repulsion weaker
// than the default is first raised to it (minimised again from `initial`);
// such a minimisation is also given up after kPassThroughCheck iterations
// when the patch passes through itself there: as the shrunk ARAP start
// expands, a weak repulsion lets folds through at once (the reference
// curtain at the prototype's repulsion of 0.1: 90 intersecting pairs after 4
// iterations, 223 at convergence 126 iterations later), and a surface that
// passed through itself may come apart again but in the wrong layer order;
// then, while it still intersects, minimise again from `initial` with
// kStiffening times the bending weight, up to kStiffeningSteps times (with the
// prototype's repulsion of 0.1 kept, the reference curtain came out clean only
// at 100 times its bending weight, and tangled again when relaxed back). A
// clean stiffer result is then relaxed: minimised again from there with the
// bending weight asked for. It starts untangled, and the repulsion keeps it so
// while it only has to find its finer folds; if it intersects (or diverges)
// all the same, the stiffer result is kept. report.lambda says which bending
// weight the patch finally has, report.stiffened_retries how many stiffer
// minimisations it took (at most rules.stiffening_steps). `budget` covers
// them all: none starts once it is spent.
Minimised minimise_patch(const EmbedDomain& domain, const std::vector<Vec3>& initial,
                         const EnergyOptions& energy_options, const SolverOptions& solver,
                         const std::vector<Obstacle>& obstacles, const Budget& budget,
                         HoleReport& report, const RetryRules& rules = {}) {
  const auto out_of_time = [&] { return budget.spent(); };
  const auto finish = [&](Minimised kept, double lambda, double repulsion) {
    Minimised result = count_if_abandoned(std::move(kept), domain);
    report.lambda = lambda;
    report.repulsion = repulsion;
    report.self_intersections = result.self_intersections;
    report.stop_reason = result.solved.stop_reason;
    return result;
  };
  const auto minimise = [&](const std::vector<Vec3>& from, double lambda, double repulsion,
                            bool watch = false) {
    EnergyOptions weights = energy_options;
    weights.lambda = lambda;
    weights.repulsion = repulsion;
    SolverOptions options = solver;
    if (watch || rules.watch_every_attempt) {
      options.watch_iteration = kPassThroughCheck;
      options.watch = [&domain](const std::vector<Vec3>& positions) {
        return !passes_through_itself(positions, domain.faces, domain.strip_face_count);
      };
    }
    return minimise_once(domain, from, weights, options, obstacles, budget, report);
  };
  const auto cancelled = [](const Minimised& m) { return m.solved.stop_reason == "cancelled"; };

  double lambda = energy_options.lambda, repulsion = energy_options.repulsion;
  const bool weak_repulsion = repulsion < EnergyOptions{}.repulsion;
  Minimised result = minimise(initial, lambda, repulsion, /*watch=*/weak_repulsion);
  const auto may_retry = [&] { return result.tangled() && !cancelled(result) && !out_of_time(); };
  if (may_retry() && weak_repulsion) {
    // A weaker repulsion than the default is raised to it first, at the
    // bending weight asked for: that alone untangles the reference curtain
    // with the prototype's weights in 272 iterations, where stiffening and
    // relaxing took 754 and ended 1% higher.
    repulsion = EnergyOptions{}.repulsion;
    result = minimise(initial, lambda, repulsion);
  }
  while (may_retry() && report.stiffened_retries < rules.stiffening_steps) {
    lambda = std::max(lambda * kStiffening, kSmallestStiffenedLambda);
    result = minimise(initial, lambda, repulsion);
    ++report.stiffened_retries;
  }
  if (report.stiffened_retries == 0 || result.tangled() || cancelled(result) || out_of_time())
    return finish(std::move(result), lambda, repulsion);
  Minimised relaxed = minimise(result.solved.positions, energy_options.lambda, repulsion);
  const bool relaxed_is_better = !relaxed.tangled() && relaxed.solved.stop_reason != "diverged";
  if (relaxed_is_better || cancelled(relaxed))
    return finish(std::move(relaxed), energy_options.lambda, repulsion);
  return finish(std::move(result), lambda, repulsion);
}

// A coarse level of the coarse-to-fine start (multilevel.h) only has to hand
// the finer level its large folds, untangled; nothing when it cannot. It is
// minimised as a patch is (minimise_patch), but at once with at least the
// default repulsion, which the retries would raise it to, and stiffened at
// most once: that untangles Contour's coarse level, while the Curtain's stays
// tangled through all four steps (its triangles span a narrow finger of the
// hole in one piece and cannot fold inside it; the fine patch is clean at the
// default repulsion), and the finer level does better from ARAP than after
// more retries. Each of its minimisations is given up when the level passes
// through itself after kPassThroughCheck iterations: the Curtain's does, by
// 48 and 15 pairs, and ends with 30 and 50 after 130 and 210 iterations; of
// the coarse levels of bench_fill's and bench_quality's cases, none that
// passed through itself there came apart again.
std::optional<std::vector<Vec3>> minimise_coarse_level(
    const EmbedDomain& level, const std::vector<Vec3>& start, EnergyOptions energy_options,
    const SolverOptions& solver, const std::vector<Obstacle>& obstacles, const Budget& budget) {
  energy_options.repulsion = std::max(energy_options.repulsion, EnergyOptions{}.repulsion);
  HoleReport level_report;  // the hole's report is the fine level's
  Minimised minimised =
      minimise_patch(level, start, energy_options, solver, obstacles, budget, level_report,
                     RetryRules{/*stiffening_steps=*/1, /*watch_every_attempt=*/true});
  if (minimised.solved.stop_reason == "cancelled") throw Error(ErrorKind::FillFailed, "cancelled");
  if (minimised.tangled()) return std::nullopt;
  return std::move(minimised.solved.positions);
}

bool all_finite(const std::vector<Vec3>& positions) {
  return std::all_of(positions.begin(), positions.end(), is_finite);
}

// Why a kept patch deserves a look, or empty; its crossings are measured on
// the output (measure_crossings), which adds them.
std::string patch_warning(const HoleReport& report, const std::string& where) {
  std::string warning;
  if (report.stop_reason == "diverged")
    warning = "the minimisation diverged after " + std::to_string(report.iterations) +
              " iterations; its lowest-energy state was kept";
  if (report.stop_reason == "time_limit")
    warning = "the time limit stopped the minimisation after " + std::to_string(report.iterations) +
              " iterations";
  return warning.empty() ? warning : where + ": " + warning;
}

HolePatch fill_one_hole(const FillContext& context, const BoundaryLoop& loop) {
  const FillOptions& options = context.options;
  HolePatch result;
  HoleReport& report = result.report;
  report.loop_id = loop.id;
  report.loop_vertex_count = static_cast<int>(loop.vertices.size());
  result.loop = loop.vertices;
  const auto start = Clock::now();
  // The time limit counts from here; flattening and triangulation run to
  // their end, the start and the minimisation stop where it passes.
  const Budget budget(options.solver.time_limit_seconds, &context.cancelled);

  const std::string where = hole_source(context.source, loop.id);
  throw_if_cancelled(context, where);
  const Strip strip = extract_strip(context.mesh, context.vertex_faces, loop, context.source);
  Flattening flat = flatten_strip(strip, where);
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

  throw_if_cancelled(context, where);
  stage = Clock::now();
  const EmbedDomain domain = make_embed_domain(strip, flat, patch);
  report.length_scale = domain.length_scale;
  EnergyOptions energy_options = options.energy;
  SolverOptions solver = options.solver;
  if (options.prototype)
    apply_prototype_weights(*options.prototype, domain.length_scale, energy_options, solver);
  std::vector<Obstacle> obstacles;
  for (const Obstacle& o : options.obstacles) {
    obstacles.push_back(normalized(o, domain.origin, domain.length_scale));
  }
  if (options.progress) {
    solver.progress = [&](const SolverProgress& p) {
      if (context.cancelled.load(std::memory_order_relaxed)) return false;
      if (options.progress(loop.id, p)) return true;
      context.cancelled = true;
      return false;
    };
  }
  const auto minimise_level = [&](const EmbedDomain& level, const std::vector<Vec3>& from) {
    return minimise_coarse_level(level, from, energy_options, solver, obstacles, budget);
  };
  // The coarse-to-fine start is the fast solver's: gradient descent follows
  // the paper (ARAP, then descent), the reference the fast solver is held to.
  MultilevelOptions multilevel = options.multilevel;
  multilevel.enabled = multilevel.enabled && solver.kind == SolverKind::Fast;
  const std::vector<Vec3> initial = multilevel_start(
      strip, flat, options.triangulate, domain, options.arap, multilevel, minimise_level, budget);
  report.seconds.arap = seconds_since(stage);

  throw_if_cancelled(context, where);
  stage = Clock::now();
  const Minimised minimised =
      minimise_patch(domain, initial, energy_options, solver, obstacles, budget, report);
  const SolverResult& solved = minimised.solved;
  report.seconds.optimize = seconds_since(stage);
  if (solved.stop_reason == "cancelled") throw Error(ErrorKind::FillFailed, where + ": cancelled");
  if (!all_finite(solved.positions))
    throw Error(ErrorKind::FillFailed,
                where + ": the patch has non-finite positions (stop: " + solved.stop_reason + ")");
  report.warning = patch_warning(report, where);

  const PatchState after_arap = measure(*minimised.energy, initial);
  const PatchState final_state = measure(*minimised.energy, solved.positions);
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

// Appends the filled patches in order. The arrays grow once to their final
// size: growing by doubling would hold up to three times a large mesh.
void stitch_all(const std::vector<HolePatch>& patches, Mesh& mesh) {
  size_t new_vertices = 0, new_faces = 0;
  for (const HolePatch& patch : patches) {
    if (!patch.report.filled) continue;
    new_vertices += patch.new_positions.size();
    new_faces += patch.faces.size();
  }
  const size_t face_count = mesh.faces.size() + new_faces;
  mesh.positions.reserve(mesh.positions.size() + new_vertices);
  mesh.faces.reserve(face_count);
  if (!mesh.face_texcoords.empty()) mesh.face_texcoords.reserve(face_count);
  if (!mesh.face_normals.empty()) mesh.face_normals.reserve(face_count);
  for (const HolePatch& patch : patches)
    if (patch.report.filled) stitch(patch, mesh);
}

// Fills the holes in parallel; a hole that fails or is cancelled comes back
// unfilled with its reason.
std::vector<HolePatch> fill_patches(const FillContext& context,
                                    const std::vector<BoundaryLoop>& loops,
                                    const std::vector<int>& fill_ids) {
  for (int id : fill_ids)
    if (id < 0 || id >= static_cast<int>(loops.size()))
      throw Error(ErrorKind::Usage, context.source + ": no loop with id " + std::to_string(id) +
                                        " (the mesh has " + std::to_string(loops.size()) +
                                        " loops)");
  std::vector<HolePatch> patches(fill_ids.size());
  // One hole: no parallel region, whose idle threads would only wait (and
  // spin, with libgomp's default wait policy) for it.
#pragma omp parallel for schedule(dynamic, 1) if (fill_ids.size() > 1)
  for (int h = 0; h < static_cast<int>(fill_ids.size()); ++h) {
    const BoundaryLoop& loop = loops[fill_ids[h]];
    try {
      patches[h] = fill_one_hole(context, loop);
    } catch (const std::exception& e) {
      // Stages that do not know the file and the loop get them here.
      const std::string where = hole_source(context.source, loop.id);
      const std::string message = e.what();
      patches[h] = HolePatch{};
      patches[h].report.loop_id = loop.id;
      patches[h].report.loop_vertex_count = static_cast<int>(loop.vertices.size());
      patches[h].report.reason =
          message.rfind(where + ": ", 0) == 0 ? message : where + ": " + message;
    }
  }
  return patches;
}

}  // namespace

FillResult fill_holes(const Mesh& mesh, const std::vector<BoundaryLoop>& loops,
                      const std::vector<int>& fill_ids, const FillOptions& options,
                      const std::string& source) {
  return fill_holes(Mesh(mesh), loops, fill_ids, options, source);
}

FillResult fill_holes(Mesh&& mesh, const std::vector<BoundaryLoop>& loops,
                      const std::vector<int>& fill_ids, const FillOptions& options,
                      const std::string& source) {
  const auto start = Clock::now();
  FillReport report;
  std::vector<HolePatch> patches;
  if (!fill_ids.empty()) {
    const VertexFaces vertex_faces = build_vertex_faces(mesh.faces, mesh.vertex_count(), source);
    report.seconds_prepare = seconds_since(start);
    const auto holes_start = Clock::now();
    std::atomic<bool> cancelled{false};
    patches = fill_patches({mesh, vertex_faces, options, source, cancelled}, loops, fill_ids);
    report.cancelled = cancelled;
    report.seconds_holes = seconds_since(holes_start);
  }
  // Holes are stitched in order, so the output does not depend on the thread count.
  const auto stitch_start = Clock::now();
  std::vector<std::vector<int>> patch_faces(patches.size());
  for (size_t h = 0, next = mesh.faces.size(); h < patches.size(); ++h) {
    if (!patches[h].report.filled) continue;
    for (size_t k = 0; k < patches[h].faces.size(); ++k)
      patch_faces[h].push_back(static_cast<int>(next++));
  }
  stitch_all(patches, mesh);
  report.seconds_stitch = seconds_since(stitch_start);
  for (HolePatch& patch : patches) report.holes.push_back(std::move(patch.report));
  const auto crossings_start = Clock::now();
  measure_crossings(mesh, patch_faces, options.obstacles, source, report);
  report.seconds_crossings = seconds_since(crossings_start);
  report.seconds_total = seconds_since(start);
  return {std::move(mesh), std::move(report)};
}

}  // namespace foldfill
