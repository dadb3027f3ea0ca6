// Dragging a filled patch by one vertex (edit.h): the fill's energy plus a
// spring from the handle to its target, minimised by the fill's solver under
// the fill's contact, so that no step crosses anything.
#include "foldfill/edit.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>

#include "embed/triangle_geometry.h"
#include "foldfill/error.h"
#include "foldfill/flatten.h"
#include "foldfill/metrics.h"
#include "foldfill/triangulate.h"
#include "pipeline/patch_scene.h"

namespace foldfill {
namespace {

// The fabric energy and the barrier, plus stiffness / 2 |x_h - target|^2 on
// the handle's free vertex h; steps bounded by the contact.
class DragObjective final : public Objective {
 public:
  DragObjective(const FabricEnergy& energy, const PatchContact& contact, int handle,
                const Vec3& target, double stiffness)
      : energy_(energy),
        contact_(contact),
        handle_(handle),
        target_(target),
        stiffness_(stiffness) {}

  Eigen::Index size() const override { return 3 * energy_.domain().free_count(); }

  double value(const Eigen::VectorXd& x, Eigen::VectorXd* gradient) const override {
    const double fabric = energy_.evaluate(x, gradient).total;
    const double barrier = contact_.evaluate(x, gradient);
    if (!std::isfinite(barrier)) return std::numeric_limits<double>::infinity();
    double spring = 0;
    for (int c = 0; c < 3; ++c) {
      const double d = x[3 * handle_ + c] - target_[c];
      spring += 0.5 * stiffness_ * d * d;
      if (gradient) (*gradient)[3 * handle_ + c] += stiffness_ * d;
    }
    return fabric + barrier + spring;
  }

  // The energy's, with the spring on the handle's diagonal.
  Eigen::SparseMatrix<double> preconditioner() const override {
    Eigen::SparseMatrix<double> p = energy_.preconditioner();
    p.coeffRef(handle_, handle_) += stiffness_;
    return p;
  }

  double step_bound(const Eigen::VectorXd& x, const Eigen::VectorXd& dx) const override {
    return contact_.step_bound(x, dx);
  }

