// A coarse-to-fine start for the minimisation of a large patch: the same hole
// meshed coarser, filled, and interpolated onto the fine patch, so that the
// fine minimisation starts near its minimum instead of from ARAP.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "foldfill/arap.h"
#include "foldfill/domain.h"
#include "foldfill/flatten.h"
#include "foldfill/triangulate.h"

namespace foldfill {

// The defaults are measured (folded sheets of 0.7k to 75k patch vertices, the
// reference and cloth cases; one thread; docs/benchmarks.md): from 3k patch
// vertices on, the coarse start always paid, 2.4x less time at 7k, 4.5x at
// 22k, 4x at 75k, with final energies equal or lower (by at most 1.3%). From
// 1k, with a coarse level that cannot be filled cleanly left out (see
// LevelMinimiser): Contour's 1.6k patch took under a third of the instructions
// and stayed clean at the prototype's repulsion, dev05's 1.8k 27% fewer, dev06's
// 1.05k ended 16% lower, a 2.1k sheet took 1.3x less time; the Curtain's 2.2k
// patch, whose coarse level tangles, 32% more then (now such a level is given
// up within a few iterations: minimise_coarse_level in inpaint.cpp). A
// coarsening of 3 or 4 did no better than 2.
struct MultilevelOptions {
  bool enabled = true;
  // A patch with fewer interior vertices starts from ARAP.
  int min_patch_vertices = 1000;
  // Density of a level / density of the next coarser one (> 1; 2 gives about a
  // quarter of the vertices).
  double coarsening = 2;
};

// Minimises the energy over a coarse level `domain` from `start`; returns all
// its positions, or nothing when the level is no start for the finer one
// (it still intersects itself: then the finer level starts from ARAP).
using LevelMinimiser = std::function<std::optional<std::vector<Vec3>>(
    const EmbedDomain& domain, const std::vector<Vec3>& start)>;

// The start of the minimisation over `domain`, the glue of `strip` (flattened
// as `flat`) and the patch that triangulate_hole(hole_polygon(strip, flat),
// triangulate) made. All domain positions (normalised, fixed vertices at
// theirs). A patch with fewer than options.min_patch_vertices interior
// vertices (or every patch, when !options.enabled) starts from
// arap_embed(domain, arap). A larger one starts from the same hole meshed at
// density / coarsening, started the same way (so recursively), minimised with
// `minimise` and interpolated (interpolate_patch), unless `minimise` gives
// nothing or the interpolated start intersects itself: then from ARAP too.
// Every level shares the loop, the strip and the normalisation of the fine one.
// Every ARAP start stops when `budget` is spent (`minimise` is expected to
// honour it as well).
std::vector<Vec3> multilevel_start(const Strip& strip, const Flattening& flat,
                                   const TriangulateOptions& triangulate, const EmbedDomain& domain,
                                   const ArapOptions& arap, const MultilevelOptions& options,
                                   const LevelMinimiser& minimise, const Budget& budget = {});

// Positions of `fine`'s vertices from `coarse_positions` (all of `coarse`'s
// vertices), linear over each coarse patch triangle in the shared rest plane:
// each free fine vertex gets the barycentric combination of the coarse patch
// triangle that contains its rest position (where rounding leaves it outside
// all, the one it is least outside of). Fixed vertices keep their positions. Both domains
// must share the strip (the same fixed vertices, faces and normalisation).
std::vector<Vec3> interpolate_patch(const EmbedDomain& coarse,
                                    const std::vector<Vec3>& coarse_positions,
                                    const EmbedDomain& fine);

}  // namespace foldfill
