// foldfill: the command-line program, a thin layer over the library.
//   foldfill holes MESH [--json]          list boundary loops and what they are
//   foldfill fill IN -o OUT [options]     fill holes (app/fill.cpp)
//   foldfill fill IN... -o OUTDIR         fill several files or a folder (app/batch.cpp)
//   foldfill demo OUTDIR                  fill a built-in folded sheet
//   foldfill render IN FILLED -o PNG      picture of a mesh before and after
//   foldfill view IN FILLED -o HTML       a page to look at them in the browser (app/view.cpp)
//   foldfill serve [MESH] [--port 8080]   a local web app to fill in the browser (app/serve.cpp)
//   foldfill help [COMMAND]               the same as --help
#include <fmt/core.h>
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "foldfill/error.h"
#include "foldfill/examples.h"
#include "foldfill/holes.h"
#include "foldfill/io.h"
#include "foldfill/render.h"
#include "foldfill/report.h"
#include "interrupt.h"
#include "paths.h"
#include "serve.h"
#include "view.h"

namespace fs = std::filesystem;
using namespace foldfill;
using namespace foldfill::cli;

namespace {

enum class Number { Real, Whole };

// The check of a number option: the whole value is a finite number (CLI11's
// own ranges let NaN through) or a whole one, in [low, high], or above `low`
// when `above_low`. CLI11 puts "--OPTION: " in front of the message.
CLI::Validator number_check(Number kind, double low, double high, bool above_low) {
  const bool bounded = high < std::numeric_limits<int>::max();
  std::string description;  // what --help shows after the type
  if (above_low) {
    description = fmt::format("> {}", low);
  } else if (bounded) {
    description = fmt::format("in [{}, {}]", low, high);
  } else if (std::isfinite(low)) {
    description = fmt::format(">= {}", low);
  }
  return CLI::Validator(
      [=](std::string& value) -> std::string {
        const char* text = value.c_str();
        char* end = nullptr;
        errno = 0;
        const bool blank = value.empty() || std::isspace(static_cast<unsigned char>(value[0]));
        const double number = blank ? 0
                              : kind == Number::Whole
                                  ? static_cast<double>(std::strtoll(text, &end, 10))
                                  : std::strtod(text, &end);
        if (blank || end == text || *end != '\0' || (kind == Number::Whole && errno == ERANGE)) {
          return "'" + value +
                 (kind == Number::Whole ? "' is not a whole number" : "' is not a number");
        }
        if (!std::isfinite(number)) return "'" + value + "' is not a finite number";
        if (above_low && number <= low) return fmt::format("'{}' is not above {}", value, low);
        if (bounded && (number < low || number > high)) {
          return fmt::format("'{}' is not in [{}, {}]", value, low, high);
        }
        if (number < low) return fmt::format("'{}' is not {} or more", value, low);
        if (number > high) return fmt::format("'{}' is too large", value);
        return "";
      },
      description);
}

CLI::Validator number_in(double low, double high = HUGE_VAL) {
  return number_check(Number::Real, low, high, false);
}
CLI::Validator number_above(double low) { return number_check(Number::Real, low, HUGE_VAL, true); }
CLI::Validator whole_number_in(double low, double high = std::numeric_limits<int>::max()) {
  return number_check(Number::Whole, low, high, false);
}

const CLI::Validator loop_list(
    [](std::string& value) -> std::string {
      if (value == "all" || value == "auto" || parse_loop_ids(value)) return "";
      return "'" + value + "' is not 'all', 'auto' or a list of loop ids such as 0,2";
    },
    "all|auto|IDS");

void add_selection_options(CLI::App* command, SelectionArgs& args) {
  command
      ->add_option("--holes", args.holes,
                   "loops to fill: 'all' (every hole; the default, said explicitly), 'auto' (the "
                   "default) or loop ids such as 0,2, filled whatever they are")
      ->check(loop_list);
  command
      ->add_option("--near", args.near,
                   "fill the loop closest to the point x,y,z, whatever it is (repeatable)")
      ->expected(3)
      ->delimiter(',')
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->check(number_in(-HUGE_VAL));
  command
      ->add_option("--keep-open", args.keep_open,
                   "instead of the default: fill all but the N longest loops (2 for a sleeve)")
      ->check(whole_number_in(0))
      ->default_str("");  // a choice of its own, not given by default
  command
      ->add_option("--max-hole-size", args.max_hole_size,
                   "fill only loops of at most N boundary edges")
      ->check(whole_number_in(1))
      ->default_str("none");
  command
      ->add_option("--max-hole-diameter", args.max_hole_diameter,
                   "fill only loops whose bounding-box diagonal is at most D mean edge lengths "
                   "of the mesh")
      ->check(number_above(0))
      ->default_str("none");
}

std::string format_vec(const Vec3& v) {
  return fmt::format("({:.6g}, {:.6g}, {:.6g})", v[0], v[1], v[2]);
}

int run_holes(const std::string& path, const SelectionArgs& args, bool json) {
  args.check();
  std::vector<std::string> read_warnings;
  const Mesh mesh = read_mesh(path, &read_warnings);
  for (const std::string& warning : read_warnings)
    fmt::print(stderr, "foldfill: warning: {}\n", warning);
  const FileFill chosen = choose_holes(mesh, path, args);
  const std::vector<BoundaryLoop>& loops = chosen.loops;
  const HoleChoice& choice = chosen.choice;
  auto is_outer = [&](int id) {
    return !std::binary_search(choice.fill.begin(), choice.fill.end(), id);
  };
  if (json) {
    nlohmann::json out = {{"file", path}, {"loops", nlohmann::json::array()}};
    for (const BoundaryLoop& loop : loops) out["loops"].push_back(loop_json(loop, choice));
    fmt::print("{}\n", out.dump(1));
    return 0;
  }
  fmt::print("{}: {} vertices, {} faces, {} boundary loops\n", path, mesh.vertex_count(),
             mesh.face_count(), loops.size());
  for (const BoundaryLoop& loop : loops) {
    fmt::print(
        "loop {}: {} vertices, length {:.6g}, centroid {}, bbox diagonal {:.6g}, turning {:.0f} "
        "deg, {} ({}): {}{}\n",
        loop.id, loop.vertices.size(), loop.length, format_vec(loop.centroid), loop.bbox_diagonal,
        loop.turning * 180 / M_PI, to_string(loop.kind),
        is_outer(loop.id) ? "left open by default" : "filled by default", explain_kind(loop),
        loop.split_at.empty() ? ""
                              : fmt::format("; split from the boundary at vertex {}",
                                            fmt::join(loop.split_at, ", ")));
  }
  return 0;
}

// One input file and -o a file (or a folder to write into): exactly the
// single-file run; several inputs or a folder: a batch.
int run_fill(FillArgs args) {
  args.selection.check();
  if (args.dry_run) return run_dry_run(args);
  if (args.output.empty()) throw UsageError("--output is required");
  std::error_code ec;
  if (args.inputs.size() > 1 || fs::is_directory(args.inputs.front(), ec)) return run_batch(args);
  const std::string input = args.inputs.front();
  const std::string output = single_output_path(input, args);
  // Once with the obstacle files named on the command line, then with the
  // mesh files that the obstacles file names as well.
  check_single_paths(input, output, args);
  load_obstacles(args);
  check_single_paths(input, output, args);
  std::vector<std::string> read_warnings;
  const Mesh mesh = read_mesh(input, &read_warnings);
  return fill_single(mesh, input, output, args, {}, read_warnings);
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
    draw_label(panels.back(), m == 0               ? std::string("input")
                              : meshes.size() == 2 ? std::string("filled")
                                                   : "filled " + std::to_string(m));
  }
  const Writing writing;
  write_png(side_by_side(panels), args.output);
}

