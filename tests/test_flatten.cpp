// Tests of the strip extraction, its LSCM flattening and the glued embedding
// domain: exact figures on exactly developable meshes with a hole, the
// refusals, and the fit on the reference cases kept from getting worse.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "foldfill/domain.h"
#include "foldfill/error.h"
#include "foldfill/examples.h"
#include "foldfill/flatten.h"
#include "foldfill/holes.h"
#include "foldfill/io.h"
#include "foldfill/topology.h"
#include "foldfill/triangulate.h"
#include "support/loops.h"
#include "support/reference_cases.h"
#include "test_geometry.h"
#include "test_support.h"

namespace foldfill {
namespace {

using testing::polygon_area;
using testing::twice_signed_area;

double distance3(const Vec3& a, const Vec3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

double distance2(const Vec2& a, const Vec2& b) { return std::hypot(a[0] - b[0], a[1] - b[1]); }

// The largest distance between matched points of `moving` and `target` after
// the best rotation and translation of `moving` (2D Kabsch).
double rigid_fit_error(const std::vector<Vec2>& moving, const std::vector<Vec2>& target) {
  const size_t n = moving.size();
  Vec2 cm{0, 0}, ct{0, 0};
  for (size_t i = 0; i < n; ++i)
    for (int d = 0; d < 2; ++d) {
      cm[d] += moving[i][d] / n;
      ct[d] += target[i][d] / n;
    }
  double along = 0, across = 0;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 p{moving[i][0] - cm[0], moving[i][1] - cm[1]};
    const Vec2 q{target[i][0] - ct[0], target[i][1] - ct[1]};
    along += q[0] * p[0] + q[1] * p[1];
    across += q[1] * p[0] - q[0] * p[1];
  }
  const double angle = std::atan2(across, along), c = std::cos(angle), s = std::sin(angle);
  double worst = 0;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 p{moving[i][0] - cm[0], moving[i][1] - cm[1]};
    const Vec2 rotated{c * p[0] - s * p[1] + ct[0], s * p[0] + c * p[1] + ct[1]};
    worst = std::max(worst, distance2(rotated, target[i]));
  }
  return worst;
}

// The hole of a mesh with one hole and one outer boundary: the shorter loop.
BoundaryLoop hole_loop(const Mesh& mesh) {
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh, "test");
  EXPECT_EQ(loops.size(), 2u);
  return *std::min_element(
      loops.begin(), loops.end(),
      [](const BoundaryLoop& a, const BoundaryLoop& b) { return a.length < b.length; });
}

Vec2 flat_centre(const DevelopableMesh& developable) {
  Vec2 centre{0, 0};
  for (const Vec2& p : developable.flat)
    for (int d = 0; d < 2; ++d) centre[d] += p[d] / developable.flat.size();
  return centre;
}

