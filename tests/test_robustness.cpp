// Noisy and awkward hole boundaries (issue 5, part 4): each one either fills
// sanely or is refused with a reason naming the file and the loop.
//
// A sane fill: the input's vertices and faces come out unchanged, the output
// is a manifold whose only open loops are the input's other loops (the hole
// is closed), no new triangle intersects any other, and no new vertex lies
// further from the loop's centroid than the hole's size (no spikes).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/examples.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/metrics.h"
#include "test_geometry.h"

namespace foldfill {
namespace {

constexpr double kEdge = 0.08;  // edge length of the test sheets

DevelopableMesh folded_sheet() { return testing::small_folded_sheet(kEdge); }

// Removes the faces of `sheet` whose flat centroid satisfies `inside`, and
// the vertices left without a face (cut_disk_hole with radius 0 removes no
// face and does just that). Where the boundary touches itself, it stays so.
template <class Inside>
DevelopableMesh cut_where(const DevelopableMesh& sheet, const Inside& inside) {
  DevelopableMesh kept = sheet;
  kept.mesh.faces.clear();
  for (const Tri& f : sheet.mesh.faces) {
    const Vec2 centroid{(sheet.flat[f[0]][0] + sheet.flat[f[1]][0] + sheet.flat[f[2]][0]) / 3,
                        (sheet.flat[f[0]][1] + sheet.flat[f[1]][1] + sheet.flat[f[2]][1]) / 3};
    if (!inside(centroid)) kept.mesh.faces.push_back(f);
  }
  return cut_disk_hole(kept, sheet.flat[0], 0).cut;
}

double flat_width(const DevelopableMesh& sheet) {
  double width = 0;
  for (const Vec2& p : sheet.flat) width = std::max(width, p[0]);
  return width;
}

// The loops the default takes for holes (the sheet's outer edge is not).
std::vector<int> hole_ids(const std::vector<BoundaryLoop>& loops) {
  return select_holes(loops, {}).fill;
}

double distance(const Vec3& a, const Vec3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

// The centroid of the loop as a curve (its edges' midpoints weighted by their
// lengths), which, unlike the mean of its vertices, does not move towards
// where the edges are short.
Vec3 loop_centre(const BoundaryLoop& loop) {
  const size_t n = loop.positions.size();
  Vec3 centre{0, 0, 0};
  double length = 0;
  for (size_t k = 0; k < n; ++k) {
    const Vec3& a = loop.positions[k];
    const Vec3& b = loop.positions[(k + 1) % n];
    const double l = distance(a, b);
    for (int c = 0; c < 3; ++c) centre[c] += l * (a[c] + b[c]) / 2;
    length += l;
  }
  for (double& c : centre) c /= length;
  return centre;
}

// No new vertex may lie further than this times the loop's bounding-box
// diagonal from the loop's centre: a flat disk's rim is at 0.35.
constexpr double kSpikeLimit = 0.6;

// Fills the loop `id` of `mesh` and checks that the fill is sane (see the top).
FillResult expect_sane_fill(const Mesh& mesh, int id, const FillOptions& options = {}) {
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh, "sheet.obj");
  const BoundaryLoop& loop = loops.at(id);
  FillResult result = fill_holes(mesh, loops, {id}, options, "sheet.obj");
  const HoleReport& hole = result.report.holes.at(0);
  EXPECT_TRUE(hole.filled) << hole.reason;
  if (!hole.filled) return result;

  EXPECT_TRUE(
      std::equal(mesh.positions.begin(), mesh.positions.end(), result.mesh.positions.begin()));
  EXPECT_TRUE(std::equal(mesh.faces.begin(), mesh.faces.end(), result.mesh.faces.begin()));
  std::vector<BoundaryLoop> after;
  EXPECT_NO_THROW(after = find_boundary_loops(result.mesh, "filled.obj"));
  EXPECT_EQ(after.size() + 1, loops.size()) << "the hole is not closed";
  for (const BoundaryLoop& open : after)
    EXPECT_NE(open.vertices, loop.vertices) << "the hole is not closed";

  EXPECT_EQ(count_self_intersections(result.mesh.positions, result.mesh.faces, mesh.face_count()),
            0);
  const Vec3 centre = loop_centre(loop);
  double farthest = 0;
  for (int v = mesh.vertex_count(); v < result.mesh.vertex_count(); ++v)
    farthest = std::max(farthest, distance(result.mesh.positions[v], centre));
  EXPECT_LE(farthest, kSpikeLimit * loop.bbox_diagonal) << "a spike";
  EXPECT_TRUE(hole.warning.empty()) << hole.warning;
  return result;
}

// Fills the loop `id`, which the fabric method refuses with `reason`: the
// fallback chain closes it and says why, the original elements unchanged.
void expect_closed_by_fallback(const Mesh& mesh, int id, const std::string& reason) {
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh, "sheet.obj");
  const FillResult result = fill_holes(mesh, loops, {id}, {}, "sheet.obj");
  const HoleReport& hole = result.report.holes.at(0);
  ASSERT_TRUE(hole.filled) << hole.reason;
  ASSERT_FALSE(hole.fallback_reasons.empty());
  EXPECT_NE(hole.fallback_reasons[0].find(reason), std::string::npos) << hole.fallback_reasons[0];
  EXPECT_NE(hole.method, FillMethod::Fabric);
  EXPECT_GT(hole.patch_min_angle_deg, 0);
  EXPECT_TRUE(
      std::equal(mesh.positions.begin(), mesh.positions.end(), result.mesh.positions.begin()));
  EXPECT_TRUE(std::equal(mesh.faces.begin(), mesh.faces.end(), result.mesh.faces.begin()));
  EXPECT_EQ(count_self_intersections(result.mesh.positions, result.mesh.faces, mesh.face_count()),
            0);
}

// The one hole of `mesh` (besides the outer edge).
int only_hole(const Mesh& mesh) {
  const std::vector<int> ids = hole_ids(find_boundary_loops(mesh));
  EXPECT_EQ(ids.size(), 1u);
  return ids.empty() ? -1 : ids[0];
}

// ---- Noise on the strip (Fig. 10 of the paper) -----------------------------------

class NoisyStrip : public ::testing::TestWithParam<double> {};

TEST_P(NoisyStrip, FillsSanely) {
  const Vec2 centre{1.9, 1.0};
  const double radius = 0.5;
  DevelopableMesh cut = cut_disk_hole(folded_sheet(), centre, radius).cut;
  // Every vertex within three edges of the hole moves by up to the given
  // share of the edge length in each coordinate.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-GetParam() * kEdge, GetParam() * kEdge);
  for (size_t v = 0; v < cut.flat.size(); ++v) {
    if (std::hypot(cut.flat[v][0] - centre[0], cut.flat[v][1] - centre[1]) > radius + 3 * kEdge)
      continue;
    for (double& x : cut.mesh.positions[v]) x += jitter(random);
  }
  expect_sane_fill(cut.mesh, only_hole(cut.mesh));
}

INSTANTIATE_TEST_SUITE_P(ShareOfEdgeLength, NoisyStrip, ::testing::Values(0.05, 0.1, 0.2));

// ---- A loop that nearly touches itself ------------------------------------------

// A C-shaped hole: a ring sector whose two tips are `gap` apart (flat).
DevelopableMesh c_shaped_hole(double gap) {
  const Vec2 centre{1.9, 1.0};
  const double inner = 0.25, outer = 0.6;
  const double half_gap_angle = std::asin(gap / 2 / inner);
  return cut_where(folded_sheet(), [&](const Vec2& p) {
    const double r = std::hypot(p[0] - centre[0], p[1] - centre[1]);
    const double angle = std::atan2(p[1] - centre[1], p[0] - centre[0]);
    return r > inner && r < outer && std::abs(angle) > half_gap_angle;
  });
}

// The smallest distance between loop vertices a quarter of the loop apart.
double closest_approach(const BoundaryLoop& loop) {
  const size_t n = loop.positions.size();
  double closest = INFINITY;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + n / 4; j + n / 4 < i + n; ++j)
      closest = std::min(closest, distance(loop.positions[i], loop.positions[j % n]));
  return closest;
}

