// Whole-fill benchmark (issue 6): for every reference case and every cloth
// case, the time per stage (median of several runs), iterations and final
// energy of the fast solver and of the paper's gradient descent run to its
// stopping rule, and the time of CGAL's Liepa fill of the same hole; then the
// time against patch size on generated sheets. Prints markdown.
//
//   build/bench/bench_fill [--runs 5] [--gd-runs 1] [--gd-max-iterations 200000]
//                          [--max-patch 100000] [--skip-gd] [--only NAME] [--threads 1]
//                          [--multilevel-from 1000]
//
// Reference cases run twice: with the prototype's weights and obstacles from
// cases.json (the paper's setting: normalised gradient-descent step 0.05),
// and at the defaults with the same obstacles (what users run); cloth cases
// at the defaults. Times are of one hole on --threads threads (default 1:
// the stages' parallel loops then run serially); "fill" is the whole
// fill_holes call (reading the mesh excluded), crossings measured on the
// output included; "start" is ARAP, or for a large patch the coarser levels
// of the coarse-to-fine start ("iters" count every minimisation of the
// patch, not its coarser levels'; --multilevel-from sets the patch size from
// which they are used); "crossings" are the crossing triangle pairs counted
// on the whole output. The Liepa time is CGAL's refine-and-fair of the same
// hole. Gradient descent stops by the same rule as the fast solver (relative
// energy change below 1e-9 for 10 iterations, or RMS gradient below 1e-6),
// capped per minimisation.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
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
#include "support/cloth_cases.h"
#include "support/loops.h"
#include "support/reference_cases.h"

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

// The mesh of `path` and its loop through `hole_vertex`, at the defaults.
Case load_case(const std::string& name, const fs::path& path, int hole_vertex) {
  Case k;
  k.name = name;
  k.mesh = read_mesh(path.string());
  k.loops = find_boundary_loops(k.mesh, k.name);
  k.hole = foldfill::testing::loop_through(k.loops, hole_vertex);
  return k;
}

std::vector<Case> reference_cases(const fs::path& shared) {
  std::vector<Case> cases;
  for (const auto& c : foldfill::testing::read_reference_cases(shared / "data" / "reference")) {
    Case k = load_case(c.file, c.path, c.hole_vertex);
    PrototypeWeights weights;
    weights.alpha = c.alpha;
    weights.beta = c.beta;
    weights.mu = c.mu;
    k.options.prototype = weights;
    if (c.two_ring) k.options.energy.bending = BendingModel::TwoRing;
    k.options.obstacles = foldfill::testing::reference_obstacles(c);
    // The same hole at the defaults, what users run (with its obstacles).
    Case defaults = k;
    defaults.name += " (defaults)";
    defaults.options = FillOptions{};
    defaults.options.obstacles = k.options.obstacles;
    k.name += " (prototype)";
    cases.push_back(std::move(k));
    cases.push_back(std::move(defaults));
  }
  return cases;
}

std::vector<Case> cloth_cases(const fs::path& shared) {
  std::vector<Case> cases;
  for (const auto& c : foldfill::testing::read_cloth_cases(shared / "data" / "cloth"))
    cases.push_back(load_case(c.name, c.hole_mesh, c.hole_vertex));
  return cases;
}

struct Timing {
  StageSeconds stages;  // medians
  double fill = 0;      // median of the whole fill_holes call
  HoleReport last;
};

Timing time_fill(const Case& c, const FillOptions& options, int runs) {
  std::vector<double> flatten, triangulate, arap, optimize, total, fill;
  Timing timing;
  for (int r = 0; r < runs; ++r) {
    FillResult result = fill_holes(c.mesh, c.loops, {c.hole}, options, c.name);
    timing.last = std::move(result.report.holes.at(0));
    const StageSeconds& s = timing.last.seconds;
    flatten.push_back(s.flatten);
    triangulate.push_back(s.triangulate);
    arap.push_back(s.arap);
    optimize.push_back(s.optimize);
    total.push_back(s.total);
    fill.push_back(result.report.seconds_total);
  }
  timing.stages = {median(flatten), median(triangulate), median(arap), median(optimize),
                   median(total)};
  timing.fill = median(fill);
  return timing;
}

