// What a patch's contact sees around it (patch_scene.h).
#include "pipeline/patch_scene.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "foldfill/collision.h"
#include "foldfill/error.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

// Whether every point of `points` is farther than `gap` from the obstacle.
bool farther_than(const Obstacle& obstacle, const std::vector<Vec3>& points, double gap) {
  return std::all_of(points.begin(), points.end(),
                     [&](const Vec3& p) { return farther_than(obstacle, p, gap); });
}

// Moves each vertex of `mesh` by `inset` against its normal (the mean of its
// faces' unit normals, weighted by their angles there).
void inset_along_normals(Mesh& mesh, double inset) {
  std::vector<Vec3> normals(mesh.positions.size(), Vec3{0, 0, 0});
  for (const Tri& f : mesh.faces) {
    const Vec3& a = mesh.positions[f[0]];
    const Vec3& b = mesh.positions[f[1]];
    const Vec3& c = mesh.positions[f[2]];
    const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    Vec3 n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    const double length = std::hypot(n[0], n[1], n[2]);
    if (!(length > 0)) continue;
    for (double& x : n) x /= length;
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = mesh.positions[f[k]];
      const Vec3& q = mesh.positions[f[(k + 1) % 3]];
      const Vec3& r = mesh.positions[f[(k + 2) % 3]];
      const Vec3 e1{q[0] - p[0], q[1] - p[1], q[2] - p[2]},
          e2{r[0] - p[0], r[1] - p[1], r[2] - p[2]};
      const double cosine = (e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2]) /
                            (std::hypot(e1[0], e1[1], e1[2]) * std::hypot(e2[0], e2[1], e2[2]));
      const double angle = std::acos(std::clamp(cosine, -1.0, 1.0));
      for (int c2 = 0; c2 < 3; ++c2) normals[f[k]][c2] += angle * n[c2];
    }
  }
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const double length = std::hypot(normals[v][0], normals[v][1], normals[v][2]);
    if (!(length > 0)) continue;
    for (int c = 0; c < 3; ++c) mesh.positions[v][c] -= inset * normals[v][c] / length;
  }
}

// `o` (a sphere, cylinder or plane) with its surface moved in by `inset`.
Obstacle shrunk(Obstacle o, double inset) {
  if (o.type == Obstacle::Type::Plane) {
    for (int c = 0; c < 3; ++c) o.center[c] -= inset * o.normal[c];
  } else {
    o.radius -= inset;
    if (o.type == Obstacle::Type::Cylinder) o.height = std::max(0.0, o.height - 2 * inset);
  }
  return o;
}

}  // namespace

Box3 reach_box(const BoundaryLoop& loop) {
  Box3 box{loop.positions.at(0), loop.positions.at(0)};
  for (const Vec3& p : loop.positions)
    for (int c = 0; c < 3; ++c) {
      box.low[c] = std::min(box.low[c], p[c]);
      box.high[c] = std::max(box.high[c], p[c]);
    }
  const double grow = 1.5 * loop.length / (2 * M_PI) + 2 * loop.mean_edge_length;
  for (int c = 0; c < 3; ++c) {
    box.low[c] -= grow;
    box.high[c] += grow;
  }
  return box;
}