TEST(NearlyTouchingLoop, CShapedHoleFills) {
  const DevelopableMesh cut = c_shaped_hole(3 * kEdge);
  expect_sane_fill(cut.mesh, only_hole(cut.mesh));
}

// The faces around such a loop bridge the gap between the tips: they are not
// an annulus but a ring with an island, still flat and still fillable.
TEST(NearlyTouchingLoop, CShapedHoleWhoseTipsComeWithinAnEdgeFills) {
  const DevelopableMesh cut = c_shaped_hole(0.5 * kEdge);
  const int id = only_hole(cut.mesh);
  EXPECT_LT(closest_approach(find_boundary_loops(cut.mesh).at(id)), 1.5 * kEdge);
  expect_sane_fill(cut.mesh, id);
}

// Where the tips touch, the boundary passes that vertex twice: it is split
// there into the C's outline and the small hole left between the tips, each a
// disk boundary of its own. The C's strip pinches where its tips nearly meet,
// so it is refused with that reason.
TEST(NearlyTouchingLoop, CShapedHoleWhoseTipsTouchIsSplitThere) {
  const DevelopableMesh cut = c_shaped_hole(1.5 * kEdge);
  const std::vector<BoundaryLoop> loops = find_boundary_loops(cut.mesh);
  ASSERT_EQ(loops.size(), 3u);
  const std::vector<int> holes = hole_ids(loops);
  ASSERT_EQ(holes.size(), 2u);
  const int c = loops[holes[0]].length > loops[holes[1]].length ? holes[0] : holes[1];
  ASSERT_EQ(loops[c].split_at.size(), 1u);
  const int v = loops[c].split_at[0];
  const auto tips = std::find_if(loops.begin(), loops.end(), [&](const BoundaryLoop& loop) {
    return loop.id != c && loop.split_at == std::vector<int>{v};
  });
  ASSERT_NE(tips, loops.end());
  EXPECT_TRUE(loops[c].is_disk);
  EXPECT_TRUE(tips->is_disk);
  EXPECT_LT(tips->length, loops[c].length / 10);
  EXPECT_TRUE(select_holes(loops, {}).warnings.empty());
  expect_closed_by_fallback(cut.mesh, c, "pinch at vertex");
}

