// The command-line program end to end: exit codes and messages for bad input,
// nothing written on failure, the input never touched, `holes` and `demo`.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <pty.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "foldfill/examples.h"
#include "foldfill/holes.h"
#include "foldfill/io.h"
#include "foldfill/render.h"
#include "foldfill/report.h"
#include "support/cli_run.h"
#include "test_support.h"

namespace foldfill {
namespace {

namespace fs = std::filesystem;
using testing::CliRun;
using testing::run_cli;
using testing::slurp;

// Runs the CLI like run_cli and sends it `signo` after `delay`.
CliRun run_cli_interrupted(const std::string& arguments, const fs::path& dir, int signo,
                           std::chrono::milliseconds delay) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string command = "exec " + std::string(FOLDFILL_CLI) + " " + arguments + " >" +
                              out.string() + " 2>" + err.string() + " </dev/null";
  const pid_t pid = fork();
  if (pid == 0) {
    // A signal ignored here (a background job) would stay ignored in the CLI.
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  std::this_thread::sleep_for(delay);
  kill(pid, signo);
  int status = 0;
  waitpid(pid, &status, 0);
  CliRun run;
  run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.out = slurp(out);
  run.err = slurp(err);
  return run;
}

// The lines of `text` (each ended by a newline).
int line_count(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// An n x n vertex grid, waved in z by `wave`, without the quads `missing`
// (given by their lower-left vertex (i, j)): an outer loop, and a hole per
// missing block.
std::string grid_obj(int n, const std::vector<std::pair<int, int>>& missing, double wave = 0.3) {
  std::string obj;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      obj += "v " + std::to_string(i) + " " + std::to_string(j) + " " +
             std::to_string(wave * std::sin(0.9 * i) * std::cos(0.6 * j)) + "\n";
    }
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      if (std::find(missing.begin(), missing.end(), std::make_pair(i, j)) != missing.end())
        continue;
      const int a = j * n + i + 1, b = a + 1, c = a + n + 1, d = a + n;
      obj += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + "\n";
      obj += "f " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(d) + "\n";
    }
  }
  return obj;
}

// A flat 4 x 4 vertex grid with its middle quad missing: an outer loop and a hole.
std::string grid_with_hole_obj() { return grid_obj(4, {{1, 1}}, 0.0); }

const char* const kNonManifoldObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = foldfill::testing::scratch_dir(
        ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  // Runs `fill` on `input` and checks the error: exit code, one line naming
  // the file, and no output file.
  void expect_fill_error(const fs::path& input, int code, const std::string& words,
                         const std::string& extra = "") {
    const fs::path output = dir_ / "out.obj";
    const CliRun run =
        run_cli("fill " + input.string() + " -o " + output.string() + " " + extra, dir_);
    EXPECT_EQ(run.code, code) << run.err;
    EXPECT_NE(run.err.find(input.filename().string()), std::string::npos) << run.err;
    EXPECT_NE(run.err.find(words), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_FALSE(fs::exists(output));
    for (const auto& entry : fs::directory_iterator(dir_)) {
      EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos);
    }
  }
  fs::path dir_;
};

TEST_F(CliTest, MissingFile) { expect_fill_error(dir_ / "absent.obj", 3, "cannot open"); }

TEST_F(CliTest, EmptyFile) {
  write_text(dir_ / "empty.obj", "");
  expect_fill_error(dir_ / "empty.obj", 4, "empty");
}

TEST_F(CliTest, GarbageBytes) {
  write_text(dir_ / "garbage.ply", std::string("\x01\x02\xff\xfe garbage \x00\x07", 16));
  expect_fill_error(dir_ / "garbage.ply", 4, "");
}

TEST_F(CliTest, TruncatedBinaryStl) {
  const std::string bytes =
      serialize_mesh(parse_mesh(grid_with_hole_obj(), MeshFormat::Obj, "grid"), MeshFormat::Stl);
  write_text(dir_ / "cut.stl", bytes.substr(0, bytes.size() - 20));
  expect_fill_error(dir_ / "cut.stl", 4, "");
}

TEST_F(CliTest, NonFiniteCoordinate) {
  write_text(dir_ / "nan.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n");
  expect_fill_error(dir_ / "nan.obj", 5, "");
}

TEST_F(CliTest, FaceIndexOutOfRange) {
  write_text(dir_ / "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  expect_fill_error(dir_ / "range.obj", 6, "out of range");
}

TEST_F(CliTest, RepeatedVertexInFace) {
  write_text(dir_ / "repeat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n");
  expect_fill_error(dir_ / "repeat.obj", 6, "");
}

TEST_F(CliTest, NonManifoldEdge) {
  write_text(dir_ / "fin.obj", kNonManifoldObj);
  expect_fill_error(dir_ / "fin.obj", 7, "edge");
}

TEST_F(CliTest, PinchedLoopNamedExplicitly) {
  // Two triangles sharing only vertex 1: its boundary touches itself there.
  write_text(dir_ / "bowtie.obj",
             "v 0 0 0\nv 1 1 0\nv 1 -1 0\nv -1 1 0\nv -1 -1 0\nf 1 2 4\nf 1 5 3\n");
  expect_fill_error(dir_ / "bowtie.obj", 8, "", "--holes 0");
}

TEST_F(CliTest, OutputOverInputIsRefused) {
  const fs::path input = dir_ / "grid.obj";
  write_text(input, grid_with_hole_obj());
  const CliRun run = run_cli("fill " + input.string() + " -o " + input.string(), dir_);
  EXPECT_EQ(run.code, 2);
  EXPECT_EQ(slurp(input), grid_with_hole_obj());
}

TEST_F(CliTest, UnknownOutputExtensionIsAUsageError) {
  const fs::path input = dir_ / "grid.obj";
  write_text(input, grid_with_hole_obj());
  const CliRun run = run_cli("fill " + input.string() + " -o " + (dir_ / "out.xyz").string(), dir_);
  EXPECT_EQ(run.code, 2) << run.err;
  EXPECT_FALSE(fs::exists(dir_ / "out.xyz"));
}

TEST_F(CliTest, NothingToFillWritesTheMeshUnchanged) {
  const fs::path input = dir_ / "triangle.obj", output = dir_ / "out.obj";
  write_text(input, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const CliRun run = run_cli("fill " + input.string() + " -o " + output.string(), dir_);
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.out.find("nothing to fill"), std::string::npos) << run.out;
  const Mesh in = read_mesh(input.string()), out = read_mesh(output.string());
  EXPECT_EQ(out.positions, in.positions);
  EXPECT_EQ(out.faces, in.faces);
}

TEST_F(CliTest, HolesJsonListsBothLoops) {
  const fs::path input = dir_ / "grid.obj";
  write_text(input, grid_with_hole_obj());
  const CliRun run = run_cli("holes --json " + input.string(), dir_);
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  ASSERT_EQ(j["loops"].size(), 2u);
  int outer = 0;
  for (const auto& loop : j["loops"]) {
    outer += loop["outer"].get<bool>();
    EXPECT_EQ(loop["vertices"].size(), loop["vertex_count"].get<size_t>());
  }
  EXPECT_EQ(outer, 1);
  const auto& hole = j["loops"][0]["outer"].get<bool>() ? j["loops"][1] : j["loops"][0];
  EXPECT_EQ(hole["vertex_count"], 4);
  EXPECT_DOUBLE_EQ(hole["length"].get<double>(), 4.0);
  EXPECT_TRUE(hole["hole_like"].get<bool>());
  EXPECT_NEAR(hole["turning"].get<double>(), 2 * M_PI, 1e-9);
  for (const auto& loop : j["loops"]) {
    EXPECT_EQ(loop["hole_like"].get<bool>(), !loop["outer"].get<bool>());
  }
}

TEST_F(CliTest, FillsASmallHoleKeepingEveryInputVertex) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.ply", report = dir_ / "r.json";
  write_text(input, grid_with_hole_obj());
  const CliRun run = run_cli(
      "fill " + input.string() + " -o " + output.string() + " --report " + report.string(), dir_);
  ASSERT_EQ(run.code, 0) << run.err;
  const Mesh in = read_mesh(input.string()), out = read_mesh(output.string());
  ASSERT_GE(out.positions.size(), in.positions.size());
  EXPECT_TRUE(std::equal(in.positions.begin(), in.positions.end(), out.positions.begin()));
  EXPECT_TRUE(std::equal(in.faces.begin(), in.faces.end(), out.faces.begin()));
  EXPECT_GE(out.faces.size(), in.faces.size() + 2);
  const nlohmann::json r = nlohmann::json::parse(slurp(report));
  ASSERT_EQ(r["holes"].size(), 1u);
  EXPECT_TRUE(r["holes"][0]["filled"].get<bool>());
  EXPECT_EQ(r["holes"][0]["loop_vertex_count"], 4);
}

TEST_F(CliTest, DemoWritesInputResultAndReport) {
  const CliRun run = run_cli("demo " + (dir_ / "demo").string() + " --quiet", dir_);
  ASSERT_EQ(run.code, 0) << run.err;
  const Mesh in = read_mesh((dir_ / "demo" / "input.obj").string());
  const Mesh out = read_mesh((dir_ / "demo" / "filled.obj").string());
  EXPECT_GT(out.positions.size(), in.positions.size());
  EXPECT_TRUE(std::equal(in.positions.begin(), in.positions.end(), out.positions.begin()));
  const nlohmann::json r = nlohmann::json::parse(slurp(dir_ / "demo" / "report.json"));
  ASSERT_EQ(r["holes"].size(), 1u);
  EXPECT_TRUE(r["holes"][0]["filled"].get<bool>());
  EXPECT_EQ(r["holes"][0]["self_intersections"], 0);
}

// The demo's patch (about 500 interior vertices) starts from ARAP by default
// and from a coarser fill with --coarse-start 100, which leaves it nearer its
// minimum; --coarse-start 0 is the default here.
TEST_F(CliTest, CoarseStartSetsWhichPatchesStartFromACoarserFill) {
  ASSERT_EQ(run_cli("demo " + (dir_ / "demo").string() + " --quiet", dir_).code, 0);
  const fs::path input = dir_ / "demo" / "input.obj";
  const auto energy_after_start = [&](const std::string& option, const std::string& name) {
    const fs::path report = dir_ / (name + ".json");
    const CliRun run =
        run_cli("fill " + input.string() + " -q -o " + (dir_ / (name + ".obj")).string() +
                    " --report " + report.string() + " " + option,
                dir_);
    EXPECT_EQ(run.code, 0) << run.err;
    const nlohmann::json hole = nlohmann::json::parse(slurp(report))["holes"].at(0);
    EXPECT_GT(hole["patch_vertex_count"].get<int>(), 100);
    return hole["energy"]["after_arap"]["total"].get<double>();
  };
  const double by_default = energy_after_start("", "default");
  const double never = energy_after_start("--coarse-start 0", "never");
  const double coarse = energy_after_start("--coarse-start 100", "coarse");
  EXPECT_EQ(by_default, never);
  EXPECT_LT(coarse, 0.5 * never);
}