// Flattening a hole cut out of an exactly developable mesh must give back its
// true flat outline: lengths, angles and shape to rounding, and the patch the
// removed area.
void expect_exact_flattening(const DevelopableMesh& developable, double hole_radius) {
  const CutMesh cut = cut_disk_hole(developable, flat_centre(developable), hole_radius);
  ASSERT_GT(cut.removed_faces, 0);
  const Mesh& mesh = cut.cut.mesh;
  const BoundaryLoop loop = hole_loop(mesh);
  const Strip strip = extract_strip(mesh, loop, "test");
  const Flattening flat = flatten_strip(strip, "test");

  EXPECT_LT(flat.edge_length_max_rel, 1e-6);
  EXPECT_LT(flat.edge_length_rms_rel, 1e-6);
  EXPECT_LT(flat.angle_sum_max, 1e-6);
  EXPECT_EQ(flat.flipped_triangles, 0);
  EXPECT_TRUE(flat.simple_polygon);
  for (const Tri& f : strip.faces)
    EXPECT_GT(twice_signed_area(flat.uv[f[0]], flat.uv[f[1]], flat.uv[f[2]]), 0);

  const std::vector<Vec2> polygon = hole_polygon(strip, flat);
  ASSERT_EQ(polygon.size(), loop.vertices.size());
  EXPECT_EQ(polygon[0], (Vec2{0, 0}));
  EXPECT_EQ(polygon[1][1], 0);
  std::vector<Vec2> truth;
  for (int v : loop.vertices) truth.push_back(cut.cut.flat[v]);
  double size = 0;
  for (const Vec2& p : truth) size = std::max(size, distance2(p, truth[0]));
  EXPECT_LT(rigid_fit_error(polygon, truth), 1e-6 * size);
  EXPECT_NEAR(polygon_area(polygon), cut.removed_area, 1e-6 * cut.removed_area);

  const FlatPatch patch = triangulate_hole(polygon);
  EXPECT_NEAR(patch.area, cut.removed_area, 0.005 * cut.removed_area);
  EXPECT_GT(patch.min_angle_deg, 20);
  std::printf("loop %zu vertices, strip %zu faces, patch %zu vertices, min angle %.1f deg\n",
              loop.vertices.size(), strip.faces.size(), patch.uv.size(), patch.min_angle_deg);

  // The glued domain: all faces counter-clockwise in the rest state, and the
  // rest lengths of the strip equal to its normalised 3D lengths.
  const EmbedDomain domain = make_embed_domain(strip, flat, patch);
  ASSERT_EQ(domain.vertex_count(),
            static_cast<int>(strip.positions.size() + patch.uv.size()) - patch.boundary_count);
  ASSERT_EQ(domain.faces.size(), strip.faces.size() + patch.faces.size());
  for (const Tri& f : domain.faces)
    EXPECT_GT(twice_signed_area(domain.rest_uv[f[0]], domain.rest_uv[f[1]], domain.rest_uv[f[2]]),
              0);
  double loop_length = 0;
  for (int k = 0; k < domain.loop_size; ++k)
    loop_length +=
        distance3(domain.fixed_positions[k], domain.fixed_positions[(k + 1) % domain.loop_size]);
  EXPECT_NEAR(loop_length / domain.loop_size, 1.0, 1e-12);
  for (int f = 0; f < domain.strip_face_count; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = domain.faces[f][k], b = domain.faces[f][(k + 1) % 3];
      EXPECT_NEAR(distance2(domain.rest_uv[a], domain.rest_uv[b]),
                  distance3(domain.fixed_positions[a], domain.fixed_positions[b]), 1e-6);
    }
}

TEST(FlattenDevelopable, CylinderSection) {
  expect_exact_flattening(make_cylinder_section(1.0, 2.5, 2.0, 0.05), 0.5);
}

TEST(FlattenDevelopable, ConeSection) {
  expect_exact_flattening(make_cone_section(0.5, 1.0, 3.0, 2.0, 0.05), 0.5);
}

TEST(FlattenDevelopable, FoldedSheet) { expect_exact_flattening(make_folded_sheet(), 0.6); }

// A flat grid of `columns` x `rows` unit cells in the z = 0 plane, cell
// (i, j) split along its (i, j)-(i+1, j+1) diagonal, minus the faces
// `removed` says, unreferenced vertices dropped.
template <class Removed>
Mesh grid_without(int columns, int rows, const Removed& removed) {
  Mesh grid;
  const auto vertex = [&](int i, int j) { return j * (columns + 1) + i; };
  for (int j = 0; j <= rows; ++j)
    for (int i = 0; i <= columns; ++i) grid.positions.push_back({double(i), double(j), 0});
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < columns; ++i) {
      const Tri lower{vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1)};
      const Tri upper{vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)};
      if (!removed(i, j, false)) grid.faces.push_back(lower);
      if (!removed(i, j, true)) grid.faces.push_back(upper);
    }
  std::vector<int> renumber(grid.positions.size(), -1);
  Mesh mesh;
  for (Tri& f : grid.faces)
    for (int& v : f) {
      if (renumber[v] < 0) {
        renumber[v] = mesh.vertex_count();
        mesh.positions.push_back(grid.positions[v]);
      }
      v = renumber[v];
    }
  mesh.faces = grid.faces;
  return mesh;
}

