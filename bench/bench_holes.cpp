// Every hole of the test surfaces (test_surfaces.h) with the default
// selection and settings, against CGAL's Liepa fill of the same holes:
// holes, how many each method of the chain filled, loops left open, time,
// and Liepa's time and count. Then many small holes: a statue-like blob with
// `--holes N` holes of 3 to 60 vertices, medians over `--runs` runs.
//
//   bench_holes [--runs 5] [--holes 200]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "bench_timing.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/liepa.h"
#include "foldfill/test_surfaces.h"

using namespace foldfill;

namespace {

struct Row {
  std::string name;
  HoledSurface surface;
};

struct Outcome {
  int holes = 0, left_open = 0, closed = 0, crossing = 0;
  std::map<FillMethod, int> methods;
  std::map<FillMethod, double> seconds;  // summed over the holes (they run in parallel)
  double min_angle = 180;
};

Outcome count(const FillResult& result, const HoleChoice& choice) {
  Outcome o;
  o.holes = static_cast<int>(choice.fill.size());
  o.left_open = static_cast<int>(choice.left_open.size());
  for (const HoleReport& hole : result.report.holes) {
    if (!hole.filled) continue;
    ++o.closed;
    ++o.methods[hole.method];
    o.seconds[hole.method] += hole.seconds.total;
    o.crossing += hole.crossings.total() > 0;
    o.min_angle = std::min(o.min_angle, hole.patch_min_angle_deg);
  }
  return o;
}

std::string methods_text(const Outcome& o) {
  std::string text;
  for (const auto& [method, n] : o.methods)
    text += (text.empty() ? "" : ", ") + std::string(to_string(method)) + " " + std::to_string(n) +
            " in " + std::to_string(static_cast<int>(1000 * o.seconds.at(method))) + " ms";
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 5, many = 200;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--runs")) runs = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--holes")) many = std::atoi(argv[i + 1]);
  }
  BlobSurfaceOptions blob;
  blob.subdivisions = 7;
  blob.holes = many;
  std::vector<Row> rows;
  rows.push_back({"sphere (65 deg cap + 3 small)", make_holed_sphere()});
  rows.push_back({"torus (outside, inside, top)", make_holed_torus()});
  rows.push_back({"blob, 60 holes of 3-60 vertices", make_holed_blob()});
  rows.push_back({"sleeve, hole longer than its ends", make_holed_sleeve()});
  rows.push_back({"sheet, hole longer than its edge", make_sheet_with_long_hole()});
  rows.push_back({"dome, hole near the top", make_holed_dome()});
  rows.push_back({"box, 4-vertex corner hole", make_box_with_corner_hole()});
  rows.push_back({"sheet, holes of 3, 4, 5 vertices", make_sheet_with_small_holes()});
  rows.push_back({"ruffle, C-shaped slot", make_ruffle_with_c_slot()});
  rows.push_back(
      {"blob, " + std::to_string(many) + " holes of 3-60 vertices", make_holed_blob(blob)});

  std::printf(
      "| surface | holes | filled (method) | left open | crossing | min angle | foldfill ms "
      "| Liepa closed | Liepa ms | ratio |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& row : rows) {
    const Mesh& mesh = row.surface.mesh;
    const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
    const HoleChoice choice = select_holes(loops, HoleSelection{});
    FillResult ours, liepa;
    const double ours_ms =
        bench::median_ms(runs, [&] { ours = fill_holes(mesh, loops, choice.fill); });
    const double liepa_ms =
        bench::median_ms(runs, [&] { liepa = fill_holes_liepa(mesh, loops, choice.fill); });
    const Outcome o = count(ours, choice), l = count(liepa, choice);
    std::printf("| %s | %d | %d (%s) | %d | %d | %.1f | %.0f | %d | %.0f | %.2f |\n",
                row.name.c_str(), o.holes, o.closed, methods_text(o).c_str(), o.left_open,
                o.crossing, o.min_angle, ours_ms, l.closed, liepa_ms, ours_ms / liepa_ms);
    std::fflush(stdout);
  }
  return 0;
}
