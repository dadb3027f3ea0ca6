// Where `fill` writes, and `fill` of several files or a folder: every file is
// filled independently (up to -j at a time), a bad file is reported and
// skipped, and a summary and a report cover them all.
//
// Parallelism: -j N runs N std::thread workers, each filling one file at a
// time; each worker sets its own OpenMP thread count to (OpenMP's default, the
// core count or OMP_NUM_THREADS) / N, so the holes of a file are still filled
// in parallel and the total stays about the core count. A file's result does
// not depend on the thread count, so the outputs do not depend on -j.
#include <fmt/core.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>

#include "commands.h"
#include "foldfill/error.h"
#include "foldfill/file.h"
#include "foldfill/io.h"
#include "foldfill/report.h"
#include "interrupt.h"
#include "paths.h"

namespace fs = std::filesystem;

namespace foldfill::cli {
namespace {

std::string lowercase_extension(const fs::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

bool has_mesh_extension(const fs::path& path) {
  const std::string extension = lowercase_extension(path);
  return extension == ".obj" || extension == ".ply" || extension == ".off" || extension == ".stl";
}

// The output file name of `input`: its own name, with the extension replaced
// by `format` when one is given.
std::string output_name(const fs::path& input, const std::string& format) {
  return format.empty() ? input.filename().string() : input.stem().string() + "." + format;
}

// The mesh files directly in `folder`, sorted by name.
std::vector<fs::path> meshes_in_folder(const fs::path& folder) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::directory_iterator entry(folder, ec), end; !ec && entry != end; entry.increment(ec)) {
    std::error_code type_ec;
    if (entry->is_regular_file(type_ec) && has_mesh_extension(entry->path())) {
      files.push_back(entry->path());
    }
  }
  if (ec) throw CannotReadError(folder.string() + ": cannot list (" + ec.message() + ")");
  if (files.empty()) {
    throw UsageError(folder.string() + ": no mesh file (.obj, .ply, .off, .stl) in this folder");
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Outputs are named like their inputs, so writing into an input's own folder
// could replace it.
void refuse_input_folder(const fs::path& input_folder, const fs::path& out_dir) {
  std::error_code ec;
  if (fs::exists(out_dir, ec) && fs::equivalent(input_folder, out_dir, ec)) {
    throw UsageError(out_dir.string() +
                     ": is the folder of the inputs; choose another output "
                     "folder (an input is never overwritten)");
  }
}

struct BatchItem {
  std::string input, output, flat_dir;
};

// The files of the batch in order: file arguments as given, each folder's
// mesh files sorted by name; each with its output path in the output folder.
std::vector<BatchItem> plan_batch(const FillArgs& args) {
  const fs::path out_dir = args.output;
  std::error_code ec;
  if (fs::exists(out_dir, ec) && !fs::is_directory(out_dir, ec)) {
    throw UsageError(args.output +
                     ": not a folder (with several inputs or a folder, -o "
                     "names the output folder)");
  }
  std::vector<BatchItem> items;
  std::map<std::string, std::string> input_of_output;
  for (const std::string& argument : args.inputs) {
    const bool folder = fs::is_directory(argument, ec);
    const fs::path parent = fs::path(argument).parent_path();
    refuse_input_folder(folder ? fs::path(argument) : parent.empty() ? "." : parent, out_dir);
    const std::vector<fs::path> files =
        folder ? meshes_in_folder(argument) : std::vector<fs::path>{argument};
    for (const fs::path& file : files) {
      const std::string name = output_name(file, args.format);
      BatchItem item{file.string(), (out_dir / name).string(),
                     args.flat_dir.empty() ? "" : (fs::path(args.flat_dir) / name).string()};
      const auto [previous, inserted] = input_of_output.emplace(item.output, item.input);
      if (!inserted) {
        throw UsageError(item.output + ": both " + previous->second + " and " + item.input +
                         " would be written here");
      }
      items.push_back(std::move(item));
    }
  }
  return items;
}

enum class FileStatus { Filled, Unchanged, PartlyFilled, Failed };

const char* status_name(FileStatus status) {
  switch (status) {
    case FileStatus::Filled:
      return "filled";
    case FileStatus::Unchanged:
      return "unchanged";
    case FileStatus::PartlyFilled:
      return "partly_filled";
    case FileStatus::Failed:
      return "failed";
  }
  return "failed";
}

struct FileOutcome {
  FileStatus status = FileStatus::Failed;
  std::string reason;  // one line; empty when filled or unchanged
  int exit_code = 0;   // what `fill` of this file alone would have returned
  int filled_holes = 0, chosen_holes = 0;
  bool written = false;      // the output file was written
  bool interrupted = false;  // a signal stopped it: nothing was written
  std::vector<std::string> warnings;
  nlohmann::json report;  // the file's report, with status, reason and exit code
};

// The message without its leading "INPUT: ", which the summary line already shows.
std::string without_source(const std::string& message, const std::string& source) {
  const std::string prefix = source + ": ";
  return message.compare(0, prefix.size(), prefix) == 0 ? message.substr(prefix.size()) : message;
}

// Filled, unchanged (nothing chosen), partly filled, or failed when no chosen
// hole could be filled; in the last two cases the mesh is still written, with
// those holes left open, as `fill` of a single file does.
FileOutcome outcome_of(const FileFill& fill, const std::string& source) {
  FileOutcome outcome;
  outcome.written = true;
  outcome.chosen_holes = static_cast<int>(fill.choice.fill.size());
  outcome.filled_holes = outcome.chosen_holes - fill.failed_hole_count();
  for (const HoleReport& hole : fill.report.holes) {
    if (hole.filled) continue;
    // The hole's reason, "SOURCE: loop ID: problem", as "loop ID: problem".
    const std::string where = fmt::format("loop {}: ", hole.loop_id);
    std::string reason = without_source(hole.reason, source);
    if (reason.compare(0, where.size(), where) != 0) reason = where + reason;
    outcome.reason += (outcome.reason.empty() ? "" : "; ") + reason;
  }
  outcome.warnings = fill.warnings();
  for (const HoleReport& hole : fill.report.holes) {
    if (!hole.warning.empty()) outcome.warnings.push_back(hole.warning);
  }
  if (outcome.chosen_holes == 0) {
    outcome.status = FileStatus::Unchanged;
  } else if (outcome.filled_holes == outcome.chosen_holes) {
    outcome.status = FileStatus::Filled;
  } else {
    outcome.status = outcome.filled_holes > 0 ? FileStatus::PartlyFilled : FileStatus::Failed;
    outcome.exit_code = exit_code(ErrorKind::FillFailed);
  }
  return outcome;
}

FileOutcome failure(const std::string& reason, int exit_code) {
  FileOutcome outcome;
  outcome.reason = reason;
  outcome.exit_code = exit_code;
  return outcome;
}

// Fills one file of the batch; never throws: a failure is its outcome.
FileOutcome fill_batch_item(const BatchItem& item, const FillArgs& args) {
  FileOutcome outcome;
  try {
    format_from_path(item.output);
    std::vector<std::string> read_warnings;
    const Mesh mesh = read_mesh(item.input, &read_warnings);
    FileFill fill = choose_holes(mesh, item.input, args.selection);
    fill.read_warnings = std::move(read_warnings);
    fill_and_write(mesh, item.input, item.output, item.flat_dir, args, {}, fill);
    outcome = outcome_of(fill, item.input);
    outcome.report = file_report(fill, item.input, item.output);
  } catch (const Interrupted&) {
    outcome.interrupted = true;
    return outcome;
  } catch (const Error& e) {
    outcome = failure(e.what(), exit_code(e.kind()));
  } catch (const std::exception& e) {
    outcome = failure(item.input + ": internal error: " + e.what(), exit_code(ErrorKind::Internal));
  }
  if (!outcome.written) outcome.report = {{"input", item.input}, {"output", nullptr}};
  outcome.report["status"] = status_name(outcome.status);
  outcome.report["reason"] = outcome.reason;
  outcome.report["exit_code"] = outcome.exit_code;
  return outcome;
}

// What the workers print as files finish: errors, warnings (not with
// --quiet), and on a terminal one progress line rewritten in place (the
// per-iteration progress of several files at once would be unreadable).
class BatchProgress {
 public:
  BatchProgress(size_t file_count, bool quiet, bool show_line)
      : file_count_(file_count), quiet_(quiet), show_line_(show_line) {}

  void finished(const BatchItem& item, const FileOutcome& outcome) {
    std::lock_guard<std::mutex> lock(mutex_);
    clear_line();
    for (const std::string& warning : outcome.warnings) {
      if (!quiet_) fmt::print(stderr, "foldfill: warning: {}\n", with_source(warning, item.input));
    }
    if (!outcome.reason.empty()) {
      fmt::print(stderr, "foldfill: error: {}: {}\n", item.input,
                 without_source(outcome.reason, item.input));
    }
    ++done_;
    if (show_line_) {
      fmt::print(stderr, "[{}/{}] {}: {}", done_, file_count_, item.input,
                 status_name(outcome.status));
      dirty_ = true;
    }
  }

  void clear_line() {
    if (dirty_) fmt::print(stderr, "\r\033[K");
    dirty_ = false;
  }

 private:
  size_t file_count_, done_ = 0;
  bool quiet_, show_line_, dirty_ = false;
  std::mutex mutex_;
};

// Runs `work` on `workers` threads (on this one when there is one worker),
// sharing OpenMP's threads among them.
void run_workers(int workers, const std::function<void()>& work) {
  if (workers == 1) {
    work();
    return;
  }
  const int threads_per_worker = std::max(1, omp_get_max_threads() / workers);
  std::vector<std::thread> pool;
  for (int w = 0; w < workers; ++w) {
    pool.emplace_back([&] {
      omp_set_num_threads(threads_per_worker);
      work();
    });
  }
  for (std::thread& thread : pool) thread.join();
}

std::string summary_line(const BatchItem& item, const FileOutcome& outcome) {
  const std::string reason = without_source(outcome.reason, item.input);
  const auto holes = [](int n) { return fmt::format("{} hole{}", n, n == 1 ? "" : "s"); };
  switch (outcome.status) {
    case FileStatus::Filled:
      return fmt::format("{}: filled {} -> {}", item.input, holes(outcome.filled_holes),
                         item.output);
    case FileStatus::Unchanged:
      return fmt::format("{}: nothing to fill, written unchanged -> {}", item.input, item.output);
    case FileStatus::PartlyFilled:
      return fmt::format("{}: partly filled, {} of {}: {} -> {}", item.input, outcome.filled_holes,
                         holes(outcome.chosen_holes), reason, item.output);
    case FileStatus::Failed:
      break;
  }
  return fmt::format("{}: failed: {}{}", item.input, reason,
                     outcome.written ? " -> " + item.output + " (holes left open)" : "");
}

}  // namespace

std::string single_output_path(const std::string& input, const FillArgs& args) {
  std::error_code ec;
  std::string output = args.output;
  if (fs::is_directory(output, ec)) {
    output = (fs::path(output) / output_name(input, args.format)).string();
  } else if (!args.format.empty() && lowercase_extension(output) != "." + args.format) {
    throw UsageError("--format " + args.format + " contradicts -o " + output +
                     " (--format names outputs written into a folder)");
  }
  format_from_path(output);  // an unknown extension fails before any work
  return output;
}

void check_single_paths(const std::string& input, const std::string& output, const FillArgs& args) {
  PathPlan plan;
  plan.reads(input, "the input file");
  plan_obstacle_reads(args, plan);
  plan.writes_file(output, "the output");
  plan.writes_file(args.report, "the report");
  plan.writes_flat_folder(args.flat_dir, "the --flat-dir folder");
  plan.check();
}

std::vector<std::string> input_files(const FillArgs& args) {
  std::vector<std::string> files;
  std::error_code ec;
  for (const std::string& argument : args.inputs) {
    if (!fs::is_directory(argument, ec)) {
      files.push_back(argument);
      continue;
    }
    for (const fs::path& file : meshes_in_folder(argument)) files.push_back(file.string());
  }
  return files;
}

int run_batch(FillArgs args) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<BatchItem> items = plan_batch(args);
  const auto check_paths = [&] {
    PathPlan plan;
    for (const BatchItem& item : items) plan.reads(item.input, "the input file");
    plan_obstacle_reads(args, plan);
    plan.writes_folder(args.output, "the output folder");
    for (const BatchItem& item : items)
      plan.writes_file(item.output, "the output of " + item.input);
    plan.writes_file(args.report, "the report");
    plan.writes_folder(args.flat_dir, "the --flat-dir folder");
    for (const BatchItem& item : items) {
      plan.writes_flat_folder(item.flat_dir, "the --flat-dir folder of " + item.input);
    }
    plan.check();
  };
  // Once with the obstacle files named on the command line, then with the
  // mesh files that the obstacles file names as well.
  check_paths();
  load_obstacles(args);
  check_paths();
  std::error_code ec;
  fs::create_directories(args.output, ec);
  if (ec) {
    throw CannotWriteError(args.output + ": cannot create the folder (" + ec.message() + ")");
  }