bool in_block(int i, int j) { return i >= 2 && i < 4 && j >= 2 && j < 4; }

TEST(ExtractStrip, NumbersLoopFirstThenRingInFaceOrder) {
  const Mesh mesh = grid_without(6, 6, [](int i, int j, bool) { return in_block(i, j); });
  const BoundaryLoop loop = hole_loop(mesh);
  const Strip strip = extract_strip(mesh, loop);
  ASSERT_EQ(strip.loop_size, 8);
  EXPECT_EQ(std::vector<int>(strip.to_input.begin(), strip.to_input.begin() + 8), loop.vertices);

  // The expected strip, found independently: faces touching the loop, in
  // input order; ring vertices numbered as they first appear there.
  const std::set<int> on_loop(loop.vertices.begin(), loop.vertices.end());
  std::vector<int> expected_faces, expected_order = loop.vertices;
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Tri& face = mesh.faces[f];
    if (!on_loop.count(face[0]) && !on_loop.count(face[1]) && !on_loop.count(face[2])) continue;
    expected_faces.push_back(f);
    for (int v : face)
      if (std::find(expected_order.begin(), expected_order.end(), v) == expected_order.end())
        expected_order.push_back(v);
  }
  EXPECT_EQ(strip.input_faces, expected_faces);
  EXPECT_EQ(strip.to_input, expected_order);
  ASSERT_EQ(strip.faces.size(), expected_faces.size());
  for (size_t f = 0; f < strip.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(strip.to_input[strip.faces[f][k]], mesh.faces[strip.input_faces[f]][k]);
      EXPECT_EQ(strip.positions[strip.faces[f][k]],
                mesh.positions[mesh.faces[strip.input_faces[f]][k]]);
    }

  // A flat strip flattens to itself: the hole is the 2 x 2 square.
  const Flattening flat = flatten_strip(strip);
  EXPECT_NEAR(polygon_area(hole_polygon(strip, flat)), 4.0, 1e-9);
  EXPECT_EQ(flatten_strip(strip).uv, flat.uv);
}

TEST(ExtractStrip, FromTheVertexFacesIsTheSameStrip) {
  const Mesh mesh = grid_without(6, 6, [](int i, int j, bool) { return in_block(i, j); });
  const BoundaryLoop loop = hole_loop(mesh);
  const VertexFaces vertex_faces = build_vertex_faces(mesh.faces, mesh.vertex_count());
  const Strip scanned = extract_strip(mesh, loop),
              indexed = extract_strip(mesh, vertex_faces, loop);
  EXPECT_EQ(indexed.positions, scanned.positions);
  EXPECT_EQ(indexed.faces, scanned.faces);
  EXPECT_EQ(indexed.to_input, scanned.to_input);
  EXPECT_EQ(indexed.input_faces, scanned.input_faces);
  EXPECT_EQ(indexed.loop_size, scanned.loop_size);
}

TEST(VertexFaces, ListsTheFacesOfEveryVertexAscending) {
  const Mesh mesh =
      grid_without(4, 3, [](int i, int j, bool upper) { return i == 1 && j == 1 && upper; });
  const VertexFaces incidence = build_vertex_faces(mesh.faces, mesh.vertex_count());
  ASSERT_EQ(incidence.vertex_count(), mesh.vertex_count());
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    std::vector<int> expected;
    for (int f = 0; f < mesh.face_count(); ++f)
      if (std::count(mesh.faces[f].begin(), mesh.faces[f].end(), v)) expected.push_back(f);
    EXPECT_EQ(std::vector<int>(incidence.faces.begin() + incidence.start[v],
                               incidence.faces.begin() + incidence.start[v + 1]),
              expected);
  }
  Mesh bad = mesh;
  bad.faces[2][1] = mesh.vertex_count();
  EXPECT_THROW(build_vertex_faces(bad.faces, bad.vertex_count()), Error);
}

