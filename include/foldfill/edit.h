// Editing a filled patch by hand: one of its vertices (the handle) is pulled
// towards a target and the patch re-minimises the fill's own fabric energy
// around it, kept from crossing anything by the fill's contact (barrier and
// step bound, contact.h). The strip and the rest of the mesh never move.
// `foldfill serve`'s edit tool drags a patch this way.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "foldfill/contact.h"
#include "foldfill/domain.h"
#include "foldfill/energy.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/mesh.h"
#include "foldfill/solver.h"

namespace foldfill {

struct EditOptions {
  // Weight of the spring that pulls the handle to its target, relative to
  // the isometric term (normalised units, as the energy's weights): the
  // handle reaches a target the cloth can reach without stretching much, and
  // lags behind one it would have to stretch for (the cloth resists, as
  // cloth held at one point does); the step bound holds it off whatever it
  // would cross.
  double handle_stiffness = 3;
  // Per drag(): the solver's iterations and time (0: none), warm-started
  // from the state the previous drag left. Iterations bound it best: a time
  // limit that passes inside an iteration's line search loses that
  // iteration's work. One iteration moves no vertex more than
  // SolverOptions::max_displacement (0.2 loop edges); 10 to 20 ms per
  // iteration on a patch of 2,000 vertices (docs/benchmarks.md, "Editing").
  int max_iterations = 2;
  double time_limit_seconds = 0;
  // settle(): at most these iterations (or seconds) with the handle held
  // where the last drag took it, so that the cloth around it relaxes.
  int settle_iterations = 200;
  double settle_seconds = 1;
};

// What one drag() did.
struct DragResult {
  int iterations = 0;
  StopReason stop_reason = StopReason::Converged;
  double seconds = 0;
};

// The editor of one filled hole. Built once (the precompute: the hole's
// domain planned again as the fill planned it, its energy with the weights
// the patch was minimised with, the contact against the output around the
// hole and the obstacles), then grab() a vertex and drag() it as often as
// wanted; the solver's preconditioner (with the handle's spring) is factored
// on the first drag of a handle and reused by the next.
class PatchEditor {
 public:
  // `input` is the mesh that was filled and `output` the fill's result for
  // it (fill_holes or fill), `hole` an index into output.report.holes,
  // `loop` that hole's loop and `options` those of the fill. Throws
  // Error(Usage) where the hole was not filled by the fabric method (a smooth
  // patch has no rest shape to keep), where planning it again does not give
  // the patch of the output, or where the patch touches its surroundings.
  PatchEditor(const Mesh& input, const FillResult& output, int hole, const BoundaryLoop& loop,
              const FillOptions& options, const std::string& source = "mesh",
              const EditOptions& edit = {});
  ~PatchEditor();
  PatchEditor(const PatchEditor&) = delete;
  PatchEditor& operator=(const PatchEditor&) = delete;

  int hole() const { return hole_; }
  // The patch's new vertices in the output.
  IndexRange vertices() const { return vertices_; }

  // Takes output vertex `vertex`, a new vertex of the patch, as the handle.
  // Throws Error(Usage) for any other vertex.
  void grab(int vertex);
  // Pulls the handle towards `target` (mesh units; clamped to the box the
  // patch cannot leave, reach_box) and minimises from the current state
  // within the options' iterations and time. Throws Error(Usage) without a
  // handle.
  DragResult drag(const Vec3& target);
  // Minimises further with the handle held at the last drag's target (the
  // options' settle_iterations and settle_seconds): what a release keeps.
  // Nothing without a drag since the grab. Deterministic where the
  // iterations end it before the time limit.
  DragResult settle();
  // Lets the handle go (its factored preconditioner is kept for a grab of it again).
  void release() { handle_ = -1; }
  int handle() const { return handle_ < 0 ? -1 : vertices_.first + handle_; }

  // The patch's new vertices (mesh units), in output order.
  std::vector<Vec3> positions() const;
  // Writes them into `output` (the fill's output mesh).
  void write(Mesh& output) const;
  // Sets the patch's state from new-vertex positions in mesh units (an undo).
  void set_positions(const std::vector<Vec3>& positions);

  // Measures the patch as it is in `output` (written there) into `report`,
  // the hole's entry: the final energy, curvature, edge length error, areas,
  // smallest angle and, with exact predicates, the crossings and min_distance
  // (measure_crossings; a warning about crossings it gave before is
  // replaced).
  void measure(const Mesh& output, HoleReport& report) const;

 private:
  struct Parts;
  std::unique_ptr<Parts> parts_;
  int hole_ = 0;
  IndexRange vertices_, faces_;
  int handle_ = -1;                                 // free index, -1: none
  std::unique_ptr<FactoredPreconditioner> factor_;  // of the objective of handle factor_handle_
  int factor_handle_ = -1;
  std::optional<Vec3> target_;  // of the last drag, normalised and clamped
  DragResult minimise(const Vec3& goal, int iterations, double seconds);
  Eigen::VectorXd x_;
};

}  // namespace foldfill
