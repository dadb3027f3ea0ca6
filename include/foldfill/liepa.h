// The smooth baseline: CGAL's triangulate_refine_and_fair_hole (Liepa 2003,
// minimal-area triangulation, refinement, then fairing). Offered as
// `foldfill fill --method liepa` and used by the benchmarks for comparison.
#pragma once

#include <string>
#include <vector>

#include "foldfill/holes.h"
#include "foldfill/inpaint.h"

namespace foldfill {

// Fills the loops `fill_ids` of `loops` the smooth way. Reports per hole the
// counts, the total time, whether the fairing succeeded (a hole whose
// fairing fails keeps its refined triangulation), the loop's mean edge length
// as length scale, and the crossings of the output (measure_crossings;
// `obstacles` are measured against, not avoided). Not the paper's method.
// Preconditions: `loops` is find_boundary_loops(mesh), `fill_ids` are ids of
// it. Throws NonManifoldError for a mesh CGAL cannot build a surface mesh
// from.
FillResult fill_holes_liepa(const Mesh& mesh, const std::vector<BoundaryLoop>& loops,
                            const std::vector<int>& fill_ids, const std::string& source = "mesh",
                            const std::vector<Obstacle>& obstacles = {});

}  // namespace foldfill
