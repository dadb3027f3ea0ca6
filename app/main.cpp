// foldfill: the command-line program, a thin layer over the library.
//   foldfill holes MESH [--json]          list boundary loops
//   foldfill fill IN -o OUT [options]     fill holes
//   foldfill demo OUTDIR                  fill a built-in folded sheet
//   foldfill render IN FILLED -o PNG      picture of a mesh before and after
#include <fmt/core.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>

#include "foldfill/error.h"
#include "foldfill/examples.h"
#include "foldfill/file.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/io.h"
#include "foldfill/liepa.h"
#include "foldfill/render.h"
#include "foldfill/report.h"

namespace fs = std::filesystem;
using namespace foldfill;

namespace {

// Options of the hole selection, shared by `holes` and `fill`.
struct SelectionArgs {
  std::string holes;  // "all" or "0,2"
  std::vector<double> near;
  int keep_open = 1;

  HoleSelection selection() const {
    HoleSelection s;
    s.keep_open = keep_open;
    if (!near.empty()) {
      s.mode = HoleSelection::Mode::Near;
      s.near = {near[0], near[1], near[2]};
    } else if (holes == "all") {
      s.mode = HoleSelection::Mode::All;
    } else if (!holes.empty()) {
      s.mode = HoleSelection::Mode::Ids;
      std::stringstream list(holes);
      for (std::string id; std::getline(list, id, ',');) {
        try {
          s.ids.push_back(std::stoi(id));
        } catch (const std::exception&) {
          throw Error(ErrorKind::Usage, "--holes: '" + holes + "' is not 'all' or a list of loop ids");
        }
      }
    }
    return s;
  }
};

void add_selection_options(CLI::App* command, SelectionArgs& args) {
  command->add_option("--holes", args.holes, "loops to fill: 'all' or ids such as 0,2");
  command->add_option("--near", args.near, "fill the loop closest to the point x,y,z")
      ->expected(3)
      ->delimiter(',');
  command->add_option("--keep-open", args.keep_open,
                      "default choice: leave the N longest loops open (2 for a sleeve)")
      ->check(CLI::NonNegativeNumber);
}

std::string format_vec(const Vec3& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v[0], v[1], v[2]); }

int run_holes(const std::string& path, const SelectionArgs& args, bool json) {
  const Mesh mesh = read_mesh(path);
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh, path);
  const std::vector<int> outer = default_outer_loops(loops, args.keep_open);
  auto is_outer = [&](int id) { return std::find(outer.begin(), outer.end(), id) != outer.end(); };
  if (json) {
    nlohmann::json out = {{"file", path}, {"loops", nlohmann::json::array()}};
    for (const BoundaryLoop& loop : loops) {
      out["loops"].push_back({{"id", loop.id},
                              {"vertex_count", loop.vertices.size()},
                              {"length", loop.length},
                              {"centroid", loop.centroid},
                              {"bbox_diagonal", loop.bbox_diagonal},
                              {"mean_edge_length", loop.mean_edge_length},
                              {"outer", is_outer(loop.id)},
                              {"disk", loop.is_disk},
                              {"reason", loop.reason},
                              {"vertices", loop.vertices}});
    }
    fmt::print("{}\n", out.dump(1));
    return 0;
  }
  fmt::print("{}: {} vertices, {} faces, {} boundary loops\n", path, mesh.vertex_count(),
             mesh.face_count(), loops.size());
  for (const BoundaryLoop& loop : loops) {
    fmt::print("loop {}: {} vertices, length {:.6g}, centroid {}, bbox diagonal {:.6g}, {}{}\n",
               loop.id, loop.vertices.size(), loop.length, format_vec(loop.centroid),
               loop.bbox_diagonal, is_outer(loop.id) ? "outer (left open by default)" : "hole",
               loop.is_disk ? "" : ", not a disk: " + loop.reason);
  }
  return 0;
}

// Progress on a terminal: one line rewritten at most ten times a second.
class ProgressLine {
 public:
  explicit ProgressLine(bool enabled) : enabled_(enabled) {}
  bool operator()(int loop_id, const SolverProgress& p) {
    if (!enabled_) return true;
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < std::chrono::milliseconds(100)) return true;
    last_ = now;
    fmt::print(stderr, "\r\033[Kloop {}: iteration {}, energy {:.6g}", loop_id, p.iteration, p.energy);
    dirty_ = true;
    return true;
  }
  void finish() {
    if (dirty_) fmt::print(stderr, "\r\033[K");
    dirty_ = false;
  }

 private:
  bool enabled_;
  bool dirty_ = false;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point last_{};
};

