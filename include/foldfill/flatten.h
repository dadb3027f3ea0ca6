// The strip around a hole and its flattening with least-squares conformal maps
// (Lévy et al. 2002), as in section 3.2 of Gisbert et al. 2023.
#pragma once

#include <string>
#include <vector>

#include "foldfill/holes.h"
#include "foldfill/mesh.h"
#include "foldfill/topology.h"

namespace foldfill {

// The faces incident to the hole's loop vertices, with local vertex indices.
// Local vertices [0, loop.size()) are the loop vertices in loop order; the
// rest are their one-ring neighbours.
struct Strip {
  std::vector<Vec3> positions;   // 3D positions, copied from the input
  std::vector<Tri> faces;        // local indices, input orientation
  std::vector<int> to_input;     // local vertex -> input vertex
  std::vector<int> input_faces;  // local face -> input face
  int loop_size = 0;             // local vertices [0, loop_size) are the loop, in order
};

// Collects the strip of `loop` (paper section 3.2: the faces whose angles at
// the loop give the flattened outline; METHOD.md 1). Precondition: `loop` is
// one of find_boundary_loops(mesh). Throws NotADiskError with a reason when the
// loop is not a disk boundary, or when the strip is not a connected planar
// surface with the loop as one boundary: an annulus, or a ring with islands
// where the loop comes back within an edge of itself (refused, for instance:
// it touches another boundary, a strip vertex's faces do not form one fan),
// since LSCM would then not give a meaningful hole outline.
// Throws BadFaceError for a face index out of range. This form scans every
// face of the mesh once.
Strip extract_strip(const Mesh& mesh, const BoundaryLoop& loop, const std::string& source = "mesh");
// The same strip in time proportional to the strip's size, from the mesh's
// `vertex_faces` (build_vertex_faces(mesh.faces, mesh.vertex_count())), built
// once and shared by the holes of a mesh; InternalError when it is not the
// mesh's.
Strip extract_strip(const Mesh& mesh, const VertexFaces& vertex_faces, const BoundaryLoop& loop,
                    const std::string& source = "mesh");

struct Flattening {
  std::vector<Vec2> uv;  // one per strip vertex; strip faces come out counter-clockwise
  // Fit of the flat hole outline against 3D:
  double edge_length_rms_rel = 0;  // RMS relative error of loop edge lengths
  double edge_length_max_rel = 0;  // max relative error of loop edge lengths
  double angle_sum_rms = 0;        // RMS error (radians) of strip angle sums at loop vertices
  double angle_sum_max = 0;        // max error (radians) of the same
  int flipped_triangles = 0;       // strip triangles with non-positive 2D area
  bool simple_polygon = true;      // the loop polygon does not cross itself
};

// Flattens the strip with LSCM (paper section 3.2; METHOD.md 1), pinning loop
// vertex 0 at (0,0) and loop vertex 1 at (L,0) with L their 3D distance, so
// that the scale is the true one. Precondition: `strip` from extract_strip.
// Throws FillFailedError when the result has flipped or degenerate triangles,
// or the hole polygon is not simple or runs clockwise (the loop is an outer
// edge: the surface lies inside it) or the LSCM system is singular;
// InternalError for an empty strip.
Flattening flatten_strip(const Strip& strip, const std::string& source = "mesh");

// The repair of a flattening that fails: the hole's outline is walked from
// the loop's 3D edge lengths and its exterior angles (the strip's angle sum
// at each loop vertex, minus pi), blended with a circle's, as little as makes
// it a simple counter-clockwise polygon that closes; the rest of the strip is
// then flattened by LSCM with the loop pinned there. Throws FillFailedError
// when no blend leaves the strip unflipped. Not in the paper: the first step
// of the fallback chain (FillMethod::FabricRepaired).
Flattening flatten_strip_repaired(const Strip& strip, const std::string& source = "mesh");

// The hole polygon of a flattening: uv of loop vertices in loop order.
// Throws InternalError when `flat` is not the strip's.
std::vector<Vec2> hole_polygon(const Strip& strip, const Flattening& flat);

}  // namespace foldfill
