// Helpers shared by the tests: where the optional shared data lives, and
// scratch folders.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace foldfill::testing {

// The shared data folder (FOLDFILL_SHARED overrides the build-time default),
// or an empty path when it is absent.
inline std::filesystem::path shared_dir() {
  const char* env = std::getenv("FOLDFILL_SHARED");
  std::filesystem::path dir = env ? env : FOLDFILL_SHARED_DIR;
  return std::filesystem::is_directory(dir / "data") ? dir : std::filesystem::path();
}

// The scratch folders this process made: removed when it exits, unless a
// test failed (they are then left to look at).
inline std::vector<std::filesystem::path>& scratch_dirs() {
  static std::vector<std::filesystem::path> dirs;
  return dirs;
}

inline void remove_scratch_dirs() {
  if (::testing::UnitTest::GetInstance()->failed_test_count() > 0) return;
  std::error_code ignored;
  for (const auto& dir : scratch_dirs()) std::filesystem::remove_all(dir, ignored);
}

// A fresh, empty scratch folder, private to this process and test (CTest runs
// tests in parallel processes).
inline std::filesystem::path scratch_dir(const std::string& name) {
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string owner = std::to_string(::getpid()) + "_" + (test ? test->name() : "none");
  for (char& c : owner)
    if (c == '/') c = '_';  // a parametrised test's name: Name/k
  auto dir = std::filesystem::temp_directory_path() / ("foldfill_test_" + name + "_" + owner);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  if (scratch_dirs().empty()) std::atexit(remove_scratch_dirs);
  scratch_dirs().push_back(dir);
  return dir;
}

}  // namespace foldfill::testing

// Skips the current test with a clear message when ../shared is not there.
#define FOLDFILL_REQUIRE_SHARED()                                                             \
  if (foldfill::testing::shared_dir().empty())                                                \
  GTEST_SKIP() << "shared data not found (looked in FOLDFILL_SHARED and " FOLDFILL_SHARED_DIR \
                  "); this test needs ../shared/data"
