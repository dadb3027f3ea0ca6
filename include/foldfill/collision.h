// The geometry of an intersection-free fill: distances between point-triangle
// (PT) and edge-edge (EE) pairs with their gradients, the log barrier of
// Incremental Potential Contact (Li et al. 2020) on them, a conservative time
// of impact along a linear step (Additive CCD, Li et al. 2021), the same for
// a triangle against an analytic obstacle (sphere, cylinder, plane), and the
// broad phase that finds the candidate pairs of a mesh whose free vertices
// move among fixed ones.
//
// Plain doubles throughout; positions and displacements of a whole mesh are
// flat arrays of 3 per vertex (x, y, z), like the rows of an Eigen row-major
// n x 3 matrix or the data of a std::vector<Vec3>. Nothing here has an
// absolute tolerance: thresholds are relative to the lengths of the inputs,
// so that scaling a problem scales every distance and leaves every time of
// impact as it is. Not in the paper (see contact.h). The functions throw
// nothing unless they say so.
#pragma once

#include <array>
#include <vector>

#include "foldfill/box_tree.h"
#include "foldfill/mesh.h"

namespace foldfill {

struct Obstacle;  // foldfill/obstacles.h

// ---------------------------------------------------------------------------
// Distances. Gradients by the envelope theorem: the gradient of d^2 with
// respect to a vertex is 2 (q_self - q_other) times that vertex's weight in
// the closest point q_self of its primitive, where (q_self, q_other) is the
// closest pair of points. They are the derivatives where the closest pair is
// unique (everywhere for a point and a proper triangle); elsewhere (parallel
// edges, a point equidistant from two edges) they are those of one of the
// closest pairs, a one-sided derivative.

// Squared distance from `p` to the triangle (a, b, c), exact for every region
// (the face, its three edges, its three corners) and for degenerate
// triangles (collinear or coincident corners: the distance to the segments).
// `gradient`, when non-null, receives d(d^2)/dp, /da, /db, /dc.
double point_triangle_distance_squared(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                       std::array<Vec3, 4>* gradient = nullptr);

// Squared distance between the segments [a0, a1] and [b0, b1], robust for
// parallel and zero-length segments. `gradient`, when non-null, receives
// d(d^2)/da0, /da1, /db0, /db1.
double edge_edge_distance_squared(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                                  std::array<Vec3, 4>* gradient = nullptr);

// Whether the point-triangle or the edge-edge pair is certainly at least
// sqrt(distance_sq) apart, by a bound a few times cheaper than the distance
// itself: their separation along the line between the point and the
// triangle's centroid, or between the segments' middles (each segment lies
// within half its projection of its middle there), and for a point across
// the triangle's plane. False where the bound is not enough (or not finite);
// a pair true here is farther than sqrt(distance_sq) by the distance
// functions above too, rounding included (the bound must pass it by a
// relative 1e-9).
bool point_triangle_farther(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                            double distance_sq);
bool edge_edge_farther(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                       double distance_sq);

// Squared distance between the segment [s0, s1] and the triangle (a, b, c):
// 0 where the segment pierces the triangle (crosses its plane strictly from
// one side to the other within it), otherwise the least of its two ends
// against the triangle (point_triangle_distance_squared) and of the segment
// against the triangle's three edges (edge_edge_distance_squared), where the
// closest pair of two disjoint convex sets like these must lie. Exact for a
// zero-length segment (a point) and for degenerate triangles (their
// segments, with no piercing test). The piercing test is in plain doubles: it
// can only be wrong where the segment passes within rounding of the
// triangle's boundary or plane, where the other candidates are within
// rounding of 0 too. `gradient`, when non-null, receives d(d^2)/ds0, /ds1,
// /da, /db, /dc: those of the least candidate (the first of equal ones), all
// zero where the segment pierces.
double segment_triangle_distance_squared(const Vec3& s0, const Vec3& s1, const Vec3& a,
                                         const Vec3& b, const Vec3& c,
                                         std::array<Vec3, 5>* gradient = nullptr);

// ---------------------------------------------------------------------------
// The barrier of IPC: b(d) = -(d - dhat)^2 ln(d / dhat) for 0 < d < dhat, 0
// for d >= dhat, +infinity for d <= 0. It is C2 at dhat and grows without
// bound as d -> 0. `derivative`, when non-null, receives db/dd (-infinity for
// d <= 0). dhat > 0.
double barrier(double d, double dhat, double* derivative = nullptr);
// The same barrier as a function of the squared distance: b(sqrt(d2)), and
// its derivative with respect to d2, db/dd / (2 d).
double barrier_of_squared(double d2, double dhat, double* derivative = nullptr);

// ---------------------------------------------------------------------------
// Continuous collision detection along a linear step: vertex x moves to
// x + t dx for t in [0, t_max].

struct CcdOptions {
  // s in (0, 1): the time of impact is taken where the distance would fall
  // below s times the distance at t = 0 (the first step goes (1 - s) of the
  // way).
  double gap = 0.1;
  // In (0, 1): steps after the first advance by this fraction of the
  // distance over the bound on the relative speed (0.9 in the paper).
  double rescaling = 0.9;
  double t_max = 1;  // >= 0
  // Iterations before giving up with the time reached so far (a valid,
  // conservative answer); a pair needs many only when it slides along at a
  // distance small against its relative motion.
  int max_iterations = 10000;
};

// Additive CCD (Li et al. 2021, "Codimensional Incremental Potential
// Contact", algorithm 1): a time of impact toi in [0, t_max] such that the
// pair's distance stays positive on [0, toi]: at least (1 - rescaling) * gap
// times its distance at t = 0 everywhere, and at least gap times that at toi
// itself when toi < t_max (up to rounding in the distance). t_max when its
// steps pass t_max before the distance falls below gap times its start (in
// particular when the pair does not move relative to itself); 0 when it
// starts in contact. The result is min(toi for an unbounded t_max, t_max):
// lowering t_max never changes a time below it, so that a minimum over many
// pairs may shrink t_max as it goes.
//
// The point p against the triangle (a, b, c), moving by dp, da, db, dc.
double point_triangle_ccd(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                          const Vec3& dp, const Vec3& da, const Vec3& db, const Vec3& dc,
                          const CcdOptions& options = {});
// The point p moving by dp against the fixed triangle (a, b, c).
double point_static_triangle_ccd(const Vec3& p, const Vec3& dp, const Vec3& a, const Vec3& b,
                                 const Vec3& c, const CcdOptions& options = {});
// The segment [a0, a1] against [b0, b1], moving by da0, da1, db0, db1.
double edge_edge_ccd(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                     const Vec3& da0, const Vec3& da1, const Vec3& db0, const Vec3& db1,
                     const CcdOptions& options = {});

// ---------------------------------------------------------------------------
// Obstacles: a triangle of the patch against an analytic obstacle (a sphere,
// a cylinder or a plane of foldfill/obstacles.h), in O(1) per face, with no
// tessellation of the obstacle.

// The least signed distance over the triangle (a, b, c) to the solid of a
// sphere, cylinder or plane obstacle: the gap when positive; when the
// triangle reaches into the solid, minus the depth of its deepest point
// (<= 0, continuous through 0).
// - Sphere of centre C and radius R: |q - C| - R, q the point of the
//   triangle nearest C (point_triangle_distance_squared); down to -R.
// - Cylinder: the CAPSULE around its axis segment (radius R, the segment of
//   length H centred at `center` along `axis`): the distance from the
//   triangle to the axis segment less R (segment_triangle_distance_squared);
//   down to -R where the triangle meets the axis segment. The capsule
//   contains the cylinder, so that a triangle at a positive value is outside
//   the cylinder. The value equals the least signed distance to the cylinder
//   beside its side and falls short of it by up to R beyond the flat caps
//   (and their rims): conservative there.
// - Plane: the least of the corners' signed distances (exact, the signed
//   distance being linear).
// `gradient`, when non-null, receives d(value)/da, /db, /dc (envelope
// theorem): the unit direction from the obstacle's nearest point to the
// triangle's, times each corner's weight in the latter; at ties those of
// one of the nearest pairs (the first corner for a plane), and zero where
// the triangle meets the sphere's centre or the axis segment (where the
// value has no direction). Throws UsageError for a mesh obstacle.
double triangle_obstacle_distance(const Obstacle& obstacle, const Vec3& a, const Vec3& b,
                                  const Vec3& c, std::array<Vec3, 3>* gradient = nullptr);
// For a cylinder: triangle_obstacle_distance, its capsule's value, which is
// at most the least signed distance over the triangle to the cylinder
// itself; `exact` receives whether the two are equal for sure: where the
// triangle is outside the capsule and the point of the axis segment nearest
// to it lies strictly inside the segment (the triangle's nearest point then
// lies beside the side). Throws UsageError for another obstacle.
double triangle_cylinder_distance(const Obstacle& cylinder, const Vec3& a, const Vec3& b,
                                  const Vec3& c, bool& exact);

// A conservative time of impact in [0, t_max] for the triangle (a, b, c)
// moving by (da, db, dc) against the fixed obstacle, for the value of
// triangle_obstacle_distance (so a cylinder as its capsule), with the
// semantics of point_triangle_ccd: the value stays positive on [0, toi], at
// least (1 - rescaling) * gap times its value d0 at t = 0, and is at least
// gap * d0 at toi when toi < t_max; t_max when it does not come that close
// (in particular when the triangle does not move); 0 when it starts at a
// value <= 0 (or not finite). min(toi for an unbounded t_max, t_max).
// Sphere and cylinder: Additive CCD steps, since the value changes by at
// most max(|da|, |db|, |dc|) dt (the signed distance of the solid is
// 1-Lipschitz and every point of the triangle moves by a convex combination
// of its corners' moves). Plane: the value is the least of three linear
// functions of t, so the time is exact: where it falls to gap * d0. Throws
// UsageError for a mesh obstacle.
double triangle_obstacle_ccd(const Obstacle& obstacle, const Vec3& a, const Vec3& b, const Vec3& c,
                             const Vec3& da, const Vec3& db, const Vec3& dc,
                             const CcdOptions& options = {});

// ---------------------------------------------------------------------------
// A mesh's collision primitives: its vertices (points), edges and faces.
// Vertices [0, fixed_count) never move; a primitive all of whose vertices
// are fixed is static, the others move. Pairs of two static primitives are
// never candidates: nothing can change between them.
struct CollisionMesh {
  std::vector<Tri> faces;
  std::vector<std::array<int, 2>> edges;  // (v0 < v1), sorted, each once
  int vertex_count = 0;
  int fixed_count = 0;
};

// The collision mesh of `faces` over `vertex_count` vertices with the edges
// of the faces. Throws InternalError for a vertex index out of range or
// fixed_count outside [0, vertex_count].
CollisionMesh make_collision_mesh(const std::vector<Tri>& faces, int vertex_count, int fixed_count);

// Candidate pairs, sorted, each once: (vertex, face) with the vertex not a
// corner of the face, and (edge, edge) with the first index below the
// second and no vertex in common.
struct CollisionCandidates {
  std::vector<IndexPair> point_triangle;
  std::vector<IndexPair> edge_edge;
  size_t size() const { return point_triangle.size() + edge_edge.size(); }
};

// Finds the candidate pairs of a CollisionMesh: the pairs (but static ones)
// whose bounding boxes are within a distance of each other along every axis.
// Box trees of the static points, edges and faces are built once, at
// construction, from the fixed vertices' positions then (those positions
// must not change); trees of the moving primitives are refitted at each
// search and rebuilt when refitting has made them much slower to search.
// Results do not depend on the thread count nor on the trees' state. One
// object must not search from two threads at once (it keeps scratch).
class CollisionBroadPhase {
 public:
  CollisionBroadPhase() = default;
  CollisionBroadPhase(const CollisionMesh& mesh, const double* positions);

