// The example meshes are the ground truth of many tests: check that they are
// exactly isometric to their flat coordinates and that cutting leaves a disk.
#include <gtest/gtest.h>

#include <cmath>

#include "foldfill/examples.h"
#include "foldfill/topology.h"

namespace foldfill {
namespace {

double length3(const Vec3& a, const Vec3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}
double length2(const Vec2& a, const Vec2& b) { return std::hypot(a[0] - b[0], a[1] - b[1]); }
double signed_area(const Vec2& a, const Vec2& b, const Vec2& c) {
  return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
}

// Largest relative difference between 3D and flat edge lengths.
double max_isometry_error(const DevelopableMesh& m) {
  double worst = 0;
  for (const Tri& f : m.mesh.faces) {
    for (int k = 0; k < 3; ++k) {
      const int a = f[k], b = f[(k + 1) % 3];
      const double flat = length2(m.flat[a], m.flat[b]);
      worst = std::max(worst,
                       std::abs(length3(m.mesh.positions[a], m.mesh.positions[b]) - flat) / flat);
    }
  }
  return worst;
}

void expect_isometric_and_ccw(const DevelopableMesh& m) {
  ASSERT_EQ(m.flat.size(), m.mesh.positions.size());
  ASSERT_FALSE(m.mesh.faces.empty());
  EXPECT_LT(max_isometry_error(m), 1e-12);
  for (const Tri& f : m.mesh.faces) {
    EXPECT_GT(signed_area(m.flat[f[0]], m.flat[f[1]], m.flat[f[2]]), 0);
  }
}

int boundary_edge_count(const Mesh& mesh) {
  int count = 0;
  for (const Edge& e : build_edge_topology(mesh.faces, mesh.vertex_count()).edges) {
    count += e.is_boundary();
  }
  return count;
}

TEST(Examples, FoldedSheetIsIsometricToItsFlatGrid) {
  FoldedSheetOptions options;
  options.edge_length = 0.1;
  const DevelopableMesh sheet = make_folded_sheet(options);
  expect_isometric_and_ccw(sheet);
  // The folds are there: the sheet is far from planar and longer than wide.
  double z_min = 1e9, z_max = -1e9, u_max = 0;
  for (size_t v = 0; v < sheet.flat.size(); ++v) {
    z_min = std::min(z_min, sheet.mesh.positions[v][2]);
    z_max = std::max(z_max, sheet.mesh.positions[v][2]);
    u_max = std::max(u_max, sheet.flat[v][0]);
  }
  EXPECT_NEAR(z_max - z_min, 2 * options.amplitude, 0.02);
  EXPECT_GT(u_max, 1.2 * options.width);
}

TEST(Examples, CylinderAndConeSectionsAreIsometric) {
  expect_isometric_and_ccw(make_cylinder_section(1.0, 2.0, 1.5, 0.05));
  expect_isometric_and_ccw(make_cone_section(0.5, 0.5, 2.0, 2.5, 0.05));
}

TEST(Examples, UFoldedSheetIsIsometricWithItsLayersTheGapApart) {
  const std::vector<Vec2> profile = u_fold_profile(2.0, 0.15, 0.1);
  const DevelopableMesh sheet = make_profile_sheet(profile, 1.0, 0.1);
  expect_isometric_and_ccw(sheet);
  EXPECT_EQ(sheet.mesh.vertex_count() % static_cast<int>(profile.size()), 0);
  double z_min = 1, z_max = -1, x_min = 1;
  for (const Vec3& p : sheet.mesh.positions) {
    z_min = std::min(z_min, p[2]);
    z_max = std::max(z_max, p[2]);
    x_min = std::min(x_min, p[0]);
  }
  EXPECT_DOUBLE_EQ(z_min, 0);
  EXPECT_DOUBLE_EQ(z_max, 0.15);
  EXPECT_NEAR(x_min, -0.075, 1e-12);  // the bend's half circle
}

TEST(Examples, CutDiskHoleLeavesOneSimpleHole) {
  FoldedSheetOptions options;
  options.edge_length = 0.05;
  const DevelopableMesh sheet = make_folded_sheet(options);
  double total_area = 0;
  for (const Tri& f : sheet.mesh.faces) {
    total_area += signed_area(sheet.flat[f[0]], sheet.flat[f[1]], sheet.flat[f[2]]);
  }
  const CutMesh cut = cut_disk_hole(sheet, {2.5, 1.5}, 0.6);
  expect_isometric_and_ccw(cut.cut);
  double kept_area = 0;
  for (const Tri& f : cut.cut.mesh.faces) {
    kept_area += signed_area(cut.cut.flat[f[0]], cut.cut.flat[f[1]], cut.cut.flat[f[2]]);
  }
  EXPECT_NEAR(total_area - kept_area, cut.removed_area, 1e-9);
  EXPECT_NEAR(cut.removed_area, M_PI * 0.6 * 0.6, 0.05);
  EXPECT_EQ(cut.removed_faces + static_cast<int>(cut.cut.mesh.faces.size()),
            static_cast<int>(sheet.mesh.faces.size()));
  // Boundary edges: the outer rectangle's plus the hole's. Euler: a disk with
  // one hole has V - E + F = 0.
  const EdgeTopology topology =
      build_edge_topology(cut.cut.mesh.faces, cut.cut.mesh.vertex_count());
  const long euler = static_cast<long>(cut.cut.mesh.positions.size()) -
                     static_cast<long>(topology.edges.size()) +
                     static_cast<long>(cut.cut.mesh.faces.size());
  EXPECT_EQ(euler, 0);
  EXPECT_GT(boundary_edge_count(cut.cut.mesh), boundary_edge_count(sheet.mesh));
}

}  // namespace
}  // namespace foldfill
