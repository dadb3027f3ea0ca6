// Replays every file of tests/data/fuzz through the fuzz targets' entry points
// (fuzz/fuzz_entry.h): the seed corpus and the inputs that once crashed a
// fuzzer. Each must be read (or rejected with a foldfill::Error) and, for OBJ,
// filled (or rejected) without any other exception or broken invariant.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/io.h"
#include "fuzz_entry.h"

namespace foldfill {
namespace {

namespace fs = std::filesystem;

// The mesh files of the folder, sorted so that failures come in a stable order.
std::vector<fs::path> fuzz_files() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(FOLDFILL_FUZZ_DATA_DIR)) {
    const std::string extension = entry.path().extension().string();
    if (extension == ".obj" || extension == ".ply" || extension == ".off" || extension == ".stl") {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

bool is_seed(const fs::path& path) { return path.filename().string().rfind("seed_", 0) == 0; }

// Runs `entry` on the bytes of `path`: a foldfill::Error is a clean outcome (the
// entry points catch it themselves), any other exception is a regression.
template <class Entry>
void expect_clean(const fs::path& path, Entry entry) {
  try {
    entry(file_bytes(path));
  } catch (const std::exception& e) {
    ADD_FAILURE() << path.filename() << ": " << e.what();
  }
}

TEST(FuzzRegressions, FolderHasSeedsOfEveryFormat) {
  for (const char* extension : {".obj", ".ply", ".off", ".stl"}) {
    const std::vector<fs::path> files = fuzz_files();
    EXPECT_TRUE(
        std::any_of(files.begin(), files.end(),
                    [&](const fs::path& p) { return is_seed(p) && p.extension() == extension; }))
        << "no seed_*" << extension << " in " << FOLDFILL_FUZZ_DATA_DIR;
  }
}

TEST(FuzzRegressions, EveryFileReadsOrFailsCleanly) {
  for (const fs::path& path : fuzz_files()) {
    const MeshFormat format = format_from_path(path.string());
    expect_clean(path, [&](const std::string& bytes) {
      const bool accepted = fuzz::read_mesh_bytes(bytes, format);
      if (is_seed(path)) {
        EXPECT_TRUE(accepted) << path.filename() << ": a seed must be valid";
      }
    });
  }
}

TEST(FuzzRegressions, EveryObjFillsOrFailsCleanly) {
  for (const fs::path& path : fuzz_files()) {
    if (path.extension() != ".obj") continue;
    expect_clean(path, [&](const std::string& bytes) {
      const int filled = fuzz::fill_mesh_bytes(bytes);
      // The seed sheet has one hole: the harness must reach the whole fill.
      if (is_seed(path)) {
        EXPECT_EQ(filled, 1) << path.filename();
      }
    });
  }
}

}  // namespace
}  // namespace foldfill
