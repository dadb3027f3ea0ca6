// What keeps a patch from crossing anything while it is minimised: a log
// barrier on the distances between the patch's primitives and everything
// around it (the patch itself, its strip, the rest of the mesh within reach,
// the obstacles as triangles) below a thickness, and a bound on each step so
// that no pair crosses during it (Incremental Potential Contact, Li et al.
// 2020; the step bound by Additive CCD, Li et al. 2021). A minimisation that
// starts with nothing crossing and keeps every step within the bound ends
// with nothing crossing. Not in the paper: it replaces the soft repulsion
// and the projection onto obstacles of section 3.4 (METHOD.md 2c) as the
// guarantee, the repulsion staying in the energy.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "foldfill/collision.h"
#include "foldfill/domain.h"
#include "foldfill/energy.h"
#include "foldfill/obstacles.h"
#include "foldfill/solver.h"

namespace foldfill {

struct ContactOptions {
  // The barrier acts between primitives closer than this (normalised: units
  // of the hole's length scale, the mean loop edge length).
  double thickness = 0.1;
  // Weight of the barrier relative to the isometric term.
  double stiffness = 1;
  // Candidate pairs, and the patch faces near each analytic obstacle, are
  // searched within thickness + skin and kept while they must still hold
  // every pair closer than the thickness (for the barrier) or that can touch
  // during a step (for the step bound): a pair comes closer by at most the
  // largest difference between its corners' displacements since the search,
  // so they last while those displacements (0, the fixed vertices', among
  // them) spread over less than the skin, or over less than thickness + skin
  // along the step. A step they do not cover searches them again at its end,
  // where the next step starts. Normalised. The default is a little over
  // twice the fast solver's longest move (SolverOptions::max_displacement,
  // 0.2): fresh candidates last for two such steps in a row, more where the
  // patch moves in one direction, and the fewer pairs the cheaper a search.
  double skin = 0.45;
  // A search of the candidates moves the anchor they hold around only for
  // the free vertices farther than moved_drift * skin from it, and searches
  // only the pairs with such a corner again, where those are at most
  // moved_share of the free vertices; all of them otherwise. The others keep
  // a displacement below moved_drift * skin, so that the candidates last a
  // little less long than fresh ones, for a search over a part of the patch.
  // moved_drift in [0, 0.5), moved_share in [0, 1] (0: every search is whole).
  double moved_drift = 0.25;
  double moved_share = 0.5;
  CcdOptions ccd;
};

// Fixed triangles a patch must not cross besides its own strip, in the
// domain's normalised coordinates: the faces of the mesh near the hole, other
// holes' patches, obstacles. Vertex indices below the domain's fixed_count
// are the domain's fixed vertices (the strip's: a face that shares one of
// them with the strip says so); index fixed_count + k is positions[k].
struct PatchScene {
  std::vector<Vec3> positions;
  std::vector<Tri> faces;
};

// The barrier and the step bound of one patch (domain + scene + analytic
// obstacles: spheres, cylinders and planes, each face of the patch against
// each, see triangle_obstacle_distance). Variables
// are the domain's free vertices (3 each, as FabricEnergy's). Evaluation
// reuses scratch buffers and a candidate list, so one object must not be used
// from two threads at once; results do not depend on the thread count.
class PatchContact {
 public:
  // What evaluate and step_bound keep the patch from: everything above, or
  // only the analytic obstacles (the patch may then cross itself, its strip
  // and the scene: a way to a start that is checked afterwards). Candidates
  // searched for the obstacles alone are searched again for everything.
  enum class Scope { Everything, ObstaclesOnly };

  // `obstacles`: spheres, cylinders and planes in the domain's normalised
  // coordinates (mesh obstacles belong in the scene, as triangles). Throws
  // UsageError unless thickness, stiffness and skin are positive and
  // moved_drift and moved_share in their ranges,
  // InternalError for a mesh obstacle or a scene face with a vertex out of
  // range. evaluate, step_bound, min_distance and positions throw
  // InternalError for an `x` of the wrong size.
  PatchContact(const EmbedDomain& domain, const PatchScene& scene, const ContactOptions& options,
               std::vector<Obstacle> obstacles = {});

  // stiffness * sum of the barrier over the pairs closer than the thickness;
  // +infinity where a pair touches. Adds stiffness * its gradient to
  // `gradient` (3 per free vertex) when non-null.
  double evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
                  Scope scope = Scope::Everything) const;
  // The largest t in [0, 1] such that no pair comes into contact on the step
  // x + s dx, s in [0, t] (conservative, see collision_step_bound).
  double step_bound(const Eigen::VectorXd& x, const Eigen::VectorXd& dx,
                    Scope scope = Scope::Everything) const;
  // The smallest distance between two primitives that may not touch (a free
  // one and any other that shares no vertex with it), or `limit` when none
  // is nearer (normalised).
  double min_distance(const Eigen::VectorXd& x, double limit) const;

