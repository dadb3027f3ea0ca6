// How far the surface around a hole is from developable: the measure that
// sends a hole to the fabric method (cloth: developable) or to a smooth fill
// (a dome, a curved statue).
#pragma once

#include "foldfill/holes.h"
#include "foldfill/mesh.h"
#include "foldfill/topology.h"

namespace foldfill {

struct Developability {
  // |sum K_i A_i| / sum H_i^2 A_i over the interior vertices of the strip's
  // outer ring (K the angle defect per area, H the mean curvature from the
  // dihedral angles, A a third of the faces' area): 1 on a sphere, 0 on a
  // developable surface however it folds; 0 where the surroundings are flat
  // or have no interior vertex.
  double ratio = 0;
  // The Gaussian curvature those vertices predict for the missing piece:
  // the mean K times the area of a disk of the loop's length (radians).
  double predicted_curvature = 0;
  int samples = 0;  // the vertices measured
};

// Measures the surroundings of `loop` from the faces around its neighbours.
// Not in the paper (which assumes developable cloth, section 3.1): it decides
// when that assumption fails. Precondition: `loop` is one of
// find_boundary_loops(mesh), `vertex_faces` the mesh's. Throws nothing.
Developability measure_developability(const Mesh& mesh, const VertexFaces& vertex_faces,
                                      const BoundaryLoop& loop);

}  // namespace foldfill
