// The smooth fills of the fallback chain, with CGAL on the hole's
// neighbourhood only: Liepa's (2003) minimal-area triangulation of the loop,
// refined to the boundary's edge lengths, then faired so that the patch meets
// its surroundings with continuous tangents or curvature.
#pragma once

#include <string>
#include <vector>

#include "foldfill/holes.h"
#include "foldfill/mesh.h"
#include "foldfill/topology.h"

namespace foldfill {

// How far the smooth fill goes.
enum class SmoothFairing {
  Curvature,      // refined, faired with continuous curvature (CGAL continuity 2)
  Tangent,        // refined, faired with continuous tangents (continuity 1: CGAL's default)
  Triangulation,  // the minimal-area triangulation of the loop alone (no new vertex)
};

// A patch in the hole's own numbering: vertex k < loop size is loop vertex k,
// vertex loop size + j is new_positions[j]. Faces are oriented like the
// mesh's.
struct SmoothPatch {
  std::vector<Vec3> new_positions;
  std::vector<Tri> faces;
  bool faired = false;  // false: the fairing's solver failed and the refined patch is kept
};

// Fills `loop` of `mesh` from the faces within `rings` rings of the loop
// (fairing of continuity k needs the k-ring; `rings` below the fairing's
// need is raised to it). Throws FillFailedError when CGAL finds no
// triangulation, and NotADiskError when the neighbourhood is not a
// manifold surface with the loop as a border. Not in the paper: a step of
// the fallback chain (FillMethod::Smooth, Liepa, Triangulation).
// Precondition: `loop` is one of find_boundary_loops(mesh) and
// `vertex_faces` the mesh's (build_vertex_faces).
SmoothPatch fill_hole_smooth(const Mesh& mesh, const VertexFaces& vertex_faces,
                             const BoundaryLoop& loop, SmoothFairing fairing,
                             const std::string& source = "mesh", int rings = 3);

}  // namespace foldfill
