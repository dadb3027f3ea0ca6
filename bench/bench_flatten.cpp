// Times the 2D patch stage (strip extraction + LSCM flattening, then the
// triangulation of the hole polygon) on the reference cases and the cloth
// cases, and prints a markdown table with the patch's size, quality and fit,
// and for the cloth cases its area against the true removed area.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bench_timing.h"
#include "foldfill/error.h"
#include "foldfill/flatten.h"
#include "foldfill/holes.h"
#include "foldfill/io.h"
#include "foldfill/triangulate.h"
#include "support/cloth_cases.h"
#include "support/reference_cases.h"

namespace {

namespace fs = std::filesystem;
using namespace foldfill;

constexpr int kRuns = 5;

struct Case {
  std::string name;
  fs::path mesh;
  int hole_vertex = -1;                // a vertex of the hole loop
  std::optional<double> removed_area;  // cloth cases: the truth
};

std::vector<Case> reference_cases(const fs::path& folder) {
  std::vector<Case> cases;
  for (const auto& entry : foldfill::testing::read_reference_cases(folder))
    cases.push_back({entry.file, entry.path, entry.hole_vertex, std::nullopt});
  return cases;
}

std::vector<Case> cloth_cases(const fs::path& folder) {
  std::vector<Case> cases;
  for (const auto& entry : foldfill::testing::read_cloth_cases(folder))
    cases.push_back({entry.name, entry.hole_mesh, entry.hole_vertex, entry.removed_area});
  return cases;
}

// The hole: the loop through `hole_vertex`, or the one loop that is not the
// longest (the cloth's outer boundary).
BoundaryLoop pick_hole(const std::vector<BoundaryLoop>& loops, const Case& c) {
  const std::vector<int> outer = longest_loops(loops, 1);
  for (const BoundaryLoop& loop : loops) {
    const bool chosen = c.hole_vertex >= 0
                            ? std::find(loop.vertices.begin(), loop.vertices.end(),
                                        c.hole_vertex) != loop.vertices.end()
                            : std::find(outer.begin(), outer.end(), loop.id) == outer.end();
    if (chosen) return loop;
  }
  throw UsageError(c.name + ": no hole loop found");
}

void print_row(const Case& c) {
  const Mesh mesh = read_mesh(c.mesh.string());
  const BoundaryLoop loop = pick_hole(find_boundary_loops(mesh, c.name), c);
  Strip strip;
  Flattening flat;
  const double flatten_ms = bench::median_ms(kRuns, [&] {
    strip = extract_strip(mesh, loop, c.name);
    flat = flatten_strip(strip, c.name);
  });
  const std::vector<Vec2> polygon = hole_polygon(strip, flat);
  FlatPatch patch;
  const double triangulate_ms = bench::median_ms(kRuns, [&] { patch = triangulate_hole(polygon); });

  std::printf("| %s | %d | %zu | %.2f | %.2f | %zu | %zu | %.1f | %.4f | %.2e | %.2e | %.4f |",
              c.name.c_str(), strip.loop_size, strip.faces.size(), flatten_ms, triangulate_ms,
              patch.uv.size(), patch.faces.size(), patch.min_angle_deg, patch.share_below_20deg,
              flat.edge_length_rms_rel, flat.angle_sum_rms, patch.area);
  if (c.removed_area)
    std::printf(" %.4f | %.3f |\n", *c.removed_area, patch.area / *c.removed_area);
  else
    std::printf(" | |\n");
}

}  // namespace

int main() {
  const char* shared = std::getenv("FOLDFILL_SHARED");  // as in the tests
  const fs::path data = fs::path(shared ? shared : FOLDFILL_SHARED_DIR) / "data";
  if (!fs::is_directory(data / "reference") || !fs::is_directory(data / "cloth")) {
    std::printf("bench_flatten: shared data not found in %s; nothing to measure\n",
                data.string().c_str());
    return 0;
  }
  try {
    std::vector<Case> cases = reference_cases(data / "reference");
    const std::vector<Case> cloth = cloth_cases(data / "cloth");
    cases.insert(cases.end(), cloth.begin(), cloth.end());
    std::printf("Flat patch stage, median of %d runs, times in ms\n\n", kRuns);
    std::printf(
        "| case | loop vertices | strip faces | flatten ms | triangulate ms | patch vertices | "
        "patch faces | min angle | share<20deg | edge length RMS rel | angle sum RMS | "
        "flat patch area | removed area | ratio |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const Case& c : cases) print_row(c);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "bench_flatten: %s\n", error.what());
    return 1;
  }
  return 0;
}