// Batch runs: a folder or several files, written into an output folder.

// The quads of a `size` x `size` block with lower-left vertex (i, j).
std::vector<std::pair<int, int>> block(int i, int j, int size) {
  std::vector<std::pair<int, int>> quads;
  for (int dj = 0; dj < size; ++dj) {
    for (int di = 0; di < size; ++di) quads.emplace_back(i + di, j + dj);
  }
  return quads;
}

// Two 3 x 3 quad holes in a 10 x 10 vertex grid: they get interior vertices.
std::string two_hole_grid_obj() {
  std::vector<std::pair<int, int>> missing = block(1, 1, 3);
  for (const auto& quad : block(5, 5, 3)) missing.push_back(quad);
  return grid_obj(10, missing);
}

// A folder with three good meshes (two formats, one with two holes), a
// non-manifold one, and a file that is not a mesh.
fs::path write_batch_folder(const fs::path& dir) {
  const fs::path in = dir / "in";
  fs::create_directories(in);
  write_text(in / "a.obj", two_hole_grid_obj());
  write_text(in / "b.obj", grid_obj(5, {{2, 1}}));
  const Mesh c = parse_mesh(grid_obj(6, {{2, 2}, {3, 2}}), MeshFormat::Obj, "c");
  write_text(in / "c.ply", serialize_mesh(c, MeshFormat::Ply));
  write_text(in / "bad.obj", kNonManifoldObj);
  write_text(in / "notes.txt", "not a mesh");
  return in;
}

