// The command-line program end to end: exit codes and messages for bad input,
// nothing written on failure, the input never touched, `holes` and `demo`.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "foldfill/examples.h"
#include "foldfill/io.h"
#include "test_support.h"

namespace foldfill {
namespace {

namespace fs = std::filesystem;

struct CliRun {
  int code = -1;
  std::string out, err;
};

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

CliRun run_cli(const std::string& arguments, const fs::path& dir) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string command = std::string(FOLDFILL_CLI) + " " + arguments + " >" + out.string() +
                              " 2>" + err.string() + " </dev/null";
  const int status = std::system(command.c_str());
  CliRun run;
  run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.out = slurp(out);
  run.err = slurp(err);
  return run;
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

}  // namespace
}  // namespace foldfill
