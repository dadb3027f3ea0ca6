// Scale benchmark (issue 5): time and peak memory per stage of a whole fill on
// large generated meshes, to show that the cost follows the holes, not the
// mesh. Prints markdown.
//
//   build/bench/bench_scale [--case all|many|long|patch] [--max-patch N]
//                           [--time-limit S] [--dir DIR]
//
// - many: a folded sheet of about 2M triangles with 50 holes of 20 to 200
//   boundary vertices, read from and written to binary PLY;
// - long: one slot-shaped hole of about 5,000 boundary vertices (a round one
//   would hold some 2.3M patch vertices);
// - patch: one round hole whose patch grows from 1k to `--max-patch` vertices.
// Peak memory of a stage: the process's VmHWM after the stage, the peak having
// been reset to the current RSS (writing 5 to /proc/self/clear_refs) before it,
// after handing freed memory back to the system (malloc_trim).
// `--time-limit` bounds the minimisation of each hole (seconds, 0: none; 30
// by default, so that the whole run takes a few minutes on 2 cores).
#include <malloc.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "foldfill/examples.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/io.h"

namespace fs = std::filesystem;
using namespace foldfill;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// ---- Memory -------------------------------------------------------------------

// A field of /proc/self/status in MiB (the kernel gives kB).
double status_mib(const std::string& field) {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind(field + ":", 0) == 0) return std::atof(line.c_str() + field.size() + 1) / 1024;
  }
  return -1;
}

// Hands the freed memory back to the system first (glibc keeps it otherwise),
// so that the RSS is what is live and the peak what the stage adds to it.
void reset_peak_memory() {
  malloc_trim(0);
  std::ofstream("/proc/self/clear_refs") << "5";
}

struct StageRow {
  std::string name;
  double seconds = 0;
  double rss_before = 0;  // MiB, when the stage started
  double peak = 0;        // MiB, highest RSS during the stage
  std::string note;
};

// Runs `work` as one stage, timed, with its peak memory.
template <class Work>
StageRow measure_stage(const std::string& name, Work&& work) {
  reset_peak_memory();
  StageRow row;
  row.name = name;
  row.rss_before = status_mib("VmRSS");
  const auto start = Clock::now();
  work(row);
  row.seconds = seconds_since(start);
  row.peak = status_mib("VmHWM");
  return row;
}

void print_stages(const std::vector<StageRow>& rows) {
  std::printf(
      "| stage | seconds | RSS before (MiB) | peak RSS (MiB) | peak - before (MiB) | note |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const StageRow& r : rows) {
    std::printf("| %s | %.3f | %.0f | %.0f | %.0f | %s |\n", r.name.c_str(), r.seconds,
                r.rss_before, r.peak, r.peak - r.rss_before, r.note.c_str());
  }
  std::fflush(stdout);
}

// ---- Generated meshes -----------------------------------------------------------

// A sheet with folds across x, fine enough to be cut into the holes below.
FoldedSheetOptions sheet_options(double width, double height, double edge_length, int folds) {
  FoldedSheetOptions sheet;
  sheet.width = width;
  sheet.height = height;
  sheet.edge_length = edge_length;
  sheet.folds = folds;
  // Keep the folds' shape of the default sheet (amplitude / wavelength).
  sheet.amplitude = 0.19 * width / folds;
  return sheet;
}

// Removes the faces whose flat centroid is inside `inside` (a predicate on flat
// points) in one pass, then the vertices left without a face (cut_disk_hole
// with radius 0 removes no face and does just that). Cutting the holes one by
// one would cost a pass over the whole mesh per hole; a hole whose boundary
// would touch itself is left so (and refused by the fill).
template <class Inside>
Mesh cut_holes(const DevelopableMesh& sheet, const Inside& inside) {
  DevelopableMesh kept;
  kept.flat = sheet.flat;
  kept.mesh.positions = sheet.mesh.positions;
  for (const Tri& f : sheet.mesh.faces) {
    Vec2 centroid{0, 0};
    for (int v : f) {
      centroid[0] += sheet.flat[v][0] / 3;
      centroid[1] += sheet.flat[v][1] / 3;
    }
    if (!inside(centroid)) kept.mesh.faces.push_back(f);
  }
  return cut_disk_hole(kept, sheet.flat[0], 0).cut.mesh;
}

