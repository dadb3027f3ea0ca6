// Additive CCD (Li et al. 2021, algorithm 1) for point-triangle and
// edge-edge pairs, and the step bound over a list of candidate pairs.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "foldfill/collision.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

using Corners = std::array<Vec3, 4>;

// The pair is corners [0, split) against [split, 4) of `x`, moving by `dx`.
// The distance of the pair changes at most as fast as l_p, the largest
// relative motion of a point of one primitive plus that of the other (a
// point of a primitive moves by a convex combination of its corners'
// motions); the mean motion, common to both, is taken out first. A step of
// eta d / l_p therefore leaves at least (1 - eta) d: the time advances by
// such steps while the distance stays above gap * d0.
//
// The sequence of times does not depend on t_max, which only ends it: the
// result is min(unbounded result, t_max).
template <typename DistanceSquared>
double additive_ccd(const Corners& x, Corners dx, int split, const DistanceSquared& distance_sq,
                    const CcdOptions& options) {
  Vec3 mean{0, 0, 0};
  for (const Vec3& d : dx)
    for (int c = 0; c < 3; ++c) mean[c] += 0.25 * d[c];
  double reach[2] = {0, 0};
  for (int k = 0; k < 4; ++k) {
    for (int c = 0; c < 3; ++c) dx[k][c] -= mean[c];
    reach[k >= split] = std::max(reach[k >= split], norm(dx[k]));
  }
  const double speed = reach[0] + reach[1];
  if (speed == 0) return distance_sq(x) > 0 ? options.t_max : 0;
  // The gap between the two primitives' boxes, a lower bound on d0: when
  // even the first step from it passes t_max, so does the one from d0, and
  // the distance need not be computed (most pairs of a broad phase).
  double gap = 0;
  for (int c = 0; c < 3; ++c) {
    double low[2] = {HUGE_VAL, HUGE_VAL}, high[2] = {-HUGE_VAL, -HUGE_VAL};
    for (int k = 0; k < 4; ++k) {
      low[k >= split] = std::min(low[k >= split], x[k][c]);
      high[k >= split] = std::max(high[k >= split], x[k][c]);
    }
    gap = std::max({gap, low[1] - high[0], low[0] - high[1]});
  }
  if ((1 - options.gap) * gap / speed > options.t_max) return options.t_max;
  const double d0 = std::sqrt(distance_sq(x));
  if (!(d0 > 0) || !(speed < HUGE_VAL)) return 0;  // in contact, or not finite
  const double target = options.gap * d0;
  double t = 0, step = (1 - options.gap) * d0 / speed;
  Corners y;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    const double next = t + step;
    if (t == 0 && next > options.t_max) return options.t_max;  // no check after the first step
    for (int k = 0; k < 4; ++k)
      for (int c = 0; c < 3; ++c) y[k][c] = x[k][c] + next * dx[k][c];
    const double d = std::sqrt(distance_sq(y));
    // The first step leaves gap * d0 by construction (rounding aside).
    if (t > 0 && !(d >= target)) return t;
    t = next;
    if (t > options.t_max) return options.t_max;
    step = options.rescaling * d / speed;
  }
  return t;
}

double point_triangle_sq(const Corners& x) {
  return point_triangle_distance_squared(x[0], x[1], x[2], x[3]);
}
double edge_edge_sq(const Corners& x) { return edge_edge_distance_squared(x[0], x[1], x[2], x[3]); }

}  // namespace

double point_triangle_ccd(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                          const Vec3& dp, const Vec3& da, const Vec3& db, const Vec3& dc,
                          const CcdOptions& options) {
  return additive_ccd({p, a, b, c}, {dp, da, db, dc}, 1, point_triangle_sq, options);
}

double point_static_triangle_ccd(const Vec3& p, const Vec3& dp, const Vec3& a, const Vec3& b,
                                 const Vec3& c, const CcdOptions& options) {
  const Vec3 zero{0, 0, 0};
  return point_triangle_ccd(p, a, b, c, dp, zero, zero, zero, options);
}

double edge_edge_ccd(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                     const Vec3& da0, const Vec3& da1, const Vec3& db0, const Vec3& db1,
                     const CcdOptions& options) {
  return additive_ccd({a0, a1, b0, b1}, {da0, da1, db0, db1}, 2, edge_edge_sq, options);
}

// Each thread keeps its own minimum and passes it as t_max to its next pairs,
// which then stop early; since a pair's result is min(its time, t_max), the
// minimum over all pairs is the same whichever thread saw which pair first.
double collision_step_bound(const CollisionMesh& mesh, const double* positions,
                            const double* displacements, const CollisionCandidates& candidates,
                            const CcdOptions& options) {
  const auto at = [](const double* array, int v) {
    const double* p = array + 3 * static_cast<ptrdiff_t>(v);
    return Vec3{p[0], p[1], p[2]};
  };
  // Fixed vertices stay where they are, whatever `displacements` says.
  const int fixed = mesh.fixed_count;
  const auto move = [&](int v) { return v < fixed ? Vec3{0, 0, 0} : at(displacements, v); };
  const long pt_count = static_cast<long>(candidates.point_triangle.size());
  const long total = pt_count + static_cast<long>(candidates.edge_edge.size());
  double bound = options.t_max;
#pragma omp parallel if (total > 32768)
  {
    CcdOptions local = options;
#pragma omp for schedule(dynamic, 256) nowait
    for (long k = 0; k < total; ++k) {
      double toi;
      if (k < pt_count) {
        const IndexPair& pair = candidates.point_triangle[k];
        const Tri& f = mesh.faces[pair[1]];
        toi = point_triangle_ccd(at(positions, pair[0]), at(positions, f[0]), at(positions, f[1]),
                                 at(positions, f[2]), move(pair[0]), move(f[0]), move(f[1]),
                                 move(f[2]), local);
      } else {
        const IndexPair& pair = candidates.edge_edge[k - pt_count];
        const auto& e = mesh.edges[pair[0]];
        const auto& g = mesh.edges[pair[1]];
        toi = edge_edge_ccd(at(positions, e[0]), at(positions, e[1]), at(positions, g[0]),
                            at(positions, g[1]), move(e[0]), move(e[1]), move(g[0]), move(g[1]),
                            local);
      }
      local.t_max = std::min(local.t_max, toi);
    }
#pragma omp critical(foldfill_collision_step_bound)
    bound = std::min(bound, local.t_max);
  }
  return bound;
}

}  // namespace foldfill
