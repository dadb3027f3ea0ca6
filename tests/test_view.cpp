// The page of `foldfill view`: curvatures, which hole each face fills, the
// binary buffers and what the page holds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "foldfill/error.h"
#include "foldfill/holes.h"
#include "foldfill/test_surfaces.h"
#include "foldfill/view.h"

namespace foldfill {
namespace {

// An n x n grid of unit squares in the plane z = 0, two triangles each.
Mesh grid(int n) {
  Mesh mesh;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) mesh.positions.push_back({double(x), double(y), 0});
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const int a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
      mesh.faces.push_back({a, b, d});
      mesh.faces.push_back({a, d, c});
    }
  }
  return mesh;
}

// The grid without the faces `removed`, then those faces appended: a fill
// that keeps the input's elements first, as foldfill's do.
struct CutAndFilled {
  Mesh input, filled;
};
CutAndFilled cut_and_fill(int n, const std::vector<int>& removed) {
  const Mesh whole = grid(n);
  CutAndFilled out;
  out.input.positions = whole.positions;
  for (int f = 0; f < whole.face_count(); ++f) {
    if (std::find(removed.begin(), removed.end(), f) == removed.end())
      out.input.faces.push_back(whole.faces[f]);
  }
  out.filled = out.input;
  for (int f : removed) out.filled.faces.push_back(whole.faces[f]);
  return out;
}

double median(std::vector<float> values) {
  values.erase(
      std::remove_if(values.begin(), values.end(), [](float v) { return !std::isfinite(v); }),
      values.end());
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

TEST(Curvature, UnitSphereHasGaussianAndMeanCurvatureOne) {
  const Mesh sphere = make_holed_sphere().mesh;
  const Curvatures c = vertex_curvatures(sphere);
  ASSERT_EQ(c.gaussian.size(), sphere.positions.size());
  EXPECT_NEAR(median(c.gaussian), 1.0, 0.1);
  EXPECT_NEAR(median(c.mean), 1.0, 0.1);
}

TEST(Curvature, PlaneIsFlatAndItsBoundaryHasNone) {
  const Mesh plane = grid(4);
  const Curvatures c = vertex_curvatures(plane);
  for (int v = 0; v < plane.vertex_count(); ++v) {
    const bool boundary = plane.positions[v][0] == 0 || plane.positions[v][0] == 4 ||
                          plane.positions[v][1] == 0 || plane.positions[v][1] == 4;
    if (boundary) {
      EXPECT_TRUE(std::isnan(c.gaussian[v])) << v;
      EXPECT_TRUE(std::isnan(c.mean[v])) << v;
    } else {
      EXPECT_NEAR(c.gaussian[v], 0, 1e-9) << v;
      EXPECT_NEAR(c.mean[v], 0, 1e-9) << v;
    }
  }
}

TEST(FaceHoles, NewFacesTakeTheLoopTheyClose) {
  // Two holes in a 6 x 6 grid: the square at (1, 1) and the square at (4, 4).
  const CutAndFilled mesh =
      cut_and_fill(6, {2 * (1 * 6 + 1), 2 * (1 * 6 + 1) + 1, 2 * (4 * 6 + 4), 2 * (4 * 6 + 4) + 1});
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh.input);
  ASSERT_EQ(loops.size(), 3u);  // the outer edge and the two holes
  std::vector<std::vector<int>> vertices;
  std::vector<int> ids;
  for (const BoundaryLoop& loop : loops) {
    vertices.push_back(loop.vertices);
    ids.push_back(loop.id);
  }
  const std::vector<int> holes = face_holes(mesh.filled, mesh.input.face_count(), vertices, ids);
  ASSERT_EQ(holes.size(), mesh.filled.faces.size());
  for (int f = 0; f < mesh.input.face_count(); ++f) EXPECT_EQ(holes[f], -1);
  const int first = mesh.input.face_count();
  auto loop_through = [&](int vertex) {
    for (const BoundaryLoop& loop : loops)
      if (std::count(loop.vertices.begin(), loop.vertices.end(), vertex)) return loop.id;
    return -99;
  };
  EXPECT_EQ(holes[first], loop_through(1 * 7 + 1));
  EXPECT_EQ(holes[first + 1], holes[first]);
  EXPECT_EQ(holes[first + 2], loop_through(4 * 7 + 4));
  EXPECT_EQ(holes[first + 3], holes[first + 2]);
  EXPECT_NE(holes[first], holes[first + 2]);
  // Without the loops the holes are not known.
  EXPECT_EQ(face_holes(mesh.filled, first, {}, {})[first], kUnknownHole);
}