std::vector<std::string> file_names(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

TEST_F(CliTest, FolderBatchGoesPastABadFileAndSummarises) {
  const fs::path in = write_batch_folder(dir_), out = dir_ / "out";
  const CliRun run = run_cli("fill " + in.string() + " -o " + out.string(), dir_);
  EXPECT_EQ(run.code, 11) << run.err;
  EXPECT_EQ(file_names(out), (std::vector<std::string>{"a.obj", "b.obj", "c.ply"}));
  for (const std::string name : {"a.obj", "b.obj", "c.ply"}) {
    const Mesh before = read_mesh((in / name).string()), after = read_mesh((out / name).string());
    EXPECT_GT(after.face_count(), before.face_count()) << name;
  }
  const size_t a = run.out.find("a.obj: filled 2 holes"), bad = run.out.find("bad.obj: failed: ");
  const size_t c = run.out.find("c.ply: filled 1 hole");
  EXPECT_LT(a, bad) << run.out;
  EXPECT_LT(bad, c) << run.out;
  EXPECT_NE(run.out.find("shared by 3 faces", bad), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("3 filled, 0 unchanged, 1 failed"), std::string::npos) << run.out;
  EXPECT_NE(run.err.find("bad.obj"), std::string::npos) << run.err;
}

TEST_F(CliTest, BatchOutputsDoNotDependOnJobs) {
  const fs::path in = write_batch_folder(dir_);
  ASSERT_EQ(run_cli("demo " + (dir_ / "demo").string() + " --quiet", dir_).code, 0);
  fs::copy_file(dir_ / "demo" / "input.obj", in / "folded.obj");
  const CliRun one =
      run_cli("fill " + in.string() + " -q -j 1 -o " + (dir_ / "one").string(), dir_);
  const CliRun three =
      run_cli("fill " + in.string() + " -q -j 3 -o " + (dir_ / "three").string(), dir_);
  EXPECT_EQ(one.code, 11) << one.err;
  EXPECT_EQ(three.code, 11) << three.err;
  const std::vector<std::string> names = file_names(dir_ / "one");
  EXPECT_EQ(names.size(), 4u);
  EXPECT_EQ(file_names(dir_ / "three"), names);
  for (const std::string& name : names) {
    EXPECT_EQ(slurp(dir_ / "one" / name), slurp(dir_ / "three" / name)) << name;
  }
}

TEST_F(CliTest, SeveralFileArgumentsWithAnOutputFormat) {
  const fs::path in = write_batch_folder(dir_), other = dir_ / "other", out = dir_ / "out";
  fs::create_directories(other);
  write_text(other / "flat.stl", serialize_mesh(parse_mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
                                                           MeshFormat::Obj, "triangle"),
                                                MeshFormat::Stl));
  const CliRun run =
      run_cli("fill " + (in / "c.ply").string() + " " + (other / "flat.stl").string() + " " +
                  (in / "a.obj").string() + " --format off -o " + out.string(),
              dir_);
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_EQ(file_names(out), (std::vector<std::string>{"a.off", "c.off", "flat.off"}));
  EXPECT_EQ(read_mesh((out / "flat.off").string()).face_count(), 1);
  EXPECT_NE(run.out.find("flat.stl: nothing to fill"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("2 filled, 1 unchanged, 0 failed"), std::string::npos) << run.out;
}

TEST_F(CliTest, BatchRefusesToWriteIntoAnInputFolder) {
  const fs::path in = write_batch_folder(dir_);
  const std::vector<std::string> before = file_names(in);
  const std::string a = (in / "a.obj").string(), b = (in / "b.obj").string();
  for (const std::string& inputs : {in.string(), a + " " + b, (in / ".").string()}) {
    const CliRun run = run_cli("fill " + inputs + " -o " + in.string(), dir_);
    EXPECT_EQ(run.code, 2) << inputs;
    EXPECT_NE(run.err.find("folder of the inputs"), std::string::npos) << run.err;
  }
  EXPECT_EQ(file_names(in), before);
  EXPECT_EQ(slurp(in / "a.obj"), two_hole_grid_obj());
}

TEST_F(CliTest, BatchRefusesTwoInputsWithTheSameOutput) {
  const fs::path in = write_batch_folder(dir_), other = dir_ / "other", out = dir_ / "out";
  fs::create_directories(other);
  fs::copy_file(in / "a.obj", other / "a.obj");
  const CliRun run = run_cli(
      "fill " + (in / "a.obj").string() + " " + (other / "a.obj").string() + " -o " + out.string(),
      dir_);
  EXPECT_EQ(run.code, 2) << run.err;
  EXPECT_NE(run.err.find("would be written here"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CliTest, BatchReportHasOneEntryPerInput) {
  const fs::path in = write_batch_folder(dir_), report = dir_ / "report.json";
  const CliRun run = run_cli(
      "fill " + in.string() + " -q -o " + (dir_ / "out").string() + " --report " + report.string(),
      dir_);
  EXPECT_EQ(run.code, 11) << run.err;
  EXPECT_TRUE(run.out.empty()) << run.out;
  const nlohmann::json r = nlohmann::json::parse(slurp(report));
  ASSERT_EQ(r["files"].size(), 4u);
  const std::vector<std::string> names = {"a.obj", "b.obj", "bad.obj", "c.ply"};
  for (size_t i = 0; i < names.size(); ++i) {
    const nlohmann::json& file = r["files"][i];
    EXPECT_EQ(file["input"], (in / names[i]).string());
    const bool bad = names[i] == "bad.obj";
    EXPECT_EQ(file["status"], bad ? "failed" : "filled");
    EXPECT_EQ(file["exit_code"], bad ? 7 : 0);
    EXPECT_EQ(file["output"].is_null(), bad);
    EXPECT_EQ(file["reason"].get<std::string>().find("shared by 3 faces") != std::string::npos,
              bad);
    EXPECT_EQ(file.contains("holes"), !bad);
  }
  EXPECT_EQ(r["files"][0]["holes"].size(), 2u);
  EXPECT_EQ(r["totals"], (nlohmann::json{{"filled", 3}, {"unchanged", 0}, {"failed", 1}}));
}

TEST_F(CliTest, SingleInputIntoAnExistingFolder) {
  const fs::path in = write_batch_folder(dir_), out = dir_ / "out";
  fs::create_directories(out);
  const CliRun run = run_cli("fill " + (in / "b.obj").string() + " -o " + out.string(), dir_);
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.out.find("wrote " + (out / "b.obj").string()), std::string::npos) << run.out;
  EXPECT_GT(read_mesh((out / "b.obj").string()).face_count(),
            read_mesh((in / "b.obj").string()).face_count());
}

// Hostile input: paths written over inputs or over each other, signals, long
// names, unwritable places, bad option values, warnings.

// A refusal before any work: `code`, one error line naming `path`.
void expect_refusal(const CliRun& run, int code, const std::string& path) {
  EXPECT_EQ(run.code, code) << run.err;
  EXPECT_EQ(run.err.rfind("foldfill: error: ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find(path), std::string::npos) << run.err;
  EXPECT_EQ(line_count(run.err), 1) << run.err;
}

// No temporary file, of this version or the last, in `dir`.
void expect_no_temporary_file(const fs::path& dir) {
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    EXPECT_EQ(name.find(".tmp"), std::string::npos) << entry.path();
    EXPECT_EQ(name.find(".foldfill-"), std::string::npos) << entry.path();
  }
}

TEST_F(CliTest, ReportEqualToTheInputIsRefused) {
  const fs::path input = dir_ / "grid.obj", other = dir_ / "other.obj";
  write_text(input, grid_with_hole_obj());
  write_text(other, grid_obj(5, {{2, 1}}));
  const CliRun single = run_cli("fill " + input.string() + " -o " + (dir_ / "out.obj").string() +
                                    " --report " + input.string(),
                                dir_);
  expect_refusal(single, 2, input.string());
  EXPECT_FALSE(fs::exists(dir_ / "out.obj"));
  const CliRun batch = run_cli("fill " + input.string() + " " + other.string() + " -o " +
                                   (dir_ / "out").string() + " --report " + other.string(),
                               dir_);
  expect_refusal(batch, 2, other.string());
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  EXPECT_EQ(slurp(input), grid_with_hole_obj());
  EXPECT_EQ(slurp(other), grid_obj(5, {{2, 1}}));
}

TEST_F(CliTest, ReportEqualToTheOutputIsRefused) {
  const fs::path input = dir_ / "grid.obj", out = dir_ / "out";
  write_text(input, grid_with_hole_obj());
  fs::create_directories(out);
  // The same path, the same place through `..` (neither exists yet), a batch
  // output.
  const std::vector<std::pair<std::string, std::string>> cases = {
      {(out / "x.obj").string(), (out / "x.obj").string()},
      {(out / ".." / "out" / "x.obj").string(), (out / "x.obj").string()},
  };
  for (const auto& [output, report] : cases) {
    const CliRun run =
        run_cli("fill " + input.string() + " -o " + output + " --report " + report, dir_);
    expect_refusal(run, 2, report);
    EXPECT_TRUE(fs::is_empty(out)) << output;
  }
  const CliRun batch =
      run_cli("fill " + input.string() + " " + (dir_ / "grid.obj").string() + " -o " +
                  (dir_ / "batch").string() + " --report " + (dir_ / "batch" / "grid.obj").string(),
              dir_);
  EXPECT_EQ(batch.code, 2) << batch.err;
  EXPECT_FALSE(fs::exists(dir_ / "batch"));
  const fs::path in = write_batch_folder(dir_);
  const CliRun folder = run_cli("fill " + in.string() + " -o " + (dir_ / "batch").string() +
                                    " --report " + (dir_ / "batch" / "a.obj").string(),
                                dir_);
  expect_refusal(folder, 2, (dir_ / "batch" / "a.obj").string());
  EXPECT_FALSE(fs::exists(dir_ / "batch"));
}

TEST_F(CliTest, WrittenPathsThatLeadToAnInputAreRefused) {
  const fs::path input = dir_ / "grid.obj";
  write_text(input, grid_with_hole_obj());
  fs::create_symlink(input, dir_ / "link.json");
  fs::create_hard_link(input, dir_ / "hard.json");
  fs::create_directories(dir_ / "sub");
  for (const fs::path& report :
       {dir_ / "link.json", dir_ / "hard.json", dir_ / "sub" / ".." / "grid.obj"}) {
    const CliRun run = run_cli("fill " + input.string() + " -o " + (dir_ / "out.obj").string() +
                                   " --report " + report.string(),
                               dir_);
    expect_refusal(run, 2, report.string());
    EXPECT_NE(run.err.find("an input is never overwritten"), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(dir_ / "out.obj"));
  }
  const CliRun output = run_cli(
      "fill " + input.string() + " -o " + (dir_ / "sub" / ".." / "grid.obj").string(), dir_);
  EXPECT_EQ(output.code, 2) << output.err;
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.json"));
  EXPECT_EQ(slurp(input), grid_with_hole_obj());
  EXPECT_EQ(fs::hard_link_count(input), 2u);
}

TEST_F(CliTest, ObstaclesFileIsNeverWritten) {
  const fs::path input = dir_ / "grid.obj", obstacles = dir_ / "obstacles.json";
  const std::string no_obstacles = "{\"obstacles\": []}\n";
  write_text(input, grid_with_hole_obj());
  write_text(obstacles, no_obstacles);
  const CliRun report =
      run_cli("fill " + input.string() + " -o " + (dir_ / "out.obj").string() + " --report " +
                  obstacles.string() + " --obstacles " + obstacles.string(),
              dir_);
  expect_refusal(report, 2, obstacles.string());
  EXPECT_FALSE(fs::exists(dir_ / "out.obj"));
  fs::create_directories(dir_ / "demo");
  write_text(dir_ / "demo" / "report.json", no_obstacles);
  const CliRun demo = run_cli("demo " + (dir_ / "demo").string() + " --obstacles " +
                                  (dir_ / "demo" / "report.json").string(),
                              dir_);
  expect_refusal(demo, 2, (dir_ / "demo" / "report.json").string());
  EXPECT_EQ(file_names(dir_ / "demo"), std::vector<std::string>{"report.json"});
  EXPECT_EQ(slurp(obstacles), no_obstacles);
  EXPECT_EQ(slurp(dir_ / "demo" / "report.json"), no_obstacles);
}

TEST_F(CliTest, FlatDirOverAnInputOrAnOutputIsRefused) {
  const fs::path input = dir_ / "grid.obj", flat = dir_ / "flat";
  write_text(input, grid_with_hole_obj());
  fs::create_directories(flat);
  const std::string fill = "fill " + input.string() + " ";
  // The flat folder is the input; the output, the report or the input is
  // one of the flat meshes.
  expect_refusal(
      run_cli(fill + "-o " + (dir_ / "out.obj").string() + " --flat-dir " + input.string(), dir_),
      2, input.string());
  for (const std::string name : {"loop0_flat_strip.obj", "loop1_flat_patch.obj"}) {
    const std::string mesh = (flat / name).string();
    expect_refusal(run_cli(fill + "-o " + mesh + " --flat-dir " + flat.string(), dir_), 2, mesh);
    expect_refusal(run_cli(fill + "-o " + (dir_ / "out.obj").string() + " --report " + mesh +
                               " --flat-dir " + flat.string(),
                           dir_),
                   2, mesh);
  }
  write_text(flat / "loop1_flat_strip.obj", grid_with_hole_obj());
  const CliRun flat_input =
      run_cli("fill " + (flat / "loop1_flat_strip.obj").string() + " -o " +
                  (dir_ / "out.obj").string() + " --flat-dir " + flat.string(),
              dir_);
  expect_refusal(flat_input, 2, (flat / "loop1_flat_strip.obj").string());
  EXPECT_FALSE(fs::exists(dir_ / "out.obj"));
  // A batch's flat folders are named like its outputs: not in the output folder.
  const fs::path in = write_batch_folder(dir_), out = dir_ / "out";
  EXPECT_EQ(
      run_cli("fill " + in.string() + " -o " + out.string() + " --flat-dir " + out.string(), dir_)
          .code,
      2);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(file_names(flat), std::vector<std::string>{"loop1_flat_strip.obj"});
  EXPECT_EQ(slurp(flat / "loop1_flat_strip.obj"), grid_with_hole_obj());
}

TEST_F(CliTest, RenderOutputEqualToAnInputIsRefused) {
  const fs::path input = dir_ / "grid.obj";
  write_text(input, grid_with_hole_obj());
  fs::create_symlink(input, dir_ / "link.png");
  for (const fs::path& picture : {input, dir_ / "link.png"}) {
    const CliRun run = run_cli("render " + input.string() + " -o " + picture.string(), dir_);
    expect_refusal(run, 2, picture.string());
  }
  EXPECT_EQ(slurp(input), grid_with_hole_obj());
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.png"));
}

// `view` of a grid and its fill: one page, with the report's figures; or,
// in a build without three.js, the message that says so (then skipped).
TEST_F(CliTest, ViewWritesOnePage) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.ply";
  const fs::path report = dir_ / "report.json", page = dir_ / "page.html";
  write_text(input, grid_obj(8, {{3, 3}, {4, 3}}));
  ASSERT_EQ(run_cli("fill " + input.string() + " -o " + output.string() + " --report " +
                        report.string() + " --quiet",
                    dir_)
                .code,
            0);
  const CliRun run = run_cli("view " + input.string() + " " + output.string() + " -o " +
                                 page.string() + " --report " + report.string(),
                             dir_);
  if (run.code == 2 && run.err.find("not available") != std::string::npos) {
    EXPECT_FALSE(fs::exists(page));
    GTEST_SKIP() << run.err;
  }
  ASSERT_EQ(run.code, 0) << run.err;
  const std::string html = slurp(page);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("id=\"foldfill-meta\""), std::string::npos);
  EXPECT_NE(html.find("\"stop_reason\""), std::string::npos);
  // Nothing loaded from elsewhere: the page works offline.
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
}

TEST_F(CliTest, ViewOutputEqualToAnInputIsRefused) {
  const fs::path input = dir_ / "grid.obj", report = dir_ / "report.json";
  write_text(input, grid_with_hole_obj());
  write_text(report, "{\"holes\": []}");
  for (const fs::path& page : {input, report}) {
    const CliRun run = run_cli(
        "view " + input.string() + " --report " + report.string() + " -o " + page.string(), dir_);
    if (run.code == 2 && run.err.find("not available") != std::string::npos)
      GTEST_SKIP() << run.err;
    expect_refusal(run, 2, page.string());
  }
  EXPECT_EQ(slurp(input), grid_with_hole_obj());
  EXPECT_EQ(slurp(report), "{\"holes\": []}");
}

TEST_F(CliTest, ViewRefusesAReportThatIsNotOne) {
  const fs::path input = dir_ / "grid.obj", report = dir_ / "notes.json";
  const fs::path page = dir_ / "page.html";
  write_text(input, grid_with_hole_obj());
  write_text(report, "[1, 2");
  CliRun run = run_cli(
      "view " + input.string() + " --report " + report.string() + " -o " + page.string(), dir_);
  if (run.code == 2 && run.err.find("not available") != std::string::npos) GTEST_SKIP() << run.err;
  expect_refusal(run, 4, report.string());
  EXPECT_FALSE(fs::exists(page));
  run = run_cli("view " + input.string() + " --layout sideways -o " + page.string(), dir_);
  EXPECT_EQ(run.code, 2) << run.err;
  EXPECT_NE(run.err.find("--layout"), std::string::npos) << run.err;
}

// A fill that takes minutes (gradient descent on about 4,000 patch vertices)
// but for its time limit.
const char* const kSlowFill = " --solver gd --density 2 --max-iterations 1000000 --time-limit 30";

TEST_F(CliTest, SignalDuringTheFillExits130AndWritesNothing) {
  const fs::path input = dir_ / "large.obj", output = dir_ / "out.obj";
  const fs::path report = dir_ / "report.json";
  write_text(input, grid_obj(40, block(5, 5, 30)));
  for (const int signo : {SIGINT, SIGTERM}) {
    const auto start = std::chrono::steady_clock::now();
    const CliRun run = run_cli_interrupted("fill " + input.string() + " -o " + output.string() +
                                               " --report " + report.string() + kSlowFill,
                                           dir_, signo, std::chrono::milliseconds(500));
    const std::chrono::duration<double> seconds = std::chrono::steady_clock::now() - start;
    EXPECT_EQ(run.code, 130) << signo << ": " << run.err;
    EXPECT_EQ(run.err, std::string("foldfill: error: interrupted (") +
                           (signo == SIGINT ? "SIGINT" : "SIGTERM") + ")\n");
    EXPECT_LT(seconds.count(), 10);
    EXPECT_FALSE(fs::exists(output));
    EXPECT_FALSE(fs::exists(report));
    expect_no_temporary_file(dir_);
  }
}

TEST_F(CliTest, SignalDuringABatchExits130AndWritesNothing) {
  const fs::path in = dir_ / "in", out = dir_ / "out", report = dir_ / "report.json";
  fs::create_directories(in);
  write_text(in / "a.obj", grid_obj(40, block(5, 5, 30)));
  write_text(in / "b.obj", grid_obj(40, block(4, 4, 30)));
  for (const std::string jobs : {"1", "2"}) {
    const CliRun run =
        run_cli_interrupted("fill " + in.string() + " -j " + jobs + " -o " + out.string() +
                                " --report " + report.string() + kSlowFill,
                            dir_, SIGINT, std::chrono::milliseconds(500));
    EXPECT_EQ(run.code, 130) << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
    EXPECT_TRUE(!fs::exists(out) || fs::is_empty(out));
    EXPECT_FALSE(fs::exists(report));
    expect_no_temporary_file(dir_);
  }
}

TEST_F(CliTest, OutputNameOf250BytesIsWritten) {
  const fs::path input = dir_ / "grid.obj";
  write_text(input, grid_with_hole_obj());
  // 250 bytes: the longest names leave no room for a suffix (NAME_MAX is 255).
  const fs::path output = dir_ / (std::string(246, 'o') + ".obj");
  const fs::path report = dir_ / (std::string(245, 'r') + ".json");
  const CliRun run = run_cli(
      "fill " + input.string() + " -o " + output.string() + " --report " + report.string(), dir_);
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_GT(read_mesh(output.string()).face_count(), read_mesh(input.string()).face_count());
  EXPECT_TRUE(nlohmann::json::parse(slurp(report))["holes"][0]["filled"].get<bool>());
  expect_no_temporary_file(dir_);
}

TEST_F(CliTest, WrittenFilesHaveTheModeOfNewFiles) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.obj";
  write_text(input, grid_with_hole_obj());
  const mode_t old_mask = umask(027);
  const CliRun run = run_cli("fill " + input.string() + " -o " + output.string(), dir_);
  umask(old_mask);
  ASSERT_EQ(run.code, 0) << run.err;
  struct stat status {};
  ASSERT_EQ(stat(output.c_str(), &status), 0);
  EXPECT_EQ(status.st_mode & 0777, 0640u);
}