double flat_width(const DevelopableMesh& sheet) {
  double width = 0;
  for (const Vec2& p : sheet.flat) width = std::max(width, p[0]);
  return width;
}

// Boundary vertices of a hole cut from the grid per radius / edge length,
// measured on these sheets (the loop follows grid edges, a staircase).
constexpr double kLoopVerticesPerRadius = 7.0;

struct Disk {
  Vec2 center;
  double radius;
};

// 50 disks on a 10 x 5 grid of the flat sheet, radii giving 20 to 200
// boundary vertices, in a shuffled order so that big and small holes mix.
std::vector<Disk> many_disks(double width, double height, double edge_length) {
  std::vector<Disk> disks;
  const int columns = 10, rows = 5;
  for (int k = 0; k < columns * rows; ++k) {
    const int size_rank = (k * 37) % (columns * rows);  // 37 is prime to 50: a permutation
    const double loop_vertices = 20 + 180.0 * size_rank / (columns * rows - 1);
    const int i = k % columns, j = k / columns;
    disks.push_back({{width * (i + 0.5) / columns, height * (j + 0.5) / rows},
                     loop_vertices / kLoopVerticesPerRadius * edge_length});
  }
  return disks;
}

// ---- One fill, stage by stage ---------------------------------------------------

struct HoleSums {
  StageSeconds seconds;  // summed over the holes
  int filled = 0, holes = 0, patch_vertices = 0, iterations = 0;
  int min_loop = 0, max_loop = 0, self_intersections = 0;
  std::map<std::string, int> stop_reasons;
  std::string failures;
};

HoleSums sum_holes(const FillReport& report) {
  HoleSums sums;
  sums.min_loop = report.holes.empty() ? 0 : report.holes[0].loop_vertex_count;
  for (const HoleReport& h : report.holes) {
    ++sums.holes;
    sums.filled += h.filled;
    sums.patch_vertices += h.patch_vertex_count;
    sums.iterations += h.iterations;
    sums.min_loop = std::min(sums.min_loop, h.loop_vertex_count);
    sums.max_loop = std::max(sums.max_loop, h.loop_vertex_count);
    sums.self_intersections += h.self_intersections;
    if (h.filled) ++sums.stop_reasons[to_string(h.stop_reason)];
    sums.seconds.flatten += h.seconds.flatten;
    sums.seconds.triangulate += h.seconds.triangulate;
    sums.seconds.arap += h.seconds.arap;
    sums.seconds.optimize += h.seconds.optimize;
    sums.seconds.total += h.seconds.total;
    if (!h.filled) sums.failures += " " + h.reason + ";";
  }
  return sums;
}

std::string format(const char* pattern, double a, double b = 0, double c = 0, double d = 0) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, a, b, c, d);
  return text;
}

