// The page of `foldfill view`: one self-contained HTML file that shows a mesh
// and its fills in the browser (three.js inlined, mesh data as base64 binary
// buffers), offline from file://.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

// Per-vertex curvatures of a triangle mesh: the Gaussian curvature (angle
// defect over a third of the area of the faces around the vertex) and the
// mean curvature (half the cotangent Laplacian of the position along the
// vertex normal, over the same area; positive where the surface bends away
// from its normal, as a sphere seen from outside). Boundary vertices, and
// vertices without area, get NaN.
struct Curvatures {
  std::vector<float> gaussian, mean;
};
Curvatures vertex_curvatures(const Mesh& mesh);

// Which hole each face belongs to: -1 for a face of the input, the loop id of
// the hole it fills for a new one, kUnknownHole for a new face whose hole is
// not known.
constexpr int kUnknownHole = -2;

// The holes of `filled`'s faces. With marks (Mesh::face_hole), the marks.
// Otherwise the faces past `input_face_count` are new: each piece of them
// (new faces joined through shared edges) takes the id of the loop in
// `loop_vertices` (one vertex list per loop, in loop order, ids by position)
// one of whose edges it has, else kUnknownHole.
std::vector<int> face_holes(const Mesh& filled, int input_face_count,
                            const std::vector<std::vector<int>>& loop_vertices,
                            const std::vector<int>& loop_ids);

enum class ViewLayout { SideBySide, Overlay };

struct ViewMesh {
  std::string name;  // shown above its panel: the file name
  const Mesh* mesh = nullptr;
};

struct ViewOptions {
  std::string title;
  ViewLayout layout = ViewLayout::SideBySide;
  // A fill's report (README, "Report"), its per-hole figures shown in a table;
  // null for none.
  nlohmann::json report;
};

// Whether this build has three.js to inline (it is taken from the npm
// package `three` at build time; without it there is no page).
bool view_available();
// What `view` says when it is not.
inline constexpr const char* kViewUnavailable =
    "view is not available: this foldfill was built without three.js (run `npm ci` in the "
    "source folder, or bash scripts/setup.sh, then build again)";

// The page for `input` and the fills of it in `filled` (none, one or
// several), each in a panel, with one camera for all. The loops of the input
// are outlined with their ids; new faces are coloured per hole (from the
// marks, else the faces past the input's in a fill that starts with the
// input's vertices and faces, with face_holes); the
// curvatures can colour the surface instead. A fill that keeps the input's
// vertices and faces as its first ones shares their buffers with the input
// (so the page is not much larger than the fill alone). `warnings` gets what
// the page leaves out (loops of a mesh that is not manifold). Precondition:
// the meshes are valid (validate_mesh). Throws UsageError when
// !view_available().
std::string view_page(const ViewMesh& input, const std::vector<ViewMesh>& filled,
                      const ViewOptions& options, std::vector<std::string>* warnings = nullptr);

// RFC 4648 base64 of `size` bytes.
std::string base64(const void* data, size_t size);

}  // namespace foldfill