 private:
  const FabricEnergy& energy_;
  const PatchContact& contact_;
  int handle_;
  Vec3 target_;
  double stiffness_;
};

// `warning` without the clause about crossings that measure_crossings adds
// ("...; the fill crosses ..." or "WHERE: the fill crosses ...").
std::string without_crossing_warning(const std::string& warning, const std::string& where) {
  const size_t at = warning.find("the fill crosses ");
  if (at == std::string::npos) return warning;
  std::string kept = warning.substr(0, at);
  if (kept == where) return "";
  if (kept.size() >= 2 && kept.compare(kept.size() - 2, 2, "; ") == 0) kept.resize(kept.size() - 2);
  return kept;
}

}  // namespace

struct PatchEditor::Parts {
  EmbedDomain domain;
  std::unique_ptr<FabricEnergy> energy;
  std::unique_ptr<PatchContact> contact;
  Box3 reach;                       // normalised
  std::vector<Obstacle> obstacles;  // mesh units, for the crossings
  std::string source;
  EditOptions edit;
  SolverOptions solver;
  double flat_area = 0;
};

PatchEditor::PatchEditor(const Mesh& input, const FillResult& output, int hole,
                         const BoundaryLoop& loop, const FillOptions& options,
                         const std::string& source, const EditOptions& edit)
    : parts_(std::make_unique<Parts>()), hole_(hole) {
  if (hole < 0 || hole >= static_cast<int>(output.report.holes.size()))
    throw UsageError(source + ": no hole " + std::to_string(hole) + " in the fill");
  const HoleReport& report = output.report.holes[hole];
  const std::string where = source + ": loop " + std::to_string(report.loop_id);
  if (!report.filled) throw UsageError(where + ": not filled, nothing to edit");
  if (report.method != FillMethod::Fabric && report.method != FillMethod::FabricRepaired)
    throw UsageError(where + ": filled by the " + std::string(to_string(report.method)) +
                     " method; only fabric patches can be edited");
  vertices_ = report.new_vertices;
  faces_ = report.new_faces;
  Parts& parts = *parts_;
  parts.source = source;
  parts.edit = edit;
  parts.obstacles = options.obstacles;
  parts.flat_area = report.flat_area;

  // The plan of fill_holes again: the same strip, flattening and flat patch.
  const Strip strip = extract_strip(input, loop, source);
  const Flattening flat = report.method == FillMethod::FabricRepaired
                              ? flatten_strip_repaired(strip, where)
                              : flatten_strip(strip, where);
  const FlatPatch patch = triangulate_hole(hole_polygon(strip, flat), options.triangulate);
  const int interior = static_cast<int>(patch.uv.size()) - patch.boundary_count;
  bool same = interior == vertices_.size() && static_cast<int>(patch.faces.size()) == faces_.size();
  for (size_t f = 0; same && f < patch.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = patch.faces[f][k];
      const int expected =
          v < patch.boundary_count ? loop.vertices[v] : vertices_.first + v - patch.boundary_count;
      if (output.mesh.faces[faces_.first + f][k] != expected) same = false;
    }
  if (!same)
    throw UsageError(where +
                     ": planning the hole again does not give the patch of the fill "
                     "(other options?); it cannot be edited");
  parts.domain = make_embed_domain(strip, flat, patch);
  const EmbedDomain& domain = parts.domain;

  // The weights the patch was minimised with.
  EnergyOptions energy_options = options.energy;
  energy_options.lambda = report.lambda;
  energy_options.repulsion = report.repulsion;
  parts.energy = std::make_unique<FabricEnergy>(domain, energy_options);

  // The scene: every face of the output near the hole but the strip's and
  // the patch's (other holes' patches included), and the obstacles.
  const Box3 reach = reach_box(loop);
  parts.reach = {normalised(reach.low, parts.domain), normalised(reach.high, parts.domain)};
  PatchScene scene;
  std::unordered_map<int, int> index;  // output vertex -> domain / scene index
  for (int k = 0; k < domain.fixed_count; ++k) index[strip.to_input[k]] = k;
  const std::vector<int> near =
      faces_near_boxes(output.mesh.positions, output.mesh.faces, {reach})[0];
  for (int f : near) {
    if (f >= faces_.first && f < faces_.end) continue;
    if (std::binary_search(strip.input_faces.begin(), strip.input_faces.end(), f)) continue;
    Tri face;
    for (int k = 0; k < 3; ++k) {
      const int v = output.mesh.faces[f][k];
      const auto [it, added] =
          index.emplace(v, domain.fixed_count + static_cast<int>(scene.positions.size()));
      if (added) scene.positions.push_back(normalised(output.mesh.positions[v], parts.domain));
      face[k] = it->second;
    }
    scene.faces.push_back(face);
  }
  SceneObstacles obstacles;
  add_scene_obstacles(where, domain, options.obstacles, reach, scene, obstacles);
  parts.contact =
      std::make_unique<PatchContact>(domain, scene, options.contact, obstacles.analytic);

  parts.solver = options.solver;
  parts.solver.kind = SolverKind::Fast;
  parts.solver.progress = nullptr;

  set_positions({output.mesh.positions.begin() + vertices_.first,
                 output.mesh.positions.begin() + vertices_.end});
  if (!std::isfinite(parts.contact->evaluate(x_, nullptr)))
    throw UsageError(where + ": the patch touches its surroundings; it cannot be edited");
}

PatchEditor::~PatchEditor() = default;

void PatchEditor::grab(int vertex) {
  if (vertex < vertices_.first || vertex >= vertices_.end)
    throw UsageError(parts_->source + ": vertex " + std::to_string(vertex) +
                     " is not a new vertex of this patch (those are " +
                     std::to_string(vertices_.first) + " to " + std::to_string(vertices_.end - 1) +
                     ")");
  handle_ = vertex - vertices_.first;
  target_.reset();
  if (factor_handle_ != handle_) factor_.reset();
}

DragResult PatchEditor::drag(const Vec3& target) {
  if (handle_ < 0) throw UsageError(parts_->source + ": no vertex grabbed");
  const Parts& parts = *parts_;
  Vec3 goal = normalised(target, parts.domain);
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(goal[c]))
      throw UsageError(parts.source + ": the target is not a finite point");
    goal[c] = std::clamp(goal[c], parts.reach.low[c], parts.reach.high[c]);
  }
  target_ = goal;
  return minimise(goal, parts.edit.max_iterations, parts.edit.time_limit_seconds);
}

