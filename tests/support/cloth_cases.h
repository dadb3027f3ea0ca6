// The simulated cloth cases of ../shared/data/cloth (manifest.json and one
// NAME.json per case: a hole cut from a cloth simulation, with the truth),
// read once for the tests and the benchmarks. Header-only and free of
// GoogleTest and Eigen, like reference_cases.h.
#pragma once

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "foldfill/error.h"

namespace foldfill::testing {

// One cloth case: its files and what its NAME.json says of the hole.
struct ClothCase {
  std::string name;                    // e.g. "dev01_sphere_small"
  std::filesystem::path hole_mesh;     // NAME_hole.obj: the cloth with the hole
  std::filesystem::path truth_mesh;    // NAME_gt.obj: the uncut cloth
  std::filesystem::path removed_mesh;  // NAME_removed.obj: the faces cut out
  int hole_vertex = 0;                 // a vertex of the hole's loop (index into the hole mesh)
  int hole_loop_size = 0;              // the vertex count of that loop
  double removed_area = 0;             // the area of the faces cut out
  std::vector<int> hole_to_truth;      // per vertex of the hole mesh, its vertex in the truth
  std::vector<int> removed_to_truth;   // per vertex of the removed mesh, its vertex in the truth
};

// The cases listed in `folder`/manifest.json, in file order; none when the
// manifest is absent. Throws ErrorKind::CannotRead when a file exists but is
// not what it should be.
inline std::vector<ClothCase> read_cloth_cases(const std::filesystem::path& folder) {
  std::vector<ClothCase> cases;
  std::ifstream manifest_file(folder / "manifest.json");
  if (!manifest_file) return cases;
  const auto read = [](std::istream& in, const std::filesystem::path& path) {
    const nlohmann::json document = nlohmann::json::parse(in, nullptr, false);
    if (document.is_discarded())
      throw CannotReadError(path.string() + ": not a JSON document");
    return document;
  };
  const nlohmann::json manifest = read(manifest_file, folder / "manifest.json");
  if (!manifest.is_array())
    throw CannotReadError((folder / "manifest.json").string() + ": not a case list");
  for (const auto& entry : manifest) {
    ClothCase c;
    c.name = entry.at("case").get<std::string>();
    c.hole_mesh = folder / (c.name + "_hole.obj");
    c.truth_mesh = folder / (c.name + "_gt.obj");
    c.removed_mesh = folder / (c.name + "_removed.obj");
    const std::filesystem::path meta_path = folder / (c.name + ".json");
    std::ifstream meta_file(meta_path);
    if (!meta_file) throw CannotReadError(meta_path.string() + ": cannot read");
    const nlohmann::json meta = read(meta_file, meta_path);
    try {
      const auto& loop = meta.at("hole_boundary").at("loop_hole_indices");
      c.hole_vertex = loop.at(0).get<int>();
      c.hole_loop_size = static_cast<int>(loop.size());
      c.removed_area = meta.at("removed").at("area").get<double>();
      c.hole_to_truth = meta.at("hole_to_gt").get<std::vector<int>>();
      c.removed_to_truth = meta.at("removed_to_gt").get<std::vector<int>>();
    } catch (const nlohmann::json::exception& e) {
      throw CannotReadError(meta_path.string() + ": " + e.what());
    }
    cases.push_back(std::move(c));
  }
  return cases;
}

}  // namespace foldfill::testing
