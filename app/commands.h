// The `fill` command of the CLI, shared by app/main.cpp (argument parsing,
// one file, demo), app/fill.cpp (filling and writing one mesh) and
// app/batch.cpp (several files or a folder).
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "exit_codes.h"
#include "foldfill/fill.h"
#include "foldfill/holes.h"
#include "foldfill/inpaint.h"

namespace foldfill::cli {

class PathPlan;  // paths.h

// Options of the hole selection, shared by `holes` and `fill`.
struct SelectionArgs {
  std::string holes;             // "all", "auto" (the default, by name) or "0,2"
  std::vector<double> near;      // x, y, z of each --near, in order
  int keep_open = -1;            // --keep-open N; -1: not given
  int max_hole_size = 0;         // --max-hole-size (boundary edges); 0: none
  double max_hole_diameter = 0;  // --max-hole-diameter (mean edge lengths of the mesh); 0: none

  // Throws UsageError for a malformed --holes list or options that
  // contradict each other (--keep-open with --holes or --near, --near with
  // --holes all or auto).
  void check() const;
  // Sets the selection of `request` (its HoleSelection and
  // max_hole_diameter_edges). Throws like check().
  void apply(FillRequest& request) const;
};

// The loop ids of a --holes list such as "0,2": each a whole non-negative
// number, nothing else; nullopt when it is not one.
std::optional<std::vector<int>> parse_loop_ids(const std::string& list);

// `message` with "SOURCE: " in front, unless it already starts with it.
std::string with_source(const std::string& message, const std::string& source);

struct FillArgs {
  std::vector<std::string> inputs;  // mesh files and folders
  std::string output;               // a mesh file, or the output folder of a batch
  std::string report, obstacles, flat_dir;
  std::vector<std::string> obstacle_meshes;  // --obstacle-mesh, in order
  std::string format;  // "obj", "ply", "off" or "stl": extension of outputs named after inputs
  int jobs = 1;        // files filled at the same time in a batch
  SelectionArgs selection;
  double lambda = FillOptions{}.energy.lambda;
  double shrink = FillOptions{}.arap.shrink;
  double density = FillOptions{}.triangulate.density;
  double repulsion = FillOptions{}.energy.repulsion;
  double thickness = FillOptions{}.contact.thickness;
  std::string method = "foldfill", bending = "quadratic", solver = "fast", preset;
  PrototypeWeights prototype;
  int max_iterations = FillOptions{}.solver.max_iterations;
  int coarse_start = FillOptions{}.multilevel.min_patch_vertices;  // 0: never
  double time_limit = 0;
  bool quiet = false, ascii = false;
  bool dry_run = false;  // --dry-run: print what would be filled, write nothing
  // The obstacles of --obstacles and --obstacle-mesh, read once (load_obstacles).
  std::vector<Obstacle> loaded_obstacles;
};

// Reads the obstacles of --obstacles, then those of --obstacle-mesh, into
// args.loaded_obstacles. Throws the errors of read_obstacles and
// read_mesh_obstacle (those of read_mesh for a mesh file).
void load_obstacles(FillArgs& args);

// Adds the obstacle files of `args` to `plan` as inputs: --obstacles,
// --obstacle-mesh, and the mesh files that the loaded --obstacles file names.
void plan_obstacle_reads(const FillArgs& args, PathPlan& plan);

// One mesh's loops, the choice of those to fill, and the fill's report.
struct FileFill {
  std::vector<std::string> read_warnings;  // of reading the mesh (read_mesh)
  std::vector<BoundaryLoop> loops;
  HoleSelection selection;  // as applied to this mesh
  HoleChoice choice;
  FillReport report;
  // The options the fill ran with, for the report (options_json).
  nlohmann::json options;
  int input_vertices = 0, input_faces = 0, output_vertices = 0, output_faces = 0;

  int failed_hole_count() const;
  // The warnings of reading the mesh, then those of the choice.
  std::vector<std::string> warnings() const;
};

using ProgressCallback = std::function<bool(int, const SolverProgress&)>;

// The loops of `mesh` (named `source` in messages) and the ones `selection`
// picks (the library's choose_holes). Throws like check() and choose_holes.
FileFill choose_holes(const Mesh& mesh, const std::string& source, const SelectionArgs& selection);

// Fills the holes chosen in `fill` as `args` say, writes the mesh to `output`
// and, when `flat_dir` is set, each hole's flat strip and patch into it; stores
// the report in `fill`. A hole that cannot be filled is left open and
// reported. `progress` may be empty; the fill is cancelled when a signal comes
// (interrupt.h). Throws CannotWriteError when an output cannot be written,
// Interrupted, with nothing written, when a signal came.
void fill_and_write(const Mesh& mesh, const std::string& source, const std::string& output,
                    const std::string& flat_dir, const FillArgs& args,
                    const ProgressCallback& progress, FileFill& fill);

// The options of a fill as its report gives them (docs/report.md,
// "options"): the fabric method's parameters after the prototype's mapping
// (null with --method liepa, which has none), the method and `selection`.

// The JSON report of one filled file (docs/report.md).
nlohmann::json file_report(const FileFill& fill, const std::string& source,
                           const std::string& output);

// `fill` of one mesh: fills, writes the output and the report (with
// `extra_report` merged in), prints progress, warnings (those of reading the
// mesh first; not with --quiet) and a summary. Returns the exit code (0, or 9
// when a hole could not be filled).
int fill_single(const Mesh& mesh, const std::string& source, const std::string& output,
                const FillArgs& args, const nlohmann::json& extra_report = {},
                const std::vector<std::string>& read_warnings = {});

// Where `fill` with one input file writes: `args.output`, or a file named
// like the input inside it when it is a folder. Throws UsageError when
// --format contradicts the output's extension or it is not a mesh format's.
std::string single_output_path(const std::string& input, const FillArgs& args);

// Checks the paths of `fill` with one input file before any work (see
// PathPlan::check): the input and the obstacle files (plan_obstacle_reads)
// against the output, --report and --flat-dir.
void check_single_paths(const std::string& input, const std::string& output, const FillArgs& args);

// `fill` with several inputs or a folder: the obstacles read once
// (load_obstacles), each file filled and written into the output folder, a
// summary, the batch report. Returns the exit code (0, or
// kBatchFailedExitCode when a file failed). Throws UsageError before any
// work for an output folder that is an input folder, two inputs that would
// be written to the same file, or any path written that is an input or
// another path written (PathPlan::check), CannotWriteError for one that
// cannot be written; Interrupted when a signal came (the files written by
// then stay, the report is not written).
int run_batch(FillArgs args);

// The mesh files of `args.inputs` in order: files as given, each folder's
// mesh files sorted by name. Throws UsageError for a folder without any,
// CannotReadError for one that cannot be listed.
std::vector<std::string> input_files(const FillArgs& args);

// `fill --dry-run`: per input file, each loop, whether the selection fills it
// and why; nothing is written. Returns the exit code: 0, or for several files
// kBatchFailedExitCode when one could not be read (a single file's error is
// thrown).
int run_dry_run(const FillArgs& args);

}  // namespace foldfill::cli
