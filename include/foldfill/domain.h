// The problem of placing one flat patch into 3D: the flattened strip and the
// flat patch glued along the hole loop, with the strip held at its 3D position.
#pragma once

#include <vector>

#include "foldfill/flatten.h"
#include "foldfill/mesh.h"
#include "foldfill/triangulate.h"

namespace foldfill {

// Vertices [0, fixed_count) are the strip's (the loop first, in loop order,
// then the one-ring), fixed at `fixed_positions`; vertices [fixed_count, n) are
// the patch's interior vertices, the unknowns. Faces [0, strip_face_count) are
// the strip's, the rest the patch's. All faces are counter-clockwise in
// `rest_uv`, the common flat rest state.
//
// Lengths are normalised: 3D positions are (p - origin) / length_scale, with
// length_scale the mean edge length of the hole loop, so that every option
// means the same on a mesh in millimetres and one in metres.
struct EmbedDomain {
  std::vector<Vec2> rest_uv;  // flat rest state, normalised
  std::vector<Tri> faces;
  std::vector<Vec3> fixed_positions;  // normalised 3D positions of the strip vertices
  int fixed_count = 0;
  int loop_size = 0;
  int strip_face_count = 0;
  Vec3 origin{};
  double length_scale = 1;

  int vertex_count() const { return static_cast<int>(rest_uv.size()); }
  int free_count() const { return vertex_count() - fixed_count; }
};

// A point in mesh units in the domain's normalised coordinates,
// (p - origin) / length_scale, and a normalised point back in mesh units.
inline Vec3 normalised(const Vec3& p, const EmbedDomain& domain) {
  const double inverse = 1 / domain.length_scale;
  return {(p[0] - domain.origin[0]) * inverse, (p[1] - domain.origin[1]) * inverse,
          (p[2] - domain.origin[2]) * inverse};
}
inline Vec3 in_mesh_units(const Vec3& x, const EmbedDomain& domain) {
  return {domain.origin[0] + domain.length_scale * x[0],
          domain.origin[1] + domain.length_scale * x[1],
          domain.origin[2] + domain.length_scale * x[2]};
}

// Glues `patch` (whose boundary vertices are the loop, in loop order) to the
// flattened strip and normalises: the input of the 3D embedding (paper
// section 3.3). Preconditions: `flat` is flatten_strip(strip) (or the
// repaired one) and `patch` triangulates hole_polygon(strip, flat). Throws
// FillFailedError when the loop has zero length, InternalError when the
// parts do not match.
EmbedDomain make_embed_domain(const Strip& strip, const Flattening& flat, const FlatPatch& patch);

}  // namespace foldfill