// Writes `mesh` as binary PLY, then reads it back, finds the loops, fills
// the holes (the loops that turn like holes) and writes the result, stage by
// stage. Returns the holes' report.
FillReport run_file_stages(const Mesh& generated, const fs::path& dir, const std::string& name,
                           const FillOptions& options) {
  const fs::path input = dir / (name + ".ply"), output = dir / (name + "_filled.ply");
  write_mesh(generated, input.string());
  std::vector<StageRow> rows;
  Mesh mesh;
  std::vector<BoundaryLoop> loops;
  HoleChoice choice;
  FillResult result;
  rows.push_back(measure_stage("read PLY", [&](StageRow& row) {
    mesh = read_mesh(input.string());
    row.note = format("%.0f vertices, %.0f triangles, %.0f MiB file", mesh.vertex_count(),
                      mesh.face_count(), fs::file_size(input) / 1048576.0);
  }));
  rows.push_back(measure_stage("find loops", [&](StageRow& row) {
    loops = find_boundary_loops(mesh, input.string());
    // The slot's loop is longer than the sheet's edge: the default picks the
    // holes by what they are, not by length.
    choice = select_holes(loops, {}, input.string());
    row.note = format("%.0f loops, %.0f to fill", loops.size(), choice.fill.size());
  }));
  rows.push_back(measure_stage("fill (all holes + stitch)", [&](StageRow& row) {
    result = fill_holes(std::move(mesh), loops, choice.fill, options, input.string());
    row.note = format("incidence %.3f s, holes %.3f s (wall), stitch %.3f s",
                      result.report.seconds_prepare, result.report.seconds_holes,
                      result.report.seconds_stitch);
  }));
  rows.push_back(measure_stage("write PLY", [&](StageRow& row) {
    write_mesh(result.mesh, output.string());
    row.note = format("%.0f vertices, %.0f triangles", result.mesh.vertex_count(),
                      result.mesh.face_count());
  }));
  print_stages(rows);

  const HoleSums sums = sum_holes(result.report);
  std::printf(
      "\nholes: %d filled of %d (loops of %d to %d vertices), %d patch vertices, %d iterations\n",
      sums.filled, sums.holes, sums.min_loop, sums.max_loop, sums.patch_vertices, sums.iterations);
  std::printf("stop reasons:");
  for (const auto& [reason, count] : sums.stop_reasons)
    std::printf(" %s %d", reason.c_str(), count);
  std::printf("; self-intersecting triangle pairs left: %d\n", sums.self_intersections);
  std::printf("\n| per-hole stage (summed over holes, all threads) | seconds |\n|---|---|\n");
  std::printf("| flatten (strip + LSCM) | %.3f |\n| triangulate | %.3f |\n| ARAP | %.3f |\n",
              sums.seconds.flatten, sums.seconds.triangulate, sums.seconds.arap);
  std::printf("| optimise | %.3f |\n| total | %.3f |\n", sums.seconds.optimize, sums.seconds.total);
  if (!sums.failures.empty()) std::printf("\nnot filled:%s\n", sums.failures.c_str());
  std::printf("\n");
  std::fflush(stdout);
  fs::remove(input);
  fs::remove(output);
  return result.report;
}

void many_holes_case(const fs::path& dir, const FillOptions& options) {
  const double edge_length = 0.0038;
  const auto start = Clock::now();
  const DevelopableMesh sheet = make_folded_sheet(sheet_options(4, 3, edge_length, 24));
  const double width = flat_width(sheet), height = 3;
  const std::vector<Disk> disks = many_disks(width, height, edge_length);
  const Mesh mesh = cut_holes(sheet, [&](const Vec2& p) {
    return std::any_of(disks.begin(), disks.end(), [&](const Disk& d) {
      return std::hypot(p[0] - d.center[0], p[1] - d.center[1]) < d.radius;
    });
  });
  std::printf("## (a) 50 holes in a 2M-triangle folded sheet\n\n");
  std::printf("sheet: edge length %g, %d vertices, %d triangles (generated in %.1f s)\n\n",
              edge_length, mesh.vertex_count(), mesh.face_count(), seconds_since(start));
  run_file_stages(mesh, dir, "many_holes", options);
}

void long_hole_case(const fs::path& dir, const FillOptions& options) {
  // A slot across the folds: a stadium of half-width 5 edges whose loop runs
  // along grid rows, about one vertex per edge length on each side.
  const double edge_length = 0.004, half_width = 5 * edge_length;
  const double slot_length = 2500 * edge_length;
  const DevelopableMesh sheet =
      make_folded_sheet(sheet_options(slot_length / 1.25 + 0.4, 0.3, edge_length, 60));
  const double width = flat_width(sheet);
  const Vec2 a{0.5 * (width - slot_length), 0.15}, b{0.5 * (width + slot_length), 0.15};
  const Mesh mesh = cut_holes(sheet, [&](const Vec2& p) {
    const double t = std::clamp((p[0] - a[0]) / (b[0] - a[0]), 0.0, 1.0);
    return std::hypot(p[0] - (a[0] + t * (b[0] - a[0])), p[1] - a[1]) < half_width;
  });
  std::printf("## (b) one hole of about 5,000 boundary vertices\n\n");
  std::printf("sheet: edge length %g, %d vertices, %d triangles; slot %g x %g (flat)\n\n",
              edge_length, mesh.vertex_count(), mesh.face_count(), slot_length, 2 * half_width);
  run_file_stages(mesh, dir, "long_hole", options);
}

