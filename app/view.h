// `foldfill view IN [FILLED...] -o PAGE.html [--report report.json]`: the
// page that shows a mesh and its fills in the browser (foldfill/view.h).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "foldfill/view.h"

namespace foldfill::cli {

struct ViewArgs {
  std::vector<std::string> meshes;  // the input, then its fills
  std::string output, report, title;
  ViewLayout layout = ViewLayout::SideBySide;
};

// Adds the `view` subcommand, its options into `args`.
CLI::App* add_view_command(CLI::App& app, ViewArgs& args);

// Checks the paths (an output that is an input is refused), reads the meshes
// and the report, writes the page. Returns the exit code.
int run_view(const ViewArgs& args);

}  // namespace foldfill::cli
