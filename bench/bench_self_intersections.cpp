// Times foldfill's self-intersection tests (count_self_intersections, which
// every minimisation of a fill ends with, and passes_through_itself, which
// looks at minimisations early) against CGAL's
// Polygon_mesh_processing::self_intersections, the baseline, on generated
// folded sheets and prints a markdown table. Three states of each sheet: as
// made (exactly developable, so that neighbouring triangles are coplanar up
// to rounding and the exact predicates' filters often fail, as on flat parts
// of a scan), every vertex moved by up to 1% of an edge (in general position,
// like a minimised patch), and crumpled by up to 60% of an edge (tangled).
// The counts must agree: the program fails otherwise.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <cstdio>
#include <iterator>
#include <random>
#include <utility>
#include <vector>

#include "bench_timing.h"
#include "foldfill/examples.h"
#include "foldfill/metrics.h"

namespace {

using namespace foldfill;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;

constexpr int kRuns = 7;

SurfaceMesh surface_mesh(const Mesh& mesh) {
  SurfaceMesh result;
  std::vector<SurfaceMesh::Vertex_index> vertex;
  for (const Vec3& p : mesh.positions) vertex.push_back(result.add_vertex({p[0], p[1], p[2]}));
  for (const Tri& f : mesh.faces) result.add_face(vertex[f[0]], vertex[f[1]], vertex[f[2]]);
  return result;
}

// Every vertex moved at random by up to `reach` along each axis (none for 0).
Mesh crumpled(Mesh mesh, double reach) {
  if (reach == 0) return mesh;
  std::mt19937 random(17);
  std::uniform_real_distribution<double> shift(-reach, reach);
  for (Vec3& p : mesh.positions)
    for (double& x : p) x += shift(random);
  return mesh;
}

bool run_case(const char* name, const Mesh& mesh) {
  const SurfaceMesh cgal_mesh = surface_mesh(mesh);
  std::vector<std::pair<SurfaceMesh::Face_index, SurfaceMesh::Face_index>> pairs;
  const double cgal_ms = bench::median_ms(kRuns, [&] {
    pairs.clear();
    CGAL::Polygon_mesh_processing::self_intersections(cgal_mesh, std::back_inserter(pairs));
  });
  int count = 0;
  const double count_ms = bench::median_ms(
      kRuns, [&] { count = count_self_intersections(mesh.positions, mesh.faces); });
  bool passes = false;
  const double passes_ms =
      bench::median_ms(kRuns, [&] { passes = passes_through_itself(mesh.positions, mesh.faces); });
  std::printf("| %s | %zu | %d | %.2f | %.2f | %.1fx | %s | %.2f |\n", name, mesh.faces.size(),
              count, cgal_ms, count_ms, cgal_ms / count_ms, passes ? "yes" : "no", passes_ms);
  if (count == static_cast<int>(pairs.size())) return true;
  std::fprintf(stderr, "%s: %d pairs, CGAL finds %zu\n", name, count, pairs.size());
  return false;
}

}  // namespace

int main() {
  std::printf("medians of %d runs, one thread\n\n", kRuns);
  std::printf(
      "| sheet | faces | intersecting pairs | CGAL ms | count ms | speed-up | passes through "
      "| passes_through_itself ms |\n|---|---|---|---|---|---|---|---|\n");
  bool agree = true;
  for (const double edge : {0.1, 0.033, 0.02}) {
    FoldedSheetOptions options;
    options.edge_length = edge;
    options.folds = 6;
    options.amplitude = 0.3;
    const Mesh folded = make_folded_sheet(options).mesh;
    for (const double reach : {0.0, 0.01, 0.6}) {
      char name[64];
      std::snprintf(name, sizeof name, "edge %g, moved by %g edge", edge, reach);
      agree = run_case(name, crumpled(folded, reach * edge)) && agree;
    }
  }
  return agree ? 0 : 1;
}
