// Edge adjacency of a triangle list, built vertex by vertex from the faces
// around each vertex (compressed rows, a counting sort): the half-edges from a
// vertex to larger ones, sorted, give its edges in order.
#include "foldfill/topology.h"

#include <algorithm>
#include <string>
#include <utility>

#include "foldfill/error.h"

namespace foldfill {
namespace {

void check_face_indices(const std::vector<Tri>& faces, int vertex_count,
                        const std::string& source) {
  for (size_t f = 0; f < faces.size(); ++f) {
    const Tri& face = faces[f];
    for (int k = 0; k < 3; ++k) {
      if (face[k] < 0 || face[k] >= vertex_count) {
        throw BadFaceError(source + ": face " + std::to_string(f) + " has vertex index " +
                           std::to_string(face[k]) + " out of range (the mesh has " +
                           std::to_string(vertex_count) + " vertices)");
      }
      if (face[k] == face[(k + 1) % 3]) {
        throw BadFaceError(source + ": face " + std::to_string(f) + " repeats vertex " +
                           std::to_string(face[k]));
      }
    }
  }
}

// A half-edge seen from its smaller endpoint v: `other` is the larger one,
// `half_edge` = 3 * face + corner (the edge face[corner] -> face[corner + 1]).
struct HalfEdgeAt {
  int other;
  int half_edge;
  bool operator<(const HalfEdgeAt& rhs) const {
    return std::pair(other, half_edge) < std::pair(rhs.other, rhs.half_edge);
  }
};

std::string edge_name(int v0, int v1) {
  return "edge (" + std::to_string(v0) + ", " + std::to_string(v1) + ")";
}

// Makes the edge (v0, run[0].other) from its half-edges `run`; throws when
// they do not form a manifold, consistently oriented edge.
Edge make_edge(const std::vector<Tri>& faces, int v0, const HalfEdgeAt* run, int run_size,
               const std::string& source) {
  Edge edge;
  edge.v0 = v0;
  edge.v1 = run[0].other;
  if (run_size > 2) {
    throw NonManifoldError(source + ": " + edge_name(edge.v0, edge.v1) + " is shared by " +
                           std::to_string(run_size) + " faces");
  }
  for (int i = 0; i < run_size; ++i) {
    const int face = run[i].half_edge / 3, corner = run[i].half_edge % 3;
    const int side = faces[face][corner] == v0 ? 0 : 1;
    if (edge.face[side] >= 0) {
      throw NonManifoldError(source + ": faces " + std::to_string(edge.face[side]) + " and " +
                             std::to_string(face) + " use " + edge_name(edge.v0, edge.v1) +
                             " in the same direction (inconsistent orientation)");
    }
    edge.face[side] = face;
    edge.opposite[side] = faces[face][(corner + 2) % 3];
  }
  return edge;
}

}  // namespace

VertexFaces build_vertex_faces(const std::vector<Tri>& faces, int vertex_count,
                               const std::string& source) {
  check_face_indices(faces, vertex_count, source);
  VertexFaces incidence;
  incidence.start.assign(static_cast<size_t>(vertex_count) + 1, 0);
  for (const Tri& face : faces)
    for (int v : face) ++incidence.start[v + 1];
  for (int v = 0; v < vertex_count; ++v) incidence.start[v + 1] += incidence.start[v];
  incidence.faces.resize(faces.size() * 3);
  // Filling in face order leaves every vertex's faces ascending.
  std::vector<int> cursor(incidence.start.begin(), incidence.start.end() - 1);
  for (size_t f = 0; f < faces.size(); ++f)
    for (int v : faces[f]) incidence.faces[cursor[v]++] = static_cast<int>(f);
  return incidence;
}

void edges_from_vertex(const std::vector<Tri>& faces, const VertexFaces& vertex_faces, int v,
                       std::vector<Edge>& edges, const std::string& source) {
  // The half-edges of v's faces to larger vertices, sorted by (other end,
  // half-edge): those of one edge are adjacent and in face order. The buffer
  // is reused by the calls of one thread (one call per vertex of a mesh).
  thread_local std::vector<HalfEdgeAt> half_edges;
  half_edges.clear();
  for (int i = vertex_faces.start[v]; i < vertex_faces.start[v + 1]; ++i) {
    const int f = vertex_faces.faces[i];
    const Tri& face = faces[f];
    const int k = face[0] == v ? 0 : face[1] == v ? 1 : 2;
    const int next = face[(k + 1) % 3], previous = face[(k + 2) % 3];
    if (next > v) half_edges.push_back({next, 3 * f + k});
    if (previous > v) half_edges.push_back({previous, 3 * f + (k + 2) % 3});
  }
  std::sort(half_edges.begin(), half_edges.end());
  edges.clear();
  for (size_t i = 0; i < half_edges.size();) {
    size_t end = i + 1;
    while (end < half_edges.size() && half_edges[end].other == half_edges[i].other) ++end;
    edges.push_back(make_edge(faces, v, &half_edges[i], static_cast<int>(end - i), source));
    i = end;
  }
}

EdgeTopology build_edge_topology(const std::vector<Tri>& faces, int vertex_count,
                                 const std::string& source) {
  const VertexFaces vertex_faces = build_vertex_faces(faces, vertex_count, source);
  EdgeTopology topology;
  topology.face_edges.assign(faces.size(), {-1, -1, -1});
  topology.edges.reserve(faces.size() * 3 / 2 + 3);
  std::vector<Edge> around;
  for (int v = 0; v < vertex_count; ++v) {
    edges_from_vertex(faces, vertex_faces, v, around, source);
    for (const Edge& edge : around) {
      const int index = static_cast<int>(topology.edges.size());
      // Face 0 has the edge as v0 -> v1 (its corner at v0), face 1 as v1 -> v0.
      for (int side = 0; side < 2; ++side) {
        const int f = edge.face[side];
        if (f < 0) continue;
        const int from = side == 0 ? edge.v0 : edge.v1;
        const int corner = faces[f][0] == from ? 0 : faces[f][1] == from ? 1 : 2;
        topology.face_edges[f][corner] = index;
      }
      topology.edges.push_back(edge);
    }
  }
  return topology;
}

}  // namespace foldfill