int run_render(const RenderArgs& args) {
  PathPlan plan;
  for (const std::string& path : args.meshes) plan.reads(path, "the input mesh");
  plan.writes_file(args.output, "the picture");
  plan.check();
  std::vector<Mesh> meshes;
  for (const std::string& path : args.meshes) meshes.push_back(read_mesh(path));
  write_picture(meshes, args);
  return 0;
}

// The built-in example: a sheet with three sinusoidal folds, exactly
// developable, with a disk cut across the folds.
int run_demo(const std::string& out_dir, FillArgs args) {
  args.selection.check();
  const std::string input = (fs::path(out_dir) / "input.obj").string();
  const std::string output = (fs::path(out_dir) / "filled.obj").string();
  args.report = (fs::path(out_dir) / "report.json").string();
  RenderArgs picture;
  picture.output = (fs::path(out_dir) / "picture.png").string();
  const auto check_paths = [&] {
    PathPlan plan;
    plan_obstacle_reads(args, plan);
    plan.writes_folder(out_dir, "the demo folder");
    plan.writes_file(input, "the demo's input");
    plan.writes_file(output, "the filled mesh");
    plan.writes_file(args.report, "the report");
    plan.writes_file(picture.output, "the picture");
    plan.writes_flat_folder(args.flat_dir, "the --flat-dir folder");
    plan.check();
  };
  // Once with the obstacle files named on the command line, then with the
  // mesh files that the obstacles file names as well.
  check_paths();
  load_obstacles(args);
  check_paths();
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) {
    throw CannotWriteError(out_dir + ": cannot create the folder (" + ec.message() + ")");
  }
  const DevelopableMesh sheet = make_folded_sheet();
  const CutMesh cut = cut_disk_hole(sheet, {2.6, 1.5}, 0.7);
  {
    const Writing writing;
    write_mesh(cut.cut.mesh, input);
  }
  if (!args.quiet) {
    fmt::print("demo: folded sheet, {} vertices, hole of flat area {:.4f} cut across its folds\n",
               cut.cut.mesh.vertex_count(), cut.removed_area);
    fmt::print("wrote {}\n", input);
  }
  const nlohmann::json truth = {{"truth", {{"removed_flat_area", cut.removed_area}}}};
  const int code = fill_single(cut.cut.mesh, input, output, args, truth);
  write_picture({cut.cut.mesh, read_mesh(output)}, picture);
  if (!args.quiet)
    fmt::print("wrote {}\nwrote {} (input | filled, new faces in orange)\n", args.report,
               picture.output);
  return code;
}