// The median time of CGAL's Liepa fill of the hole (the whole call, as for
// foldfill's: its crossings measured on the output included).
double time_liepa(const Case& c, int runs) {
  std::vector<double> seconds;
  for (int r = 0; r < runs; ++r) {
    seconds.push_back(fill_holes_liepa(c.mesh, c.loops, {c.hole}, c.name).report.seconds_total);
  }
  return median(seconds);
}

struct CaseRow {
  std::string name;
  double fill = 0, gd_fill = 0, liepa = 0;
  double energy = 0, gd_energy = 0;
  int crossings = 0;
  bool has_gd = false;
  bool defaults = false;  // the case runs at the default settings
};

CaseRow print_case(const Case& c, int runs, int gd_runs, int gd_max_iterations) {
  CaseRow row{c.name};
  const Timing fast = time_fill(c, c.options, runs);
  if (!fast.last.filled) {
    std::printf("| %s | failed: %s |\n", c.name.c_str(), fast.last.reason.c_str());
    return row;
  }
  row.fill = fast.fill;
  row.energy = fast.last.energy_final.total;
  row.crossings = fast.last.self_intersections;
  row.defaults = !c.options.prototype;
  row.liepa = time_liepa(c, runs);
  const StageSeconds& s = fast.stages;
  std::printf("| %s | %d | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %d | %s | %d | %.6g | %g, %g |",
              c.name.c_str(), fast.last.loop_vertex_count, fast.last.patch_vertex_count,
              1e3 * s.flatten, 1e3 * s.triangulate, 1e3 * s.arap, 1e3 * s.optimize, 1e3 * fast.fill,
              fast.last.iterations, to_string(fast.last.start), row.crossings, row.energy,
              fast.last.lambda, fast.last.repulsion);
  if (gd_runs > 0) {
    FillOptions gd_options = c.options;
    gd_options.solver.kind = SolverKind::GradientDescent;
    gd_options.solver.max_iterations = gd_max_iterations;
    const Timing gd = time_fill(c, gd_options, gd_runs);
    row.has_gd = gd.last.filled;
    row.gd_fill = gd.fill;
    row.gd_energy = gd.last.energy_final.total;
    std::printf(" %.0f | %d | %s | %.6g | %.5f | %.0fx |", 1e3 * gd.fill, gd.last.iterations,
                to_string(gd.last.stop_reason), row.gd_energy, row.energy / row.gd_energy,
                row.gd_fill / row.fill);
  } else {
    std::printf(" - | - | - | - | - | - |");
  }
  std::printf(" %.1f | %.1fx |\n", 1e3 * row.liepa, row.fill / row.liepa);
  std::fflush(stdout);
  return row;
}