// A keyhole: a disk with a slot one or two edges wide running out of it.
TEST(NearlyTouchingLoop, KeyholeFills) {
  const Vec2 centre{1.9, 1.0};
  const DevelopableMesh cut = cut_where(folded_sheet(), [&](const Vec2& p) {
    const bool disk = std::hypot(p[0] - centre[0], p[1] - centre[1]) < 0.3;
    const bool slot =
        p[0] > centre[0] && p[0] < centre[0] + 0.7 && std::abs(p[1] - centre[1]) < 0.6 * kEdge;
    return disk || slot;
  });
  expect_sane_fill(cut.mesh, only_hole(cut.mesh));
}

// ---- Next to the outer edge -----------------------------------------------------

// The sheet without the faces `removed` (indices into its faces).
Mesh without_faces(const Mesh& mesh, std::vector<int> removed) {
  std::sort(removed.begin(), removed.end(), std::greater<int>());
  Mesh result = mesh;
  for (int f : removed) result.faces.erase(result.faces.begin() + f);
  return result;
}

// A hole whose loop comes within `rings` edges of the sheet's left edge.
DevelopableMesh hole_near_the_edge(int rings) {
  const double radius = 0.4;
  return cut_disk_hole(folded_sheet(), {radius + (rings + 0.5) * kEdge, 1.0}, radius).cut;
}

