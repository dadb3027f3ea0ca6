// Running the foldfill CLI from a test: its exit code and what it printed.
// The including test defines FOLDFILL_CLI, the path of the built program.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace foldfill::testing {

// The whole file at `path`, as bytes; empty when it cannot be read.
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct CliRun {
  int code = -1;  // the exit code, -1 when the program did not exit (a signal)
  std::string out, err;
};

// Runs `FOLDFILL_CLI arguments` through the shell, with no input, its output
// and errors captured in files of `dir`.
inline CliRun run_cli(const std::string& arguments, const std::filesystem::path& dir) {
  const std::filesystem::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string command = std::string(FOLDFILL_CLI) + " " + arguments + " >" + out.string() +
                              " 2>" + err.string() + " </dev/null";
  const int status = std::system(command.c_str());
  CliRun run;
  run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.out = slurp(out);
  run.err = slurp(err);
  return run;
}

}  // namespace foldfill::testing