  std::vector<FileOutcome> outcomes(items.size());
  BatchProgress progress(items.size(), args.quiet, !args.quiet && isatty(STDERR_FILENO));
  std::atomic<size_t> next{0};
  // After a signal, the workers start no other file, and the one being filled
  // is cancelled.
  run_workers(std::min<int>(args.jobs, static_cast<int>(items.size())), [&] {
    for (size_t i = next++; i < items.size() && !interrupted(); i = next++) {
      outcomes[i] = fill_batch_item(items[i], args);
      if (!outcomes[i].interrupted) progress.finished(items[i], outcomes[i]);
    }
  });
  progress.clear_line();
  stop_if_interrupted();

  std::map<FileStatus, int> counts;
  nlohmann::json files = nlohmann::json::array();
  for (size_t i = 0; i < items.size(); ++i) {
    ++counts[outcomes[i].status];
    files.push_back(outcomes[i].report);
    if (!args.quiet) fmt::print("{}\n", summary_line(items[i], outcomes[i]));
  }
  // A partly filled file is written, but counts as failed: holes were left open.
  const int failed = counts[FileStatus::Failed] + counts[FileStatus::PartlyFilled];
  if (!args.quiet) {
    fmt::print("{} filled, {} unchanged, {} failed\n", counts[FileStatus::Filled],
               counts[FileStatus::Unchanged], failed);
  }
  if (!args.report.empty()) {
    const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - start;
    const nlohmann::json report = {{"foldfill_version", version()},
                                   {"files", files},
                                   {"totals",
                                    {{"filled", counts[FileStatus::Filled]},
                                     {"unchanged", counts[FileStatus::Unchanged]},
                                     {"failed", failed}}},
                                   {"seconds_total", seconds.count()}};
    const Writing writing;
    write_file_atomically(args.report, report.dump(1) + "\n");
  }
  return failed > 0 ? kBatchFailedExitCode : 0;
}

}  // namespace foldfill::cli