DragResult PatchEditor::settle() {
  if (handle_ < 0 || !target_) return {};
  return minimise(*target_, parts_->edit.settle_iterations, parts_->edit.settle_seconds);
}

DragResult PatchEditor::minimise(const Vec3& goal, int iterations, double seconds) {
  const auto start = std::chrono::steady_clock::now();
  const Parts& parts = *parts_;
  const DragObjective objective(*parts.energy, *parts.contact, handle_, goal,
                                parts.edit.handle_stiffness);
  // The preconditioner does not depend on the target: factored once per handle.
  if (!factor_) {
    factor_ = std::make_unique<FactoredPreconditioner>(objective);
    factor_handle_ = handle_;
  }
  SolverOptions solver = parts.solver;
  solver.max_iterations = iterations;
  solver.time_limit_seconds = seconds;
  const SolverResult solved = minimize(objective, x_, solver, Budget(), factor_.get());
  DragResult result;
  // A start the objective refuses (Diverged after 0 iterations) leaves the state.
  if (solved.x.allFinite()) x_ = solved.x;
  result.iterations = solved.iterations;
  result.stop_reason = solved.stop_reason;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

std::vector<Vec3> PatchEditor::positions() const {
  const std::vector<Vec3> all = parts_->energy->positions(x_);
  std::vector<Vec3> out;
  out.reserve(vertices_.size());
  for (int v = parts_->domain.fixed_count; v < parts_->domain.vertex_count(); ++v)
    out.push_back(in_mesh_units(all[v], parts_->domain));
  return out;
}

void PatchEditor::write(Mesh& output) const {
  const std::vector<Vec3> patch = positions();
  std::copy(patch.begin(), patch.end(), output.positions.begin() + vertices_.first);
}

void PatchEditor::set_positions(const std::vector<Vec3>& positions) {
  if (static_cast<int>(positions.size()) != vertices_.size())
    throw InternalError("PatchEditor::set_positions: wrong vertex count");
  std::vector<Vec3> all = parts_->domain.fixed_positions;
  for (const Vec3& p : positions) all.push_back(normalised(p, parts_->domain));
  x_ = parts_->energy->variables(all);
}

void PatchEditor::measure(const Mesh& output, HoleReport& report) const {
  const Parts& parts = *parts_;
  const FabricEnergy& energy = *parts.energy;
  const std::vector<Vec3> positions = energy.positions(x_);
  const PatchState state = measure_patch(energy, positions);
  report.energy_final = state.energy;
  report.gaussian_mean_abs_final = state.curvature.mean_abs;
  report.gaussian_variance_final = state.curvature.variance;
  report.edge_length_rms_rel_final = state.edge_length_rms_rel;
  const std::vector<Tri> faces(output.faces.begin() + faces_.first,
                               output.faces.begin() + faces_.end);
  report.patch_area = total_area(output.positions, faces);
  if (parts.flat_area > 0) report.area_ratio_to_flat = report.patch_area / parts.flat_area;
  double smallest = 180;
  for (const Tri& f : faces)
    smallest = std::min(
        smallest, geometry::smallest_angle_deg(
                      {output.positions[f[0]], output.positions[f[1]], output.positions[f[2]]}));
  report.patch_min_angle_deg = smallest;

  FillReport one;
  one.holes.push_back(report);
  one.holes[0].warning = without_crossing_warning(
      report.warning, parts.source + ": loop " + std::to_string(report.loop_id) + ": ");
  std::vector<int> patch_faces(faces_.size());
  std::iota(patch_faces.begin(), patch_faces.end(), faces_.first);
  measure_crossings(output, {patch_faces}, parts.obstacles, parts.source, one);
  report.crossings = one.holes[0].crossings;
  report.self_intersections = one.holes[0].self_intersections;
  report.min_distance = one.holes[0].min_distance;
  report.warning = one.holes[0].warning;
}

}  // namespace foldfill
