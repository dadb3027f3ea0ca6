// Edge adjacency of a triangle list: the one connectivity structure the stages share.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

// An undirected edge (v0 < v1) with the faces on each side. `face[0]` is the
// face that contains the directed edge v0 -> v1, `face[1]` the one that
// contains v1 -> v0; -1 where there is none (a boundary edge). `opposite[k]`
// is the vertex of `face[k]` that is not on the edge (-1 with no face).
struct Edge {
  int v0 = -1, v1 = -1;
  int face[2] = {-1, -1};
  int opposite[2] = {-1, -1};
  bool is_boundary() const { return face[0] < 0 || face[1] < 0; }
};

struct EdgeTopology {
  std::vector<Edge> edges;  // sorted by (v0, v1)
  // Per face, the edge index of (f[0],f[1]), (f[1],f[2]), (f[2],f[0]).
  std::vector<std::array<int, 3>> face_edges;
};

// The faces around every vertex in compressed rows: the faces of vertex v are
// `faces[start[v]] .. faces[start[v + 1] - 1]`, ascending. Built once per mesh
// (O(V + F) time, 4 (V + 1 + 3 F) bytes), it lets per-hole work touch only the
// faces near the hole instead of scanning the whole mesh.
struct VertexFaces {
  std::vector<int> start;  // vertex_count + 1 offsets into `faces`
  std::vector<int> faces;  // face indices, grouped by vertex

  int vertex_count() const { return static_cast<int>(start.size()) - 1; }
};

// Throws BadFaceError naming `source` for a face index out of range or a face
// that repeats a vertex.
VertexFaces build_vertex_faces(const std::vector<Tri>& faces, int vertex_count,
                               const std::string& source = "mesh");

// The edges (v, w) with w > v, in increasing w, from the faces around v
// (`vertex_faces` of `faces`), into `edges` (cleared first). Throws like
// build_edge_topology. Calling it for v = 0, 1, ... gives every edge once, in
// the order of EdgeTopology::edges, holding only one vertex's edges at a time.
void edges_from_vertex(const std::vector<Tri>& faces, const VertexFaces& vertex_faces, int v,
                       std::vector<Edge>& edges, const std::string& source = "mesh");

// Builds the edges of `faces` over `vertex_count` vertices in O(F log F).
// Throws NonManifoldError naming `source` when an edge has more than two
// faces or two faces use it in the same direction (inconsistent orientation).
EdgeTopology build_edge_topology(const std::vector<Tri>& faces, int vertex_count,
                                 const std::string& source = "mesh");

}  // namespace foldfill
