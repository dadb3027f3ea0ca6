// Plain triangle-mesh data shared by every stage of foldfill.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
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

// The scalar types of PLY properties. Every value of each of them is exactly
// a double.
enum class ScalarType : uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

// A per-vertex or per-face scalar of the input that is not geometry (a PLY
// property: colour, normal, quality, label), carried to a PLY output in its
// own type.
struct ScalarProperty {
  std::string name;
  ScalarType type = ScalarType::Float64;
  std::vector<double> values;  // one per vertex or per face
};

// An OBJ statement that is not geometry and that sets the state of the faces
// after it (`mtllib`, `o`, `g`, `usemtl`, `s`), written back where it was.
struct ObjStatement {
  int before_face = 0;  // the first face after it (the face count when none follows)
  std::string text;     // the line as read, from its keyword, without trailing blanks
};

// A triangle mesh as flat arrays. Faces index `positions` (0-based) and are
// oriented counter-clockwise seen from their front side.
//
// Everything after the faces is optional and empty unless a reader or a fill
// set it, so that a plain mesh stays cheap to copy. Each per-element array is
// either empty or has one entry per vertex (per face); a fill extends them
// over the elements it appends (mark_new_elements, foldfill/marks.h).
//
// The OBJ attributes are carried through so that writing an OBJ keeps the
// texture coordinates and normals of the original faces. When a mesh has
// them, `face_texcoords` / `face_normals` have one entry per face (-1 marks a
// corner without one); faces appended by foldfill get {-1, -1, -1}.
struct Mesh {
  std::vector<Vec3> positions;
  std::vector<Tri> faces;

  std::vector<Vec2> texcoords;               // OBJ `vt` (u, v), in file order
  std::vector<Vec3> normals;                 // OBJ `vn`, in file order
  std::vector<Tri> face_texcoords;           // empty, or one per face
  std::vector<Tri> face_normals;             // empty, or one per face
  std::vector<ObjStatement> obj_statements;  // ascending before_face

  // PLY: the type x, y and z are written in, Float32 when the input's were
  // all float (positions then hold float values), else Float64.
  ScalarType coordinate_type = ScalarType::Float64;
  std::vector<ScalarProperty> vertex_properties;  // PLY, in file order
  std::vector<ScalarProperty> face_properties;    // PLY, in file order

  // Which fill put each element there: -1 for the input's own, the loop id
  // of the hole it fills for a new one. Empty unless the mesh is a fill's
  // output.
  std::vector<int> vertex_hole;
  std::vector<int> face_hole;

  int vertex_count() const { return static_cast<int>(positions.size()); }
  int face_count() const { return static_cast<int>(faces.size()); }
};

}  // namespace foldfill