// A face with an edge on the outer loop and its third vertex on the hole's
// loop (so the hole is one ring from the outer edge), or -1.
int bridge_face(const Mesh& mesh) {
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
  const int hole = only_hole(mesh), outer = 1 - hole;
  const auto on = [&](int id, int v) {
    const std::vector<int>& vertices = loops[id].vertices;
    return std::find(vertices.begin(), vertices.end(), v) != vertices.end();
  };
  const auto bridge = std::find_if(mesh.faces.begin(), mesh.faces.end(), [&](const Tri& f) {
    return on(outer, f[0]) + on(outer, f[1]) + on(outer, f[2]) == 2 &&
           on(hole, f[0]) + on(hole, f[1]) + on(hole, f[2]) == 1;
  });
  return bridge == mesh.faces.end() ? -1 : static_cast<int>(bridge - mesh.faces.begin());
}

TEST(NextToTheOuterEdge, OneRingAwayFills) {
  const Mesh mesh = hole_near_the_edge(1).mesh;
  ASSERT_GE(bridge_face(mesh), 0);
  expect_sane_fill(mesh, only_hole(mesh));
}

TEST(NextToTheOuterEdge, TwoRingsAwayFills) {
  const Mesh mesh = hole_near_the_edge(2).mesh;
  EXPECT_LT(bridge_face(mesh), 0);
  expect_sane_fill(mesh, only_hole(mesh));
}

// One ring away, less a face that bridges the ring: the hole's boundary and
// the outer one then meet at that face's vertex on the hole, and the boundary
// runs through it twice. It is split there: the hole is a loop of its own,
// chosen by the default (the outer edge is the longest), and filled.
TEST(NextToTheOuterEdge, AHoleTouchingItAtOneVertexIsSplitOffAndFilled) {
  const Mesh mesh = hole_near_the_edge(1).mesh;
  const int bridge = bridge_face(mesh);
  ASSERT_GE(bridge, 0);
  const Mesh touching = without_faces(mesh, {bridge});
  const std::vector<BoundaryLoop> loops = find_boundary_loops(touching);
  ASSERT_EQ(loops.size(), 2u);
  const HoleChoice choice = select_holes(loops, {});
  ASSERT_EQ(choice.fill.size(), 1u);
  const BoundaryLoop& hole = loops[choice.fill[0]];
  const BoundaryLoop& outer = loops[1 - choice.fill[0]];
  EXPECT_TRUE(hole.is_disk);
  EXPECT_TRUE(outer.is_disk);
  EXPECT_TRUE(turns_like_a_hole(hole));
  EXPECT_FALSE(turns_like_a_hole(outer));
  ASSERT_EQ(hole.split_at.size(), 1u);
  EXPECT_EQ(hole.split_at, outer.split_at);
  EXPECT_TRUE(choice.warnings.empty());
  expect_sane_fill(touching, choice.fill[0]);
}

// ---- Uneven edge lengths ----------------------------------------------------------

// Splits each loop edge (a, b) of loop `loop` for k in [first, last) into
// `pieces` edges, replacing the face on the edge by a fan from its third vertex.
Mesh split_loop_edges(const Mesh& mesh, const BoundaryLoop& loop, int first, int last, int pieces) {
  Mesh split = mesh;
  const int n = static_cast<int>(loop.vertices.size());
  for (int k = first; k < last; ++k) {
    const int a = loop.vertices[k], b = loop.vertices[(k + 1) % n];
    // The face on the boundary edge has it as b -> a (the loop runs against the faces).
    const auto face = std::find_if(split.faces.begin(), split.faces.end(), [&](const Tri& f) {
      for (int c = 0; c < 3; ++c)
        if (f[c] == b && f[(c + 1) % 3] == a) return true;
      return false;
    });
    EXPECT_NE(face, split.faces.end());
    const Tri old = *face;
    int c = 0;
    while (old[c] != b) ++c;
    const int apex = old[(c + 2) % 3];
    split.faces.erase(face);
    int previous = b;
    for (int p = 1; p <= pieces; ++p) {
      int next = a;
      if (p < pieces) {
        const double t = static_cast<double>(p) / pieces;
        const Vec3 &pb = mesh.positions[b], &pa = mesh.positions[a];
        split.positions.push_back({pb[0] + t * (pa[0] - pb[0]), pb[1] + t * (pa[1] - pb[1]),
                                   pb[2] + t * (pa[2] - pb[2])});
        next = split.vertex_count() - 1;
      }
      split.faces.push_back({previous, next, apex});
      previous = next;
    }
  }
  return split;
}