  // The pairs of faces of mesh() whose boxes meet at `x` (touching counts),
  // one of them the patch's: a superset of the pairs that can intersect.
  // Sorted; the lower index first where both are the patch's.
  std::vector<IndexPair> patch_face_pairs(const Eigen::VectorXd& x) const;

  // The collision mesh's positions with the free vertices at `x`: its faces
  // (mesh().faces) are the domain's, in order, then the scene's.
  std::vector<Vec3> positions(const Eigen::VectorXd& x) const;

  // How many times the candidate pairs were searched (most of the
  // contact's cost), and how many of those searched only the pairs of the
  // vertices that moved far (ContactOptions::moved_share).
  int candidate_searches() const { return candidate_searches_; }
  int partial_candidate_searches() const { return partial_candidate_searches_; }

  const ContactOptions& options() const { return options_; }
  const CollisionMesh& mesh() const { return broad_phase_.mesh(); }
  // The patch's faces in mesh().faces: [first_patch_face(), end_patch_face()).
  int first_patch_face() const { return first_patch_face_; }
  int end_patch_face() const { return end_patch_face_; }

 private:
  // All collision-mesh positions with the free ones from x.
  const double* place(const Eigen::VectorXd& x) const;
  // The candidates at the current points: the pairs and the obstacles'
  // faces (Scope::Everything), or the obstacles' faces alone; partial where
  // few vertices moved far. With `step`, the step that ends at the current
  // points, whose start they must cover too.
  void refresh_candidates(Scope scope = Scope::Everything, const double* step = nullptr) const;
  // Fills active_ with the candidates that may come closer than `distance`
  // at the current points or, with `move` (3 per collision vertex; null:
  // none), anywhere along the step from them by `move`; false, with active_
  // untouched, where the candidates need not hold all such pairs.
  bool gather(double distance, const double* move) const;
  // gather for `scope`: false where the candidates were searched for the
  // obstacles alone and `scope` is everything; active_ left without pairs
  // for the obstacles alone.
  bool gather(Scope scope, double distance, const double* move) const;
  void select_candidates(double distance) const;
  bool refresh_moved_vertices(const double* step) const;
  void refresh_obstacle_candidates(double reach) const;
  // A candidate's distance at the anchor.
  double anchor_distance_pt(const IndexPair& pair) const;
  double anchor_distance_ee(const IndexPair& pair) const;

  // The barrier and the step bound of the patch's faces against the
  // analytic obstacles (added to `value` and to `gradient` when non-null).
  // The barrier takes the faces of obstacle_candidates_; the step bound too
  // when `candidates_cover` (gather held for the step), every face otherwise.
  double obstacle_barrier(double* gradient) const;
  double obstacle_step_bound(double t_max, bool candidates_cover) const;

  ContactOptions options_;
  std::vector<Obstacle> obstacles_;
  int fixed_count_ = 0;  // of the collision mesh: the domain's fixed vertices and the scene's
  int first_patch_face_ = 0, end_patch_face_ = 0;  // the patch's faces in the collision mesh
  mutable CollisionBroadPhase broad_phase_;
  mutable std::vector<double> points_, anchor_, displacement_, gradient_;
  // Candidates near the anchor, their distances there, and those a call uses.
  mutable CollisionCandidates candidates_, active_;
  mutable std::vector<double> point_triangle_distance_, edge_edge_distance_;
  // (patch face, obstacle) pairs nearer than thickness + skin at the anchor,
  // in order: the others stay farther than the thickness while gather holds.
  mutable std::vector<std::array<int, 2>> obstacle_candidates_;
  // The pairs of meeting boxes of a patch face whose corners are all fixed
  // (an ear of the loop) and another face that does not move: they never change.
  std::vector<IndexPair> fixed_patch_pairs_;
  // The partial refresh's scratch: which vertices moved, the pairs searched
  // again, the merged lists.
  mutable std::vector<char> moved_;
  mutable CollisionCandidates touched_;
  mutable std::vector<IndexPair> merged_pairs_;
  mutable std::vector<double> merged_distances_;
  mutable bool has_candidates_ = false;
  mutable Scope candidates_scope_ = Scope::Everything;  // of the last search
  mutable int candidate_searches_ = 0;
  mutable int partial_candidate_searches_ = 0;
};

// The fabric energy plus the contact's barrier, bounded by its steps: what
// the solver minimises for a patch that must not cross anything. Without a
// contact, the fabric energy alone.
class PatchObjective final : public Objective {
 public:
  PatchObjective(const FabricEnergy& energy, const PatchContact* contact,
                 PatchContact::Scope scope = PatchContact::Scope::Everything)
      : energy_(energy), contact_(contact), scope_(scope) {}

  Eigen::Index size() const override { return 3 * energy_.domain().free_count(); }
  double value(const Eigen::VectorXd& x, Eigen::VectorXd* gradient) const override;
  Eigen::SparseMatrix<double> preconditioner() const override { return energy_.preconditioner(); }
  double step_bound(const Eigen::VectorXd& x, const Eigen::VectorXd& dx) const override;

 private:
  const FabricEnergy& energy_;
  const PatchContact* contact_;
  PatchContact::Scope scope_;
};

}  // namespace foldfill
