// The crossings of the filled holes, measured on the output: each patch
// against itself, against the rest of the mesh and against the obstacles.
#include <algorithm>
#include <string>
#include <vector>

#include "foldfill/inpaint.h"
#include "foldfill/metrics.h"

namespace foldfill {
namespace {

// "itself, the rest of the mesh and an obstacle (patch_patch 1, ...)": the
// parts whose counts are not 0.
std::string crossing_warning(const Crossings& c) {
  std::vector<std::string> what, counts;
  const auto add = [&](int count, const char* name, const char* key) {
    if (count == 0) return;
    what.push_back(name);
    counts.push_back(std::string(key) + " " + std::to_string(count));
  };
  add(c.patch_patch, "itself", "patch_patch");
  add(c.patch_mesh, "the rest of the mesh", "patch_mesh");
  add(c.patch_obstacles, c.patch_obstacles == 1 ? "an obstacle" : "obstacles", "patch_obstacles");
  std::string text = "the fill crosses ";
  for (size_t k = 0; k < what.size(); ++k)
    text += (k == 0 ? "" : k + 1 == what.size() ? " and " : ", ") + what[k];
  text += " (";
  for (size_t k = 0; k < counts.size(); ++k) text += (k == 0 ? "" : ", ") + counts[k];
  return text + ")";
}

// Whether the triangle reaches into the obstacle deeper than `tolerance`. A
// mesh obstacle with no tolerance: by the exact test; with one (the cloth
// around the hole rests on it or a little inside), deeper than it at the
// triangle's corners, edge midpoints or centroid.
bool crosses_deeper(const Obstacle& obstacle, const std::array<Vec3, 3>& triangle,
                    double tolerance) {
  if (obstacle.type != Obstacle::Type::Mesh || !(tolerance > 0))
    return crosses(obstacle, triangle, tolerance);
  const auto mix = [&](double a, double b, double c) {
    Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = a * triangle[0][k] + b * triangle[1][k] + c * triangle[2][k];
    return p;
  };
  for (const Vec3& p : {triangle[0], triangle[1], triangle[2], mix(0.5, 0.5, 0), mix(0, 0.5, 0.5),
                        mix(0.5, 0, 0.5), mix(1.0 / 3, 1.0 / 3, 1.0 / 3)})
    if (signed_distance(obstacle, p) < -tolerance) return true;
  return false;
}

// The new faces that cross into an obstacle, and the least distance from them
// to the obstacles when below `limit`.
void measure_obstacles(const Mesh& mesh, const std::vector<int>& patch,
                       const std::vector<Obstacle>& obstacles, double tolerance, int& crossing,
                       double& limit) {
  crossing = 0;
  for (int f : patch) {
    const Tri& t = mesh.faces[f];
    const std::array<Vec3, 3> triangle{mesh.positions[t[0]], mesh.positions[t[1]],
                                       mesh.positions[t[2]]};
    bool crossed = false;
    for (const Obstacle& obstacle : obstacles) {
      if (!crossed && crosses_deeper(obstacle, triangle, tolerance)) {
        crossed = true;
        limit = 0;
      }
      if (limit > 0) limit = std::min(limit, distance(obstacle, triangle, limit));
    }
    crossing += crossed;
  }
}

}  // namespace

void measure_crossings(const Mesh& mesh, const std::vector<std::vector<int>>& patch_faces,
                       const std::vector<Obstacle>& obstacles, const std::string& source,
                       FillReport& report) {
  std::vector<int> measured;  // the holes with a patch
  std::vector<Box3> boxes;
  for (int h = 0; h < static_cast<int>(report.holes.size()); ++h) {
    const HoleReport& hole = report.holes[h];
    if (!hole.filled || h >= static_cast<int>(patch_faces.size()) || patch_faces[h].empty())
      continue;
    measured.push_back(h);
    boxes.push_back(bounding_box(mesh.positions, mesh.faces, patch_faces[h],
                                 kCrossingReach * hole.length_scale));
  }
  const std::vector<std::vector<int>> nearby = faces_near_boxes(mesh.positions, mesh.faces, boxes);
#pragma omp parallel for schedule(dynamic, 1) if (measured.size() > 1)
  for (int k = 0; k < static_cast<int>(measured.size()); ++k) {
    HoleReport& hole = report.holes[measured[k]];
    const std::vector<int>& patch = patch_faces[measured[k]];
    const double h = hole.length_scale;
    const SubsetCrossings pairs =
        count_subset_crossings(mesh.positions, mesh.faces, patch, kCrossingReach * h, &nearby[k]);
    double nearest = pairs.min_distance;
    int crossing = 0;
    measure_obstacles(mesh, patch, obstacles,
                      std::max(kObstacleTolerance, hole.obstacle_allowance) * h, crossing, nearest);
    hole.crossings = {pairs.within, pairs.with_others, crossing};
    hole.self_intersections = hole.crossings.total();
    hole.min_distance = h > 0 ? nearest / h : 0;
    if (hole.crossings.total() == 0) continue;
    const std::string where = source + ": loop " + std::to_string(hole.loop_id) + ": ";
    hole.warning =
        (hole.warning.empty() ? where : hole.warning + "; ") + crossing_warning(hole.crossings);
  }
}

}  // namespace foldfill
