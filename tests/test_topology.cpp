// Edge topology on tiny meshes built in code.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/topology.h"

namespace foldfill {
namespace {

// A (cells x cells) grid of unit squares, each split along its diagonal,
// counter-clockwise seen from +z. Vertex (i, j) is j * (cells + 1) + i.
std::vector<Tri> grid_faces(int cells) {
  std::vector<Tri> faces;
  const int row = cells + 1;
  for (int j = 0; j < cells; ++j) {
    for (int i = 0; i < cells; ++i) {
      const int a = j * row + i, b = a + 1, c = a + row + 1, d = a + row;
      faces.push_back({a, b, c});
      faces.push_back({a, c, d});
    }
  }
  return faces;
}

const std::vector<Tri> kTetrahedron = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};

int boundary_edge_count(const EdgeTopology& topology) {
  return static_cast<int>(std::count_if(topology.edges.begin(), topology.edges.end(),
                                        [](const Edge& e) { return e.is_boundary(); }));
}

// Checks every invariant the header promises, against the faces themselves.
void expect_consistent(const std::vector<Tri>& faces, const EdgeTopology& topology) {
  ASSERT_EQ(topology.face_edges.size(), faces.size());
  for (size_t i = 0; i < topology.edges.size(); ++i) {
    const Edge& e = topology.edges[i];
    EXPECT_LT(e.v0, e.v1);
    if (i > 0) {
      const Edge& prev = topology.edges[i - 1];
      EXPECT_TRUE(prev.v0 < e.v0 || (prev.v0 == e.v0 && prev.v1 < e.v1)) << "edges not sorted";
    }
    EXPECT_TRUE(e.face[0] >= 0 || e.face[1] >= 0);
    for (int side = 0; side < 2; ++side) {
      if (e.face[side] < 0) {
        EXPECT_EQ(e.opposite[side], -1);
        continue;
      }
      const Tri& f = faces[e.face[side]];
      const int from = side == 0 ? e.v0 : e.v1, to = side == 0 ? e.v1 : e.v0;
      bool found = false;
      for (int k = 0; k < 3; ++k) {
        if (f[k] == from && f[(k + 1) % 3] == to) {
          found = true;
          EXPECT_EQ(e.opposite[side], f[(k + 2) % 3]);
          EXPECT_EQ(topology.face_edges[e.face[side]][k], static_cast<int>(i));
        }
      }
      EXPECT_TRUE(found) << "face " << e.face[side] << " lacks " << from << "->" << to;
    }
  }
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Edge& e = topology.edges.at(topology.face_edges[f][k]);
      const int a = faces[f][k], b = faces[f][(k + 1) % 3];
      EXPECT_EQ(e.v0, std::min(a, b));
      EXPECT_EQ(e.v1, std::max(a, b));
    }
  }
}

// The message of the Error of kind `kind` thrown by building `faces`.
std::string build_error(const std::vector<Tri>& faces, int vertex_count, ErrorKind kind) {
  try {
    build_edge_topology(faces, vertex_count, "test.obj");
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), kind) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error thrown";
  return "";
}

TEST(Topology, TetrahedronIsClosed) {
  const EdgeTopology topology = build_edge_topology(kTetrahedron, 4);
  EXPECT_EQ(topology.edges.size(), 6u);
  EXPECT_EQ(boundary_edge_count(topology), 0);
  expect_consistent(kTetrahedron, topology);
}

TEST(Topology, SingleTriangle) {
  const std::vector<Tri> faces = {{2, 0, 1}};
  const EdgeTopology topology = build_edge_topology(faces, 3);
  ASSERT_EQ(topology.edges.size(), 3u);
  EXPECT_EQ(boundary_edge_count(topology), 3);
  // Edge (0, 1) is used 0 -> 1 by the face: it is on side 0.
  EXPECT_EQ(topology.edges[0].v0, 0);
  EXPECT_EQ(topology.edges[0].v1, 1);
  EXPECT_EQ(topology.edges[0].face[0], 0);
  EXPECT_EQ(topology.edges[0].face[1], -1);
  EXPECT_EQ(topology.edges[0].opposite[0], 2);
  // Edge (0, 2) is used 2 -> 0: side 1.
  EXPECT_EQ(topology.edges[1].v1, 2);
  EXPECT_EQ(topology.edges[1].face[0], -1);
  EXPECT_EQ(topology.edges[1].face[1], 0);
  EXPECT_EQ(topology.edges[1].opposite[1], 1);
  expect_consistent(faces, topology);
}