TEST(UnevenEdges, OneSideSplitIntoTinyEdgesFills) {
  const DevelopableMesh cut = cut_disk_hole(folded_sheet(), {1.9, 1.0}, 0.5).cut;
  const std::vector<BoundaryLoop> loops = find_boundary_loops(cut.mesh);
  const BoundaryLoop& loop = loops.at(only_hole(cut.mesh));
  const int n = static_cast<int>(loop.vertices.size());
  const Mesh split = split_loop_edges(cut.mesh, loop, 0, n / 4, 10);
  const FillResult result = expect_sane_fill(split, only_hole(split));
  EXPECT_EQ(result.report.holes.at(0).loop_vertex_count, n + (n / 4) * 9);
}

// ---- Tiny holes -------------------------------------------------------------------

// The faces around the vertex nearest the sheet's middle, in fan order.
std::vector<int> middle_fan(const DevelopableMesh& sheet) {
  Vec2 middle{flat_width(sheet) / 2, 1.0};
  int centre = 0;
  for (int v = 0; v < sheet.mesh.vertex_count(); ++v)
    if (std::hypot(sheet.flat[v][0] - middle[0], sheet.flat[v][1] - middle[1]) <
        std::hypot(sheet.flat[centre][0] - middle[0], sheet.flat[centre][1] - middle[1]))
      centre = v;
  std::vector<int> around;
  for (int f = 0; f < sheet.mesh.face_count(); ++f) {
    const Tri& t = sheet.mesh.faces[f];
    if (t[0] == centre || t[1] == centre || t[2] == centre) around.push_back(f);
  }
  // Order the fan: each face's edge leaving the centre is the next one's edge entering it.
  const auto after = [&](int f) {
    const Tri& t = sheet.mesh.faces[f];
    int c = 0;
    while (t[c] != centre) ++c;
    return t[(c + 1) % 3];
  };
  const auto before = [&](int f) {
    const Tri& t = sheet.mesh.faces[f];
    int c = 0;
    while (t[c] != centre) ++c;
    return t[(c + 2) % 3];
  };
  for (size_t k = 1; k < around.size(); ++k) {
    const auto next = std::find_if(around.begin() + k, around.end(),
                                   [&](int f) { return after(f) == before(around[k - 1]); });
    std::iter_swap(around.begin() + k, next);
  }
  return around;
}

class TinyHole : public ::testing::TestWithParam<int> {};

TEST_P(TinyHole, Fills) {
  const DevelopableMesh sheet = folded_sheet();
  const std::vector<int> fan = middle_fan(sheet);
  ASSERT_GE(fan.size(), 4u);
  const int faces_removed = GetParam();
  const Mesh mesh =
      without_faces(sheet.mesh, std::vector<int>(fan.begin(), fan.begin() + faces_removed));
  const int id = only_hole(mesh);
  ASSERT_GE(id, 0);
  EXPECT_EQ(find_boundary_loops(mesh)[id].vertices.size(), static_cast<size_t>(faces_removed + 2));
  expect_sane_fill(mesh, id);
}

// One missing triangle (3 loop vertices), two (a quad), three (5 vertices).
INSTANTIATE_TEST_SUITE_P(MissingFanTriangles, TinyHole, ::testing::Values(1, 2, 3));

}  // namespace
}  // namespace foldfill