TEST_F(CliTest, FlatDirUnderARegularFileIsAWriteError) {
  const fs::path input = dir_ / "grid.obj", notes = dir_ / "notes.txt";
  write_text(input, grid_with_hole_obj());
  write_text(notes, "not a folder");
  const std::string flat = (notes / "sub").string();
  expect_refusal(run_cli("fill " + input.string() + " -o " + (dir_ / "out.obj").string() +
                             " --flat-dir " + flat,
                         dir_),
                 10, flat);
  EXPECT_FALSE(fs::exists(dir_ / "out.obj"));
  const fs::path in = write_batch_folder(dir_);
  expect_refusal(
      run_cli("fill " + in.string() + " -o " + (dir_ / "out").string() + " --flat-dir " + flat,
              dir_),
      10, flat);
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  expect_refusal(run_cli("demo " + (notes / "demo").string(), dir_), 10, (notes / "demo").string());
  EXPECT_EQ(slurp(notes), "not a folder");
}

TEST_F(CliTest, NanAndInfiniteOptionValuesAreRefused) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.obj";
  write_text(input, grid_with_hole_obj());
  const std::string fill = "fill " + input.string() + " -o " + output.string() + " ";
  const std::string render = "render " + input.string() + " -o " + (dir_ / "p.png").string() + " ";
  for (const std::string& command :
       {fill + "--lambda nan", fill + "--shrink nan", fill + "--time-limit nan",
        fill + "--density nan", fill + "--repulsion nan", fill + "--alpha nan", fill + "--beta nan",
        fill + "--mu nan", fill + "--near nan,nan,nan", fill + "--max-iterations nan",
        fill + "--lambda inf", fill + "--repulsion inf", fill + "--time-limit inf",
        fill + "--near 0,0,inf", fill + "--alpha -inf", render + "--azimuth nan",
        render + "--elevation inf"}) {
    const CliRun run = run_cli(command, dir_);
    const std::string option = command.substr(command.rfind("--"));
    const std::string name = option.substr(0, option.find(' '));
    EXPECT_EQ(run.code, 2) << command;
    EXPECT_EQ(run.err.rfind("foldfill: error: " + name + ": ", 0), 0u) << run.err;
    EXPECT_EQ(line_count(run.err), 1) << run.err;
  }
  EXPECT_FALSE(fs::exists(output));
  EXPECT_FALSE(fs::exists(dir_ / "p.png"));
}

TEST_F(CliTest, TrailingGarbageInOptionValuesIsRefused) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.obj";
  write_text(input, grid_with_hole_obj());
  const std::string fill = "fill " + input.string() + " -o " + output.string() + " ";
  for (const std::string option :
       {"--holes 1abc", "--holes 0,", "--holes 0,,1", "--holes 1.0", "--holes 0x1",
        "--max-iterations 10abc", "--lambda 0.1x", "--keep-open 1z", "--jobs 2x"}) {
    const CliRun run = run_cli(fill + option, dir_);
    EXPECT_EQ(run.code, 2) << option;
    EXPECT_EQ(run.err.rfind("foldfill: error: " + option.substr(0, option.find(' ')) + ": ", 0), 0u)
        << run.err;
    EXPECT_EQ(line_count(run.err), 1) << run.err;
  }
  EXPECT_FALSE(fs::exists(output));
}

TEST_F(CliTest, UsageErrorsAreOneLine) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.obj";
  write_text(input, grid_with_hole_obj());
  const std::string fill = "fill " + input.string() + " ";
  for (const std::string& arguments :
       {fill + "-o " + output.string() + " --bogus", fill + "-o", fill, std::string(),
        fill + "-o " + output.string() + " --method x", std::string("holes")}) {
    const CliRun run = run_cli(arguments, dir_);
    EXPECT_EQ(run.code, 2) << arguments;
    EXPECT_EQ(run.err.rfind("foldfill: error: ", 0), 0u) << run.err;
    EXPECT_EQ(line_count(run.err), 1) << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
  }
  EXPECT_FALSE(fs::exists(output));
  for (const std::string arguments : {"--help", "fill --help", "--version"}) {
    const CliRun run = run_cli(arguments, dir_);
    EXPECT_EQ(run.code, 0) << arguments;
    EXPECT_NE(run.out.find(arguments == "--version" ? "foldfill 0.1.0"
                           : arguments == "--help"  ? "fill"
                                                    : "--output"),
              std::string::npos)
        << run.out;
    EXPECT_TRUE(run.err.empty()) << run.err;
  }
}

// A 5 x 5 vertex grid and a triangle that touches its corner vertex: the two
// pieces meet only there, so the triangle's loop (loop 1) is not a disk
// boundary and the default leaves it open with a warning.
std::string pinched_hole_obj() { return grid_obj(5, {}, 0.0) + "v -1 0 0\nv 0 -1 0\nf 1 26 27\n"; }

// An open cylinder: two loops of the same length, tube ends, neither turning
// like a hole.
std::string tube_obj() {
  std::string obj;
  const int sides = 12, rings = 4;
  for (int r = 0; r < rings; ++r) {
    for (int i = 0; i < sides; ++i) {
      const double t = 2 * M_PI * i / sides;
      obj += "v " + std::to_string(std::cos(t)) + " " + std::to_string(std::sin(t)) + " " +
             std::to_string(r) + "\n";
    }
  }
  for (int r = 0; r + 1 < rings; ++r) {
    for (int i = 0; i < sides; ++i) {
      const int a = r * sides + i + 1, b = r * sides + (i + 1) % sides + 1;
      obj += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(b + sides) +
             "\n";
      obj += "f " + std::to_string(a) + " " + std::to_string(b + sides) + " " +
             std::to_string(a + sides) + "\n";
    }
  }
  return obj;
}

TEST_F(CliTest, QuietPrintsNoWarnings) {
  const fs::path in = dir_ / "in";
  fs::create_directories(in);
  write_text(in / "a.obj", pinched_hole_obj());
  write_text(in / "b.obj", pinched_hole_obj());
  const CliRun single =
      run_cli("fill " + (in / "a.obj").string() + " -q -o " + (dir_ / "a.obj").string(), dir_);
  EXPECT_EQ(single.code, 0) << single.err;
  EXPECT_TRUE(single.err.empty()) << single.err;
  EXPECT_TRUE(single.out.empty()) << single.out;
  const CliRun batch = run_cli("fill " + in.string() + " -q -o " + (dir_ / "out").string(), dir_);
  EXPECT_EQ(batch.code, 0) << batch.err;
  EXPECT_TRUE(batch.err.empty()) << batch.err;
  EXPECT_TRUE(batch.out.empty()) << batch.out;
  // Without --quiet they are there.
  const CliRun loud =
      run_cli("fill " + (in / "a.obj").string() + " -o " + (dir_ / "a.obj").string(), dir_);
  EXPECT_NE(loud.err.find("foldfill: warning: "), std::string::npos) << loud.err;
}

TEST_F(CliTest, WarningsNameTheirFileOnce) {
  const fs::path in = dir_ / "in";
  fs::create_directories(in);
  write_text(in / "pinched.obj", pinched_hole_obj());
  write_text(in / "tube.obj", tube_obj());
  const std::string pinched = (in / "pinched.obj").string(), tube = (in / "tube.obj").string();
  const CliRun single = run_cli("fill " + pinched + " -o " + (dir_ / "a.obj").string(), dir_);
  EXPECT_EQ(single.code, 0) << single.err;
  EXPECT_NE(single.err.find("foldfill: warning: " + pinched + ": loop 1 is not a disk boundary"),
            std::string::npos)
      << single.err;
  const CliRun batch = run_cli("fill " + in.string() + " -o " + (dir_ / "out").string(), dir_);
  EXPECT_NE(batch.err.find("foldfill: warning: " + pinched + ": loop 1 is not a disk boundary"),
            std::string::npos)
      << batch.err;
  // The default leaves both ends of the tube open, without a warning.
  EXPECT_EQ(batch.err.find(tube), std::string::npos) << batch.err;
  for (const CliRun& run : {single, batch}) {
    std::istringstream lines(run.err);
    for (std::string line; std::getline(lines, line);) {
      EXPECT_TRUE(line.rfind("foldfill: warning: " + pinched + ": ", 0) == 0 ||
                  line.rfind("foldfill: warning: " + tube + ": ", 0) == 0 ||
                  line.rfind("foldfill: error: " + tube + ": ", 0) == 0)
          << line;
    }
    for (const std::string& path : {pinched, tube}) {
      EXPECT_EQ(run.err.find(path + ": " + path), std::string::npos) << run.err;
      EXPECT_EQ(run.out.find(path + ": " + path), std::string::npos) << run.out;
      EXPECT_EQ(run.err.find(path + ": loop 1: " + path), std::string::npos) << run.err;
      EXPECT_EQ(run.out.find(path + ": loop 1: " + path), std::string::npos) << run.out;
    }
  }
}

// A closed box of 12 triangles, [x0, x1] x [y0, y1] x [z0, z1], as OBJ text.
std::string box_obj(double x0, double x1, double y0, double y1, double z0, double z1) {
  std::string obj;
  for (int k = 0; k < 8; ++k)
    obj += "v " + std::to_string(k & 1 ? x1 : x0) + " " + std::to_string(k & 2 ? y1 : y0) + " " +
           std::to_string(k & 4 ? z1 : z0) + "\n";
  for (const char* faces : {"1 3 4", "1 4 2", "5 6 8", "5 8 7", "1 2 6", "1 6 5", "3 7 8", "3 8 4",
                            "1 5 7", "1 7 3", "2 4 8", "2 8 6"})
    obj += std::string("f ") + faces + "\n";
  return obj;
}

