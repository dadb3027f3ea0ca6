// Coarse-to-fine start (see multilevel.h). The levels are meshes of one flat
// hole polygon at different densities: they share the loop exactly (no point is
// ever put on it) and the strip, so a coarse level's minimised surface is a
// map of the same flat domain, which the fine vertices sample by their rest
// positions.
#include "foldfill/multilevel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "foldfill/box_tree.h"
#include "foldfill/error.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

// Barycentric coordinates of p in the triangle (a, b, c).
std::array<double, 3> barycentric(const Vec2& p, const Vec2& a, const Vec2& b, const Vec2& c) {
  const double twice_area = cross(a, b, c);
  const double wa = cross(p, b, c) / twice_area, wb = cross(a, p, c) / twice_area;
  return {wa, wb, 1 - wa - wb};
}

// Triangles of the plane in the shared box tree (as boxes at z = 0): a
// point's candidates are the triangles whose bounding boxes come within
// `reach` of it, about the spacing of the triangles, so that a point that
// rounding puts just outside the patch still finds its nearest triangles.
class TriangleLocator {
 public:
  TriangleLocator(const std::vector<Vec2>& points, const std::vector<Tri>& triangles)
      : points_(points), triangles_(triangles) {
    std::vector<Box3> boxes;
    boxes.reserve(triangles.size());
    Vec2 min = points[triangles.at(0)[0]], max = min;
    for (const Tri& t : triangles) {
      Box3 box{{points[t[0]][0], points[t[0]][1], 0}, {points[t[0]][0], points[t[0]][1], 0}};
      for (int v : t)
        for (int d = 0; d < 2; ++d) {
          box.low[d] = std::min(box.low[d], points[v][d]);
          box.high[d] = std::max(box.high[d], points[v][d]);
          min[d] = std::min(min[d], points[v][d]);
          max[d] = std::max(max[d], points[v][d]);
        }
      boxes.push_back(box);
    }
    reach_ =
        std::sqrt((max[0] - min[0]) * (max[1] - min[1]) / static_cast<double>(triangles.size()));
    if (!(reach_ > 0)) reach_ = std::max({max[0] - min[0], max[1] - min[1], 1.0});
    tree_.build(boxes);
  }

  // The triangle containing p (the first by index where several do), or
  // where p lies outside all (by rounding), the one it is least outside of;
  // with p's barycentric coordinates in it, clamped to the triangle. Throws
  // when no triangle is near p.
  std::pair<int, std::array<double, 3>> locate(const Vec2& p) const {
    candidates_.clear();
    tree_.for_each_meeting(Box3{{p[0], p[1], 0}, {p[0], p[1], 0}}, reach_,
                           [&](int t) { candidates_.push_back(t); });
    std::sort(candidates_.begin(), candidates_.end());
    int best = -1;
    std::array<double, 3> best_weights{};
    double best_inside = -INFINITY;  // the smallest barycentric coordinate
    for (int id : candidates_) {
      const Tri& t = triangles_[id];
      const std::array<double, 3> w = barycentric(p, points_[t[0]], points_[t[1]], points_[t[2]]);
      const double inside = std::min({w[0], w[1], w[2]});
      if (inside > best_inside) {
        best_inside = inside;
        best = id;
        best_weights = w;
      }
      if (inside >= 0) break;
    }
    if (best < 0) throw InternalError("interpolate_patch: a fine vertex lies outside the patch");
    double sum = 0;
    for (double& w : best_weights) sum += w = std::max(w, 0.0);
    for (double& w : best_weights) w /= sum;
    return {best, best_weights};
  }

 private:
  const std::vector<Vec2>& points_;
  const std::vector<Tri>& triangles_;
  double reach_ = 1;
  BoxTree tree_;
  mutable std::vector<int> candidates_;  // scratch of locate
};

void check_same_strip(const EmbedDomain& coarse, const std::vector<Vec3>& coarse_positions,
                      const EmbedDomain& fine) {
  if (coarse.fixed_count != fine.fixed_count || coarse.loop_size != fine.loop_size ||
      coarse.strip_face_count != fine.strip_face_count || coarse.length_scale != fine.length_scale)
    throw InternalError("interpolate_patch: the domains do not share their strip");
  if (coarse_positions.size() != coarse.rest_uv.size())
    throw InternalError("interpolate_patch: " + std::to_string(coarse_positions.size()) +
                        " positions for " + std::to_string(coarse.rest_uv.size()) + " vertices");
}

}  // namespace

std::vector<Vec3> interpolate_patch(const EmbedDomain& coarse,
                                    const std::vector<Vec3>& coarse_positions,
                                    const EmbedDomain& fine) {
  check_same_strip(coarse, coarse_positions, fine);
  std::vector<Vec3> positions = fine.fixed_positions;
  if (fine.free_count() == 0) return positions;
  const std::vector<Tri> coarse_patch(coarse.faces.begin() + coarse.strip_face_count,
                                      coarse.faces.end());
  const TriangleLocator grid(coarse.rest_uv, coarse_patch);
  positions.reserve(fine.rest_uv.size());
  for (int v = fine.fixed_count; v < fine.vertex_count(); ++v) {
    const auto [triangle, weights] = grid.locate(fine.rest_uv[v]);
    Vec3 p{0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d)
        p[d] += weights[k] * coarse_positions[coarse_patch[triangle][k]][d];
    positions.push_back(p);
  }
  return positions;
}

double mean_patch_edge_length(const EmbedDomain& domain) {
  double sum = 0;
  long count = 0;
  for (size_t f = static_cast<size_t>(domain.strip_face_count); f < domain.faces.size(); ++f) {
    const Tri& t = domain.faces[f];
    for (int k = 0; k < 3; ++k) {
      sum += distance(domain.rest_uv[t[k]], domain.rest_uv[t[(k + 1) % 3]]);
      ++count;
    }
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

std::vector<EmbedDomain> coarser_levels(const Strip& strip, const Flattening& flat,
                                        const TriangulateOptions& triangulate,
                                        const EmbedDomain& domain,
                                        const MultilevelOptions& options) {
  std::vector<EmbedDomain> levels;
  if (options.min_patch_vertices <= 0 || domain.free_count() < options.min_patch_vertices)
    return levels;
  if (!(options.coarsening > 1))
    throw UsageError("multilevel coarsening must be above 1, not " +
                     std::to_string(options.coarsening));
  if (!(options.interpolation_clearance >= 0) || !std::isfinite(options.interpolation_clearance))
    throw UsageError("multilevel interpolation clearance must be finite and at least 0, not " +
                     std::to_string(options.interpolation_clearance));
  TriangulateOptions coarser = triangulate;
  int finer_free_count = domain.free_count();
  while (finer_free_count >= options.min_patch_vertices) {
    coarser.density /= options.coarsening;
    EmbedDomain level =
        make_embed_domain(strip, flat, triangulate_hole(hole_polygon(strip, flat), coarser));
    // Along a loop of long edges a coarser density can leave the patch as it
    // is; coarsening would then never end.
    if (level.free_count() >= finer_free_count) break;
    finer_free_count = level.free_count();
    levels.push_back(std::move(level));
  }
  return levels;
}

}  // namespace foldfill
