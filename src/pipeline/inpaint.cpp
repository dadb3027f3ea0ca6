// The whole fill of section 3 of Gisbert et al. 2023, hole by hole: plan
// (flatten the strip, mesh the flat patch, glue them into a normalised
// domain), start (ARAP from a shrunk rest shape, or coarser levels of the same
// hole), one minimisation of the fabric energy that crosses nothing (see
// contact.h), the measurements, then stitch the new vertices and faces.
#include "foldfill/inpaint.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <numeric>
#include <optional>
#include <unordered_map>

#include "embed/triangle_geometry.h"
#include "foldfill/box_tree.h"
#include "foldfill/developability.h"
#include "foldfill/domain.h"
#include "foldfill/error.h"
#include "foldfill/flatten.h"
#include "foldfill/marks.h"
#include "foldfill/metrics.h"
#include "foldfill/multilevel.h"
#include "foldfill/smooth_fill.h"
#include "foldfill/topology.h"
#include "foldfill/untangle.h"
#include "pipeline/patch_scene.h"

namespace foldfill {
namespace {

using Clock = std::chrono::steady_clock;

// Primitives of a start nearer than this (normalised) touch: the start is
// not one that crosses nothing.
constexpr double kTouching = 1e-6;
// A patch face with an angle under this (degrees) counts as of zero area.
constexpr double kDegenerateAngle = 1e-3;

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

std::vector<Tri> patch_faces(const EmbedDomain& domain) {
  return {domain.faces.begin() + domain.strip_face_count, domain.faces.end()};
}

}  // namespace

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

namespace {

void check_options(const FillOptions& options, const std::string& source) {
  const StartOptions& start = options.start;
  const UntangleOptions& untangle = start.untangle;
  const bool weights_positive = std::all_of(untangle.weights.begin(), untangle.weights.end(),
                                            [](double w) { return w > 0 && std::isfinite(w); });
  if (!(start.obstacle_clearance > 0 && std::isfinite(start.obstacle_clearance)) ||
      start.membrane_bisections < 0 || untangle.rounds < 0 || untangle.iterations_per_round < 1 ||
      untangle.separation_iterations < 0 || !weights_positive ||
      !(untangle.relative_energy_tol > 0 && std::isfinite(untangle.relative_energy_tol)))
    throw UsageError(source +
                     ": start options out of range (obstacle_clearance, the untangling "
                     "weights and its relative_energy_tol must be positive, "
                     "membrane_bisections and rounds at least 0, iterations_per_round at least 1)");
  if (!options.prototype) return;
  const bool weights_set = options.energy.lambda != EnergyOptions{}.lambda ||
                           options.energy.repulsion != EnergyOptions{}.repulsion ||
                           options.solver.step != SolverOptions{}.step;
  if (weights_set)
    throw UsageError(source +
                     ": the prototype's weights replace lambda, repulsion and "
                     "the descent step; set one or the other");
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

// `message` without a leading "WHERE: ".
std::string without_prefix(const std::string& message, const std::string& where) {
  return message.rfind(where + ": ", 0) == 0 ? message.substr(where.size() + 2) : message;
}

void throw_if_cancelled(const FillContext& context, const std::string& where) {
  if (context.cancelled.load(std::memory_order_relaxed))
    throw FillFailedError(where + ": cancelled");
}

// ---- Reach ------------------------------------------------------------------

bool inside(const Box3& box, const Vec3& p) {
  for (int c = 0; c < 3; ++c)
    if (!(p[c] >= box.low[c] && p[c] <= box.high[c])) return false;
  return true;
}

// ---- The plan ---------------------------------------------------------------

// What a hole's fill is computed from: the strip around it, its flattening,
// the flat patch and their glue, the normalised domain.
struct HolePlan {
  Strip strip;
  Flattening flat;
  FlatPatch patch;
  EmbedDomain domain;
};

HolePlan plan_hole(const FillContext& context, const BoundaryLoop& loop, HoleReport& report) {
  const auto start = Clock::now();
  const std::string where = hole_source(context.source, loop.id);
  HolePlan plan;
  plan.strip = extract_strip(context.mesh, context.vertex_faces, loop, context.source);
  try {
    plan.flat = flatten_strip(plan.strip, where);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::FillFailed || !context.options.fallback.enabled) throw;
    report.fallback_reasons.push_back(std::string(to_string(FillMethod::Fabric)) + ": " +
                                      without_prefix(e.what(), where));
    report.method = FillMethod::FabricRepaired;
    plan.flat = flatten_strip_repaired(plan.strip, where);
  }
  report.seconds.flatten = seconds_since(start);

  const auto stage = Clock::now();
  plan.patch = triangulate_hole(hole_polygon(plan.strip, plan.flat), context.options.triangulate);
  report.seconds.triangulate = seconds_since(stage);
  report.min_angle_deg = plan.patch.min_angle_deg;
  report.share_below_20deg = plan.patch.share_below_20deg;
  report.flat_area = plan.patch.area;
  if (context.options.keep_flat) {
    report.flat_strip = flat_mesh(plan.flat.uv, plan.strip.faces);
    report.flat_patch = flat_mesh(plan.patch.uv, plan.patch.faces);
  }
  plan.domain = make_embed_domain(plan.strip, plan.flat, plan.patch);
  report.length_scale = plan.domain.length_scale;
  return plan;
}

// ---- The scene: what the patch must not cross ------------------------------

// The surroundings of one hole: the faces of the input near it and the
// patches of the holes filled before it that it may reach.
struct Surroundings {
  Box3 reach;
  const std::vector<int>* nearby_faces = nullptr;  // ascending indices into the input's faces
  std::vector<const HolePatch*> earlier;
};

// Vertices of the scene, found by a key (an input vertex, or a vertex of
// another patch), numbered as PatchScene wants: the strip's own vertices
// are the domain's fixed ones.
class SceneBuilder {
 public:
  SceneBuilder(const HolePlan& plan, PatchScene& scene) : plan_(plan), scene_(scene) {
    for (int k = 0; k < plan.domain.fixed_count; ++k) index_of_input_[plan.strip.to_input[k]] = k;
  }

  // The scene index of input vertex `v` at `p` (mesh units).
  int input_vertex(int v, const Vec3& p) {
    const auto [it, inserted] = index_of_input_.emplace(v, next_index());
    if (inserted) scene_.positions.push_back(normalised(p, plan_.domain));
    return it->second;
  }
  // A new scene vertex at `p` (mesh units).
  int new_vertex(const Vec3& p) {
    scene_.positions.push_back(normalised(p, plan_.domain));
    return next_index() - 1;
  }
  // A scene vertex at `x`, already normalised.
  int normalised_vertex(const Vec3& x) {
    scene_.positions.push_back(x);
    return next_index() - 1;
  }
  void face(const Tri& f) { scene_.faces.push_back(f); }