TEST_F(CliTest, ABadObstacleMeshFailsLikeABadInput) {
  write_text(dir_ / "grid.obj", grid_obj(8, {{3, 3}, {3, 4}, {4, 3}, {4, 4}}, 0.0));
  write_text(dir_ / "garbage.obj", "this is not a mesh\n");
  write_text(dir_ / "fan.obj", kNonManifoldObj);
  const auto expect_error = [&](const std::string& options, int code, const fs::path& named) {
    SCOPED_TRACE(options);
    const CliRun run = run_cli("fill " + (dir_ / "grid.obj").string() + " -o " +
                                   (dir_ / "out.obj").string() + " " + options,
                               dir_);
    EXPECT_EQ(run.code, code) << run.err;
    EXPECT_EQ(run.err.rfind("foldfill: error: " + named.string() + ": ", 0), 0u) << run.err;
    EXPECT_EQ(line_count(run.err), 1) << run.err;
    EXPECT_FALSE(fs::exists(dir_ / "out.obj"));
  };
  expect_error("--obstacle-mesh " + (dir_ / "absent.obj").string(), 3, dir_ / "absent.obj");
  expect_error("--obstacle-mesh " + (dir_ / "garbage.obj").string(), 4, dir_ / "garbage.obj");
  expect_error("--obstacle-mesh " + (dir_ / "fan.obj").string(), 7, dir_ / "fan.obj");
  // Named in the obstacles file, relative to its folder.
  fs::create_directories(dir_ / "scene");
  write_text(dir_ / "scene" / "obstacles.json",
             R"({"obstacles": [{"type": "mesh", "file": "../garbage.obj"}]})");
  expect_error("--obstacles " + (dir_ / "scene" / "obstacles.json").string(), 4,
               dir_ / "scene" / ".." / "garbage.obj");
}

TEST_F(CliTest, AnObstacleMeshIsNeverWritten) {
  const fs::path input = dir_ / "grid.obj", body = dir_ / "body.obj";
  write_text(input, grid_with_hole_obj());
  const std::string box = box_obj(0, 1, 0, 1, -2, -1);
  write_text(body, box);
  const std::string fill = "fill " + input.string() + " ";
  expect_refusal(run_cli(fill + "-o " + body.string() + " --obstacle-mesh " + body.string(), dir_),
                 2, body.string());
  expect_refusal(run_cli(fill + "-o " + (dir_ / "out.obj").string() + " --report " + body.string() +
                             " --obstacle-mesh " + body.string(),
                         dir_),
                 2, body.string());
  // A mesh named in the obstacles file, as written by --report.
  write_text(dir_ / "obstacles.json", R"({"obstacles": [{"type": "mesh", "file": "body.obj"}]})");
  expect_refusal(run_cli(fill + "-o " + (dir_ / "out.obj").string() + " --report " + body.string() +
                             " --obstacles " + (dir_ / "obstacles.json").string(),
                         dir_),
                 2, body.string());
  // A batch, and the demo, whose input it would be.
  fs::create_directories(dir_ / "in");
  write_text(dir_ / "in" / "a.obj", grid_with_hole_obj());
  expect_refusal(run_cli("fill " + (dir_ / "in").string() + " -o " + dir_.string() + " --report " +
                             body.string() + " --obstacle-mesh " + body.string(),
                         dir_),
                 2, body.string());
  fs::create_directories(dir_ / "demo");
  write_text(dir_ / "demo" / "input.obj", box);
  expect_refusal(run_cli("demo " + (dir_ / "demo").string() + " --obstacle-mesh " +
                             (dir_ / "demo" / "input.obj").string(),
                         dir_),
                 2, (dir_ / "demo" / "input.obj").string());
  EXPECT_EQ(slurp(body), box);
  EXPECT_EQ(slurp(dir_ / "demo" / "input.obj"), box);
  EXPECT_FALSE(fs::exists(dir_ / "out.obj"));
}

// A box under the sheet, named by --obstacle-mesh, stays clear of the fill,
// and so does a plane the sheet already lies below (the fill goes no deeper
// than the cloth around the hole). CGAL's Liepa fill does not avoid
// obstacles: through a sphere poking up into the hole, its crossings are
// reported and warned per hole.
TEST_F(CliTest, CrossingsAreReportedAndWarnedPerHole) {
  const fs::path input = dir_ / "grid.obj", report = dir_ / "report.json";
  std::vector<std::pair<int, int>> block;
  for (int i = 3; i < 7; ++i)
    for (int j = 3; j < 7; ++j) block.push_back({i, j});
  write_text(input, grid_obj(10, block, 0.0));
  write_text(dir_ / "plane.json",
             R"({"obstacles": [{"type": "plane", "point": [0, 0, 0.5], "normal": [0, 0, 1]}]})");
  write_text(dir_ / "under.obj", box_obj(2, 6, 2, 6, -2, -0.5));
  write_text(dir_ / "far.obj", box_obj(20, 21, 20, 21, 20, 21));
  const std::string fill = "fill " + input.string() + " -o " + (dir_ / "out.obj").string() +
                           " --report " + report.string() + " ";
  const CliRun clean = run_cli(fill + "--obstacle-mesh " + (dir_ / "under.obj").string() +
                                   " --obstacle-mesh " + (dir_ / "far.obj").string(),
                               dir_);
  ASSERT_EQ(clean.code, 0) << clean.err;
  EXPECT_TRUE(clean.err.empty()) << clean.err;
  nlohmann::json hole = nlohmann::json::parse(slurp(report))["holes"][0];
  EXPECT_EQ(hole["crossings"],
            (nlohmann::json{{"patch_patch", 0}, {"patch_mesh", 0}, {"patch_obstacles", 0}}));
  EXPECT_EQ(hole["self_intersections"], 0);
  EXPECT_GT(hole["min_distance"].get<double>(), 0);

  const CliRun below = run_cli(fill + "--obstacles " + (dir_ / "plane.json").string(), dir_);
  ASSERT_EQ(below.code, 0) << below.err;
  EXPECT_TRUE(below.err.empty()) << below.err;
  hole = nlohmann::json::parse(slurp(report))["holes"][0];
  EXPECT_EQ(hole["self_intersections"], 0);
  EXPECT_GT(hole["obstacle_allowance"].get<double>(), 0.5);

  write_text(dir_ / "sphere.json",
             R"({"obstacles": [{"type": "sphere", "center": [5, 5, -2.85], "radius": 3}]})");
  const CliRun guarded = run_cli(fill + "--obstacles " + (dir_ / "sphere.json").string(), dir_);
  ASSERT_EQ(guarded.code, 0) << guarded.err;
  EXPECT_TRUE(guarded.err.empty()) << guarded.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(report))["holes"][0]["self_intersections"], 0);
  const std::string liepa_fill =
      fill + "--method liepa --obstacles " + (dir_ / "sphere.json").string();
  const CliRun crossing = run_cli(liepa_fill, dir_);
  ASSERT_EQ(crossing.code, 0) << crossing.err;
  hole = nlohmann::json::parse(slurp(report))["holes"][0];
  const int faces = hole["crossings"]["patch_obstacles"];
  EXPECT_GT(faces, 0);
  EXPECT_EQ(hole["self_intersections"], faces);
  EXPECT_EQ(hole["min_distance"], 0);
  const std::string warning = "foldfill: warning: " + input.string() +
                              ": loop 1: the fill crosses obstacles (patch_obstacles " +
                              std::to_string(faces) + ")\n";
  EXPECT_EQ(crossing.err, warning);
  // In a batch too, and not with --quiet.
  fs::create_directories(dir_ / "in");
  fs::copy_file(input, dir_ / "in" / "grid.obj");
  const CliRun batch = run_cli("fill " + (dir_ / "in").string() + " -o " + (dir_ / "out").string() +
                                   " --method liepa --obstacles " + (dir_ / "sphere.json").string(),
                               dir_);
  ASSERT_EQ(batch.code, 0) << batch.err;
  EXPECT_NE(batch.err.find("foldfill: warning: " + (dir_ / "in" / "grid.obj").string() +
                           ": loop 1: the fill crosses obstacles (patch_obstacles "),
            std::string::npos)
      << batch.err;
  const CliRun quiet = run_cli(liepa_fill + " -q", dir_);
  EXPECT_EQ(quiet.code, 0) << quiet.err;
  EXPECT_TRUE(quiet.err.empty()) << quiet.err;
}

// A flat 9 x 9 vertex grid with a one-cell hole (loop 1, 4 vertices, near
// (1.5, 1.5)) and a 2 x 2-cell one (loop 2, 8 vertices, near (5, 5)).
std::string grid_with_two_holes_obj() {
  return grid_obj(9, {{1, 1}, {4, 4}, {5, 4}, {4, 5}, {5, 5}}, 0.0);
}

// The lines of `text` that contain `words`.
int lines_with(const std::string& text, const std::string& words) {
  std::istringstream lines(text);
  int count = 0;
  for (std::string line; std::getline(lines, line);) count += line.find(words) != std::string::npos;
  return count;
}

TEST_F(CliTest, DryRunWritesNothing) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.obj", report = dir_ / "r.json";
  write_text(input, grid_with_two_holes_obj());
  const CliRun run = run_cli("fill " + input.string() + " -o " + output.string() + " --report " +
                                 report.string() + " --dry-run",
                             dir_);
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_FALSE(fs::exists(output));
  EXPECT_FALSE(fs::exists(report));
  EXPECT_NE(run.out.find("would fill loops 1, 2"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("loop 0: leave open (not a hole): outer edge, 32 vertices, turning -360 "
                         "deg: turns by -360 degrees, like a sheet's outer edge"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("loop 1: fill (a hole): hole, 4 vertices, turning 360 deg: turns by 360"),
            std::string::npos)
      << run.out;
  // Without -o, and over a folder.
  const CliRun bare = run_cli("fill " + input.string() + " --dry-run", dir_);
  EXPECT_EQ(bare.code, 0) << bare.err;
  EXPECT_EQ(bare.out, run.out);
  const CliRun folder = run_cli("fill " + dir_.string() + " --dry-run", dir_);
  EXPECT_EQ(folder.code, 0) << folder.err;
  EXPECT_NE(folder.out.find(input.string() + ": 3 boundary loops"), std::string::npos)
      << folder.out;
  EXPECT_EQ(run_cli("fill " + input.string(), dir_).code, 2);  // -o needed to fill
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir_)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"grid.obj", "stderr.txt", "stdout.txt"}));
}