struct FillArgs {
  std::string input, output, report, obstacles, flat_dir;
  SelectionArgs selection;
  double lambda = FillOptions{}.energy.lambda;
  double shrink = FillOptions{}.arap.shrink;
  double density = FillOptions{}.triangulate.density;
  double repulsion = FillOptions{}.energy.repulsion;
  std::string method = "foldfill", bending = "quadratic", solver = "fast", preset;
  PrototypeWeights prototype;
  int max_iterations = FillOptions{}.solver.max_iterations;
  double time_limit = 0;
  bool quiet = false, ascii = false;
};

FillOptions make_fill_options(const FillArgs& args) {
  FillOptions options;
  options.energy.lambda = args.lambda;
  options.energy.repulsion = args.repulsion;
  options.energy.bending = args.bending == "two-ring" ? BendingModel::TwoRing : BendingModel::Quadratic;
  options.arap.shrink = args.shrink;
  options.triangulate.density = args.density;
  options.solver.kind = args.solver == "gd" ? SolverKind::GradientDescent : SolverKind::Fast;
  options.solver.max_iterations = args.max_iterations;
  options.solver.time_limit_seconds = args.time_limit;
  if (args.preset == "prototype") options.prototype = args.prototype;
  if (!args.obstacles.empty()) options.obstacles = read_obstacles(args.obstacles);
  options.keep_flat = !args.flat_dir.empty();
  return options;
}

void write_flat_meshes(const FillReport& report, const std::string& dir) {
  fs::create_directories(dir);
  for (const HoleReport& hole : report.holes) {
    if (!hole.filled) continue;
    write_mesh(hole.flat_strip, (fs::path(dir) / fmt::format("loop{}_flat_strip.obj", hole.loop_id)).string());
    write_mesh(hole.flat_patch, (fs::path(dir) / fmt::format("loop{}_flat_patch.obj", hole.loop_id)).string());
  }
}

// Fills `mesh` as the arguments say, writes the output and the report, and
// prints a summary. Returns the exit code.
int fill_and_write(const Mesh& mesh, const std::string& source, const FillArgs& args,
                   nlohmann::json extra_report = {}) {
  const std::vector<BoundaryLoop> loops = find_boundary_loops(mesh, source);
  const HoleChoice choice = select_holes(loops, args.selection.selection(), source);
  for (const std::string& warning : choice.warnings) fmt::print(stderr, "foldfill: warning: {}\n", warning);
  FillOptions options = make_fill_options(args);
  ProgressLine progress(!args.quiet && isatty(STDERR_FILENO));
  options.progress = [&](int id, const SolverProgress& p) { return progress(id, p); };
  const FillResult result = args.method == "liepa"
                                ? fill_holes_liepa(mesh, loops, choice.fill, source)
                                : fill_holes(mesh, loops, choice.fill, options, source);
  progress.finish();

  WriteOptions write_options;
  write_options.binary = !args.ascii;
  write_mesh(result.mesh, args.output, write_options);
  int failed = 0;
  for (const HoleReport& hole : result.report.holes) {
    if (hole.filled) {
      if (!args.quiet) {
        fmt::print("filled loop {} ({} boundary vertices): {} new vertices, {} faces, {} iterations, {:.3f} s\n",
                   hole.loop_id, hole.loop_vertex_count, hole.patch_vertex_count,
                   hole.patch_face_count, hole.iterations, hole.seconds.total);
      }
    } else {
      ++failed;
      fmt::print(stderr, "foldfill: error: {}\n", hole.reason);
    }
  }
  if (!args.quiet) {
    if (choice.fill.empty()) fmt::print("nothing to fill: the mesh was written unchanged\n");
    for (int id : choice.left_open) {
      fmt::print("left open: loop {} ({} vertices)\n", id, loops[id].vertices.size());
    }
    fmt::print("wrote {}\n", args.output);
  }
  if (!args.report.empty()) {
    nlohmann::json report = to_json(result.report);
    report["input"] = source;
    report["output"] = args.output;
    report["filled_loops"] = choice.fill;
    report["left_open_loops"] = choice.left_open;
    report["warnings"] = choice.warnings;
    if (!extra_report.is_null()) report.update(extra_report);
    write_file_atomically(args.report, report.dump(1) + "\n");
  }
  if (!args.flat_dir.empty()) write_flat_meshes(result.report, args.flat_dir);
  return failed > 0 ? static_cast<int>(ErrorKind::FillFailed) : 0;
}