// --help with each option's default in brackets after its type,
// `--lambda FLOAT:>= 0 [0.0002]`, where it has one (an empty list has none).
class DefaultsFormatter : public CLI::Formatter {
 public:
  std::string make_option_opts(const CLI::Option* option) const override {
    std::string out;
    if (!option->get_option_text().empty()) return " " + option->get_option_text();
    if (option->get_type_size() == 0) return out;
    if (!option->get_type_name().empty()) out += " " + get_label(option->get_type_name());
    const std::string value = option->get_default_str();
    if (!value.empty() && value != "[]") out += " [" + value + "]";
    if (option->get_expected_max() == CLI::detail::expected_max_vector_size) {
      out += " ...";
    } else if (option->get_expected_min() > 1) {
      out += " x " + std::to_string(option->get_expected());
    }
    if (option->get_required()) out += " " + get_label("REQUIRED");
    return out;
  }
};

// A parse error of CLI11 in the form of the others, "--OPTION: problem" (or
// "ARGUMENT: problem"), on one line.
std::string usage_message(const CLI::ParseError& error) {
  std::string message = error.what();
  std::replace(message.begin(), message.end(), '\n', ' ');
  if (dynamic_cast<const CLI::ExtrasError*>(&error)) {
    // "The following argument(s) were not expected: A B"
    const std::string arguments = message.substr(message.find(": ") + 2);
    return arguments + ": " +
           (arguments[0] == '-' ? "not an option of this command"
                                : "not expected here (too many arguments)");
  }
  if (dynamic_cast<const CLI::RequiredError*>(&error)) {
    const std::string suffix = " is required";
    if (message == "A subcommand is required")
      return "a command is required: holes, fill, demo, render or help";
    if (message.size() > suffix.size() &&
        message.compare(message.size() - suffix.size(), suffix.size(), suffix) == 0)
      return message.substr(0, message.size() - suffix.size()) + ": required";
  }
  return message;
}

// Refuses the options given to `command` (fill or demo) that would have no
// effect with the others: the prototype's weights without --preset
// prototype, the weights it sets with it, the fabric method's parameters with
// --method liepa, --coarse-start with --solver gd.
void check_options_apply(const CLI::App* command, const FillArgs& args) {
  const auto given = [&](const char* option) { return command->count(option) > 0; };
  const auto refuse_each = [&](std::initializer_list<const char*> options, const std::string& why) {
    for (const char* option : options)
      if (given(option)) throw CLI::ValidationError(option, why);
  };
  if (args.method == "liepa") {
    refuse_each({"--lambda", "--shrink", "--density", "--repulsion", "--thickness", "--bending",
                 "--solver", "--preset", "--alpha", "--beta", "--mu", "--max-iterations",
                 "--coarse-start", "--time-limit", "--flat-dir"},
                "has no effect with --method liepa (a parameter of the fabric method)");
  }
  if (args.preset == "prototype") {
    refuse_each({"--lambda", "--repulsion"},
                "has no effect with --preset prototype (its --alpha, --beta and --mu set it)");
  } else {
    refuse_each({"--alpha", "--beta", "--mu"}, "has no effect without --preset prototype");
  }
  if (args.solver == "gd")
    refuse_each({"--coarse-start"}, "has no effect with --solver gd (it always starts from ARAP)");
}