void expect_not_a_disk(const Mesh& mesh, const BoundaryLoop& loop, const std::string& reason) {
  try {
    extract_strip(mesh, loop, "grid.obj");
    ADD_FAILURE() << "no error thrown";
  } catch (const Error& error) {
    EXPECT_EQ(error.kind(), ErrorKind::NotADisk) << error.what();
    const std::string message = error.what();
    EXPECT_EQ(message.rfind("grid.obj: loop " + std::to_string(loop.id) + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(reason), std::string::npos) << message;
  }
}

int grid_vertex_at(const Mesh& mesh, double x, double y) {
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.positions[v][0] == x && mesh.positions[v][1] == y) return v;
  ADD_FAILURE() << "no vertex at " << x << ", " << y;
  return 0;
}

TEST(ExtractStrip, FlattensAHoleSplitWhereItTouchesTheOuterBoundary) {
  // The hole: the cells of [1, 4] x [2, 4] and the triangle (0,2)-(1,2)-(1,3),
  // which reaches the grid's left side at vertex (0, 2) without taking a
  // boundary edge, so the hole and the outer boundary share that vertex. The
  // boundary is split there; the hole's strip pinches at it but still lies
  // flat around the hole.
  const Mesh mesh = grid_without(6, 6, [](int i, int j, bool upper) {
    return (i >= 1 && i < 4 && j >= 2 && j < 4) || (i == 0 && j == 2 && !upper);
  });
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh, "grid.obj");
  ASSERT_EQ(loops.size(), 2u);
  const int corner = grid_vertex_at(mesh, 0, 2);
  for (const BoundaryLoop& loop : loops) {
    EXPECT_TRUE(loop.is_disk);
    EXPECT_EQ(loop.split_at, std::vector<int>{corner});
  }
  const BoundaryLoop& hole = loops[0].length < loops[1].length ? loops[0] : loops[1];
  EXPECT_EQ(hole.vertices.size(), 11u);
  const Strip strip = extract_strip(mesh, hole, "grid.obj");
  const Flattening flat = flatten_strip(strip, "grid.obj");
  EXPECT_EQ(flat.flipped_triangles, 0);
  EXPECT_TRUE(flat.simple_polygon);
  EXPECT_LT(flat.edge_length_max_rel, 1e-6);

  // The outer loop is split at the same vertex, but it is an outer edge.
  const BoundaryLoop& outer = &hole == &loops[0] ? loops[1] : loops[0];
  EXPECT_THROW(flatten_strip(extract_strip(mesh, outer, "grid.obj"), "grid.obj"), Error);
}

TEST(ExtractStrip, RefusesALoopWhoseStripIsNotAnAnnulus) {
  // A lone triangle: its loop's strip is the whole disk.
  Mesh triangle;
  triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  triangle.faces = {{0, 1, 2}};
  BoundaryLoop loop;
  loop.vertices = {0, 2, 1};
  expect_not_a_disk(triangle, loop, "do not form a flat ring around the hole");
}

TEST(ExtractStrip, RefusesALoopFlaggedAsNoDisk) {
  const Mesh mesh = grid_without(6, 6, [](int i, int j, bool) { return in_block(i, j); });
  BoundaryLoop loop = hole_loop(mesh);
  loop.is_disk = false;
  loop.reason = "touches itself at vertex 7";
  expect_not_a_disk(mesh, loop, "touches itself at vertex 7");
}