TEST(Topology, GridEdgesAndOpposites) {
  const std::vector<Tri> faces = grid_faces(2);
  const EdgeTopology topology = build_edge_topology(faces, 9);
  EXPECT_EQ(topology.edges.size(), 16u);  // Euler: V - E + F = 1 for a disk
  EXPECT_EQ(boundary_edge_count(topology), 8);
  expect_consistent(faces, topology);
  // The diagonal (0, 4) of the first cell: faces (0,1,4) and (0,4,3).
  const auto diagonal = std::find_if(topology.edges.begin(), topology.edges.end(),
                                     [](const Edge& e) { return e.v0 == 0 && e.v1 == 4; });
  ASSERT_NE(diagonal, topology.edges.end());
  EXPECT_EQ(diagonal->face[0], 1);
  EXPECT_EQ(diagonal->opposite[0], 3);
  EXPECT_EQ(diagonal->face[1], 0);
  EXPECT_EQ(diagonal->opposite[1], 1);
}

TEST(Topology, UnreferencedVerticesAreFine) {
  const std::vector<Tri> faces = {{5, 7, 6}};
  const EdgeTopology topology = build_edge_topology(faces, 10);
  EXPECT_EQ(topology.edges.size(), 3u);
  expect_consistent(faces, topology);
}

TEST(Topology, EmptyMesh) {
  const EdgeTopology topology = build_edge_topology({}, 0);
  EXPECT_TRUE(topology.edges.empty());
  EXPECT_TRUE(topology.face_edges.empty());
}

TEST(Topology, EdgeWithThreeFacesThrows) {
  const std::vector<Tri> faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  EXPECT_EQ(build_error(faces, 5, ErrorKind::NonManifold),
            "test.obj: edge (0, 1) is shared by 3 faces");
}

TEST(Topology, InconsistentOrientationThrows) {
  const std::vector<Tri> faces = {{0, 1, 2}, {3, 2, 1}, {0, 1, 3}};
  EXPECT_EQ(build_error(faces, 4, ErrorKind::NonManifold),
            "test.obj: faces 0 and 2 use edge (0, 1) in the same direction (inconsistent "
            "orientation)");
}

TEST(Topology, FlippedFaceInGridThrows) {
  std::vector<Tri> faces = grid_faces(3);
  std::swap(faces[7][1], faces[7][2]);
  EXPECT_NE(build_error(faces, 16, ErrorKind::NonManifold).find("inconsistent orientation"),
            std::string::npos);
}

TEST(Topology, BadIndicesThrowBadFace) {
  EXPECT_NE(build_error({{0, 1, 3}}, 3, ErrorKind::BadFace).find("face 0 has vertex index 3"),
            std::string::npos);
  EXPECT_NE(build_error({{0, 1, -1}}, 3, ErrorKind::BadFace).find("out of range"),
            std::string::npos);
  EXPECT_NE(build_error({{0, 1, 1}}, 3, ErrorKind::BadFace).find("repeats vertex 1"),
            std::string::npos);
}

TEST(Topology, LargeGridIsConsistent) {
  const int cells = 300;
  const std::vector<Tri> faces = grid_faces(cells);
  const EdgeTopology topology = build_edge_topology(faces, (cells + 1) * (cells + 1));
  const int vertices = (cells + 1) * (cells + 1);
  EXPECT_EQ(static_cast<int>(topology.edges.size()), vertices + static_cast<int>(faces.size()) - 1);
  EXPECT_EQ(boundary_edge_count(topology), 4 * cells);
}

}  // namespace
}  // namespace foldfill