// A picture file: render writes PNG only.
const CLI::Validator png_path(
    [](std::string& value) -> std::string {
      std::string extension = fs::path(value).extension().string();
      std::transform(extension.begin(), extension.end(), extension.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      if (extension == ".png") return "";
      return "'" + value + "': render writes PNG pictures only (a .png file)";
    },
    "FILE.png");

void add_fill_options(CLI::App* command, FillArgs& args) {
  add_selection_options(command, args.selection);
  command
      ->add_option("--method", args.method,
                   "'foldfill', or 'liepa': CGAL's smooth fill, for comparison")
      ->check(CLI::IsMember({"foldfill", "liepa"}));
  command->add_option("--lambda", args.lambda, "bending stiffness (normalised)")
      ->check(number_in(0));
  command->add_option("--shrink,-c", args.shrink, "ARAP shrink factor c in (0, 1]")
      ->check(number_in(0.01, 1.0));
  command->add_option("--density", args.density, "interior vertex density relative to the boundary")
      ->check(number_in(0.1, 10.0));
  command->add_option("--repulsion", args.repulsion, "self-repulsion weight (normalised)")
      ->check(number_in(0));
  command
      ->add_option("--thickness", args.thickness,
                   "distance (in hole edge lengths) the patch keeps from anything it touches")
      ->check(number_in(1e-4, 1.0));
  command->add_option("--bending", args.bending, "bending model")
      ->check(CLI::IsMember({"quadratic", "two-ring"}));
  command->add_option("--solver", args.solver, "energy minimiser")
      ->check(CLI::IsMember({"fast", "gd"}));
  command->add_option("--preset", args.preset, "'prototype': the paper's weights in mesh units")
      ->check(CLI::IsMember({"prototype"}));
  command
      ->add_option("--alpha", args.prototype.alpha,
                   "prototype edge weight (with --preset prototype)")
      ->check(number_above(0));
  command
      ->add_option("--beta", args.prototype.beta,
                   "prototype bending weight (with --preset prototype)")
      ->check(number_in(0));
  command
      ->add_option("--mu", args.prototype.mu,
                   "prototype repulsion weight (with --preset prototype)")
      ->check(number_in(0));
  command->add_option("--obstacles", args.obstacles, "obstacles file (JSON or prototype text)");
  command
      ->add_option("--obstacle-mesh", args.obstacle_meshes,
                   "a triangle mesh to stay outside of (OBJ, PLY, OFF, STL; repeatable)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  command->add_option("--max-iterations", args.max_iterations, "iteration cap per hole")
      ->check(whole_number_in(1));
  command
      ->add_option("--coarse-start", args.coarse_start,
                   "patches of this many interior vertices or more start from a coarser fill "
                   "(fast solver; 0: never)")
      ->check(whole_number_in(0));
  command
      ->add_option("--time-limit", args.time_limit,
                   "seconds per hole for the minimisation (0: none)")
      ->check(number_in(0));
  command->add_option("--flat-dir", args.flat_dir, "write each hole's flat strip and patch here");
  command->add_flag("--quiet,-q", args.quiet, "print errors only");
  command->add_flag("--ascii", args.ascii, "write PLY/STL as text");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"foldfill: fills holes in fabric meshes so that folds continue through them"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("foldfill ") + version());
  // Every option's default in --help (the subcommands inherit both).
  app.formatter(std::make_shared<DefaultsFormatter>());
  app.option_defaults()->always_capture_default();

  std::string help_topic;
  CLI::App* help_command =
      app.add_subcommand("help", "the same as --help; `help COMMAND`: that command's --help");
  help_command->add_option("command", help_topic, "a command")
      ->check(CLI::IsMember({"holes", "fill", "demo", "render", "view", "serve"}));

  std::string holes_path;
  SelectionArgs holes_selection;
  bool holes_json = false;
  CLI::App* holes = app.add_subcommand("holes", "list the boundary loops of a mesh");
  holes->add_option("mesh", holes_path, "mesh file (OBJ, PLY, OFF, STL)")->required();
  holes->add_flag("--json", holes_json, "print JSON");
  holes
      ->add_option("--keep-open", holes_selection.keep_open,
                   "count the N longest loops as left open, the rest as filled")
      ->check(whole_number_in(0))
      ->default_str("");

  FillArgs fill_args;
  CLI::App* fill = app.add_subcommand("fill", "fill holes and write the result");
  fill->add_option("inputs", fill_args.inputs, "input meshes, or folders of meshes")->required();
  fill->add_option("-o,--output", fill_args.output,
                   "output mesh (format by extension), or output folder (required unless "
                   "--dry-run)");
  fill->add_flag("--dry-run", fill_args.dry_run,
                 "print each loop, whether it would be filled and why; write nothing");
  fill->add_option("--report", fill_args.report, "write a JSON report here");
  fill->add_option("--format", fill_args.format,
                   "format of outputs written into a folder (default: the input's)")
      ->check(CLI::IsMember({"obj", "ply", "off", "stl"}));
  fill->add_option("-j,--jobs", fill_args.jobs, "files filled in parallel")
      ->check(whole_number_in(1));
  add_fill_options(fill, fill_args);

  std::string demo_dir;
  FillArgs demo_args;
  CLI::App* demo =
      app.add_subcommand("demo", "fill a built-in folded sheet, write input, result and report");
  demo->add_option("outdir", demo_dir, "output folder")->required();
  add_fill_options(demo, demo_args);

  RenderArgs render_args;
  CLI::App* render_command = app.add_subcommand(
      "render", "PNG of meshes side by side, the last one's new faces in orange");
  render_command->add_option("meshes", render_args.meshes, "input mesh, then filled mesh(es)")
      ->required();
  render_command->add_option("-o,--output", render_args.output, "PNG file")
      ->required()
      ->check(png_path);
  render_command->add_option("--azimuth", render_args.azimuth, "degrees")
      ->check(number_in(-HUGE_VAL));
  render_command->add_option("--elevation", render_args.elevation, "degrees")
      ->check(number_in(-HUGE_VAL));
  render_command->add_option("--width", render_args.width, "pixels per panel")
      ->check(whole_number_in(16, 8192));
  render_command->add_option("--height", render_args.height, "pixels")
      ->check(whole_number_in(16, 8192));

  ViewArgs view_args;
  CLI::App* view_command = add_view_command(app, view_args);
  ServeArgs serve_args;
  CLI::App* serve_command = add_serve_command(app, serve_args);

  install_interrupt_handlers();
  try {
    app.parse(argc, argv);
    if (*help_command) {
      // app.help() would show the help of the command parsed, `help` itself.
      fmt::print("{}", help_topic.empty() ? app.get_formatter()->make_help(
                                                &app, app.get_name(), CLI::AppFormatMode::Normal)
                                          : app.get_subcommand(help_topic)->help(app.get_name()));
      return 0;
    }
    if (*fill) check_options_apply(fill, fill_args);
    if (*demo) check_options_apply(demo, demo_args);
    if (*holes) return run_holes(holes_path, holes_selection, holes_json);
    if (*fill) return run_fill(fill_args);
    if (*demo) return run_demo(demo_dir, demo_args);
    if (*render_command) return run_render(render_args);
    if (*view_command) return run_view(view_args);
    if (*serve_command) return run_serve(serve_args);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // One line, like every error; the command's --help lists its options.
    std::string help = "foldfill --help";
    for (const CLI::App* command :
         {holes, fill, demo, render_command, view_command, serve_command}) {
      if (command->parsed()) help = "foldfill " + command->get_name() + " --help";
    }
    fmt::print(stderr, "foldfill: error: {} (see {})\n", usage_message(e), help);
    return exit_code(ErrorKind::Usage);
  } catch (const Interrupted& e) {
    fmt::print(stderr, "foldfill: error: {}\n", e.what());
    return kInterruptedExitCode;
  } catch (const Error& e) {
    fmt::print(stderr, "foldfill: error: {}\n", e.what());
    return exit_code(e.kind());
  } catch (const std::exception& e) {
    fmt::print(stderr, "foldfill: internal error: {}\n", e.what());
    return exit_code(ErrorKind::Internal);
  }
  return 0;
}
