// Filling and writing one mesh for the `fill` and `demo` commands, and the
// one-file run with its progress line and summary.
#include <fmt/core.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>

#include "commands.h"
#include "foldfill/error.h"
#include "foldfill/file.h"
#include "foldfill/io.h"
#include "foldfill/obstacles.h"
#include "foldfill/report.h"
#include "interrupt.h"
#include "paths.h"

namespace fs = std::filesystem;

namespace foldfill::cli {
namespace {

// What a hole's minimisation is doing: "folds first", "minimising", on a
// coarser level "coarse level 2, folds first".
std::string stage_label(const SolverProgress& p) {
  const char* stage = p.stage == MinimisationStage::FoldsFirst ? "folds first" : "minimising";
  return p.coarse_level > 0 ? fmt::format("coarse level {}, {}", p.coarse_level, stage) : stage;
}

// Progress on a terminal: one line, rewritten at most ten times a second and
// whenever a minimisation starts (each counts its iterations from 0):
// "hole 1 of 2 (loop 3), minimising (started again after folds first):
// iteration 40, energy 12.5, 2.1 s", the time counted from the fill's start.
class ProgressLine {
 public:
  ProgressLine(bool enabled, const std::vector<int>& hole_ids)
      : enabled_(enabled), hole_ids_(hole_ids), start_(std::chrono::steady_clock::now()) {}
  ~ProgressLine() { finish(); }
  bool operator()(int loop_id, const SolverProgress& p) {
    if (!enabled_) return true;
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    const std::string label = stage_label(p);
    Stages& stages = stages_[loop_id];
    // A hole's first minimisation, and each that starts again, is shown at once.
    const bool new_stage = label != stages.current;
    if (new_stage && !stages.current.empty()) stages.previous = stages.current;
    stages.current = label;
    if (!new_stage && now - last_ < std::chrono::milliseconds(100)) return true;
    last_ = now;
    const auto hole = std::find(hole_ids_.begin(), hole_ids_.end(), loop_id);
    const std::chrono::duration<double> elapsed = now - start_;
    fmt::print(
        stderr, "\r\033[Khole {} of {} (loop {}), {}{}: iteration {}, energy {:.6g}, {:.1f} s",
        hole - hole_ids_.begin() + 1, hole_ids_.size(), loop_id, label,
        stages.previous.empty() ? "" : fmt::format(" (started again after {})", stages.previous),
        p.iteration, p.energy, elapsed.count());
    dirty_ = true;
    return true;
  }
  void finish() {
    if (dirty_) fmt::print(stderr, "\r\033[K");
    dirty_ = false;
  }

