// The reference cases of ../shared/data/reference/cases.json (the authors'
// prototype examples), read once for the tests and the benchmarks.
// Header-only and free of GoogleTest and Eigen, so that every test and
// benchmark can include it whatever layer it links.
#pragma once

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/obstacles.h"

namespace foldfill::testing {

// One entry of cases.json.
struct ReferenceCase {
  std::string file;            // the mesh's file name, as listed
  std::filesystem::path path;  // the mesh's full path
  int hole_vertex = 0;         // a vertex of the hole's loop
  int hole_loop_size = 0;      // the vertex count of that loop
  int outer_loops = 0;         // the other loops: the garment's open edges
  // The prototype's weights (see PrototypeWeights) and bending model.
  double alpha = 0, beta = 0, mu = 0;
  bool two_ring = false;     // BendingModel::TwoRing, else Quadratic
  nlohmann::json obstacles;  // the entry's obstacle list, as written (see reference_obstacles)
};

// The cases listed in `folder`/cases.json, in file order; none when the file
// is absent. Throws ErrorKind::CannotRead when the file exists but is not a
// case list.
inline std::vector<ReferenceCase> read_reference_cases(const std::filesystem::path& folder) {
  std::vector<ReferenceCase> cases;
  std::ifstream in(folder / "cases.json");
  if (!in) return cases;
  const nlohmann::json listing = nlohmann::json::parse(in, nullptr, false);
  if (listing.is_discarded() || !listing.contains("cases"))
    throw CannotReadError((folder / "cases.json").string() + ": not a case list");
  for (const auto& entry : listing["cases"]) {
    ReferenceCase c;
    c.file = entry.at("file").get<std::string>();
    c.path = folder / c.file;
    c.hole_vertex = entry.at("hole_vertex").get<int>();
    c.hole_loop_size = entry.value("hole_loop_size", 0);
    c.outer_loops = entry.value("outer_loops", 0);
    if (entry.contains("prototype")) {
      const auto& p = entry["prototype"];
      c.alpha = p.at("alpha").get<double>();
      c.beta = p.at("beta").get<double>();
      c.mu = p.at("mu").get<double>();
      c.two_ring = p.value("bending", "") == "two_ring";
    }
    c.obstacles = entry.value("obstacles", nlohmann::json::array());
    cases.push_back(std::move(c));
  }
  return cases;
}

// The case's obstacles, parsed as the CLI parses an obstacle file. Kept apart
// from read_reference_cases, which then needs no link to the embed layer.
inline std::vector<Obstacle> reference_obstacles(const ReferenceCase& c) {
  return obstacles_from_json(c.obstacles, c.path.string());
}

}  // namespace foldfill::testing