void check_output_path(const std::string& input, const std::string& output) {
  format_from_path(output);  // an unknown extension fails before any work
  std::error_code ec;
  if (fs::exists(output, ec) && fs::equivalent(input, output, ec)) {
    throw Error(ErrorKind::Usage, output + ": refusing to overwrite the input file");
  }
}

int run_fill(const FillArgs& args) {
  check_output_path(args.input, args.output);
  const Mesh mesh = read_mesh(args.input);
  return fill_and_write(mesh, args.input, args);
}

struct RenderArgs {
  std::vector<std::string> meshes;
  std::string output;
  double azimuth = 30, elevation = 35;
  int width = 640, height = 480;
};

// Pictures of the meshes side by side, from one camera framing the new faces
// of the last mesh (those past the first mesh's face count), highlighted.
void write_picture(const std::vector<Mesh>& meshes, const RenderArgs& args) {
  const int first_new = meshes.front().face_count();
  const Mesh& last = meshes.back();
  const std::vector<Tri> new_faces(last.faces.begin() + std::min(first_new, last.face_count()),
                                   last.faces.end());
  Camera camera = frame(last.positions, new_faces);
  camera.radius *= new_faces.empty() ? 1.0 : 1.6;
  camera.azimuth_deg = args.azimuth;
  camera.elevation_deg = args.elevation;
  RenderOptions options;
  options.width = args.width;
  options.height = args.height;
  std::vector<Image> panels;
  for (size_t m = 0; m < meshes.size(); ++m) {
    options.highlight_from = m == 0 ? -1 : first_new;
    panels.push_back(render(meshes[m], camera, options));
  }
  write_png(side_by_side(panels), args.output);
}

int run_render(const RenderArgs& args) {
  std::vector<Mesh> meshes;
  for (const std::string& path : args.meshes) meshes.push_back(read_mesh(path));
  write_picture(meshes, args);
  return 0;
}

// The built-in example: a sheet with three sinusoidal folds, exactly
// developable, with a disk cut across the folds.
int run_demo(const std::string& out_dir, FillArgs args) {
  fs::create_directories(out_dir);
  const DevelopableMesh sheet = make_folded_sheet();
  const CutMesh cut = cut_disk_hole(sheet, {2.6, 1.5}, 0.7);
  const std::string input = (fs::path(out_dir) / "input.obj").string();
  write_mesh(cut.cut.mesh, input);
  args.input = input;
  args.output = (fs::path(out_dir) / "filled.obj").string();
  args.report = (fs::path(out_dir) / "report.json").string();
  if (!args.quiet) {
    fmt::print("demo: folded sheet, {} vertices, hole of flat area {:.4f} cut across its folds\n",
               cut.cut.mesh.vertex_count(), cut.removed_area);
    fmt::print("wrote {}\n", input);
  }
  const nlohmann::json truth = {{"truth", {{"removed_flat_area", cut.removed_area}}}};
  const int code = fill_and_write(cut.cut.mesh, input, args, truth);
  RenderArgs picture;
  picture.output = (fs::path(out_dir) / "picture.png").string();
  write_picture({cut.cut.mesh, read_mesh(args.output)}, picture);
  if (!args.quiet) fmt::print("wrote {}\nwrote {} (input | filled, new faces in orange)\n", args.report, picture.output);
  return code;
}

