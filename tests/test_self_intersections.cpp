// count_self_intersections and count_subset_crossings against CGAL's
// Polygon_mesh_processing::self_intersections over the whole mesh, and the
// latter's distance against a test of every pair, on randomly crumpled grids.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <iterator>
#include <random>
#include <utility>
#include <vector>

#include "embed/triangle_geometry.h"
#include "foldfill/metrics.h"

namespace foldfill {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;

// The intersecting pairs PMP finds over all faces, counting those with a face
// of index >= counted_from.
int pmp_count(const std::vector<Vec3>& positions, const std::vector<Tri>& faces, int counted_from) {
  SurfaceMesh mesh;
  std::vector<SurfaceMesh::Vertex_index> vertex;
  for (const Vec3& p : positions) vertex.push_back(mesh.add_vertex({p[0], p[1], p[2]}));
  for (const Tri& f : faces) mesh.add_face(vertex[f[0]], vertex[f[1]], vertex[f[2]]);
  std::vector<std::pair<SurfaceMesh::Face_index, SurfaceMesh::Face_index>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(mesh, std::back_inserter(pairs));
  int count = 0;
  for (const auto& [a, b] : pairs)
    count += static_cast<int>(a.idx()) >= counted_from || static_cast<int>(b.idx()) >= counted_from;
  return count;
}

// An (n + 1) x (n + 1) grid: the outer ring of squares first (the "strip"),
// then the inner ones (the "patch"); returns the strip's face count.
int grid(int n, std::vector<Vec3>& positions, std::vector<Tri>& faces) {
  positions.clear();
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) positions.push_back({double(i), double(j), 0.0});
  const auto id = [&](int i, int j) { return i * (n + 1) + j; };
  std::vector<Tri> strip, patch;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      std::vector<Tri>& to = i > 0 && j > 0 && i < n - 1 && j < n - 1 ? patch : strip;
      if ((i + j) % 2) {
        to.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        to.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        to.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        to.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  faces = strip;
  faces.insert(faces.end(), patch.begin(), patch.end());
  return static_cast<int>(strip.size());
}

// The least distance between a face of `subset` and a face that shares no
// vertex with it (0 where they intersect), at most `reach`: every pair.
double brute_force_distance(const std::vector<Vec3>& positions, const std::vector<Tri>& faces,
                            const std::vector<int>& subset, double reach) {
  const auto triangle = [&](const Tri& f) {
    return Kernel::Triangle_3({positions[f[0]][0], positions[f[0]][1], positions[f[0]][2]},
                              {positions[f[1]][0], positions[f[1]][1], positions[f[1]][2]},
                              {positions[f[2]][0], positions[f[2]][1], positions[f[2]][2]});
  };
  double best = reach;
  for (int f : subset)
    for (const Tri& g : faces) {
      const Tri& t = faces[f];
      bool shared = false;
      for (int v : g) shared = shared || v == t[0] || v == t[1] || v == t[2];
      if (shared || triangle(t).is_degenerate() || triangle(g).is_degenerate()) continue;
      const geometry::Triangle a{positions[t[0]], positions[t[1]], positions[t[2]]},
          b{positions[g[0]], positions[g[1]], positions[g[2]]};
      best = std::min(best, CGAL::do_intersect(triangle(t), triangle(g))
                                ? 0.0
                                : geometry::disjoint_triangle_distance(a, b));
    }
  return best;
}

TEST(SelfIntersections, CountEqualsCgalsOnCrumpledGrids) {
  std::mt19937 random(12345);
  std::uniform_int_distribution<int> step(-4, 4);
  std::uniform_real_distribution<double> real(-2, 2);
  int intersecting = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<Vec3> positions;
    std::vector<Tri> faces;
    const int strip_faces = grid(3 + static_cast<int>(random() % 8), positions, faces);
    // Moves by multiples of 1/2 or 1/4 (many exactly coplanar or touching
    // pairs) or by random reals; two thirds of the vertices move.
    const int mode = trial % 3;
    for (Vec3& p : positions) {
      if (random() % 3 == 0) continue;
      for (int c = 0; c < 3; ++c)
        p[c] += mode == 0   ? 0.5 * step(random)
                : mode == 1 ? (c == 2 ? 1.0 : 0.25) * step(random)
                            : real(random);
    }
    if (random() % 2) {  // a vertex onto the midpoint of two others: degenerate faces
      const size_t a = random() % positions.size(), b = random() % positions.size(),
                   c = random() % positions.size();
      for (int k = 0; k < 3; ++k) positions[a][k] = 0.5 * (positions[b][k] + positions[c][k]);
    }
    const int total = static_cast<int>(faces.size());
    for (const int counted_from : {0, strip_faces, total / 2, total}) {
      const int expected = pmp_count(positions, faces, counted_from);
      EXPECT_EQ(count_self_intersections(positions, faces, counted_from), expected)
          << "trial " << trial << ", counted from face " << counted_from;
      intersecting += expected > 0;
      std::vector<int> subset;
      for (int f = counted_from; f < total; ++f) subset.push_back(f);
      const double reach = 1.5;
      const SubsetCrossings crossings = count_subset_crossings(positions, faces, subset, reach);
      EXPECT_EQ(crossings.within + crossings.with_others, expected)
          << "trial " << trial << ", counted from face " << counted_from;
      // From every pair of overlapping closed boxes with a counted face.
      std::vector<std::array<int, 2>> pairs;
      const auto box_of = [&](const Tri& t, int c, bool high) {
        const double a = positions[t[0]][c], b = positions[t[1]][c], d = positions[t[2]][c];
        return high ? std::max({a, b, d}) : std::min({a, b, d});
      };
      for (int f = 0; f < total; ++f)
        for (int g = std::max(f + 1, counted_from); g < total; ++g) {
          bool meet = true;
          for (int c = 0; c < 3; ++c)
            meet = meet && box_of(faces[f], c, false) <= box_of(faces[g], c, true) &&
                   box_of(faces[g], c, false) <= box_of(faces[f], c, true);
          if (meet) pairs.push_back({g, f});
        }
      EXPECT_EQ(any_crossing(positions, faces, counted_from, total, pairs), expected > 0)
          << "trial " << trial << ", counted from face " << counted_from;
      EXPECT_EQ(crossings.within,
                pmp_count(positions, {faces.begin() + counted_from, faces.end()}, 0))
          << "trial " << trial << ", counted from face " << counted_from;
      if (counted_from == strip_faces) {
        EXPECT_NEAR(crossings.min_distance, brute_force_distance(positions, faces, subset, reach),
                    1e-14)
            << "trial " << trial;
      }
    }
  }
  EXPECT_GT(intersecting, 300);  // the comparison is not only of zeros
}

}  // namespace
}  // namespace foldfill
