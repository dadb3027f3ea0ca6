// Whole-fill benchmark: for every reference case and every cloth case, the
// time per stage (median of several runs), iterations and final energy of the
// fast solver and of the paper's gradient descent, and the time of CGAL's
// Liepa fill of the same hole; then the time against patch size on generated
// sheets. Prints markdown.
//
//   build/bench/bench_fill [--runs 5] [--gd-runs 3] [--max-patch 100000] [--skip-gd]
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "foldfill/examples.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/io.h"
#include "foldfill/liepa.h"
#include "foldfill/obstacles.h"

namespace fs = std::filesystem;
using namespace foldfill;

namespace {

struct Case {
  std::string name;
  Mesh mesh;
  std::vector<BoundaryLoop> loops;
  int hole = -1;
  FillOptions options;
};

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

int loop_containing(const std::vector<BoundaryLoop>& loops, int vertex) {
  for (const BoundaryLoop& loop : loops) {
    if (std::find(loop.vertices.begin(), loop.vertices.end(), vertex) != loop.vertices.end()) return loop.id;
  }
  return -1;
}

std::vector<Case> reference_cases(const fs::path& shared) {
  std::vector<Case> cases;
  const fs::path dir = shared / "data" / "reference";
  std::ifstream in(dir / "cases.json");
  if (!in) return cases;
  for (const auto& c : nlohmann::json::parse(in)["cases"]) {
    Case k;
    k.name = c["file"].get<std::string>();
    k.mesh = read_mesh((dir / k.name).string());
    k.loops = find_boundary_loops(k.mesh, k.name);
    k.hole = loop_containing(k.loops, c["hole_vertex"]);
    PrototypeWeights weights;
    weights.alpha = c["prototype"]["alpha"];
    weights.beta = c["prototype"]["beta"];
    weights.mu = c["prototype"]["mu"];
    k.options.prototype = weights;
    if (c["prototype"]["bending"] == "two_ring") k.options.energy.bending = BendingModel::TwoRing;
    k.options.obstacles = parse_obstacles(nlohmann::json{{"obstacles", c["obstacles"]}}.dump(), k.name);
    cases.push_back(std::move(k));
  }
  return cases;
}

std::vector<Case> cloth_cases(const fs::path& shared) {
  std::vector<Case> cases;
  const fs::path dir = shared / "data" / "cloth";
  std::ifstream in(dir / "manifest.json");
  if (!in) return cases;
  for (const auto& c : nlohmann::json::parse(in)) {
    Case k;
    k.name = c["case"].get<std::string>();
    k.mesh = read_mesh((dir / (k.name + "_hole.obj")).string());
    k.loops = find_boundary_loops(k.mesh, k.name);
    std::ifstream meta(dir / (k.name + ".json"));
    const int first = nlohmann::json::parse(meta)["hole_boundary"]["loop_hole_indices"][0];
    k.hole = loop_containing(k.loops, first);
    cases.push_back(std::move(k));
  }
  return cases;
}

struct Timing {
  StageSeconds seconds;  // medians
  HoleReport last;
};

Timing time_fill(const Case& c, const FillOptions& options, int runs) {
  std::vector<double> flatten, triangulate, arap, optimize, total;
  Timing timing;
  for (int r = 0; r < runs; ++r) {
    const FillResult result = fill_holes(c.mesh, c.loops, {c.hole}, options, c.name);
    timing.last = result.report.holes.at(0);
    const StageSeconds& s = timing.last.seconds;
    flatten.push_back(s.flatten);
    triangulate.push_back(s.triangulate);
    arap.push_back(s.arap);
    optimize.push_back(s.optimize);
    total.push_back(s.total);
  }
  timing.seconds = {median(flatten), median(triangulate), median(arap), median(optimize), median(total)};
  return timing;
}

double time_liepa(const Case& c, int runs) {
  std::vector<double> seconds;
  for (int r = 0; r < runs; ++r) {
    seconds.push_back(fill_holes_liepa(c.mesh, c.loops, {c.hole}, c.name).report.holes.at(0).seconds.total);
  }
  return median(seconds);
}

void print_case_table(const std::vector<Case>& cases, int runs, int gd_runs) {
  std::printf(
      "| case | loop | patch verts | flatten ms | triangulate ms | ARAP ms | optimize ms | total ms | "
      "iters | E final | GD total ms | GD iters | GD stop | E GD | E/E_GD | speed-up | Liepa ms | "
      "total / Liepa |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Case& c : cases) {
    if (c.hole < 0) {
      std::printf("| %s | hole loop not found |\n", c.name.c_str());
      continue;
    }
    const Timing fast = time_fill(c, c.options, runs);
    if (!fast.last.filled) {
      std::printf("| %s | failed: %s |\n", c.name.c_str(), fast.last.reason.c_str());
      continue;
    }
    const double liepa = time_liepa(c, runs);
    const StageSeconds& s = fast.seconds;
    std::printf("| %s | %d | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %d | %.6g |", c.name.c_str(),
                fast.last.loop_vertex_count, fast.last.patch_vertex_count, 1e3 * s.flatten,
                1e3 * s.triangulate, 1e3 * s.arap, 1e3 * s.optimize, 1e3 * s.total,
                fast.last.iterations, fast.last.energy_final.total);
    if (gd_runs > 0) {
      FillOptions gd_options = c.options;
      gd_options.solver.kind = SolverKind::GradientDescent;
      gd_options.solver.max_iterations = 200000;
      const Timing gd = time_fill(c, gd_options, gd_runs);
      std::printf(" %.1f | %d | %s | %.6g | %.4f | %.1fx |", 1e3 * gd.seconds.total, gd.last.iterations,
                  gd.last.stop_reason.c_str(), gd.last.energy_final.total,
                  fast.last.energy_final.total / gd.last.energy_final.total,
                  gd.seconds.total / s.total);
    } else {
      std::printf(" - | - | - | - | - | - |");
    }
    std::printf(" %.1f | %.1fx |\n", 1e3 * liepa, s.total / liepa);
    std::fflush(stdout);
  }
}

// Time against patch size: a folded sheet whose resolution grows, with a hole
// of fixed size, so the patch has about `target` vertices.
void print_scaling_table(int max_patch, int runs) {
  std::printf("\n| target patch verts | patch verts | loop verts | flatten ms | triangulate ms | ARAP ms | "
              "optimize ms | total ms | iters | ms per 1k patch verts |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (int target : {1000, 3000, 10000, 30000, 100000}) {
    if (target > max_patch) break;
    const double radius = 0.8;
    FoldedSheetOptions sheet;
    sheet.width = 3;
    sheet.height = 2.4;
    sheet.folds = 3;
    sheet.amplitude = 0.15;
    sheet.edge_length = std::sqrt(M_PI * radius * radius / (0.866 * target));
    Case c;
    c.name = "sheet";
    c.mesh = cut_disk_hole(make_folded_sheet(sheet), {1.9, 1.2}, radius).cut.mesh;
    c.loops = find_boundary_loops(c.mesh);
    c.hole = select_holes(c.loops, HoleSelection{}).fill.at(0);
    const Timing t = time_fill(c, c.options, target >= 30000 ? 1 : runs);
    const StageSeconds& s = t.seconds;
    std::printf("| %d | %d | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %d | %.2f |\n", target,
                t.last.patch_vertex_count, t.last.loop_vertex_count, 1e3 * s.flatten,
                1e3 * s.triangulate, 1e3 * s.arap, 1e3 * s.optimize, 1e3 * s.total, t.last.iterations,
                1e3 * s.total / (t.last.patch_vertex_count / 1000.0));
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 5, gd_runs = 3, max_patch = 100000;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    const bool has_value = i + 1 < argc;
    if (flag == "--skip-gd") {
      gd_runs = 0;
    } else if (flag == "--runs" && has_value) {
      runs = std::max(1, std::atoi(argv[++i]));
    } else if (flag == "--gd-runs" && has_value) {
      gd_runs = std::max(0, std::atoi(argv[++i]));
    } else if (flag == "--max-patch" && has_value) {
      max_patch = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: bench_fill [--runs N] [--gd-runs N] [--skip-gd] [--max-patch N]\n");
      return 2;
    }
  }
  omp_set_num_threads(1);  // one hole per case: time the hole, not the thread pool
  std::printf("# foldfill fill benchmark\n\nmachine: %u hardware threads; medians of %d runs (GD: %d)\n\n",
              std::thread::hardware_concurrency(), runs, gd_runs);
  const char* env = std::getenv("FOLDFILL_SHARED");
  const fs::path shared = env ? env : FOLDFILL_SHARED_DIR;
  if (fs::is_directory(shared / "data")) {
    std::vector<Case> cases = reference_cases(shared);
    std::vector<Case> cloth = cloth_cases(shared);
    cases.insert(cases.end(), std::make_move_iterator(cloth.begin()), std::make_move_iterator(cloth.end()));
    print_case_table(cases, runs, gd_runs);
  } else {
    std::printf("shared data not found at %s: skipping the reference and cloth cases\n", shared.c_str());
  }
  print_scaling_table(max_patch, runs);
  return 0;
}