TEST_F(CliTest, HolesAllFillsTheHolesAndSaysOnceWhatStaysOpen) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.obj";
  write_text(input, grid_with_two_holes_obj());
  const CliRun run = run_cli(
      "fill " + input.string() + " -o " + output.string() + " --holes all --max-iterations 50",
      dir_);
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_TRUE(run.err.empty()) << run.err;
  EXPECT_EQ(lines_with(run.out, "left open"), 1) << run.out;
  EXPECT_NE(run.out.find("1 loop left open as outer edges: 0 (outer edge, 32 vertices)"),
            std::string::npos)
      << run.out;
  EXPECT_EQ(lines_with(run.out, "filled loop"), 2) << run.out;
  EXPECT_TRUE(fs::exists(output));
}

TEST_F(CliTest, MaxHoleSizeAndDiameterLeaveLargerHolesOpen) {
  const fs::path input = dir_ / "grid.obj";
  write_text(input, grid_with_two_holes_obj());
  const std::string dry = "fill " + input.string() + " --dry-run ";
  CliRun run = run_cli(dry + "--max-hole-size 6", dir_);
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.out.find("would fill loop 1\n"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("loop 2: leave open (too many edges): hole, 8 vertices"),
            std::string::npos)
      << run.out;
  // The mesh's mean edge length is (2 + sqrt 2) / 3: the one-cell hole's
  // diagonal is 1.24 of them, the 2 x 2 hole's 2.49.
  run = run_cli(dry + "--max-hole-diameter 2", dir_);
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.out.find("loop 2: leave open (too wide)"), std::string::npos) << run.out;
  run = run_cli(dry + "--max-hole-diameter 3", dir_);
  EXPECT_NE(run.out.find("would fill loops 1, 2"), std::string::npos) << run.out;
  EXPECT_EQ(run_cli(dry + "--max-hole-size 0", dir_).code, 2);
  EXPECT_EQ(run_cli(dry + "--max-hole-diameter -1", dir_).code, 2);
}

TEST_F(CliTest, EachNearPointPicksItsLoop) {
  const fs::path input = dir_ / "grid.obj";
  write_text(input, grid_with_two_holes_obj());
  const std::string dry = "fill " + input.string() + " --dry-run ";
  CliRun run = run_cli(dry + "--near 1.5,1.5,0 --near 5,5,0.1", dir_);
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.out.find("would fill loops 1, 2"), std::string::npos) << run.out;
  run = run_cli(dry + "--near 5,5,0 --holes 0", dir_);
  EXPECT_NE(run.out.find("would fill loops 0, 2"), std::string::npos) << run.out;
  EXPECT_EQ(run_cli(dry + "--near 5,5", dir_).code, 2);
  EXPECT_EQ(run_cli(dry + "--near 5,5,0 --holes all", dir_).code, 2);
  EXPECT_EQ(run_cli(dry + "--near 5,5,0 --keep-open 1", dir_).code, 2);
}

TEST_F(CliTest, NearAPointFarFromEveryLoopIsAnError) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.obj";
  write_text(input, grid_with_two_holes_obj());
  const CliRun run = run_cli(
      "fill " + input.string() + " -o " + output.string() + " --near 1.5,1.5,0 --near 4,4,50",
      dir_);
  EXPECT_EQ(run.code, 2) << run.err;
  EXPECT_NE(
      run.err.find(input.string() + ": no loop near the point (4, 4, 50): the nearest, loop "),
      std::string::npos)
      << run.err;
  EXPECT_EQ(line_count(run.err), 1) << run.err;
  EXPECT_FALSE(fs::exists(output));
}