void print_case_table(const std::vector<Case>& cases, int runs, int gd_runs,
                      int gd_max_iterations) {
  std::printf(
      "| case | loop | patch verts | flatten ms | triangulate ms | start ms | optimize ms "
      "| fill ms | iters | start | crossings | E | lambda, rep. | GD fill ms | GD iters | GD stop "
      "| E GD | E / E GD | speed-up | Liepa ms | fill / Liepa |\n");
  std::printf(
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::vector<CaseRow> rows;
  for (const Case& c : cases) {
    if (c.hole < 0) {
      std::printf("| %s | hole loop not found |\n", c.name.c_str());
      continue;
    }
    rows.push_back(print_case(c, runs, gd_runs, gd_max_iterations));
  }
  int lower_or_equal = 0, compared = 0;
  for (const CaseRow& row : rows) {
    if (!row.has_gd) continue;
    ++compared;
    lower_or_equal += row.energy <= row.gd_energy;
  }
  if (compared > 0)
    std::printf("\nfast final energy <= gradient descent's on %d of %d cases\n", lower_or_equal,
                compared);
  // Against Liepa at the settings users run: the reference cases at the
  // defaults and the cloth cases.
  std::vector<double> ratios;
  int crossings = 0, within = 0;
  for (const CaseRow& row : rows) {
    crossings += row.crossings;
    if (!row.defaults || !(row.liepa > 0)) continue;
    ratios.push_back(row.fill / row.liepa);
    within += row.fill <= 5 * row.liepa;
  }
  if (!ratios.empty())
    std::printf(
        "at the defaults: fill / Liepa median %.1fx, largest %.1fx, %d of %zu cases within 5x\n",
        median(ratios), *std::max_element(ratios.begin(), ratios.end()), within, ratios.size());
  std::printf("crossing triangle pairs over all cases (against the whole output): %d\n", crossings);
}

// Time against patch size: a folded sheet whose resolution grows, with a hole
// of fixed size, so the patch has about `target` vertices. Each size is also
// filled from ARAP alone (the coarse-to-fine start off), the baseline.
void print_scaling_table(int max_patch, int runs, int multilevel_from) {
  std::printf(
      "\n| target patch verts | patch verts | loop verts | flatten ms | triangulate ms | start ms "
      "| optimize ms | fill ms | iters | us per patch vert | single-level fill ms | single-level "
      "iters | speed-up |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
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
    c.options.multilevel.min_patch_vertices = multilevel_from;
    const int size_runs = target >= 30000 ? 1 : runs;
    const Timing t = time_fill(c, c.options, size_runs);
    FillOptions single_level = c.options;
    single_level.multilevel.min_patch_vertices = 0;
    const Timing baseline = time_fill(c, single_level, size_runs);
    const StageSeconds& s = t.stages;
    std::printf(
        "| %d | %d | %d | %.1f | %.1f | %.1f | %.1f | %.1f | %d | %.1f | %.1f | %d | %.1fx |\n",
        target, t.last.patch_vertex_count, t.last.loop_vertex_count, 1e3 * s.flatten,
        1e3 * s.triangulate, 1e3 * s.arap, 1e3 * s.optimize, 1e3 * t.fill, t.last.iterations,
        1e6 * t.fill / t.last.patch_vertex_count, 1e3 * baseline.fill, baseline.last.iterations,
        baseline.fill / t.fill);
    std::fflush(stdout);
  }
}

int usage() {
  std::fprintf(stderr,
               "usage: bench_fill [--runs N] [--gd-runs N] [--gd-max-iterations N] [--skip-gd] "
               "[--max-patch N] [--only NAME] [--threads N] [--multilevel-from N]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 5, gd_runs = 1, gd_max_iterations = 200000, max_patch = 100000, threads = 1;
  int multilevel_from = MultilevelOptions{}.min_patch_vertices;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    const bool has_value = i + 1 < argc;
    if (flag == "--skip-gd") {
      gd_runs = 0;
    } else if (flag == "--runs" && has_value) {
      runs = std::max(1, std::atoi(argv[++i]));
    } else if (flag == "--gd-runs" && has_value) {
      gd_runs = std::max(0, std::atoi(argv[++i]));
    } else if (flag == "--gd-max-iterations" && has_value) {
      gd_max_iterations = std::max(1, std::atoi(argv[++i]));
    } else if (flag == "--max-patch" && has_value) {
      max_patch = std::atoi(argv[++i]);
    } else if (flag == "--threads" && has_value) {
      threads = std::max(1, std::atoi(argv[++i]));
    } else if (flag == "--multilevel-from" && has_value) {
      multilevel_from = std::atoi(argv[++i]);
    } else if (flag == "--only" && has_value) {
      only = argv[++i];
    } else {
      return usage();
    }
  }
  omp_set_num_threads(threads);  // one hole per case: its stages' loops share them
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d", std::localtime(&now));
  std::printf(
      "# foldfill fill benchmark\n\n%s, %u hardware threads, %d per fill; medians of %d "
      "runs (gradient descent: %d, at most %d iterations)\n\n",
      date, std::thread::hardware_concurrency(), threads, runs, gd_runs, gd_max_iterations);
  const char* env = std::getenv("FOLDFILL_SHARED");
  const fs::path shared = env ? env : FOLDFILL_SHARED_DIR;
  if (fs::is_directory(shared / "data")) {
    std::vector<Case> cases = reference_cases(shared);
    std::vector<Case> cloth = cloth_cases(shared);
    cases.insert(cases.end(), std::make_move_iterator(cloth.begin()),
                 std::make_move_iterator(cloth.end()));
    cases.erase(
        std::remove_if(cases.begin(), cases.end(),
                       [&](const Case& c) { return c.name.find(only) == std::string::npos; }),
        cases.end());
    for (Case& c : cases) c.options.multilevel.min_patch_vertices = multilevel_from;
    print_case_table(cases, runs, gd_runs, gd_max_iterations);
  } else {
    std::printf("shared data not found at %s: skipping the reference and cloth cases\n",
                shared.c_str());
  }
  if (only.empty() || only == "sheet") print_scaling_table(max_patch, runs, multilevel_from);
  return 0;
}
