// Edge adjacency of a triangle list, built by bucketing half-edges on their
// smaller endpoint (a counting sort) and sorting each small bucket.
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
        throw Error(ErrorKind::BadFace, source + ": face " + std::to_string(f) +
                                            " has vertex index " + std::to_string(face[k]) +
                                            " out of range (the mesh has " +
                                            std::to_string(vertex_count) + " vertices)");
      }
      if (face[k] == face[(k + 1) % 3]) {
        throw Error(ErrorKind::BadFace, source + ": face " + std::to_string(f) +
                                            " repeats vertex " + std::to_string(face[k]));
      }
    }
  }
}

// A half-edge seen from the bucket of its smaller endpoint: `other` is the
// larger endpoint, `half_edge` = 3 * face + corner (the edge face[k] -> face[k+1]).
struct BucketEntry {
  int other;
  int half_edge;
  bool operator<(const BucketEntry& rhs) const {
    return std::pair(other, half_edge) < std::pair(rhs.other, rhs.half_edge);
  }
};

// Half-edges grouped by smaller endpoint (CSR layout), each bucket sorted by
// (larger endpoint, half-edge), so equal undirected edges are adjacent and in
// face order.
struct HalfEdgeBuckets {
  std::vector<int> start;  // bucket of vertex v is entries[start[v], start[v + 1])
  std::vector<BucketEntry> entries;
};

HalfEdgeBuckets bucket_half_edges(const std::vector<Tri>& faces, int vertex_count) {
  HalfEdgeBuckets buckets;
  buckets.start.assign(vertex_count + 1, 0);
  for (const Tri& face : faces) {
    for (int k = 0; k < 3; ++k) ++buckets.start[std::min(face[k], face[(k + 1) % 3]) + 1];
  }
  for (int v = 0; v < vertex_count; ++v) buckets.start[v + 1] += buckets.start[v];

  buckets.entries.resize(faces.size() * 3);
  std::vector<int> cursor(buckets.start.begin(), buckets.start.end() - 1);
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = faces[f][k], b = faces[f][(k + 1) % 3];
      buckets.entries[cursor[std::min(a, b)]++] = {std::max(a, b), static_cast<int>(3 * f + k)};
    }
  }
  for (int v = 0; v < vertex_count; ++v) {
    std::sort(buckets.entries.begin() + buckets.start[v],
              buckets.entries.begin() + buckets.start[v + 1]);
  }
  return buckets;
}

std::string edge_name(int v0, int v1) {
  return "edge (" + std::to_string(v0) + ", " + std::to_string(v1) + ")";
}

// Makes the edge (v0, v1) from its half-edges `run` and records it in
// `face_edges`; throws when the half-edges do not form a manifold,
// consistently oriented edge.
Edge make_edge(const std::vector<Tri>& faces, int v0, const BucketEntry* run, int run_size,
               int edge_index, std::vector<std::array<int, 3>>& face_edges,
               const std::string& source) {
  Edge edge;
  edge.v0 = v0;
  edge.v1 = run[0].other;
  if (run_size > 2) {
    throw Error(ErrorKind::NonManifold, source + ": " + edge_name(edge.v0, edge.v1) +
                                            " is shared by " + std::to_string(run_size) + " faces");
  }
  for (int i = 0; i < run_size; ++i) {
    const int face = run[i].half_edge / 3, corner = run[i].half_edge % 3;
    const int side = faces[face][corner] == v0 ? 0 : 1;
    if (edge.face[side] >= 0) {
      throw Error(ErrorKind::NonManifold, source + ": faces " + std::to_string(edge.face[side]) +
                                              " and " + std::to_string(face) + " use " +
                                              edge_name(edge.v0, edge.v1) +
                                              " in the same direction (inconsistent orientation)");
    }
    edge.face[side] = face;
    edge.opposite[side] = faces[face][(corner + 2) % 3];
    face_edges[face][corner] = edge_index;
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

EdgeTopology build_edge_topology(const std::vector<Tri>& faces, int vertex_count,
                                 const std::string& source) {
  check_face_indices(faces, vertex_count, source);
  const HalfEdgeBuckets buckets = bucket_half_edges(faces, vertex_count);

  EdgeTopology topology;
  topology.face_edges.assign(faces.size(), {-1, -1, -1});
  topology.edges.reserve(faces.size() * 3 / 2 + 3);
  for (int v = 0; v < vertex_count; ++v) {
    const int end = buckets.start[v + 1];
    for (int i = buckets.start[v]; i < end;) {
      int run_end = i + 1;
      while (run_end < end && buckets.entries[run_end].other == buckets.entries[i].other) {
        ++run_end;
      }
      topology.edges.push_back(make_edge(faces, v, &buckets.entries[i], run_end - i,
                                         static_cast<int>(topology.edges.size()),
                                         topology.face_edges, source));
      i = run_end;
    }
  }
  return topology;
}

}  // namespace foldfill