 private:
  int next_index() const {
    return plan_.domain.fixed_count + static_cast<int>(scene_.positions.size());
  }

  const HolePlan& plan_;
  PatchScene& scene_;
  std::unordered_map<int, int> index_of_input_;
};

// The scene of a hole: the input's faces near it but the strip's, the
// earlier patches it may reach, and a mesh obstacle's faces near the hole;
// into `obstacles`, the spheres, cylinders and planes the contact sees. Each
// obstacle is moved in as deep as the strip already reaches into it (the
// cloth may rest on or a hair inside an obstacle), and a hair more.
PatchScene make_scene(const FillContext& context, const HolePlan& plan, const Surroundings& around,
                      const std::string& where, SceneObstacles& obstacles) {
  PatchScene scene;
  SceneBuilder builder(plan, scene);
  const Mesh& mesh = context.mesh;
  const std::vector<int>& strip_faces = plan.strip.input_faces;  // ascending
  if (around.nearby_faces) {
    for (int f : *around.nearby_faces) {
      if (std::binary_search(strip_faces.begin(), strip_faces.end(), f)) continue;
      Tri face;
      for (int k = 0; k < 3; ++k)
        face[k] = builder.input_vertex(mesh.faces[f][k], mesh.positions[mesh.faces[f][k]]);
      builder.face(face);
    }
  }
  for (const HolePatch* patch : around.earlier) {
    const int loop_size = static_cast<int>(patch->loop.size());
    std::vector<int> index(loop_size + patch->new_positions.size());
    for (int k = 0; k < loop_size; ++k)
      index[k] = builder.input_vertex(patch->loop[k], mesh.positions[patch->loop[k]]);
    for (size_t k = 0; k < patch->new_positions.size(); ++k)
      index[loop_size + k] = builder.new_vertex(patch->new_positions[k]);
    for (const Tri& f : patch->faces) builder.face({index[f[0]], index[f[1]], index[f[2]]});
  }

  add_scene_obstacles(where, plan.domain, context.options.obstacles, around.reach, scene,
                      obstacles);
  return scene;
}

// ---- The start -----------------------------------------------------------------

// Puts the free vertices of `positions` at least `clearance` outside every
// obstacle they are in or near.
void clear_obstacles(const EmbedDomain& domain, const std::vector<Obstacle>& obstacles,
                     double clearance, std::vector<Vec3>& positions) {
  for (const Obstacle& o : obstacles) {
    for (int v = domain.fixed_count; v < domain.vertex_count(); ++v) {
      Vec3& p = positions[v];
      if (farther_than(o, p, clearance)) continue;
      push_outside(o, p);
      const double gap = clearance - signed_distance(o, p);
      if (!(gap > 0)) continue;
      const Vec3 n = outward_normal(o, p);
      for (int c = 0; c < 3; ++c) p[c] += gap * n[c];
    }
  }
}

// Puts the free vertices of `positions` at least `clearance` outside every
// obstacle by moving them all one way: along the obstacle's outward normal
// at the centroid of those within `clearance` of it. Where nearest points
// would take neighbouring vertices to different sides of an edge or a
// corner, this lifts the patch over it like a tent.
void lift_over_obstacles(const EmbedDomain& domain, const std::vector<Obstacle>& obstacles,
                         double clearance, std::vector<Vec3>& positions) {
  for (const Obstacle& o : obstacles) {
    Vec3 centroid{0, 0, 0};
    int count = 0;
    for (int v = domain.fixed_count; v < domain.vertex_count(); ++v) {
      if (farther_than(o, positions[v], clearance)) continue;
      for (int c = 0; c < 3; ++c) centroid[c] += positions[v][c];
      ++count;
    }
    if (count == 0) continue;
    for (double& x : centroid) x /= count;
    const Vec3 n = outward_normal(o, centroid);
    if (!(std::hypot(n[0], n[1], n[2]) > 0)) continue;
    for (int v = domain.fixed_count; v < domain.vertex_count(); ++v) {
      Vec3& p = positions[v];
      if (farther_than(o, p, clearance)) continue;
      // The least lift along n that clears it, by doubling then bisection.
      const auto at = [&](double t) {
        return Vec3{p[0] + t * n[0], p[1] + t * n[1], p[2] + t * n[2]};
      };
      double low = 0, high = clearance;
      for (int k = 0; k < 60 && signed_distance(o, at(high)) < clearance; ++k) high *= 2;
      for (int k = 0; k < 40; ++k) {
        const double mid = 0.5 * (low + high);
        (signed_distance(o, at(mid)) < clearance ? low : high) = mid;
      }
      p = at(high);
    }
  }
}

// The clearances a start is tried with: `clearance`, then (with
// obstacles) the largest circumradius of the rest triangles, beyond which no
// triangle whose corners are that far outside a convex obstacle (or a convex
// part of one, a box's corner) can reach into it.
std::vector<double> clearances(const EmbedDomain& domain, const std::vector<Obstacle>& obstacles,
                               double clearance) {
  std::vector<double> result{clearance};
  if (obstacles.empty()) return result;
  double largest = 0;
  for (size_t f = domain.strip_face_count; f < domain.faces.size(); ++f) {
    const Vec2& a = domain.rest_uv[domain.faces[f][0]];
    const Vec2& b = domain.rest_uv[domain.faces[f][1]];
    const Vec2& c = domain.rest_uv[domain.faces[f][2]];
    const double ab = std::hypot(b[0] - a[0], b[1] - a[1]);
    const double bc = std::hypot(c[0] - b[0], c[1] - b[1]);
    const double ca = std::hypot(a[0] - c[0], a[1] - c[1]);
    const double twice_area =
        std::abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    if (twice_area > 0) largest = std::max(largest, ab * bc * ca / (2 * twice_area));
  }
  if (largest > clearance) result.push_back(1.1 * largest);
  return result;
}

// Whether the patch at `positions` crosses nothing (itself, its strip, the
// scene: exact predicates) and touches nothing: no pair (and no face
// against an obstacle) is nearer than kTouching, so that the barrier is
// finite there.
bool crosses_nothing(const PatchContact& contact, const std::vector<Vec3>& positions,
                     const FabricEnergy& energy) {
  const Eigen::VectorXd x = energy.variables(positions);
  // A pair nearer than this may cross once the patch is back in the mesh's
  // units, rounded: it touches.
  if (contact.min_distance(x, kTouching) < kTouching) return false;
  return !any_crossing(contact.positions(x), contact.mesh().faces, contact.first_patch_face(),
                       contact.end_patch_face(), contact.patch_face_pairs(x));
}

// One level of the start: a domain with its energy and contact.
struct Level {
  const EmbedDomain& domain;
  const FabricEnergy& energy;
  const PatchContact& contact;
  const std::vector<Obstacle>& obstacles;
  const StartOptions& options;
};

// A start for `level` that crosses nothing: `candidate` cleared of the
// obstacles when it crosses nothing; else the first point that does not on
// the way from it to the membrane (bisected); each tried with the
// clearances in turn; nothing when the membrane crosses something too.
// `blend` receives how far along the way it is.
std::optional<std::vector<Vec3>> clean_start(const Level& level, const std::vector<Vec3>& candidate,
                                             double& blend) {
  blend = 0;
  const EmbedDomain& domain = level.domain;
  const std::vector<Vec3> membrane_shape = membrane_embed(domain);
  for (double clearance : clearances(domain, level.obstacles, level.options.obstacle_clearance)) {
    std::vector<Vec3> start = candidate;
    clear_obstacles(domain, level.obstacles, clearance, start);
    if (crosses_nothing(level.contact, start, level.energy)) return start;
    if (!level.obstacles.empty()) {
      start = candidate;
      lift_over_obstacles(domain, level.obstacles, clearance, start);
      if (crosses_nothing(level.contact, start, level.energy)) return start;
    }
    std::vector<Vec3> membrane = membrane_shape;
    clear_obstacles(domain, level.obstacles, clearance, membrane);
    if (!crosses_nothing(level.contact, membrane, level.energy)) continue;
    const auto mix = [&](double s) {
      std::vector<Vec3> x = candidate;
      for (int v = domain.fixed_count; v < domain.vertex_count(); ++v)
        for (int c = 0; c < 3; ++c) x[v][c] = (1 - s) * candidate[v][c] + s * membrane_shape[v][c];
      clear_obstacles(domain, level.obstacles, clearance, x);
      return x;
    };
    double clean = 1, crossing = 0;
    for (int step = 0; step < level.options.membrane_bisections; ++step) {
      const double s = 0.5 * (clean + crossing);
      (crosses_nothing(level.contact, mix(s), level.energy) ? clean : crossing) = s;
    }
    blend = clean;
    return clean == 1 ? membrane : mix(clean);
  }
  return std::nullopt;
}

// `positions` (cleared of the obstacles) untangled (untangle.h) and cleared
// again, when that crosses nothing; nothing otherwise.
std::optional<std::vector<Vec3>> untangled(const Level& level, const std::vector<Vec3>& positions,
                                           const Budget& budget) {
  const std::optional<Eigen::VectorXd> x =
      untangle(level.energy, level.contact, level.energy.variables(positions),
               level.options.untangle, budget);
  if (!x) return std::nullopt;
  std::vector<Vec3> result = level.energy.positions(*x);
  clear_obstacles(level.domain, level.obstacles, level.options.obstacle_clearance, result);
  // Untangling stops once nothing crosses, when pairs may still touch: a few
  // guarded iterations of the fabric energy with the barrier push them apart
  // (every step bounded so that nothing crosses).
  Eigen::VectorXd variables = level.energy.variables(result);
  if (level.contact.min_distance(variables, kTouching) < kTouching) {
    SolverOptions separate;
    separate.max_iterations = level.options.untangle.separation_iterations;
    separate.relative_energy_tol = level.options.untangle.relative_energy_tol;
    const PatchObjective objective(level.energy, &level.contact);
    variables = minimize(objective, variables, separate, budget).x;
    result = level.energy.positions(variables);
  }
  if (!crosses_nothing(level.contact, result, level.energy)) return std::nullopt;
  return result;
}

bool all_finite(const std::vector<Vec3>& positions) {
  return std::all_of(positions.begin(), positions.end(), is_finite);
}

// ---- The minimisation ----------------------------------------------------------

SolverResult minimise(const FabricEnergy& energy, const PatchContact* contact,
                      const std::vector<Vec3>& start, const SolverOptions& solver,
                      const Budget& budget) {
  const PatchObjective objective(energy, contact);
  return minimize(objective, energy.variables(start), solver, budget);
}

// `positions` as a clean start for `level`: as they are where they cross
// and touch nothing (crosses_nothing), else cleared of the obstacles where
// that makes them so; nothing otherwise.
std::optional<std::vector<Vec3>> as_clean_start(const Level& level, std::vector<Vec3> positions) {
  if (!all_finite(positions)) return std::nullopt;
  if (crosses_nothing(level.contact, positions, level.energy)) return positions;
  if (level.obstacles.empty()) return std::nullopt;
  clear_obstacles(level.domain, level.obstacles, level.options.obstacle_clearance, positions);
  if (crosses_nothing(level.contact, positions, level.energy)) return positions;
  return std::nullopt;
}

// Where a level's minimisation starts after the folds-first pass.
struct FoldsFirst {
  std::vector<Vec3> positions;
  int iterations = 0;
  FoldsFirstPass pass = FoldsFirstPass::None;
  bool cancelled = false;
};

// The folds-first pass of a level from a start that crosses nothing: where
// the bending weight is below stiff_lambda, a first minimisation with that
// weight lets the cloth form its large folds while it is stiff, and the
// weight asked for then lets the finer ones form between them. From a
// crumpling start, a floppy patch otherwise jams in many small wrinkles that
// cannot pass each other to make room. Guarded (`guarded`: level.contact),
// with `unguarded_first` (FillOptions::unguarded_folds_first) the pass runs
// first with the contact's analytic obstacles only, and its end is kept
// where it is a clean start (as_clean_start); the guarded pass runs
// otherwise. Where no pair comes within the thickness the two take the same
// path, the first without the pairs' searches and step bounds.
FoldsFirst fold_first(const Level& level, bool guarded, const std::vector<Vec3>& start,
                      const SolverOptions& solver, double stiff_lambda, bool unguarded_first,
                      const Budget& budget) {
  FoldsFirst result{start};
  if (!(level.energy.options().lambda < stiff_lambda) || solver.kind != SolverKind::Fast)
    return result;
  EnergyOptions stiff_options = level.energy.options();
  stiff_options.lambda = stiff_lambda;
  const FabricEnergy stiff(level.domain, stiff_options);
  // The same stop as the main minimisation's: a looser one (1e-4) leaves
  // folds that the main one reaches a higher minimum from (sim2: +4 %).
  SolverOptions stiff_solver = solver;
  if (solver.progress)
    stiff_solver.progress = [&](SolverProgress p) {
      p.stage = MinimisationStage::FoldsFirst;
      return solver.progress(p);
    };
  if (guarded && unguarded_first) {
    const PatchObjective obstacles_only(stiff, &level.contact, PatchContact::Scope::ObstaclesOnly);
    const SolverResult folded =
        minimize(obstacles_only, stiff.variables(start), stiff_solver, budget);
    result.iterations = folded.iterations;
    result.cancelled = folded.stop_reason == StopReason::Cancelled;
    if (result.cancelled) return result;
    if (std::optional<std::vector<Vec3>> clean = as_clean_start(level, stiff.positions(folded.x))) {
      result.positions = std::move(*clean);
      result.pass = FoldsFirstPass::Unguarded;
      return result;
    }
  }
  const SolverResult folded =
      minimise(stiff, guarded ? &level.contact : nullptr, start, stiff_solver, budget);
  result.positions = stiff.positions(folded.x);
  result.iterations += folded.iterations;
  result.cancelled = folded.stop_reason == StopReason::Cancelled;
  result.pass = guarded ? FoldsFirstPass::Guarded : FoldsFirstPass::Unguarded;
  return result;
}

// A coarse level's minimisation (MultilevelOptions::unguarded_first): with
// `unguarded_first`, first with the analytic obstacles only, its end kept
// where it is a clean start that keeps the level's thickness from
// everything; otherwise guarded, from `start`. `unguarded` receives whether
// the first was kept.
SolverResult minimise_coarse_level(const Level& level, const std::vector<Vec3>& start,
                                   const SolverOptions& solver, bool unguarded_first,
                                   const Budget& budget, bool& unguarded) {
  unguarded = false;
  int tried_iterations = 0;
  if (unguarded_first) {
    const PatchObjective obstacles_only(level.energy, &level.contact,
                                        PatchContact::Scope::ObstaclesOnly);
    const SolverResult result =
        minimize(obstacles_only, level.energy.variables(start), solver, budget);
    if (result.stop_reason == StopReason::Cancelled) return result;
    const std::vector<Vec3> positions = level.energy.positions(result.x);
    const double thickness = level.contact.options().thickness;
    if (all_finite(positions) && crosses_nothing(level.contact, positions, level.energy) &&
        level.contact.min_distance(result.x, thickness) >= thickness) {
      unguarded = true;
      return result;
    }
    tried_iterations = result.iterations;
  }
  SolverResult result = minimise(level.energy, &level.contact, start, solver, budget);
  result.iterations += tried_iterations;
  return result;
}

// The start of the minimisation over plan.domain and its kind: the domain's
// ARAP start, or with the fast solver and a large patch its coarser levels,
// the coarsest from ARAP (untangled where it and its membrane cross
// something), each minimised (the coarsest folds first: fold_first; then
// minimise_coarse_level) and interpolated onto the next finer one; each
// level's start made clean (clean_start). A coarse level keeps the
// contact's thickness plus MultilevelOptions::interpolation_clearance from
// everything, so that its interpolation crosses nothing. A coarse level with
// no clean start ends the coarse levels: the domain then starts from ARAP.
struct Start {
  std::vector<Vec3> positions;
  StartKind kind = StartKind::Arap;
  double blend = 0;
  FoldsFirstPass folds_first = FoldsFirstPass::None;  // the coarsest level's, with coarse levels
  int unguarded_coarse_levels = 0;                    // HoleReport::unguarded_coarse_levels
};

Start place_start(const FillContext& context, const HolePlan& plan, const PatchScene& scene,
                  const SceneObstacles& obstacles, const EnergyOptions& energy_options,
                  const SolverOptions& solver, const FabricEnergy& energy,
                  const PatchContact& contact, const Budget& budget) {
  const FillOptions& options = context.options;
  std::vector<EmbedDomain> levels;
  // The coarse-to-fine start is the fast solver's: gradient descent follows
  // the paper (ARAP, then descent), the reference the fast solver is held to.
  if (solver.kind == SolverKind::Fast)
    levels =
        coarser_levels(plan.strip, plan.flat, options.triangulate, plan.domain, options.multilevel);
  Start start;
  std::optional<std::vector<Vec3>> coarse;  // the finest coarse level's result, interpolated
  bool coarsest_untangled = false;
  bool unguarded_so_far = false;  // every coarse level so far minimised unguarded, its end kept
  for (size_t k = levels.size(); k-- > 0 && !budget.spent();) {
    const EmbedDomain& level = levels[k];
    SolverOptions level_solver = solver;
    if (solver.progress)
      level_solver.progress = [&, k](SolverProgress p) {
        p.coarse_level = static_cast<int>(k) + 1;
        return solver.progress(p);
      };
    const EmbedDomain& finer = k == 0 ? plan.domain : levels[k - 1];
    const FabricEnergy level_energy(level, energy_options);
    ContactOptions level_contact_options = options.contact;
    level_contact_options.thickness +=
        options.multilevel.interpolation_clearance * mean_patch_edge_length(finer);
    const PatchContact level_contact(level, scene, level_contact_options, obstacles.analytic);
    const Level here{level, level_energy, level_contact, obstacles.normalised, options.start};
    double blend = 0;
    std::vector<Vec3> candidate =
        coarse ? std::move(*coarse) : arap_embed(level, options.arap, budget);
    std::optional<std::vector<Vec3>> from = clean_start(here, candidate, blend);
    // The coarsest level's ARAP start and its membrane cross something: it
    // is untangled, as the patch's would be, but with fewer triangles.
    if (!from && k + 1 == levels.size()) {
      clear_obstacles(level, obstacles.normalised, options.start.obstacle_clearance, candidate);
      from = untangled(here, candidate, budget);
      coarsest_untangled = from.has_value();
    }
    if (!from) {
      coarse.reset();
      break;
    }
    // The coarsest level forms the large folds (fold_first).
    if (k + 1 == levels.size()) {
      const FoldsFirst folded =
          fold_first(here, true, *from, level_solver, options.stiff_start_lambda,
                     options.unguarded_folds_first, budget);
      if (folded.cancelled) throw FillFailedError("cancelled");
      start.folds_first = folded.pass;
      unguarded_so_far =
          options.multilevel.unguarded_first && folded.pass != FoldsFirstPass::Guarded;
      *from = folded.positions;
    }
    bool unguarded = false;
    const SolverResult solved =
        minimise_coarse_level(here, *from, level_solver, unguarded_so_far, budget, unguarded);
    if (solved.stop_reason == StopReason::Cancelled) throw FillFailedError("cancelled");
    unguarded_so_far = unguarded;
    start.unguarded_coarse_levels += unguarded;
    coarse = interpolate_patch(level, level_energy.positions(solved.x), finer);
  }
  const Level fine{plan.domain, energy, contact, obstacles.normalised, options.start};
  // An interpolated coarse level can cross something where the finer
  // triangles cut across a tight fold: the domain then starts from ARAP.
  if (coarse) {
    clear_obstacles(plan.domain, obstacles.normalised, options.start.obstacle_clearance, *coarse);
    if (crosses_nothing(contact, *coarse, energy)) {
      start.positions = std::move(*coarse);
      start.kind = coarsest_untangled ? StartKind::CoarseLevelsUntangled : StartKind::CoarseLevels;
      return start;
    }
  }
  std::vector<Vec3> arap = arap_embed(plan.domain, options.arap, budget);
  if (std::optional<std::vector<Vec3>> clean = clean_start(fine, arap, start.blend)) {
    start.positions = std::move(*clean);
    start.kind = start.blend > 0 ? StartKind::TowardsMembrane : StartKind::Arap;
    return start;
  }
  clear_obstacles(plan.domain, obstacles.normalised, options.start.obstacle_clearance, arap);
  if (std::optional<std::vector<Vec3>> clean = untangled(fine, arap, budget)) {
    start.positions = std::move(*clean);
    start.kind = StartKind::Untangled;
    return start;
  }
  start.positions = std::move(arap);
  start.kind = StartKind::Unguarded;
  return start;
}

// Why a kept patch deserves a look, or empty; its crossings are measured on
// the output (measure_crossings), which adds them.
// Why no start that crosses nothing was found: the time limit ended the
// search for one (`timed_out`), or every kind of start was tried.
std::string no_clean_start(bool timed_out) {
  return timed_out ? "the time limit passed before a start that crosses nothing was found"
                   : "no start that crosses nothing was found (the ARAP start and the "
                     "membrane both cross something, and untangling did not clear them)";
}

// `start_timed_out`: the time limit ended the search for a start.
std::string patch_warning(const HoleReport& report, const std::string& where,
                          bool start_timed_out) {
  std::string warning;
  if (report.stop_reason == StopReason::Diverged)
    warning = "the minimisation diverged after " + std::to_string(report.iterations) +
              " iterations; its lowest-energy state was kept";
  if (report.stop_reason == StopReason::TimeLimit)
    warning = "the time limit stopped the minimisation after " + std::to_string(report.iterations) +
              " iterations";
  if (report.start == StartKind::Unguarded)
    warning += (warning.empty() ? "" : "; ") + no_clean_start(start_timed_out) +
               ": minimised without the guarantee";
  return warning.empty() ? warning : where + ": " + warning;
}

// The fabric method, from the LSCM flattening or, where that fails, a
// repaired one.
// Thrown by fill_fabric, when told to, where no start that crosses nothing
// was found: the chain tries the other steps before it minimises without the
// guarantee, from `start` (the search for a clean one is not run again).
struct UnguardedStart {
  std::vector<Vec3> positions;  // the domain's positions the patch is minimised from unguarded
  bool timed_out = false;       // the time limit ended the search for a clean start
};
struct NoCleanStart : FillFailedError {
  NoCleanStart(const std::string& where, UnguardedStart unguarded_start)
      : FillFailedError(where + ": " + no_clean_start(unguarded_start.timed_out)),
        start(std::move(unguarded_start)) {}
  UnguardedStart start;
};

// `unguarded_start` (may be null): the start of an earlier call's NoCleanStart
// for the same hole, minimised from without the guarantee.
HolePatch fill_fabric(const FillContext& context, const BoundaryLoop& loop,
                      const Surroundings& around, HolePatch&& result, bool minimise_unguarded,
                      const UnguardedStart* unguarded_start = nullptr) {
  const FillOptions& options = context.options;
  HoleReport& report = result.report;
  const auto start = Clock::now();
  // The time limit counts from here; flattening and triangulation run to
  // their end, the start and the minimisation stop where it passes.
  const Budget budget(options.solver.time_limit_seconds, &context.cancelled);
  const std::string where = hole_source(context.source, loop.id);

  // Plan.
  throw_if_cancelled(context, where);
  const HolePlan plan = plan_hole(context, loop, report);
  const EmbedDomain& domain = plan.domain;

  // The weights, and what the patch must not cross.
  throw_if_cancelled(context, where);
  auto stage = Clock::now();
  // The weights and the solver's settings of this hole: copies of the
  // user's, derived per hole (the prototype's weights at this hole's length
  // scale, the progress that also answers FillOptions::progress). The time
  // limit is the hole's budget alone, counted from the start of the hole.
  EnergyOptions energy_options = options.energy;
  SolverOptions solver = options.solver;
  solver.time_limit_seconds = 0;
  if (options.prototype)
    apply_prototype_weights(*options.prototype, domain.length_scale, energy_options, solver);
  report.lambda = energy_options.lambda;
  report.repulsion = energy_options.repulsion;
  solver.progress = [&](const SolverProgress& p) {
    if (options.solver.progress && !options.solver.progress(p)) context.cancelled = true;
    if (options.progress && !options.progress(loop.id, p)) context.cancelled = true;
    return !context.cancelled.load(std::memory_order_relaxed);
  };
  SceneObstacles obstacles;
  const PatchScene scene = make_scene(context, plan, around, where, obstacles);
  report.obstacle_allowance = obstacles.allowance;
  const FabricEnergy energy(domain, energy_options);
  const PatchContact contact(domain, scene, options.contact, obstacles.analytic);

  // Start.
  Start initial;
  if (unguarded_start) {
    if (static_cast<int>(unguarded_start->positions.size()) != domain.vertex_count())
      throw InternalError(where + ": an unguarded start of another domain");
    initial.positions = unguarded_start->positions;
    initial.kind = StartKind::Unguarded;
  } else {
    initial = place_start(context, plan, scene, obstacles, energy_options, solver, energy, contact,
                          budget);
  }
  report.start = initial.kind;
  report.start_blend = initial.blend;
  report.seconds.arap = seconds_since(stage);

  // Minimise.
  throw_if_cancelled(context, where);
  stage = Clock::now();
  const bool guarded = initial.kind != StartKind::Unguarded;
  // A search for a clean start that found none before the time limit passed
  // did not try every kind of start.
  const bool start_timed_out =
      unguarded_start ? unguarded_start->timed_out : !guarded && budget.spent();
  if (!guarded && !minimise_unguarded)
    throw NoCleanStart(where, {std::move(initial.positions), start_timed_out});
  // From the coarse levels the large folds are there; else folds first.
  const bool from_coarse_levels =
      initial.kind == StartKind::CoarseLevels || initial.kind == StartKind::CoarseLevelsUntangled;
  report.folds_first = initial.folds_first;
  report.unguarded_coarse_levels = initial.unguarded_coarse_levels;
  FoldsFirst folded{initial.positions};
  if (!from_coarse_levels) {
    folded = fold_first(Level{domain, energy, contact, obstacles.normalised, options.start},
                        guarded, initial.positions, solver, options.stiff_start_lambda,
                        options.unguarded_folds_first, budget);
    if (folded.cancelled) throw FillFailedError(where + ": cancelled");
    report.folds_first = folded.pass;
  }
  SolverResult solved =
      minimise(energy, guarded ? &contact : nullptr, folded.positions, solver, budget);
  solved.iterations += folded.iterations;
  report.iterations = solved.iterations;
  report.stop_reason = solved.stop_reason;
  report.seconds.optimize = seconds_since(stage);
  if (solved.stop_reason == StopReason::Cancelled) throw FillFailedError(where + ": cancelled");
  const std::vector<Vec3> final_positions = energy.positions(solved.x);
  if (!all_finite(final_positions))
    throw FillFailedError(where + ": the patch has non-finite positions (stop: " +
                          to_string(solved.stop_reason) + ")");
  report.warning = patch_warning(report, where, start_timed_out);

  // Measure.
  const PatchState after_start = measure_patch(energy, initial.positions);
  const PatchState final_state = measure_patch(energy, final_positions);
  report.energy_after_arap = after_start.energy;
  report.energy_final = final_state.energy;
  report.gaussian_mean_abs_after_arap = after_start.curvature.mean_abs;
  report.gaussian_variance_after_arap = after_start.curvature.variance;
  report.gaussian_mean_abs_final = final_state.curvature.mean_abs;
  report.gaussian_variance_final = final_state.curvature.variance;
  report.edge_length_rms_rel_after_arap = after_start.edge_length_rms_rel;
  report.edge_length_rms_rel_final = final_state.edge_length_rms_rel;
  const double scale2 = domain.length_scale * domain.length_scale;
  report.area_ratio_to_flat =
      total_area(final_positions, patch_faces(domain)) * scale2 / plan.patch.area;

  // Back to the mesh's units. Patch vertex k < loop_size is loop vertex k;
  // the domain's free vertices are the patch's interior vertices, in order.
  for (int v = domain.fixed_count; v < domain.vertex_count(); ++v)
    result.new_positions.push_back(in_mesh_units(final_positions[v], domain));
  if (!std::all_of(result.new_positions.begin(), result.new_positions.end(),
                   [&](const Vec3& p) { return inside(around.reach, p); }))
    report.warning += (report.warning.empty() ? where + ": " : std::string("; ")) +
                      "the patch left the region its collisions were checked in";
  result.faces = plan.patch.faces;
  report.patch_vertex_count = static_cast<int>(result.new_positions.size());
  report.patch_face_count = static_cast<int>(result.faces.size());
  report.flattening_fit = plan.flat;
  report.flattening_fit.uv.clear();
  report.filled = true;
  report.seconds.total = seconds_since(start);
  return std::move(result);
}

// The smallest 3D angle (degrees) of a patch's faces, in the hole's numbering.
double patch_min_angle(const Mesh& mesh, const HolePatch& patch) {
  const int loop_size = static_cast<int>(patch.loop.size());
  double smallest = 180;
  for (const Tri& f : patch.faces) {
    geometry::Triangle t;
    for (int k = 0; k < 3; ++k)
      t[k] = f[k] < loop_size ? mesh.positions[patch.loop[f[k]]]
                              : patch.new_positions[f[k] - loop_size];
    smallest = std::min(smallest, geometry::smallest_angle_deg(t));
  }
  return smallest;
}

// Throws when the patch has a face with an angle under `min_angle` degrees
// (or zero area), so that the chain goes on.
void check_patch_shape(const Mesh& mesh, HolePatch& patch, double min_angle,
                       const std::string& where) {
  patch.report.patch_min_angle_deg = patch_min_angle(mesh, patch);
  if (!(patch.report.patch_min_angle_deg > kDegenerateAngle))
    throw FillFailedError(where + ": the patch has a face of zero area");
  if (patch.report.patch_min_angle_deg < min_angle)
    throw FillFailedError(where + ": the patch has a face with a " +
                          std::to_string(patch.report.patch_min_angle_deg) + " degree angle");
}

// One smooth step of the chain.
HolePatch fill_smooth(const FillContext& context, const BoundaryLoop& loop, FillMethod method,
                      HolePatch&& result) {
  const SmoothFairing fairing = method == FillMethod::Smooth  ? SmoothFairing::Curvature
                                : method == FillMethod::Liepa ? SmoothFairing::Tangent
                                                              : SmoothFairing::Triangulation;
  const auto start = Clock::now();
  HoleReport& report = result.report;
  SmoothPatch smooth =
      fill_hole_smooth(context.mesh, context.vertex_faces, loop, fairing, context.source);
  result.new_positions = std::move(smooth.new_positions);
  result.faces = std::move(smooth.faces);
  report.method = method;
  if (!smooth.faired && fairing != SmoothFairing::Triangulation)
    report.warning = hole_source(context.source, loop.id) +
                     ": CGAL's fairing failed; the refined patch is kept unfaired";
  report.patch_vertex_count = static_cast<int>(result.new_positions.size());
  report.patch_face_count = static_cast<int>(result.faces.size());
  report.length_scale = loop.mean_edge_length;
  report.filled = true;
  report.seconds.total = seconds_since(start);
  return std::move(result);
}

// Throws when a new vertex of a smooth patch lies inside an obstacle deeper
// than the loop does (which the smooth fills do not see).
void check_outside_obstacles(const HolePatch& patch, const std::vector<Obstacle>& obstacles,
                             const Mesh& mesh, double length_scale, const std::string& where) {
  for (const Obstacle& obstacle : obstacles) {
    double depth = 0;
    for (int v : patch.loop) depth = std::max(depth, -signed_distance(obstacle, mesh.positions[v]));
    const double allowed = depth + kMeshClearance * length_scale;
    for (const Vec3& p : patch.new_positions)
      if (signed_distance(obstacle, p) < -allowed)
        throw FillFailedError(where + ": the patch enters an obstacle");
  }
}

// The pairs of crossing faces between a candidate patch and itself, the
// input's faces within its reach and the earlier patches it can meet,
// counted with exact predicates on a compact copy of those faces.
int patch_crossings(const FillContext& context, const Surroundings& around,
                    const HolePatch& patch) {
  std::vector<Vec3> positions;
  std::vector<Tri> faces;
  std::unordered_map<int, int> local;  // input vertex -> local
  const auto input_vertex = [&](int v) {
    const auto [it, added] = local.emplace(v, static_cast<int>(positions.size()));
    if (added) positions.push_back(context.mesh.positions[v]);
    return it->second;
  };
  const auto add_patch = [&](const HolePatch& p) {
    const int loop_size = static_cast<int>(p.loop.size());
    const int first_new = static_cast<int>(positions.size());
    positions.insert(positions.end(), p.new_positions.begin(), p.new_positions.end());
    for (const Tri& f : p.faces) {
      Tri t;
      for (int k = 0; k < 3; ++k)
        t[k] = f[k] < loop_size ? input_vertex(p.loop[f[k]]) : first_new + f[k] - loop_size;
      faces.push_back(t);
    }
  };
  if (around.nearby_faces)
    for (int f : *around.nearby_faces) {
      const Tri& face = context.mesh.faces[f];
      faces.push_back({input_vertex(face[0]), input_vertex(face[1]), input_vertex(face[2])});
    }
  for (const HolePatch* earlier : around.earlier) add_patch(*earlier);
  const int first_patch_face = static_cast<int>(faces.size());
  add_patch(patch);
  std::vector<int> subset(faces.size() - first_patch_face);
  std::iota(subset.begin(), subset.end(), first_patch_face);
  const SubsetCrossings pairs = count_subset_crossings(positions, faces, subset, 0);
  return pairs.within + pairs.with_others;
}

// The fallback chain. Cloth is developable, so the fabric method (from a
// repaired flattening where LSCM's fails) comes first, then the smooth fills,
// each more certain to close the hole. Where the surroundings are far from
// developable, the curvature-following smooth fill comes first (the fabric
// method next, when the smooth patch enters an obstacle); a hole of 3
// vertices has one fill, its triangle. Every step passed over leaves its
// reason in the report.
HolePatch fill_one_hole(const FillContext& context, const BoundaryLoop& loop,
                        const Surroundings& around) {
  const FallbackOptions& fallback = context.options.fallback;
  const std::string where = hole_source(context.source, loop.id);
  HolePatch blank;
  blank.report.loop_id = loop.id;
  blank.report.loop_vertex_count = static_cast<int>(loop.vertices.size());
  blank.loop = loop.vertices;
  std::vector<std::string> reasons;
  const auto passed = [&](FillMethod method, const std::string& why) {
    reasons.push_back(std::string(to_string(method)) + ": " + without_prefix(why, where));
  };
  // A step's own reasons (the LSCM flattening's failure before its repair)
  // join the chain's.
  const auto take_reasons = [&](HoleReport& report) {
    reasons.insert(reasons.end(), report.fallback_reasons.begin(), report.fallback_reasons.end());
    report.fallback_reasons.clear();
  };

  std::vector<FillMethod> steps = {FillMethod::Fabric, FillMethod::Smooth, FillMethod::Liepa,
                                   FillMethod::Triangulation};
  if (!fallback.enabled) {
    steps = {FillMethod::Fabric};
  } else if (loop.vertices.size() == 3 && loop.is_disk) {
    passed(FillMethod::Fabric, "a hole of 3 vertices has one fill, its triangle");
    steps = {FillMethod::Triangulation};
  } else {
    const Developability surroundings =
        measure_developability(context.mesh, context.vertex_faces, loop);
    if (surroundings.ratio > fallback.max_developability_ratio) {
      char why[160];
      std::snprintf(why, sizeof why,
                    "the surroundings are not developable (Gaussian / squared mean curvature "
                    "%.2f, predicted curvature of the missing piece %.0f degrees)",
                    surroundings.ratio, surroundings.predicted_curvature * 180 / M_PI);
      passed(FillMethod::Fabric, why);
      steps = {FillMethod::Smooth, FillMethod::Fabric, FillMethod::Liepa,
               FillMethod::Triangulation};
    }
  }

  // The first patch that crosses something, kept in case no later step's
  // patch crosses nothing.
  std::optional<HolePatch> crossing;
  // Set when the fabric method found no start that crosses nothing: the
  // start it is then minimised from, unguarded, if no later step does better.
  std::optional<UnguardedStart> fabric_deferred;
  for (size_t k = 0; k < steps.size(); ++k) {
    throw_if_cancelled(context, where);
    const bool last = k + 1 == steps.size();
    HolePatch patch = blank;
    try {
      if (steps[k] == FillMethod::Fabric) {
        patch = fill_fabric(context, loop, around, std::move(patch), !fallback.enabled);
        // Its triangles are those of a quality flat triangulation, strained
        // by the cloth: only a degenerate one counts.
        if (fallback.enabled)
          check_patch_shape(context.mesh, patch, kDegenerateAngle, where);
        else
          patch.report.patch_min_angle_deg = patch_min_angle(context.mesh, patch);
      } else {
        patch = fill_smooth(context, loop, steps[k], std::move(patch));
        check_patch_shape(context.mesh, patch, last ? kDegenerateAngle : fallback.min_angle_deg,
                          where);
        if (!last)
          check_outside_obstacles(patch, context.options.obstacles, context.mesh,
                                  loop.mean_edge_length, where);
      }
      take_reasons(patch.report);
      // The smooth fills and an unguarded fabric fill promise nothing.
      const bool guaranteed =
          steps[k] == FillMethod::Fabric && patch.report.start != StartKind::Unguarded;
      if (fallback.enabled && !guaranteed) {
        const int crossings = patch_crossings(context, around, patch);
        if (crossings > 0) {
          passed(patch.report.method,
                 "the patch has " + std::to_string(crossings) + " pairs of crossing faces");
          if (!crossing) crossing = std::move(patch);
          continue;
        }
      }
      patch.report.fallback_reasons = reasons;
      return patch;
    } catch (const NoCleanStart& e) {
      fabric_deferred = e.start;
      take_reasons(patch.report);
      passed(patch.report.method, e.what());
    } catch (const Error& e) {
      throw_if_cancelled(context, where);
      // Options that make no sense are the caller's to fix, not the hole's.
      if (!fallback.enabled || e.kind() == ErrorKind::Usage) throw;
      take_reasons(patch.report);
      passed(
          patch.report.method == FillMethod::FabricRepaired ? FillMethod::FabricRepaired : steps[k],
          e.what());
    }
  }
  // No patch crosses nothing. The one of the first step that gave one is
  // kept (its crossings are in the report): the fabric method without the
  // guarantee, where it came before the patches that cross.
  if (fabric_deferred && (!crossing || steps.front() == FillMethod::Fabric)) {
    try {
      HolePatch patch =
          fill_fabric(context, loop, around, HolePatch(blank), true, &*fabric_deferred);
      patch.report.fallback_reasons.clear();
      patch.report.patch_min_angle_deg = patch_min_angle(context.mesh, patch);
      crossing = std::move(patch);
    } catch (const Error& e) {
      throw_if_cancelled(context, where);
      passed(FillMethod::Fabric, e.what());
    }
  }
  if (crossing) {
    crossing->report.fallback_reasons = reasons;
    return std::move(*crossing);
  }
  // The first step's reason leads; the others follow.
  const std::string first = to_string(FillMethod::Fabric) + std::string(": ");
  std::string all =
      reasons.front().rfind(first, 0) == 0 ? reasons.front().substr(first.size()) : reasons.front();
  if (reasons.size() > 1) {
    all += " (the fallbacks failed too:";
    for (size_t k = 1; k < reasons.size(); ++k) all += (k > 1 ? "; " : " ") + reasons[k];
    all += ")";
  }
  throw FillFailedError(where + ": " + all);
}

// ---- Stitching -------------------------------------------------------------------

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

// ---- All holes ---------------------------------------------------------------------

// The holes (positions in `boxes`) grouped by overlapping reach, each group
// ascending, groups in order of their first hole.
std::vector<std::vector<int>> overlap_groups(const std::vector<Box3>& boxes) {
  const int n = static_cast<int>(boxes.size());
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  BoxTree(boxes).for_each_meeting_pair(0.0, [&](int a, int b) {
    const int ra = root(a), rb = root(b);
    parent[std::max(ra, rb)] = std::min(ra, rb);
  });
  std::vector<std::vector<int>> groups;
  std::vector<int> group_of(n, -1);
  for (int i = 0; i < n; ++i) {
    int& g = group_of[root(i)];
    if (g < 0) {
      g = static_cast<int>(groups.size());
      groups.emplace_back();
    }
    groups[g].push_back(i);
  }
  return groups;
}

HolePatch unfilled(const FillContext& context, const BoundaryLoop& loop,
                   const std::string& message) {
  // Stages that do not know the file and the loop get them here.
  const std::string where = hole_source(context.source, loop.id);
  HolePatch patch;
  patch.report.loop_id = loop.id;
  patch.report.loop_vertex_count = static_cast<int>(loop.vertices.size());
  patch.report.cancelled = context.cancelled.load(std::memory_order_relaxed);
  patch.report.reason = message.rfind(where + ": ", 0) == 0 ? message : where + ": " + message;
  return patch;
}

// Fills the holes, groups in parallel; a hole that fails or is cancelled
// comes back unfilled with its reason.
std::vector<HolePatch> fill_patches(const FillContext& context,
                                    const std::vector<BoundaryLoop>& loops,
                                    const std::vector<int>& fill_ids) {
  for (int id : fill_ids)
    if (id < 0 || id >= static_cast<int>(loops.size()))
      throw UsageError(context.source + ": no loop with id " + std::to_string(id) +
                       " (the mesh has " + std::to_string(loops.size()) + " loops)");
  const int count = static_cast<int>(fill_ids.size());
  std::vector<Box3> reach(count);
  for (int h = 0; h < count; ++h) reach[h] = reach_box(loops[fill_ids[h]]);
  const std::vector<std::vector<int>> nearby =
      faces_near_boxes(context.mesh.positions, context.mesh.faces, reach);
  const std::vector<std::vector<int>> groups = overlap_groups(reach);
  std::vector<HolePatch> patches(count);
  // One group: no parallel region, whose idle threads would only wait (and
  // spin, with libgomp's default wait policy) for it.
#pragma omp parallel for schedule(dynamic, 1) if (groups.size() > 1)
  for (int g = 0; g < static_cast<int>(groups.size()); ++g) {
    for (size_t k = 0; k < groups[g].size(); ++k) {
      const int h = groups[g][k];
      const BoundaryLoop& loop = loops[fill_ids[h]];
      Surroundings around{reach[h], &nearby[h], {}};
      for (size_t e = 0; e < k; ++e)
        if (patches[groups[g][e]].report.filled && overlap(reach[h], reach[groups[g][e]]))
          around.earlier.push_back(&patches[groups[g][e]]);
      try {
        patches[h] = fill_one_hole(context, loop, around);
      } catch (const std::exception& e) {
        patches[h] = unfilled(context, loop, e.what());
      }
    }
  }
  return patches;
}

}  // namespace

const char* to_string(FillMethod method) {
  switch (method) {
    case FillMethod::Fabric:
      return "fabric";
    case FillMethod::FabricRepaired:
      return "fabric-repaired";
    case FillMethod::Smooth:
      return "smooth";
    case FillMethod::Liepa:
      return "liepa";
    case FillMethod::Triangulation:
      return "triangulation";
  }
  return "fabric";
}

const char* to_string(FoldsFirstPass pass) {
  switch (pass) {
    case FoldsFirstPass::None:
      return "none";
    case FoldsFirstPass::Unguarded:
      return "unguarded";
    case FoldsFirstPass::Guarded:
      return "guarded";
  }
  return "none";
}

const char* to_string(StartKind start) {
  switch (start) {
    case StartKind::Arap:
      return "arap";
    case StartKind::CoarseLevels:
      return "coarse_levels";
    case StartKind::TowardsMembrane:
      return "towards_membrane";
    case StartKind::CoarseLevelsUntangled:
      return "coarse_levels_untangled";
    case StartKind::Untangled:
      return "untangled";
    case StartKind::Unguarded:
      return "unguarded";
  }
  return "arap";
}

FillResult fill_holes(const Mesh& mesh, const std::vector<BoundaryLoop>& loops,
                      const std::vector<int>& fill_ids, const FillOptions& options,
                      const std::string& source) {
  return fill_holes(Mesh(mesh), loops, fill_ids, options, source);
}

FillResult fill_holes(Mesh&& mesh, const std::vector<BoundaryLoop>& loops,
                      const std::vector<int>& fill_ids, const FillOptions& options,
                      const std::string& source) {
  check_options(options, source);
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
  mark_new_elements(mesh, loops, report);
  const auto crossings_start = Clock::now();
  measure_crossings(mesh, patch_faces, options.obstacles, source, report);
  report.seconds_crossings = seconds_since(crossings_start);
  report.seconds_total = seconds_since(start);
  return {std::move(mesh), std::move(report)};
}

}  // namespace foldfill