 private:
  struct Stages {
    std::string current, previous;  // stage_label of the minimisation now and the one before
  };
  bool enabled_;
  std::vector<int> hole_ids_;  // the loops being filled, in order
  std::chrono::steady_clock::time_point start_;
  bool dirty_ = false;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point last_{};
  std::map<int, Stages> stages_;  // by loop id
};

FillOptions make_fill_options(const FillArgs& args) {
  FillOptions options;
  options.energy.lambda = args.lambda;
  options.energy.repulsion = args.repulsion;
  options.contact.thickness = args.thickness;
  options.energy.bending =
      args.bending == "two-ring" ? BendingModel::TwoRing : BendingModel::Quadratic;
  options.arap.shrink = args.shrink;
  options.triangulate.density = args.density;
  options.solver.kind = args.solver == "gd" ? SolverKind::GradientDescent : SolverKind::Fast;
  options.solver.max_iterations = args.max_iterations;
  options.multilevel.min_patch_vertices = args.coarse_start;
  options.solver.time_limit_seconds = args.time_limit;
  if (args.preset == "prototype") options.prototype = args.prototype;
  options.obstacles = args.loaded_obstacles;
  options.keep_flat = !args.flat_dir.empty();
  return options;
}

void write_flat_meshes(const FillReport& report, const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw CannotWriteError(dir + ": cannot create the folder (" + ec.message() + ")");
  for (const HoleReport& hole : report.holes) {
    if (!hole.filled) continue;
    write_mesh(hole.flat_strip,
               (fs::path(dir) / fmt::format("loop{}_flat_strip.obj", hole.loop_id)).string());
    write_mesh(hole.flat_patch,
               (fs::path(dir) / fmt::format("loop{}_flat_patch.obj", hole.loop_id)).string());
  }
}

void print_warning(const std::string& warning, const std::string& source, bool quiet) {
  if (!quiet) fmt::print(stderr, "foldfill: warning: {}\n", with_source(warning, source));
}

std::string plural(size_t count, const char* noun) {
  return fmt::format("{} {}{}", count, noun, count == 1 ? "" : "s");
}

// The loops left open, one line for the outer edges and tube ends (not holes)
// and one for the others (not named, filtered out, among the longest, not a
// disk).
void print_left_open(const FileFill& fill) {
  std::vector<std::string> edges, others;
  for (int id : fill.choice.left_open) {
    const BoundaryLoop& loop = fill.loops[id];
    const ChoiceReason reason = fill.choice.reasons[id];
    const std::string what =
        reason == ChoiceReason::NotAHole ? to_string(loop.kind) : to_string(reason);
    (reason == ChoiceReason::NotAHole ? edges : others)
        .push_back(fmt::format("{} ({}, {} vertices)", id, what, loop.vertices.size()));
  }
  if (!edges.empty()) {
    fmt::print("{} left open as outer edges: {}\n", plural(edges.size(), "loop"),
               fmt::join(edges, ", "));
  }
  if (!others.empty()) {
    fmt::print("{} left open: {}\n", plural(others.size(), "loop"), fmt::join(others, ", "));
  }
}

void print_single_summary(const FileFill& fill, const std::string& source,
                          const std::string& output, bool quiet) {
  for (const HoleReport& hole : fill.report.holes) {
    if (!hole.filled) {
      fmt::print(stderr, "foldfill: error: {}\n", with_source(hole.reason, source));
    } else if (!quiet) {
      const bool fabric =
          hole.method == FillMethod::Fabric || hole.method == FillMethod::FabricRepaired;
      fmt::print("filled loop {} ({} boundary vertices): {} new vertices, {} faces, {}, {:.3f} s\n",
                 hole.loop_id, hole.loop_vertex_count, hole.patch_vertex_count,
                 hole.patch_face_count,
                 fabric ? plural(hole.iterations, "iteration")
                        : std::string("by the ") + to_string(hole.method) + " fill",
                 hole.seconds.total);
    }
  }
  if (quiet) return;
  if (fill.choice.fill.empty()) fmt::print("nothing to fill: the mesh was written unchanged\n");
  print_left_open(fill);
  fmt::print("wrote {}\n", output);
}

}  // namespace

void load_obstacles(FillArgs& args) {
  args.loaded_obstacles.clear();
  if (!args.obstacles.empty()) args.loaded_obstacles = read_obstacles(args.obstacles);
  for (const std::string& path : args.obstacle_meshes)
    args.loaded_obstacles.push_back(read_mesh_obstacle(path));
}

void plan_obstacle_reads(const FillArgs& args, PathPlan& plan) {
  plan.reads(args.obstacles, "the obstacles file");
  for (const std::string& path : args.obstacle_meshes) plan.reads(path, "an obstacle mesh");
  for (const Obstacle& obstacle : args.loaded_obstacles)
    if (obstacle.type == Obstacle::Type::Mesh)
      plan.reads(obstacle.mesh->source(), "an obstacle mesh");
}

void SelectionArgs::check() const {
  if (!holes.empty() && holes != "all" && holes != "auto" && !parse_loop_ids(holes)) {
    throw UsageError("--holes: '" + holes + "' is not 'all', 'auto' or a list of loop ids");
  }
  if (near.size() % 3 != 0) {
    throw UsageError("--near: each point needs three numbers, x,y,z");
  }
  if (keep_open >= 0 && (!holes.empty() || !near.empty())) {
    throw UsageError(
        "--keep-open: not with --holes or --near (it is a choice of its own: all but "
        "the N longest loops)");
  }
  if (!near.empty() && (holes == "all" || holes == "auto")) {
    throw UsageError("--near: not with --holes " + holes +
                     " (--near names loops; so does --holes with loop ids)");
  }
}

void SelectionArgs::apply(FillRequest& request) const {
  check();
  HoleSelection& s = request.selection;
  s = HoleSelection{};
  if (keep_open >= 0) {
    s.mode = HoleSelection::Mode::KeepOpen;
    s.keep_open = keep_open;
  } else if (holes == "all") {
    s.mode = HoleSelection::Mode::All;
  } else if (!holes.empty() && holes != "auto") {
    s.mode = HoleSelection::Mode::Ids;
    s.ids = *parse_loop_ids(holes);
  }
  if (!near.empty()) {
    s.mode = HoleSelection::Mode::Near;
    for (size_t k = 0; k < near.size(); k += 3)
      s.near.push_back({near[k], near[k + 1], near[k + 2]});
  }
  s.max_hole_size = max_hole_size;
  request.max_hole_diameter_edges = max_hole_diameter;
}

std::optional<std::vector<int>> parse_loop_ids(const std::string& list) {
  std::vector<int> ids;
  std::stringstream items(list);
  for (std::string item; std::getline(items, item, ',');) {
    int id = 0;
    const char* end = item.data() + item.size();
    const auto [stop, error] = std::from_chars(item.data(), end, id);
    if (item.empty() || item[0] == '-' || error != std::errc() || stop != end) return std::nullopt;
    ids.push_back(id);
  }
  if (ids.empty() || list.back() == ',') return std::nullopt;
  return ids;
}

std::string with_source(const std::string& message, const std::string& source) {
  const std::string prefix = source + ": ";
  return message.compare(0, prefix.size(), prefix) == 0 ? message : prefix + message;
}

int FileFill::failed_hole_count() const {
  int failed = 0;
  for (const HoleReport& hole : report.holes) failed += hole.filled ? 0 : 1;
  return failed;
}

std::vector<std::string> FileFill::warnings() const {
  std::vector<std::string> all = read_warnings;
  all.insert(all.end(), choice.warnings.begin(), choice.warnings.end());
  return all;
}

FileFill choose_holes(const Mesh& mesh, const std::string& source, const SelectionArgs& selection) {
  FillRequest request;
  request.source = source;
  selection.apply(request);
  ChosenHoles chosen = foldfill::choose_holes(mesh, request);
  FileFill fill;
  fill.loops = std::move(chosen.loops);
  fill.choice = std::move(chosen.choice);
  fill.selection = chosen.selection;
  return fill;
}

void fill_and_write(const Mesh& mesh, const std::string& source, const std::string& output,
                    const std::string& flat_dir, const FillArgs& args,
                    const ProgressCallback& progress, FileFill& fill) {
  FillRequest request;
  request.source = source;
  request.algorithm = args.method == "liepa" ? FillAlgorithm::Liepa : FillAlgorithm::Fabric;
  request.options = make_fill_options(args);
  request.options.progress = [&](int id, const SolverProgress& p) {
    return !interrupted() && (!progress || progress(id, p));
  };
  // Only the fabric fill watches the progress callback: a signal during the
  // smooth one ends the process at once.
  std::optional<WatchedFill> watched;
  if (request.algorithm == FillAlgorithm::Fabric) watched.emplace();
  FillOutput result = foldfill::fill(mesh, {fill.loops, fill.choice, fill.selection}, request);
  watched.reset();
  fill.options = options_json(request, fill.selection);
  fill.input_vertices = mesh.vertex_count();
  fill.input_faces = mesh.face_count();
  fill.output_vertices = result.mesh.vertex_count();
  fill.output_faces = result.mesh.face_count();
  const Writing writing;  // nothing is written once a signal came
  WriteOptions write_options;
  write_options.binary = !args.ascii;
  write_mesh(result.mesh, output, write_options);
  if (!flat_dir.empty()) write_flat_meshes(result.report, flat_dir);
  fill.report = std::move(result.report);
}

nlohmann::json file_report(const FileFill& fill, const std::string& source,
                           const std::string& output) {
  nlohmann::json report =
      report_json(fill.report, fill.loops, fill.choice, fill.options,
                  {fill.input_vertices, fill.input_faces, fill.output_vertices, fill.output_faces});
  report["input"] = source;
  report["output"] = output;
  report["warnings"] = fill.warnings();
  return report;
}

int run_dry_run(const FillArgs& args) {
  const std::vector<std::string> files = input_files(args);
  int failed = 0;
  for (const std::string& file : files) {
    FileFill fill;
    try {
      fill = choose_holes(read_mesh(file), file, args.selection);
    } catch (const Error& e) {
      if (files.size() == 1) throw;
      fmt::print(stderr, "foldfill: error: {}\n", e.what());
      ++failed;
      continue;
    }
    for (const std::string& warning : fill.choice.warnings)
      print_warning(warning, file, args.quiet);
    fmt::print("{}: {}, would fill {}\n", file, plural(fill.loops.size(), "boundary loop"),
               fill.choice.fill.empty()
                   ? std::string("nothing")
                   : fmt::format("{} {}", fill.choice.fill.size() == 1 ? "loop" : "loops",
                                 fmt::join(fill.choice.fill, ", ")));
    for (const BoundaryLoop& loop : fill.loops) {
      const bool filled =
          std::binary_search(fill.choice.fill.begin(), fill.choice.fill.end(), loop.id);
      fmt::print("loop {}: {} ({}): {}, {} vertices, turning {:.0f} deg: {}\n", loop.id,
                 filled ? "fill" : "leave open", to_string(fill.choice.reasons[loop.id]),
                 to_string(loop.kind), loop.vertices.size(), loop.turning * 180 / M_PI,
                 explain_kind(loop));
    }
  }
  fmt::print("dry run: nothing written\n");
  return failed > 0 ? kBatchFailedExitCode : 0;
}

int fill_single(const Mesh& mesh, const std::string& source, const std::string& output,
                const FillArgs& args, const nlohmann::json& extra_report,
                const std::vector<std::string>& read_warnings) {
  for (const std::string& warning : read_warnings) print_warning(warning, source, args.quiet);
  FileFill fill = choose_holes(mesh, source, args.selection);
  fill.read_warnings = read_warnings;
  for (const std::string& warning : fill.choice.warnings) {
    print_warning(warning, source, args.quiet);
  }
  ProgressLine progress(!args.quiet && isatty(STDERR_FILENO), fill.choice.fill);
  fill_and_write(
      mesh, source, output, args.flat_dir, args,
      [&](int id, const SolverProgress& p) { return progress(id, p); }, fill);
  progress.finish();
  for (const HoleReport& hole : fill.report.holes) {
    if (!hole.warning.empty()) print_warning(hole.warning, source, args.quiet);
  }
  print_single_summary(fill, source, output, args.quiet);
  if (!args.report.empty()) {
    nlohmann::json report = file_report(fill, source, output);
    if (!extra_report.is_null()) report.update(extra_report);
    const Writing writing;
    write_file_atomically(args.report, report.dump(1) + "\n");
  }
  return fill.failed_hole_count() > 0 ? exit_code(ErrorKind::FillFailed) : 0;
}

}  // namespace foldfill::cli