void add_scene_obstacles(const std::string& where, const EmbedDomain& domain,
                         const std::vector<Obstacle>& obstacles_in_mesh_units,
                         const Box3& reach_box, PatchScene& scene, SceneObstacles& obstacles) {
  const Box3 reach{normalised(reach_box.low, domain), normalised(reach_box.high, domain)};
  // The hole's width (normalised: its loop's length, loop_size edges of
  // length_scale, over pi), and at least a few edges: deeper inside an
  // obstacle than this, the strip is not resting on it.
  const double deepest = std::max(domain.loop_size / M_PI, kMostEdgesInside);
  for (const Obstacle& obstacle : obstacles_in_mesh_units) {
    // "obstacle K", with its file for a mesh, as the messages name it.
    const std::string name =
        "obstacle " + std::to_string(obstacles.normalised.size() + 1) +
        (obstacle.type == Obstacle::Type::Mesh ? " (" + obstacle.mesh->source() + ")" : "");
    // How far the obstacle reaches from the hole, in hole lengths: beyond
    // kFarthestObstacle the geometry's constructions overflow.
    double farthest = norm(sub(obstacle.center, domain.origin)) + obstacle.radius + obstacle.height;
    if (obstacle.type == Obstacle::Type::Mesh) {
      farthest = 0;
      for (const Vec3& p : obstacle.mesh->mesh().positions)
        farthest = std::max(farthest, norm(sub(p, domain.origin)));
    }
    if (!(farthest / domain.length_scale < kFarthestObstacle)) {
      throw UsageError(where + ": " + name +
                       " reaches farther than 1e80 hole lengths from the hole: is it in the "
                       "input's units and place?");
    }
    const Obstacle o = normalized(obstacle, domain.origin, domain.length_scale);
    obstacles.normalised.push_back(o);
    // How deep the strip reaches into the obstacle: its vertices, and for a
    // sphere, cylinder or plane its faces (a patch face holds a loop edge,
    // whose middle a curved obstacle's surface may pass above).
    double depth = 0;
    for (const Vec3& p : domain.fixed_positions) depth = std::max(depth, -signed_distance(o, p));
    if (o.type != Obstacle::Type::Mesh) {
      for (int f = 0; f < domain.strip_face_count; ++f) {
        const Tri& t = domain.faces[f];
        depth = std::max(depth, -triangle_obstacle_distance(o, domain.fixed_positions[t[0]],
                                                            domain.fixed_positions[t[1]],
                                                            domain.fixed_positions[t[2]]));
      }
    }
    if (depth > deepest) {
      throw UsageError(where + ": the hole's surroundings lie " +
                       std::to_string(depth * domain.length_scale) + " deep inside " + name +
                       ", more than the hole is wide: is the obstacle placed, scaled and "
                       "oriented as the input?");
    }
    Mesh triangles;
    if (o.type == Obstacle::Type::Mesh) {
      triangles = o.mesh->mesh();
      // Where the strip rests on the obstacle or a little inside, its
      // triangles are moved in, each vertex along its normal, by that depth
      // and a hair, so that the strip lies outside them.
      if (depth > 0 || !farther_than(o, domain.fixed_positions, kMeshClearance)) {
        const double inset = depth + kMeshClearance;
        inset_along_normals(triangles, inset);
        obstacles.allowance = std::max(obstacles.allowance, inset);
      }
    } else {
      const double inset = depth + kMeshClearance;
      obstacles.allowance = std::max(obstacles.allowance, inset);
      if (o.type == Obstacle::Type::Plane || o.radius > inset)
        obstacles.analytic.push_back(shrunk(o, inset));
      continue;
    }
    std::vector<int> index(triangles.positions.size(), -1);
    for (const Tri& f : triangles.faces) {
      Box3 box{triangles.positions[f[0]], triangles.positions[f[0]]};
      for (int v : f)
        for (int c = 0; c < 3; ++c) {
          box.low[c] = std::min(box.low[c], triangles.positions[v][c]);
          box.high[c] = std::max(box.high[c], triangles.positions[v][c]);
        }
      if (!overlap(box, reach)) continue;
      Tri face;
      for (int k = 0; k < 3; ++k) {
        int& i = index[f[k]];
        if (i < 0) {
          i = domain.fixed_count + static_cast<int>(scene.positions.size());
          scene.positions.push_back(triangles.positions[f[k]]);
        }
        face[k] = i;
      }
      scene.faces.push_back(face);
    }
  }
}

PatchState measure_patch(const FabricEnergy& energy, const std::vector<Vec3>& positions) {
  const EmbedDomain& domain = energy.domain();
  PatchState state;
  state.energy = energy.evaluate(energy.variables(positions));
  std::vector<int> free(domain.free_count());
  std::iota(free.begin(), free.end(), domain.fixed_count);
  state.curvature = gaussian_curvature_stats(positions, domain.faces, free);
  std::vector<std::array<int, 2>> edges;
  std::vector<double> rest;
  for (const FabricEnergy::Spring& s : energy.springs()) {
    edges.push_back({s.i, s.j});
    rest.push_back(s.rest_length);
  }
  state.edge_length_rms_rel = rms_relative_edge_error(positions, edges, rest);
  return state;
}

}  // namespace foldfill