// Time against patch size: a sheet whose resolution grows, with a hole of
// fixed size, so that the patch has about `target` vertices.
void patch_size_case(int max_patch, const FillOptions& options) {
  std::printf("## (c) time against patch size\n\n");
  std::printf(
      "| target | patch verts | loop verts | flatten s | triangulate s | ARAP s | optimise s | "
      "total s | iterations | optimise ms per iteration | stop | ms per 1k patch verts | "
      "peak - before (MiB) | past the limit s |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int target : {1000, 3000, 10000, 30000, 100000, 200000, 800000}) {
    if (target > max_patch) break;
    const double radius = 0.8;
    // The patch's spacing follows the loop's edges, which zigzag along the
    // grid and are longer than its edges: a hole of area A gets about
    // 0.65 A / (0.866 e^2) patch vertices.
    const double edge_length = std::sqrt(0.65 * M_PI * radius * radius / (0.866 * target));
    const DevelopableMesh sheet = make_folded_sheet(sheet_options(3, 2.4, edge_length, 3));
    const Mesh mesh = cut_disk_hole(sheet, {1.9, 1.2}, radius).cut.mesh;
    const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh);
    const std::vector<int> fill = select_holes(loops, HoleSelection{}).fill;
    FillResult result;
    const StageRow row =
        measure_stage("fill", [&](StageRow&) { result = fill_holes(mesh, loops, fill, options); });
    const HoleReport& h = result.report.holes.at(0);
    const StageSeconds& s = h.seconds;
    // How long the hole took beyond its time limit (which counts from the
    // hole's start); "-" without a limit.
    const double limit = options.solver.time_limit_seconds;
    const std::string past = limit > 0 ? format("%.3f", s.total - limit) : "-";
    std::printf(
        "| %d | %d | %d | %.3f | %.3f | %.3f | %.3f | %.3f | %d | %.1f | %s | %.1f | %.0f | %s |\n",
        target, h.patch_vertex_count, h.loop_vertex_count, s.flatten, s.triangulate, s.arap,
        s.optimize, s.total, h.iterations, 1e3 * s.optimize / std::max(h.iterations, 1),
        h.filled ? to_string(h.stop_reason) : h.reason.c_str(),
        1e3 * s.total / (h.patch_vertex_count / 1000.0), row.peak - row.rss_before, past.c_str());
    std::fflush(stdout);
  }
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::string which = "all";
  int max_patch = 100000;
  FillOptions options;
  options.solver.time_limit_seconds = 30;
  fs::path dir = fs::temp_directory_path();
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    const bool has_value = i + 1 < argc;
    if (flag == "--case" && has_value) {
      which = argv[++i];
    } else if (flag == "--max-patch" && has_value) {
      max_patch = std::atoi(argv[++i]);
    } else if (flag == "--time-limit" && has_value) {
      options.solver.time_limit_seconds = std::atof(argv[++i]);
    } else if (flag == "--dir" && has_value) {
      dir = argv[++i];
    } else {
      std::fprintf(stderr,
                   "usage: bench_scale [--case all|many|long|patch] [--max-patch N] "
                   "[--time-limit S] [--dir DIR]\n");
      return 2;
    }
  }
  dir /= "foldfill_bench_scale_" + std::to_string(::getpid());
  fs::create_directories(dir);
  std::printf(
      "# foldfill scale benchmark\n\nmachine: %u hardware threads, %d OpenMP threads; "
      "time limit per hole: %s\n\n",
      std::thread::hardware_concurrency(), omp_get_max_threads(),
      options.solver.time_limit_seconds > 0
          ? format("%g s", options.solver.time_limit_seconds).c_str()
          : "none");
  if (which == "all" || which == "many") many_holes_case(dir, options);
  if (which == "all" || which == "long") long_hole_case(dir, options);
  if (which == "all" || which == "patch") patch_size_case(max_patch, options);
  fs::remove_all(dir);
  return 0;
}