// A loop the user names is filled whatever its kind (the fill decides what it
// can do with it); here only the selection is checked.
TEST_F(CliTest, NamedOuterLoopIsSelected) {
  const fs::path input = dir_ / "grid.obj";
  write_text(input, grid_with_two_holes_obj());
  for (const char* option : {"--holes 0", "--near 4,-0.2,0"}) {
    const CliRun run =
        run_cli("fill " + input.string() + " --dry-run " + std::string(option), dir_);
    EXPECT_EQ(run.code, 0) << run.err;
    EXPECT_NE(run.out.find("loop 0: fill (named): outer edge"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("loop 1: leave open (not named): hole"), std::string::npos) << run.out;
  }
}

// --keep-open N is the rule by length, only when asked: on a tube it fills
// one end, and says that the default would not.
TEST_F(CliTest, KeepOpenFillsAllButTheLongestLoops) {
  const fs::path input = dir_ / "tube.obj";
  write_text(input, tube_obj());
  CliRun run = run_cli("fill " + input.string() + " --dry-run", dir_);
  EXPECT_NE(run.out.find("would fill nothing"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("loop 0: leave open (not a hole): tube end"), std::string::npos)
      << run.out;
  run = run_cli("fill " + input.string() + " --dry-run --keep-open 1", dir_);
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.out.find("loop 1: fill (not among the longest): tube end"), std::string::npos)
      << run.out;
  EXPECT_NE(run.err.find("--keep-open 1 fills other loops than the default"), std::string::npos)
      << run.err;
  EXPECT_EQ(run_cli("fill " + input.string() + " --dry-run --keep-open 1 --holes 1", dir_).code, 2);
}

TEST_F(CliTest, HolesPrintsEachLoopsKindAndWhy) {
  const fs::path input = dir_ / "tube.obj";
  write_text(input, tube_obj());
  CliRun run = run_cli("holes " + input.string(), dir_);
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_EQ(lines_with(run.out,
                       "tube end (left open by default): turns by 0 degrees, like the "
                       "end of a tube"),
            2)
      << run.out;
  run = run_cli("holes --json " + input.string(), dir_);
  ASSERT_EQ(run.code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  for (const auto& loop : j["loops"]) {
    EXPECT_EQ(loop["kind"], "tube_end");
    EXPECT_EQ(loop["kind_reason"], "turns_like_a_tube_end");
    EXPECT_NE(loop["explanation"].get<std::string>().find("like the end of a tube"),
              std::string::npos);
    EXPECT_TRUE(loop["outer"].get<bool>());
  }
}

// The six reference inputs with the default selection: each file's one hole
// (the loop of cases.json) filled, every outer edge left open, exit 0.
TEST_F(CliTest, BatchOverTheReferenceFolderFillsSix) {
  FOLDFILL_REQUIRE_SHARED();
  const fs::path in = foldfill::testing::shared_dir() / "data" / "reference";
  const fs::path out = dir_ / "out";
  const CliRun run = run_cli("fill " + in.string() + " -o " + out.string() + " -j 2", dir_);
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.out.find("6 filled, 0 unchanged, 0 failed"), std::string::npos) << run.out;
  for (const char* name : {"contour_hole.obj", "curtain_hole.obj", "paper1_hole.obj",
                           "paper2_hole.obj", "sim1_hole.obj", "sim2_hole.obj"}) {
    const Mesh before = read_mesh((in / name).string()), after = read_mesh((out / name).string());
    EXPECT_EQ(find_boundary_loops(after).size() + 1, find_boundary_loops(before).size()) << name;
  }
}

// ---- The report and docs/report.md ----------------------------------------

// The keys of a table of docs/report.md: dotted path -> its "present" column.
using KeyTable = std::map<std::string, std::string>;

// The tables of docs/report.md: the rows of the section "One file", then those
// of "Several files". A row is "| `path` | present | value | meaning |".
std::pair<KeyTable, KeyTable> documented_keys() {
  std::ifstream in(std::string(FOLDFILL_DOCS_DIR) + "/report.md");
  EXPECT_TRUE(in.good()) << "cannot read docs/report.md";
  KeyTable single, batch;
  KeyTable* table = nullptr;
  for (std::string line; std::getline(in, line);) {
    if (line == "## One file") table = &single;
    if (line == "## Several files") table = &batch;
    if (!table || line.rfind("| `", 0) != 0) continue;
    const size_t end = line.find('`', 3);
    const size_t cell = line.find('|', end);
    const size_t next = line.find('|', cell + 1);
    std::string present = line.substr(cell + 1, next - cell - 1);
    present.erase(0, present.find_first_not_of(' '));
    present.erase(present.find_last_not_of(' ') + 1);
    EXPECT_TRUE(table->emplace(line.substr(3, end - 3), present).second)
        << "listed twice: " << line;
  }
  return {single, batch};
}

// Every key path of `value` under `path` (objects in arrays under "path[]").
void collect_keys(const nlohmann::json& value, const std::string& path,
                  std::set<std::string>& keys) {
  if (value.is_object()) {
    for (const auto& item : value.items()) {
      const std::string key = path.empty() ? item.key() : path + "." + item.key();
      keys.insert(key);
      collect_keys(item.value(), key, keys);
    }
  } else if (value.is_array()) {
    for (const nlohmann::json& element : value) {
      if (!element.is_object()) continue;
      keys.insert(path + "[]");
      collect_keys(element, path + "[]", keys);
    }
  }
}

// The objects at `path` in `root` (each element for a segment "name[]"),
// null ones left out.
std::vector<const nlohmann::json*> objects_at(const nlohmann::json& root, const std::string& path) {
  std::vector<const nlohmann::json*> found = {&root};
  std::stringstream segments(path);
  for (std::string segment; !path.empty() && std::getline(segments, segment, '.');) {
    const bool each = segment.size() > 2 && segment.compare(segment.size() - 2, 2, "[]") == 0;
    if (each) segment.resize(segment.size() - 2);
    std::vector<const nlohmann::json*> next;
    for (const nlohmann::json* object : found) {
      if (!object->is_object() || !object->contains(segment)) continue;
      const nlohmann::json& value = (*object)[segment];
      if (!each) {
        next.push_back(&value);
        continue;
      }
      for (const nlohmann::json& element : value) next.push_back(&element);
    }
    found = std::move(next);
  }
  std::vector<const nlohmann::json*> objects;
  for (const nlohmann::json* value : found)
    if (value->is_object()) objects.push_back(value);
  return objects;
}

// Checks `report` against `table`: every key documented, every key documented
// as always present there wherever its parent is an object. Adds the keys
// seen to `seen`.
void expect_documented(const nlohmann::json& report, const KeyTable& table, const std::string& what,
                       std::set<std::string>& seen) {
  std::set<std::string> keys;
  collect_keys(report, "", keys);
  for (const std::string& key : keys) {
    EXPECT_TRUE(table.count(key)) << what << ": key " << key << " is not in docs/report.md";
  }
  seen.insert(keys.begin(), keys.end());
  for (const auto& [key, present] : table) {
    if (present != "always" || key.size() < 2 || key.compare(key.size() - 2, 2, "[]") == 0)
      continue;
    const size_t dot = key.rfind('.');
    const std::string parent = dot == std::string::npos ? "" : key.substr(0, dot);
    const std::string name = dot == std::string::npos ? key : key.substr(dot + 1);
    for (const nlohmann::json* object : objects_at(report, parent)) {
      EXPECT_TRUE(object->contains(name))
          << what << ": " << key << " is documented as always present but is missing";
    }
  }
}

TEST_F(CliTest, ReportKeysAreThoseOfDocsReportMd) {
  const auto [single, batch_only] = documented_keys();
  ASSERT_GT(single.size(), 50u);
  // A batch entry is a file's report with the batch's own keys.
  KeyTable batch = batch_only;
  // (a file that could not be read has only input, output and those).
  for (const auto& [key, present] : single) {
    const bool kept = key == "input" || key == "output";
    batch.emplace("files[]." + key, kept ? present : "the file was filled");
  }

  const fs::path input = dir_ / "grid.obj", report = dir_ / "r.json";
  write_text(input, grid_with_two_holes_obj());
  const std::string fill = "fill " + input.string() + " -o " + (dir_ / "out.obj").string() +
                           " --report " + report.string() + " ";
  std::set<std::string> seen;
  struct Run {
    std::string what, arguments;
  };
  std::vector<Run> runs = {{"fabric", fill},
                           {"liepa", fill + "--method liepa"},
                           {"prototype, gd", fill + "--holes 1 --preset prototype --solver gd "
                                                    "--max-iterations 200 --max-hole-size 6"}};
  if (!foldfill::testing::shared_dir().empty()) {
    const fs::path reference = foldfill::testing::shared_dir() / "data/reference/paper2_hole.obj";
    runs.push_back({"paper2", "fill " + reference.string() + " -o " +
                                  (dir_ / "paper2.obj").string() + " --report " + report.string() +
                                  " --preset prototype --alpha 0.4 --beta 0.02 --mu 0.01"});
  }
  for (const Run& run : runs) {
    const CliRun result = run_cli(run.arguments, dir_);
    ASSERT_EQ(result.code, 0) << run.what << ": " << result.err;
    expect_documented(nlohmann::json::parse(slurp(report)), single, run.what, seen);
  }

  const CliRun demo =
      run_cli("demo " + (dir_ / "demo").string() + " --quiet --max-iterations 50", dir_);
  ASSERT_EQ(demo.code, 0) << demo.err;
  expect_documented(nlohmann::json::parse(slurp(dir_ / "demo" / "report.json")), single, "demo",
                    seen);

  fs::create_directories(dir_ / "in");
  fs::copy_file(input, dir_ / "in" / "a.obj");
  write_text(dir_ / "in" / "b.obj", "not a mesh\n");
  const CliRun many = run_cli("fill " + (dir_ / "in").string() + " -o " + (dir_ / "out").string() +
                                  " --report " + report.string(),
                              dir_);
  EXPECT_EQ(many.code, 11) << many.err;
  std::set<std::string> seen_in_batch;
  expect_documented(nlohmann::json::parse(slurp(report)), batch, "batch", seen_in_batch);

  for (const auto& [key, present] : single) {
    EXPECT_TRUE(seen.count(key) || present != "always")
        << key << " is documented as always present but no report held it";
  }
  for (const auto& [key, present] : batch_only) {
    EXPECT_TRUE(seen_in_batch.count(key) || present != "always")
        << key << " is documented as always present but the batch report did not hold it";
  }
}

TEST_F(CliTest, ReportSaysWhatWasFilledWhatIsOpenAndWithWhat) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.obj", report = dir_ / "r.json";
  write_text(input, grid_with_two_holes_obj());
  const std::string fill =
      "fill " + input.string() + " -o " + output.string() + " --report " + report.string() + " ";
  CliRun run = run_cli(fill + "--max-hole-size 4 --density 1.5", dir_);
  ASSERT_EQ(run.code, 0) << run.err;
  nlohmann::json r = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(r["foldfill_version"], version());
  EXPECT_EQ(r["counts"],
            (nlohmann::json{{"input_vertices", 81},
                            {"input_faces", 2 * 64 - 10},
                            {"boundary_loops", 3},
                            {"output_vertices", read_mesh(output.string()).vertex_count()},
                            {"output_faces", read_mesh(output.string()).face_count()}}));
  EXPECT_EQ(r["filled_loops"], nlohmann::json({1}));
  EXPECT_EQ(r["left_open_loops"],
            (nlohmann::json{{{"loop_id", 0}, {"kind", "outer_edge"}, {"reason", "not_a_hole"}},
                            {{"loop_id", 2}, {"kind", "hole"}, {"reason", "too_many_edges"}}}));
  const nlohmann::json& options = r["options"];
  EXPECT_EQ(options["method"], "foldfill");
  EXPECT_EQ(options["density"], 1.5);
  EXPECT_EQ(options["lambda"], 0.0002);
  EXPECT_EQ(options["solver"], "fast");
  EXPECT_TRUE(options["step"].is_null());
  EXPECT_EQ(options["selection"]["mode"], "default");
  EXPECT_EQ(options["selection"]["max_hole_size"], 4);
  const nlohmann::json& hole = r["holes"][0];
  EXPECT_EQ(hole["status"], "filled");
  EXPECT_EQ(hole["method"], "fabric");
  EXPECT_TRUE(hole["warning"].is_null());
  EXPECT_TRUE(hole["reason"].is_null());
  const double patch_area = hole["patch_area"], flat_area = hole["flat_area"];
  EXPECT_GT(patch_area, 0);
  EXPECT_NEAR(flat_area, 1, 1e-9);  // the missing unit square, flat
  EXPECT_NEAR(hole["area_ratio_to_flat"].get<double>(), patch_area / flat_area, 1e-9);

  // Liepa measures none of the fabric method's figures: null, not zero.
  run = run_cli(fill + "--method liepa --holes 1,2", dir_);
  ASSERT_EQ(run.code, 0) << run.err;
  r = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(r["filled_loops"], nlohmann::json({1, 2}));
  EXPECT_EQ(r["left_open_loops"],
            (nlohmann::json{{{"loop_id", 0}, {"kind", "outer_edge"}, {"reason", "not_named"}}}));
  EXPECT_EQ(r["options"]["method"], "liepa");
  EXPECT_EQ(r["options"]["selection"]["mode"], "ids");
  EXPECT_EQ(r["options"]["selection"]["holes"], nlohmann::json({1, 2}));
  for (const char* key : {"lambda", "repulsion", "shrink", "solver", "fallback"})
    EXPECT_TRUE(r["options"][key].is_null()) << key;
  for (const nlohmann::json& liepa : r["holes"]) {
    EXPECT_EQ(liepa["method"], "liepa");
    EXPECT_EQ(liepa["status"], "filled");
    EXPECT_GT(liepa["patch_area"].get<double>(), 0);
    for (const char* key : {"energy", "flattening", "triangulation", "area_ratio_to_flat",
                            "flat_area", "iterations", "lambda", "stop_reason"})
      EXPECT_TRUE(liepa[key].is_null()) << key;
    EXPECT_TRUE(liepa["seconds"]["flatten"].is_null());
    EXPECT_GE(liepa["seconds"]["total"].get<double>(), 0);
  }
  const std::string text = slurp(report);
  EXPECT_EQ(text.find("simple_polygon"), std::string::npos);
  EXPECT_EQ(text.find("area_ratio_to_flat\": 0"), std::string::npos);

  // With the prototype's weights, the mapped ones: repulsion mu / alpha;
  // lambda depends on the hole (quadratic bending), so it is the hole's.
  run = run_cli(fill + "--holes 1 --preset prototype --alpha 0.2 --mu 0.05 --max-iterations 100",
                dir_);
  ASSERT_EQ(run.code, 0) << run.err;
  r = nlohmann::json::parse(slurp(report));
  EXPECT_NEAR(r["options"]["repulsion"].get<double>(), 0.25, 1e-12);
  EXPECT_TRUE(r["options"]["lambda"].is_null());
  EXPECT_EQ(r["options"]["prototype"]["alpha"], 0.2);
  EXPECT_NEAR(r["holes"][0]["lambda"].get<double>(),
              0.001 * 0.003 / (0.2 * std::pow(r["holes"][0]["length_scale"].get<double>(), 2)),
              1e-12);
}

// A chosen hole that is not filled is in left_open_loops, with its status, and
// not in filled_loops.
TEST(ReportLoops, AChosenHoleNotFilledIsLeftOpen) {
  std::vector<BoundaryLoop> loops(4);
  for (int id = 0; id < 4; ++id) loops[id].id = id;
  loops[0].kind = LoopKind::OuterEdge;
  HoleChoice choice;
  choice.fill = {1, 2, 3};
  choice.left_open = {0};
  choice.reasons = {ChoiceReason::NotAHole, ChoiceReason::IsAHole, ChoiceReason::IsAHole,
                    ChoiceReason::IsAHole};
  FillReport report;
  report.holes.resize(3);
  report.holes[0].loop_id = 1;
  report.holes[0].filled = true;
  report.holes[1].loop_id = 2;
  report.holes[1].reason = "mesh: loop 2: the strip is not an annulus";
  report.holes[2].loop_id = 3;
  report.holes[2].cancelled = true;
  EXPECT_EQ(filled_loops(report), std::vector<int>{1});
  EXPECT_EQ(left_open_loops(loops, choice, report),
            (nlohmann::json{{{"loop_id", 0}, {"kind", "outer_edge"}, {"reason", "not_a_hole"}},
                            {{"loop_id", 2}, {"kind", "hole"}, {"reason", "failed"}},
                            {{"loop_id", 3}, {"kind", "hole"}, {"reason", "cancelled"}}}));
  const nlohmann::json failed = to_json(report.holes[1]);
  EXPECT_EQ(failed["status"], "failed");
  EXPECT_EQ(failed["reason"], report.holes[1].reason);
  for (const char* key : {"method", "patch_area", "new_faces", "crossings", "energy"})
    EXPECT_TRUE(failed[key].is_null()) << key;
  EXPECT_EQ(to_json(report.holes[2])["status"], "cancelled");
}

// ---- The command line ------------------------------------------------------

TEST_F(CliTest, VersionAndHelpCommand) {
  const CliRun version_run = run_cli("--version", dir_);
  EXPECT_EQ(version_run.code, 0);
  EXPECT_EQ(version_run.out, "foldfill " + std::string(version()) + "\n");
  const CliRun help = run_cli("--help", dir_), help_command = run_cli("help", dir_);
  EXPECT_EQ(help_command.code, 0) << help_command.err;
  EXPECT_EQ(help_command.out, help.out);
  EXPECT_NE(help.out.find("help"), std::string::npos) << help.out;
  for (const char* command : {"fill", "holes", "demo", "render", "view", "serve"}) {
    const CliRun topic = run_cli(std::string("help ") + command, dir_);
    EXPECT_EQ(topic.code, 0) << topic.err;
    EXPECT_EQ(topic.out, run_cli(std::string(command) + " --help", dir_).out) << command;
  }
  const CliRun unknown = run_cli("help fil", dir_);
  EXPECT_EQ(unknown.code, 2);
  EXPECT_EQ(unknown.err.rfind("foldfill: error: command: ", 0), 0u) << unknown.err;
}

