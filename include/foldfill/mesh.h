// Plain triangle-mesh data shared by every stage of foldfill.
#pragma once

#include <array>
#include <cmath>
#include <vector>

namespace foldfill {

using Vec2 = std::array<double, 2>;
using Vec3 = std::array<double, 3>;
using Tri = std::array<int, 3>;

inline bool is_finite(const Vec3& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// An axis-aligned box, corners low and high.
struct Box3 {
  Vec3 low{}, high{};
};

// Whether two closed boxes share a point.
inline bool overlap(const Box3& a, const Box3& b) {
  for (int c = 0; c < 3; ++c)
    if (a.high[c] < b.low[c] || b.high[c] < a.low[c]) return false;
  return true;
}

// A triangle mesh as flat arrays. Faces index `positions` (0-based) and are
// oriented counter-clockwise seen from their front side.
//
// The optional OBJ attributes are carried through so that writing an OBJ keeps
// the texture coordinates and normals of the original faces. When a mesh has
// them, `face_texcoords` / `face_normals` have one entry per face (-1 marks a
// corner without one); faces appended by foldfill get {-1, -1, -1}.
struct Mesh {
  std::vector<Vec3> positions;
  std::vector<Tri> faces;

  std::vector<Vec2> texcoords;      // OBJ `vt` (u, v), in file order
  std::vector<Vec3> normals;        // OBJ `vn`, in file order
  std::vector<Tri> face_texcoords;  // empty, or one per face
  std::vector<Tri> face_normals;    // empty, or one per face

  int vertex_count() const { return static_cast<int>(positions.size()); }
  int face_count() const { return static_cast<int>(faces.size()); }
};

}  // namespace foldfill
