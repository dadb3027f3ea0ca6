// `foldfill view`: the page of a mesh and its fills.
#include "view.h"

#include <fmt/core.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "foldfill/error.h"
#include "foldfill/file.h"
#include "foldfill/io.h"
#include "interrupt.h"
#include "paths.h"

namespace fs = std::filesystem;

namespace foldfill::cli {

CLI::App* add_view_command(CLI::App& app, ViewArgs& args) {
  CLI::App* command = app.add_subcommand(
      "view", "one HTML page (works offline) to turn, compare and inspect a mesh and its fills");
  command->add_option("meshes", args.meshes, "input mesh, then filled mesh(es)")->required();
  command->add_option("-o,--output", args.output, "HTML file")->required();
  command->add_option("--report", args.report, "a fill's JSON report: its per-hole figures");
  command->add_option("--title", args.title, "the page's title (default: the input's file name)");
  const std::map<std::string, ViewLayout> layouts = {{"side-by-side", ViewLayout::SideBySide},
                                                     {"overlay", ViewLayout::Overlay}};
  command
      ->add_option("--layout", args.layout,
                   "'side-by-side' (default) or 'overlay' (one mesh at a time, T switches)")
      ->transform(CLI::CheckedTransformer(layouts, CLI::ignore_case));
  return command;
}

int run_view(const ViewArgs& args) {
  if (!view_available()) throw UsageError(kViewUnavailable);
  PathPlan plan;
  for (const std::string& path : args.meshes) plan.reads(path, "the input mesh");
  plan.reads(args.report, "the report");
  plan.writes_file(args.output, "the page");
  plan.check();

  ViewOptions options;
  options.layout = args.layout;
  options.title =
      args.title.empty() ? fs::path(args.meshes.front()).filename().string() : args.title;
  if (!args.report.empty()) {
    const std::string text = read_file(args.report);
    options.report = nlohmann::json::parse(text, nullptr, false);
    if (options.report.is_discarded() || !options.report.is_object() ||
        !options.report.contains("holes") || !options.report["holes"].is_array()) {
      throw BadFormatError(args.report + ": not a fill's report (JSON with a \"holes\" list)");
    }
  }
  std::vector<Mesh> meshes;
  meshes.reserve(args.meshes.size());
  for (const std::string& path : args.meshes) {
    std::vector<std::string> warnings;
    meshes.push_back(read_mesh(path, &warnings));
    for (const std::string& warning : warnings)
      fmt::print(stderr, "foldfill: warning: {}\n", warning);
    stop_if_interrupted();
  }
  const ViewMesh input{fs::path(args.meshes.front()).filename().string(), &meshes.front()};
  std::vector<ViewMesh> filled;
  for (size_t m = 1; m < meshes.size(); ++m)
    filled.push_back({fs::path(args.meshes[m]).filename().string(), &meshes[m]});
  std::vector<std::string> warnings;
  const std::string page = view_page(input, filled, options, &warnings);
  for (const std::string& warning : warnings)
    fmt::print(stderr, "foldfill: warning: {}\n", warning);
  {
    const Writing writing;
    write_file_atomically(args.output, page);
  }
  return 0;
}

}  // namespace foldfill::cli