// The line of --help that shows `option`.
std::string help_line(const std::string& help, const std::string& option) {
  std::istringstream lines(help);
  for (std::string line; std::getline(lines, line);)
    if (line.find(" " + option + " ") != std::string::npos ||
        line.find("," + option + " ") != std::string::npos)
      return line;
  return "";
}

TEST_F(CliTest, HelpShowsTheDefaults) {
  const CliRun fill = run_cli("fill --help", dir_);
  ASSERT_EQ(fill.code, 0) << fill.err;
  for (const auto& [option, value] :
       std::vector<std::pair<std::string, std::string>>{{"--lambda", "0.0002"},
                                                        {"--shrink", "0.5"},
                                                        {"--density", "1"},
                                                        {"--repulsion", "1"},
                                                        {"--thickness", "0.1"},
                                                        {"--bending", "quadratic"},
                                                        {"--solver", "fast"},
                                                        {"--method", "foldfill"},
                                                        {"--max-iterations", "20000"},
                                                        {"--coarse-start", "1000"},
                                                        {"--time-limit", "0"},
                                                        {"--alpha", "0.1"},
                                                        {"--jobs", "1"}}) {
    const std::string line = help_line(fill.out, option);
    EXPECT_NE(line.find("[" + value + "]"), std::string::npos) << option << ": " << line;
  }
  const CliRun render = run_cli("render --help", dir_);
  EXPECT_NE(help_line(render.out, "--width").find("[640]"), std::string::npos) << render.out;
}

TEST_F(CliTest, OptionsWithoutEffectAreRefused) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.obj";
  write_text(input, grid_with_hole_obj());
  const std::string fill = "fill " + input.string() + " -o " + output.string() + " ";
  for (const auto& [arguments, message] : std::vector<std::pair<std::string, std::string>>{
           {"--alpha 0.2", "--alpha: has no effect without --preset prototype"},
           {"--mu 0.2", "--mu: has no effect without --preset prototype"},
           {"--preset prototype --lambda 0.1",
            "--lambda: has no effect with --preset prototype (its --alpha, --beta and --mu set "
            "it)"},
           {"--method liepa --lambda 0.1",
            "--lambda: has no effect with --method liepa (a parameter of the fabric method)"},
           {"--method liepa -c 0.4", "--shrink: has no effect with --method liepa"},
           {"--method liepa --time-limit 3", "--time-limit: has no effect with --method liepa"},
           {"--method liepa --flat-dir " + (dir_ / "flat").string(),
            "--flat-dir: has no effect with --method liepa"},
           {"--solver gd --coarse-start 10", "--coarse-start: has no effect with --solver gd"}}) {
    const CliRun run = run_cli(fill + arguments, dir_);
    EXPECT_EQ(run.code, 2) << arguments;
    EXPECT_EQ(run.err.rfind("foldfill: error: " + message, 0), 0u) << run.err;
    EXPECT_NE(run.err.find("(see foldfill fill --help)\n"), std::string::npos) << run.err;
    EXPECT_EQ(line_count(run.err), 1) << run.err;
  }
  const CliRun demo = run_cli("demo " + (dir_ / "demo").string() + " --beta 0.1", dir_);
  EXPECT_EQ(demo.code, 2);
  EXPECT_EQ(demo.err.rfind("foldfill: error: --beta: has no effect without --preset prototype", 0),
            0u)
      << demo.err;
  EXPECT_FALSE(fs::exists(output));
  EXPECT_FALSE(fs::exists(dir_ / "demo"));
  EXPECT_FALSE(fs::exists(dir_ / "flat"));
}

TEST_F(CliTest, UsageErrorsNameTheOptionOrArgument) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.obj";
  write_text(input, grid_with_hole_obj());
  const std::string fill = "fill " + input.string() + " ";
  for (const auto& [arguments, line] : std::vector<std::pair<std::string, std::string>>{
           {fill + "-o " + output.string() + " --bogus",
            "--bogus: not an option of this command (see foldfill fill --help)"},
           {"fill", "inputs: required (see foldfill fill --help)"},
           {"", "a command is required: holes, fill, demo, render or help (see foldfill --help)"},
           {"render " + input.string(), "--output: required (see foldfill render --help)"},
           {"holes " + input.string() + " extra",
            "extra: not expected here (too many arguments) (see foldfill holes --help)"}}) {
    const CliRun run = run_cli(arguments, dir_);
    EXPECT_EQ(run.code, 2) << arguments;
    EXPECT_EQ(run.err, "foldfill: error: " + line + "\n") << arguments;
  }
}

// A report or an output in a folder that does not exist is refused before
// any work (code 10), the output is not written.
TEST_F(CliTest, AMissingReportOrOutputFolderIsFoundBeforeAnyWork) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.obj";
  write_text(input, grid_with_hole_obj());
  const fs::path missing = dir_ / "missing";
  CliRun run = run_cli("fill " + input.string() + " -o " + output.string() + " --report " +
                           (missing / "r.json").string(),
                       dir_);
  EXPECT_EQ(run.code, 10) << run.err;
  EXPECT_EQ(run.err, "foldfill: error: " + (missing / "r.json").string() +
                         ": cannot write (no folder " + missing.string() + ")\n");
  EXPECT_FALSE(fs::exists(output));
  run = run_cli("fill " + input.string() + " -o " + (missing / "out.obj").string(), dir_);
  EXPECT_EQ(run.code, 10) << run.err;
  EXPECT_NE(run.err.find("no folder " + missing.string()), std::string::npos) << run.err;
  // A batch too: nothing filled, nothing written.
  fs::create_directories(dir_ / "in");
  fs::copy_file(input, dir_ / "in" / "a.obj");
  run = run_cli("fill " + (dir_ / "in").string() + " -o " + (dir_ / "out").string() + " --report " +
                    (missing / "r.json").string(),
                dir_);
  EXPECT_EQ(run.code, 10) << run.err;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
  EXPECT_FALSE(fs::exists(missing));
}

TEST_F(CliTest, RenderWritesLabelledPngOnly) {
  const fs::path input = dir_ / "grid.obj";
  write_text(input, grid_with_hole_obj());
  for (const char* name : {"p.jpg", "p.PNG.gif", "p"}) {
    const CliRun run = run_cli(
        "render " + input.string() + " " + input.string() + " -o " + (dir_ / name).string(), dir_);
    EXPECT_EQ(run.code, 2) << name;
    EXPECT_EQ(run.err, "foldfill: error: --output: '" + (dir_ / name).string() +
                           "': render writes PNG pictures only (a .png file) (see foldfill "
                           "render --help)\n");
    EXPECT_FALSE(fs::exists(dir_ / name));
  }
  const CliRun run = run_cli(
      "render " + input.string() + " " + input.string() + " -o " + (dir_ / "p.PNG").string(), dir_);
  EXPECT_EQ(run.code, 0) << run.err;
  EXPECT_EQ(slurp(dir_ / "p.PNG").substr(1, 3), "PNG");
}

TEST(RenderLabel, DrawsTheTextInTheTopLeftCorner) {
  Image image{200, 100, std::vector<std::uint8_t>(200 * 100 * 3, 128)};
  draw_label(image, "input");
  // Scale 1: 5 glyphs 6 pixels apart from (4, 4), on white.
  const auto grey = [&](int x, int y) { return image.rgb[(y * image.width + x) * 3]; };
  int dark = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      // The box: a margin of 2, then the text (29 x 7) with 2 more around it.
      const bool in_box = x >= 2 && x < 2 + 2 + 29 + 2 && y >= 2 && y < 2 + 2 + 7 + 2;
      if (in_box) {
        EXPECT_TRUE(grey(x, y) == 255 || grey(x, y) == 40) << x << ", " << y;
      } else {
        EXPECT_EQ(grey(x, y), 128) << x << ", " << y;
      }
      dark += grey(x, y) == 40;
    }
  }
  // "I": a bar of 5 pixels and two of 3: 11 pixels in the first glyph.
  int first = 0;
  for (int y = 4; y < 11; ++y)
    for (int x = 4; x < 9; ++x) first += grey(x, y) == 40;
  EXPECT_EQ(first, 11);
  EXPECT_GT(dark, 40);
  Image other{200, 100, std::vector<std::uint8_t>(200 * 100 * 3, 128)};
  draw_label(other, "filled");
  EXPECT_NE(other.rgb, image.rgb);
}

// Runs the CLI with its stderr on a terminal (a pseudo-terminal read here),
// stdout to a file; returns what the terminal showed.
CliRun run_cli_on_terminal(const std::string& arguments, const fs::path& dir) {
  CliRun run;
  int terminal = -1, program_side = -1;
  if (openpty(&terminal, &program_side, nullptr, nullptr, nullptr) != 0) return run;
  const std::string command = "exec " + std::string(FOLDFILL_CLI) + " " + arguments + " >" +
                              (dir / "stdout.txt").string() + " </dev/null";
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(program_side, STDERR_FILENO);
    close(terminal);
    close(program_side);
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  close(program_side);
  char buffer[4096];
  for (ssize_t n; (n = read(terminal, buffer, sizeof buffer)) > 0;) run.err.append(buffer, n);
  close(terminal);
  int status = 0;
  waitpid(pid, &status, 0);
  run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.out = slurp(dir / "stdout.txt");
  return run;
}

TEST_F(CliTest, ProgressShowsTheStageHoleIterationAndTime) {
  // The demo's patch (about 500 interior vertices) with two coarser levels:
  // each minimisation is announced, and the one it started again after.
  const CliRun run =
      run_cli_on_terminal("demo " + (dir_ / "demo").string() + " --coarse-start 100", dir_);
  ASSERT_EQ(run.code, 0) << run.err;
  for (const std::string& words :
       {std::string("\r\033[Khole 1 of 1 (loop 1), coarse level 2, folds first: iteration 1, "
                    "energy "),
        std::string("\r\033[Khole 1 of 1 (loop 1), coarse level 2, minimising (started again "
                    "after coarse level 2, folds first): iteration 1, energy "),
        std::string("\r\033[Khole 1 of 1 (loop 1), coarse level 1, minimising (started again "
                    "after coarse level 2, minimising): iteration 1, energy "),
        std::string("\r\033[Khole 1 of 1 (loop 1), minimising (started again after coarse "
                    "level 1, minimising): iteration 1, energy ")})
    EXPECT_NE(run.err.find(words), std::string::npos) << words << "\n" << run.err;
  EXPECT_NE(run.err.find(" s\r\033[K"), std::string::npos) << run.err;
  // The line is gone once the fill is done.
  ASSERT_GE(run.err.size(), 4u);
  EXPECT_EQ(run.err.substr(run.err.size() - 4), "\r\033[K") << run.err;
  const CliRun quiet = run_cli_on_terminal("demo " + (dir_ / "demo").string() + " -q", dir_);
  EXPECT_EQ(quiet.code, 0);
  EXPECT_TRUE(quiet.err.empty()) << quiet.err;
}

}  // namespace
}  // namespace foldfill
