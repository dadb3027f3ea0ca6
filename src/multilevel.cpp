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

// Triangles of the plane bucketed by a uniform grid of about one triangle per
// cell: a point's candidates are the triangles whose (slightly grown) bounding
// box covers its cell.
class TriangleGrid {
 public:
  TriangleGrid(const std::vector<Vec2>& points, const std::vector<Tri>& triangles)
      : points_(points), triangles_(triangles) {
    min_ = max_ = points[triangles.at(0)[0]];
    for (const Tri& t : triangles)
      for (int v : t)
        for (int d = 0; d < 2; ++d) {
          min_[d] = std::min(min_[d], points[v][d]);
          max_[d] = std::max(max_[d], points[v][d]);
        }
    const double width = max_[0] - min_[0], height = max_[1] - min_[1];
    cell_ = std::sqrt(width * height / static_cast<double>(triangles.size()));
    if (!(cell_ > 0)) cell_ = std::max({width, height, 1.0});
    columns_ = static_cast<int>(width / cell_) + 1;
    rows_ = static_cast<int>(height / cell_) + 1;
    // A point that rounding puts just outside its triangle still finds it.
    const double margin = 1e-9 * cell_;

    std::vector<std::array<int, 4>> boxes;  // first column, last column, first row, last row
    boxes.reserve(triangles.size());
    offsets_.assign(static_cast<size_t>(columns_) * rows_ + 1, 0);
    for (const Tri& t : triangles) {
      Vec2 low = points[t[0]], high = points[t[0]];
      for (int v : t)
        for (int d = 0; d < 2; ++d) {
          low[d] = std::min(low[d], points[v][d]);
          high[d] = std::max(high[d], points[v][d]);
        }
      boxes.push_back({column(low[0] - margin), column(high[0] + margin), row(low[1] - margin),
                       row(high[1] + margin)});
      const std::array<int, 4>& box = boxes.back();
      for (int y = box[2]; y <= box[3]; ++y)
        for (int x = box[0]; x <= box[1]; ++x) ++offsets_[y * columns_ + x + 1];
    }
    for (size_t c = 1; c < offsets_.size(); ++c) offsets_[c] += offsets_[c - 1];
    triangle_ids_.resize(offsets_.back());
    std::vector<int> next(offsets_.begin(), offsets_.end() - 1);
    for (size_t t = 0; t < boxes.size(); ++t) {
      const std::array<int, 4>& box = boxes[t];
      for (int y = box[2]; y <= box[3]; ++y)
        for (int x = box[0]; x <= box[1]; ++x)
          triangle_ids_[next[y * columns_ + x]++] = static_cast<int>(t);
    }
  }

  // The triangle containing p, or where p lies outside all (by rounding), the
  // one it is least outside of; with p's barycentric coordinates in it,
  // clamped to the triangle. Throws when no triangle is near p.
  std::pair<int, std::array<double, 3>> locate(const Vec2& p) const {
    const int c = row(p[1]) * columns_ + column(p[0]);
    int best = -1;
    std::array<double, 3> best_weights{};
    double best_inside = -INFINITY;  // the smallest barycentric coordinate
    for (int k = offsets_[c]; k < offsets_[c + 1]; ++k) {
      const Tri& t = triangles_[triangle_ids_[k]];
      const std::array<double, 3> w = barycentric(p, points_[t[0]], points_[t[1]], points_[t[2]]);
      const double inside = std::min({w[0], w[1], w[2]});
      if (inside > best_inside) {
        best_inside = inside;
        best = triangle_ids_[k];
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
  int column(double x) const {
    return std::clamp(static_cast<int>(std::floor((x - min_[0]) / cell_)), 0, columns_ - 1);
  }
  int row(double y) const {
    return std::clamp(static_cast<int>(std::floor((y - min_[1]) / cell_)), 0, rows_ - 1);
  }

  const std::vector<Vec2>& points_;
  const std::vector<Tri>& triangles_;
  Vec2 min_{}, max_{};
  double cell_ = 1;
  int columns_ = 1, rows_ = 1;
  std::vector<int> offsets_, triangle_ids_;  // triangles of cell c: [offsets_[c], offsets_[c + 1])
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
  const TriangleGrid grid(coarse.rest_uv, coarse_patch);
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