  // Every candidate pair (see CollisionCandidates) of primitives whose boxes
  // at `positions` are within `distance` along every axis: a superset of the
  // pairs closer than `distance`. With `displacements` (may be null), each
  // moving primitive's box spans it at x and at x + dx (its swept box): then
  // a superset of the pairs that come closer than `distance` at some t in
  // [0, 1] of the step x + t dx. Fixed vertices' displacements are ignored.
  // `candidates` is overwritten; its vectors keep their capacity.
  void find(const double* positions, const double* displacements, double distance,
            CollisionCandidates& candidates);
  // The candidate pairs closer than `distance` at `positions`, exactly:
  // find(positions, nullptr, distance) then keep_candidates_within, in one
  // pass that keeps only the close pairs.
  void find_within(const double* positions, double distance, CollisionCandidates& candidates);
  // The candidate pairs closer than `distance` at `positions`, exactly, that
  // have a corner among the `moved` vertices (one flag per vertex; fixed
  // vertices' flags are ignored): what find_within finds, less the pairs
  // none of whose corners moved. `candidates` is overwritten.
  void find_within_touching(const double* positions, double distance,
                            const std::vector<char>& moved, CollisionCandidates& candidates);

  // Every pair of faces whose boxes at `positions` meet (touching counts),
  // one of them moving: (moving, static), and (moving, moving) with the
  // lower index first; sorted. A superset of the intersecting pairs with a
  // moving face. `pairs` is overwritten.
  void meeting_faces(const double* positions, std::vector<IndexPair>& pairs);
  // The static faces whose boxes meet `box` (touching counts), ascending.
  std::vector<int> static_faces_meeting(const Box& box) const;