TEST(FaceHoles, MarksWin) {
  CutAndFilled mesh = cut_and_fill(3, {0, 1});
  mesh.filled.face_hole.assign(mesh.filled.faces.size(), -1);
  mesh.filled.face_hole.back() = 7;
  const std::vector<int> holes = face_holes(mesh.filled, mesh.input.face_count(), {}, {});
  EXPECT_EQ(holes.back(), 7);
  EXPECT_EQ(holes[holes.size() - 2], -1);
}

TEST(Base64, Rfc4648Vectors) {
  const std::string text = "foobar";
  const char* expected[] = {"", "Zg==", "Zm8=", "Zm9v", "Zm9vYg==", "Zm9vYmE=", "Zm9vYmFy"};
  for (size_t n = 0; n <= text.size(); ++n) EXPECT_EQ(base64(text.data(), n), expected[n]);
}

// The JSON header of a page.
nlohmann::json page_meta(const std::string& page) {
  const std::string open = "<script type=\"application/json\" id=\"foldfill-meta\">";
  const size_t from = page.find(open) + open.size();
  return nlohmann::json::parse(page.substr(from, page.find("</script>", from) - from));
}

TEST(ViewPage, AFillThatStartsWithTheInputSharesItsBuffers) {
  const CutAndFilled mesh = cut_and_fill(8, {2 * (3 * 8 + 3), 2 * (3 * 8 + 3) + 1});
  ViewOptions options;
  options.title = "a </script> title";
  options.report = {{"output", "filled.obj"},
                    {"holes", {{{"loop_id", 1}, {"filled", true}, {"seconds", {{"total", 0.5}}}}}}};
  if (!view_available()) {
    EXPECT_THROW(view_page({"in.obj", &mesh.input}, {}, options), Error);
    GTEST_SKIP() << kViewUnavailable;
  }
  const std::string page = view_page({"in.obj", &mesh.input}, {{"out.obj", &mesh.filled}}, options);
  EXPECT_EQ(page.find("a </script> title"), std::string::npos);
  EXPECT_NE(page.find("<title>a &lt;/script&gt; title</title>"), std::string::npos);
  const nlohmann::json meta = page_meta(page);
  EXPECT_EQ(meta["title"], "a </script> title");
  ASSERT_EQ(meta["meshes"].size(), 2u);
  const nlohmann::json& in = meta["meshes"][0];
  const nlohmann::json& out = meta["meshes"][1];
  EXPECT_EQ(in["positions"]["offset"], out["positions"]["offset"]);
  EXPECT_EQ(in["positions"]["length"], mesh.input.vertex_count() * 3);
  EXPECT_EQ(in["index"]["offset"], out["index"]["offset"]);
  EXPECT_EQ(in["index"]["length"], mesh.input.face_count() * 3);
  EXPECT_EQ(out["index"]["length"], mesh.filled.face_count() * 3);
  EXPECT_TRUE(out["shows_loops"]);
  // The new faces are one group, after the input's.
  ASSERT_EQ(out["groups"].size(), 2u);
  EXPECT_EQ(out["groups"][0]["hole"], -1);
  EXPECT_EQ(out["groups"][1]["count"], 2);
  EXPECT_EQ(meta["holes"].size(), 1u);
  EXPECT_EQ(meta["holes"][0], out["groups"][1]["hole"]);
  EXPECT_EQ(meta["loops"].size(), 2u);
  ASSERT_EQ(meta["report"].size(), 1u);
  EXPECT_EQ(meta["report"][0]["seconds"], 0.5);
  // Positions and faces once, with the curvature bytes and the loops.
  const size_t blob = meta["blob_size"];
  EXPECT_LT(blob, size_t(mesh.filled.vertex_count()) * 12 + size_t(mesh.filled.face_count()) * 12 +
                      size_t(mesh.filled.vertex_count()) * 4 + 1000);
}

TEST(ViewPage, AnotherMeshHasItsOwnBuffersAndNoLoops) {
  if (!view_available()) GTEST_SKIP() << kViewUnavailable;
  const Mesh a = grid(3), b = grid(4);
  const nlohmann::json meta = page_meta(view_page({"a.obj", &a}, {{"b.obj", &b}}, {}));
  EXPECT_NE(meta["meshes"][0]["positions"]["offset"], meta["meshes"][1]["positions"]["offset"]);
  EXPECT_FALSE(meta["meshes"][1]["shows_loops"]);
  EXPECT_TRUE(meta["holes"].empty());
}

}  // namespace
}  // namespace foldfill
