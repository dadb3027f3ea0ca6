// The command-line program end to end: exit codes and messages for bad input,
// nothing written on failure, the input never touched, `holes` and `demo`.
#include <gtest/gtest.h>
#include <sys/wait.h>

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

// A 4 x 4 vertex grid with its middle quad missing: an outer loop and a hole.
std::string grid_with_hole_obj() {
  std::string obj;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) obj += "v " + std::to_string(i) + " " + std::to_string(j) + " 0\n";
  }
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      if (i == 1 && j == 1) continue;
      const int a = j * 4 + i + 1, b = a + 1, c = a + 5, d = a + 4;
      obj += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + "\n";
      obj += "f " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(d) + "\n";
    }
  }
  return obj;
}

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
    const CliRun run = run_cli("fill " + input.string() + " -o " + output.string() + " " + extra, dir_);
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
  const std::string bytes = serialize_mesh(parse_mesh(grid_with_hole_obj(), MeshFormat::Obj, "grid"), MeshFormat::Stl);
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
  write_text(dir_ / "fin.obj",
             "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  expect_fill_error(dir_ / "fin.obj", 7, "edge");
}

TEST_F(CliTest, PinchedLoopNamedExplicitly) {
  // Two triangles sharing only vertex 1: its boundary touches itself there.
  write_text(dir_ / "bowtie.obj", "v 0 0 0\nv 1 1 0\nv 1 -1 0\nv -1 1 0\nv -1 -1 0\nf 1 2 4\nf 1 5 3\n");
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
}

TEST_F(CliTest, FillsASmallHoleKeepingEveryInputVertex) {
  const fs::path input = dir_ / "grid.obj", output = dir_ / "out.ply", report = dir_ / "r.json";
  write_text(input, grid_with_hole_obj());
  const CliRun run = run_cli("fill " + input.string() + " -o " + output.string() + " --report " +
                              report.string(),
                          dir_);
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

}  // namespace
}  // namespace foldfill
