// What a patch's contact sees around it, shared by the fill (inpaint.cpp) and
// the editor (edit.cpp): the region a patch cannot leave and the obstacles in
// the domain's normalised units. Private to the pipeline layer.
#pragma once

#include <string>
#include <vector>

#include "foldfill/contact.h"
#include "foldfill/domain.h"
#include "foldfill/energy.h"
#include "foldfill/holes.h"
#include "foldfill/mesh.h"
#include "foldfill/metrics.h"
#include "foldfill/obstacles.h"

namespace foldfill {

// How far (in units of the length scale) an obstacle is moved in beyond the
// depth the strip reaches into it (a mesh obstacle: where the strip lies on
// it), so that the strip is outside.
constexpr double kMeshClearance = 0.01;
// The strip may lie inside an obstacle by the hole's width or this many edges,
// whichever is more (scan noise, a garment pressed into a body).
constexpr double kMostEdgesInside = 4;
// An obstacle that reaches farther from a hole than this many hole lengths is
// refused: the squares and products of its normalised coordinates would
// overflow in the geometry's constructions.
constexpr double kFarthestObstacle = 1e80;

// A box, in the mesh's units, that a hole's patch cannot leave: the loop's
// box grown by one and a half times the radius of a disk of the loop's
// length (no point of a flat patch is farther from its boundary, and the
// patch stretches little), plus two edges for the strip. Everything the
// patch might cross lies in it.
Box3 reach_box(const BoundaryLoop& loop);

// The normalised obstacles of a hole, with what the contact sees of them.
struct SceneObstacles {
  std::vector<Obstacle> normalised;  // all of them
  // The spheres, cylinders and planes shrunk by the depth the strip reaches
  // into them (and a hair), which the contact keeps every patch face out of.
  std::vector<Obstacle> analytic;
  double allowance = 0;  // how deep the patch may reach into an obstacle
};

// The obstacles of a hole over `domain`: each normalised into
// obstacles.normalised; the spheres, cylinders and planes, moved in as deep as
// the strip already reaches into them (the cloth may rest on or a hair inside
// an obstacle) and a hair more, into obstacles.analytic; a mesh obstacle's
// faces within `reach_box` (mesh units), moved in likewise where the strip
// rests on it, appended to `scene`. Throws UsageError naming `where` when the
// strip lies deeper inside an obstacle than the hole is wide (and more than
// a few edges): such an obstacle is not where the cloth is (misplaced,
// scaled or turned inside out), and no fill could keep out of it.
void add_scene_obstacles(const std::string& where, const EmbedDomain& domain,
                         const std::vector<Obstacle>& obstacles_in_mesh_units,
                         const Box3& reach_box, PatchScene& scene, SceneObstacles& obstacles);

// The quality figures of one state of a patch (normalised positions), as the
// fill reports them and the editor measures them again.
struct PatchState {
  EnergyTerms energy;
  CurvatureStats curvature;
  double edge_length_rms_rel = 0;
};
PatchState measure_patch(const FabricEnergy& energy, const std::vector<Vec3>& positions);

}  // namespace foldfill
