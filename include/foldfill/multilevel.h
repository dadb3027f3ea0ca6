// A coarse-to-fine start for the minimisation of a large patch: the same hole
// meshed coarser, filled, and interpolated onto the fine patch, so that the
// fine minimisation starts near its minimum instead of from ARAP.
#pragma once

#include <vector>

#include "foldfill/arap.h"
#include "foldfill/domain.h"
#include "foldfill/flatten.h"
#include "foldfill/triangulate.h"

namespace foldfill {

// Defaults measured on folded sheets, the reference and the cloth cases
// (docs/benchmarks.md, "Coarse-to-fine start").
struct MultilevelOptions {
  // A patch with fewer interior vertices starts from ARAP; 0: every patch does.
  int min_patch_vertices = 1000;
  // Density of a level / density of the next coarser one (> 1; 2 gives about a
  // quarter of the vertices).
  double coarsening = 2;
  // A coarse level's patch keeps this many of the next finer level's mean
  // rest edge lengths from everything on top of the contact's thickness
  // (>= 0). The finer level's vertices are interpolated onto the coarse
  // surface, and its triangles then cut across the coarse triangles' bends,
  // by up to about their circumradius (0.58 edge for an equilateral one)
  // across the sharpest: with more clearance the interpolated start crosses
  // nothing where the coarse one bends near other cloth or an obstacle, and
  // the finer level need not start again from ARAP. The default, chosen by
  // measurement (docs/benchmarks.md, issue 17's fifth speed round), clears
  // the bends of the reference cases; half an edge also clears a sharp spike
  // but engages the barrier on coarse levels that otherwise come near
  // nothing, which then cost more and end higher.
  double interpolation_clearance = 0.2;
  // A coarse level's minimisation (after the folds-first pass, on the
  // coarsest) runs first kept out of the analytic obstacles only
  // (PatchContact::Scope::ObstaclesOnly), and its end is kept where it
  // crosses and touches nothing and keeps the level's thickness (with the
  // clearance above) from everything: what the guarded minimisation keeps
  // for the interpolation, and where it would have taken the same path.
  // Otherwise it runs again guarded, and so do the finer levels. Coarse
  // levels are a way to the patch's start, checked as every start is; the
  // patch's own minimisation stays guarded. Not tried after a guarded
  // folds-first pass (the level then comes near something). false: always
  // guarded.
  bool unguarded_first = true;
};

// The mean rest length of the edges of `domain`'s patch faces (normalised).
double mean_patch_edge_length(const EmbedDomain& domain);

// The coarser levels of the hole that `domain` meshes (the glue of `strip`,
// flattened as `flat`, and the patch that triangulate_hole(hole_polygon(strip,
// flat), triangulate) made), finest first: level k meshes the same flat
// polygon at density / coarsening^(k+1), and there is a level after each one
// (the domain first) of at least options.min_patch_vertices free vertices.
// None when min_patch_vertices is 0 or the domain has fewer free vertices. Every level shares the
// loop, the strip and the normalisation of the domain. The fill starts the
// coarsest level from ARAP, minimises it, interpolates it onto the next finer
// one (interpolate_patch), and so on up to the domain. Not in the paper.
// Precondition: `domain` is make_embed_domain(strip, flat, the patch above).
// Throws UsageError for a coarsening not above 1, and what
// triangulate_hole and make_embed_domain throw.
std::vector<EmbedDomain> coarser_levels(const Strip& strip, const Flattening& flat,
                                        const TriangulateOptions& triangulate,
                                        const EmbedDomain& domain,
                                        const MultilevelOptions& options);

// Positions of `fine`'s vertices from `coarse_positions` (all of `coarse`'s
// vertices), linear over each coarse patch triangle in the shared rest plane:
// each free fine vertex gets the barycentric combination of the coarse patch
// triangle that contains its rest position (where rounding leaves it outside
// all, the one it is least outside of). Fixed vertices keep their positions. Both domains
// must share the strip (the same fixed vertices, faces and normalisation);
// InternalError otherwise, or when `coarse_positions` is not one per vertex
// of `coarse`.
std::vector<Vec3> interpolate_patch(const EmbedDomain& coarse,
                                    const std::vector<Vec3>& coarse_positions,
                                    const EmbedDomain& fine);

}  // namespace foldfill