void add_fill_options(CLI::App* command, FillArgs& args) {
  add_selection_options(command, args.selection);
  command->add_option("--method", args.method, "'foldfill', or 'liepa': CGAL's smooth fill, for comparison")
      ->check(CLI::IsMember({"foldfill", "liepa"}));
  command->add_option("--lambda", args.lambda, "bending stiffness (normalised)")->check(CLI::NonNegativeNumber);
  command->add_option("--shrink,-c", args.shrink, "ARAP shrink factor c in (0, 1]")->check(CLI::Range(0.01, 1.0));
  command->add_option("--density", args.density, "interior vertex density relative to the boundary")
      ->check(CLI::Range(0.1, 10.0));
  command->add_option("--repulsion", args.repulsion, "self-repulsion weight (normalised)")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--bending", args.bending, "bending model")
      ->check(CLI::IsMember({"quadratic", "two-ring"}));
  command->add_option("--solver", args.solver, "energy minimiser")->check(CLI::IsMember({"fast", "gd"}));
  command->add_option("--preset", args.preset, "'prototype': the paper's weights in mesh units")
      ->check(CLI::IsMember({"prototype"}));
  command->add_option("--alpha", args.prototype.alpha, "prototype edge weight (with --preset prototype)");
  command->add_option("--beta", args.prototype.beta, "prototype bending weight (with --preset prototype)");
  command->add_option("--mu", args.prototype.mu, "prototype repulsion weight (with --preset prototype)");
  command->add_option("--obstacles", args.obstacles, "obstacles file (JSON or prototype text)");
  command->add_option("--max-iterations", args.max_iterations, "iteration cap per hole")
      ->check(CLI::PositiveNumber);
  command->add_option("--time-limit", args.time_limit, "seconds per hole for the minimisation (0: none)")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--flat-dir", args.flat_dir, "write each hole's flat strip and patch here");
  command->add_flag("--quiet,-q", args.quiet, "print errors only");
  command->add_flag("--ascii", args.ascii, "write PLY/STL as text");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"foldfill: fills holes in fabric meshes so that folds continue through them"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "foldfill 0.1.0");

  std::string holes_path;
  SelectionArgs holes_selection;
  bool holes_json = false;
  CLI::App* holes = app.add_subcommand("holes", "list the boundary loops of a mesh");
  holes->add_option("mesh", holes_path, "mesh file (OBJ, PLY, OFF, STL)")->required();
  holes->add_flag("--json", holes_json, "print JSON");
  holes->add_option("--keep-open", holes_selection.keep_open, "loops counted as outer (default 1)");

  FillArgs fill_args;
  CLI::App* fill = app.add_subcommand("fill", "fill holes and write the result");
  fill->add_option("input", fill_args.input, "input mesh")->required();
  fill->add_option("-o,--output", fill_args.output, "output mesh (format by extension)")->required();
  fill->add_option("--report", fill_args.report, "write a JSON report here");
  add_fill_options(fill, fill_args);

  std::string demo_dir;
  FillArgs demo_args;
  CLI::App* demo = app.add_subcommand("demo", "fill a built-in folded sheet, write input, result and report");
  demo->add_option("outdir", demo_dir, "output folder")->required();
  add_fill_options(demo, demo_args);

  RenderArgs render_args;
  CLI::App* render_command =
      app.add_subcommand("render", "PNG of meshes side by side, the last one's new faces in orange");
  render_command->add_option("meshes", render_args.meshes, "input mesh, then filled mesh(es)")->required();
  render_command->add_option("-o,--output", render_args.output, "PNG file")->required();
  render_command->add_option("--azimuth", render_args.azimuth, "degrees");
  render_command->add_option("--elevation", render_args.elevation, "degrees");
  render_command->add_option("--width", render_args.width, "pixels per panel")->check(CLI::Range(16, 8192));
  render_command->add_option("--height", render_args.height, "pixels")->check(CLI::Range(16, 8192));

  try {
    app.parse(argc, argv);
    if (*holes) return run_holes(holes_path, holes_selection, holes_json);
    if (*fill) return run_fill(fill_args);
    if (*demo) return run_demo(demo_dir, demo_args);
    if (*render_command) return run_render(render_args);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : static_cast<int>(ErrorKind::Usage);
  } catch (const Error& e) {
    fmt::print(stderr, "foldfill: error: {}\n", e.what());
    return e.exit_code();
  } catch (const std::exception& e) {
    fmt::print(stderr, "foldfill: internal error: {}\n", e.what());
    return static_cast<int>(ErrorKind::Internal);
  }
  return 0;
}
