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
  std::vector<Edge> edges;                 // sorted by (v0, v1)
  std::vector<std::array<int, 3>> face_edges;  // edge index of (f[0],f[1]), (f[1],f[2]), (f[2],f[0])
};

// Builds the edges of `faces` over `vertex_count` vertices in O(F log F).
// Throws Error(NonManifold) naming `source` when an edge has more than two
// faces or two faces use it in the same direction (inconsistent orientation).
EdgeTopology build_edge_topology(const std::vector<Tri>& faces, int vertex_count,
                                 const std::string& source = "mesh");

}  // namespace foldfill