TEST(FlattenStrip, RefusesAnOutlineThatCannotLieFlat) {
  // A collar whose inner ring (the hole) ripples up and down, so that it is
  // far longer than the outer ring: no flat annulus has such a hole.
  const int segments = 48;
  const Mesh collar = testing::rippled_collar(segments);
  const std::vector<BoundaryLoop> loops = find_boundary_loops(collar, "collar");
  ASSERT_EQ(loops.size(), 2u);
  const BoundaryLoop& inner = loops[0].vertices[0] < segments ? loops[0] : loops[1];
  const Strip strip = extract_strip(collar, inner, "collar");
  try {
    flatten_strip(strip, "collar: loop 0");
    ADD_FAILURE() << "no error thrown";
  } catch (const Error& error) {
    EXPECT_EQ(error.kind(), ErrorKind::FillFailed) << error.what();
    EXPECT_EQ(std::string(error.what()),
              "collar: loop 0: the flattened hole outline crosses itself");
  }
}

// ---- Reference cases --------------------------------------------------------

// Fit figures measured on the reference cases, with a margin (x 1.25): they
// may get better, not worse.
struct FitLimits {
  double edge_length_rms_rel, edge_length_max_rel, angle_sum_rms, angle_sum_max;
};
// contour_hole is flat: its figures are rounding errors, bounded by 1e-8.
const std::map<std::string, FitLimits> kReferenceLimits = {
    {"contour_hole.obj", {1e-8, 1e-8, 1e-8, 1e-8}},
    {"curtain_hole.obj", {5.2e-2, 7.1e-2, 3.6e-3, 3.3e-2}},
    {"paper1_hole.obj", {2.8e-3, 4.7e-3, 1.7e-4, 5.2e-4}},
    {"paper2_hole.obj", {9.7e-3, 1.7e-2, 6.2e-4, 1.8e-3}},
    {"sim1_hole.obj", {4.1e-2, 7.0e-2, 1.6e-3, 4.3e-3}},
    {"sim2_hole.obj", {2.8e-2, 4.9e-2, 4.8e-3, 1.1e-2}},
};

TEST(FlattenReference, FitDoesNotGetWorse) {
  FOLDFILL_REQUIRE_SHARED();
  const auto cases = testing::read_reference_cases(testing::shared_dir() / "data" / "reference");
  ASSERT_EQ(cases.size(), kReferenceLimits.size());
  for (const testing::ReferenceCase& entry : cases) {
    const std::string& name = entry.file;
    SCOPED_TRACE(name);
    const Mesh mesh = read_mesh(entry.path.string());
    const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh, name);
    const int id = testing::loop_through(loops, entry.hole_vertex);
    ASSERT_GE(id, 0);
    const BoundaryLoop& loop = loops[id];
    EXPECT_EQ(static_cast<int>(loop.vertices.size()), entry.hole_loop_size);
    const Strip strip = extract_strip(mesh, loop, name);
    const Flattening flat = flatten_strip(strip, name);
    std::printf(
        "%-18s loop %3d  strip %4zu faces  edge length rms %.3e max %.3e  "
        "angle sum rms %.3e max %.3e\n",
        name.c_str(), strip.loop_size, strip.faces.size(), flat.edge_length_rms_rel,
        flat.edge_length_max_rel, flat.angle_sum_rms, flat.angle_sum_max);
    EXPECT_EQ(flat.flipped_triangles, 0);
    EXPECT_TRUE(flat.simple_polygon);
    const FitLimits& limits = kReferenceLimits.at(name);
    EXPECT_LE(flat.edge_length_rms_rel, limits.edge_length_rms_rel);
    EXPECT_LE(flat.edge_length_max_rel, limits.edge_length_max_rel);
    EXPECT_LE(flat.angle_sum_rms, limits.angle_sum_rms);
    EXPECT_LE(flat.angle_sum_max, limits.angle_sum_max);

    // The outline meshes into a valid patch (uneven outlines cost some angle).
    const FlatPatch patch = triangulate_hole(hole_polygon(strip, flat));
    EXPECT_GT(patch.min_angle_deg, 10);
    EXPECT_LT(patch.share_below_20deg, 0.01);
  }
}

}  // namespace
}  // namespace foldfill