  const CollisionMesh& mesh() const { return mesh_; }

 private:
  void moving_boxes(const double* positions, const double* displacements);
  void update_trees();
  void static_order(std::vector<int>& points, std::vector<int>& edges) const;
  template <typename KeepPointTriangle, typename KeepEdgeEdge>
  void search(const double* positions, const double* displacements, double distance,
              const KeepPointTriangle& keep_pt, const KeepEdgeEdge& keep_ee,
              CollisionCandidates& candidates);

  CollisionMesh mesh_;
  // Mesh indices of the static and moving edges and faces (vertices are
  // static below fixed_count).
  std::vector<int> static_edges_, moving_edges_, static_faces_, moving_faces_;
  BoxTree static_points_, static_edge_tree_, static_face_tree_;
  BoxTree moving_points_, moving_edge_tree_, moving_face_tree_;
  // Costs of the moving trees when last built (see BoxTree::cost), and
  // whether they have been.
  double built_cost_[3] = {0, 0, 0};
  bool moving_built_ = false;
  std::vector<Box> point_boxes_, edge_boxes_, face_boxes_;  // moving primitives
  std::vector<BoxTree::SearchPart> parts_[5];               // of the five searches (see find)
  std::vector<std::array<int, 2>> work_;                    // (search, part)
  std::vector<std::vector<IndexPair>> point_triangle_parts_, edge_edge_parts_;  // per thread
  std::vector<int> sort_scratch_;
  // find_within_touching's scratch: the moving points, edges and faces with
  // a moved corner (indices into the moving lists), which moving edges those
  // are, their boxes and trees.
  std::vector<int> touched_points_, touched_edges_, touched_faces_;
  std::vector<char> edge_touched_;
  std::vector<Box> touched_boxes_;
  BoxTree touched_tree_;
};

// The largest step fraction t in [0, t_max] such that no candidate pair comes
// into contact on [0, t] along positions + t displacements (both 3 per vertex
// of `mesh`): the minimum of the pairs' Additive CCD times of impact (see
// point_triangle_ccd). The candidates must cover the step: found with the
// displacements (swept boxes), or within a distance above the largest
// difference between two vertices' displacements, 0 included (a pair's
// distance falls at most by the largest difference of its corners' moves).
// Fixed vertices' displacements are ignored. t_max for no pair.
// In parallel; the result does not depend on the thread count.
double collision_step_bound(const CollisionMesh& mesh, const double* positions,
                            const double* displacements, const CollisionCandidates& candidates,
                            const CcdOptions& options = {});

// Sum over the candidate pairs of barrier(distance, dhat); adds `weight` times
// its gradient (3 per vertex) to `gradient` when non-null. In parallel over
// blocks of a fixed number of pairs, summed in the candidates' order block by
// block: the same bit for bit for the same candidates, whatever the thread
// count. A pair at distance 0 makes it +infinity (the gradient is then not
// meaningful).
double barrier_potential(const CollisionMesh& mesh, const double* positions,
                         const CollisionCandidates& candidates, double dhat, double weight = 1,
                         double* gradient = nullptr);

// Removes the candidate pairs at `distance` or more at `positions` (order
// kept). Boxes let through many pairs of neighbouring primitives that are
// far from each other (a vertex and the faces two rings away).
void keep_candidates_within(const CollisionMesh& mesh, const double* positions, double distance,
                            CollisionCandidates& candidates);

// Use in a minimisation that must stay intersection-free (from a start where
// every pair is at a positive distance), with a thickness dhat and a skin:
// - the barrier's pairs: find_within(x0, dhat + skin). While every vertex
//   stays within skin / 2 of x0, every pair closer than dhat is in the list
//   (a pair at dhat + skin or more at x0 stays at dhat or more), so
//   barrier_potential over it is the barrier over all pairs; search again
//   past that.
// - each step x + a dx: t = collision_step_bound over find(x, dx, 0) (swept
//   boxes), then a line search over a in (0, t] only. When x + t dx also
//   stays within skin / 2 of x0, the barrier's list covers the step as well
//   (its pairs are the only ones that can come closer than dhat) and can
//   replace the swept search.

}  // namespace foldfill
