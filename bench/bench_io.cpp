// Read and write times of each mesh format on a 1001 x 1001 grid (about 1M
// vertices, 2M triangles) with full-precision double coordinates. Each file is
// written once to a temporary folder, removed at the end.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "foldfill/io.h"

namespace {

using foldfill::Mesh;

constexpr int kGridSide = 1001;

// A gently folded sheet: no coordinate has a short decimal form.
Mesh grid_mesh() {
  Mesh mesh;
  mesh.positions.reserve(kGridSide * kGridSide);
  for (int j = 0; j < kGridSide; ++j) {
    for (int i = 0; i < kGridSide; ++i) {
      const double x = i * 1.37e-3 + 1e-4 * std::sin(0.3 * j);
      const double y = j * 0.91e-3 + 1e-4 * std::cos(0.7 * i);
      mesh.positions.push_back({x, y, 0.05 * std::sin(3.0 * x) * std::cos(2.0 * y)});
    }
  }
  mesh.faces.reserve(2 * (kGridSide - 1) * (kGridSide - 1));
  for (int j = 0; j + 1 < kGridSide; ++j) {
    for (int i = 0; i + 1 < kGridSide; ++i) {
      const int v = j * kGridSide + i;
      mesh.faces.push_back({v, v + 1, v + kGridSide + 1});
      mesh.faces.push_back({v, v + kGridSide + 1, v + kGridSide});
    }
  }
  return mesh;
}

const Mesh& shared_grid() {
  static const Mesh mesh = grid_mesh();
  return mesh;
}

std::filesystem::path bench_dir() {
  return std::filesystem::temp_directory_path() / "foldfill_bench_io";
}

struct FormatCase {
  std::string name;
  std::string extension;
  bool binary;
};

std::string path_of(const FormatCase& format, const std::string& role) {
  return (bench_dir() / (format.name + "_" + role + "." + format.extension)).string();
}

// The grid written in `format`, once.
const std::string& input_file(const FormatCase& format) {
  static std::map<std::string, std::string> written;
  auto [entry, inserted] = written.try_emplace(format.name, path_of(format, "input"));
  if (inserted) {
    std::filesystem::create_directories(bench_dir());
    foldfill::write_mesh(shared_grid(), entry->second, {format.binary});
  }
  return entry->second;
}

void read_benchmark(benchmark::State& state, const FormatCase& format) {
  const std::string& path = input_file(format);
  for (auto _ : state) {
    Mesh mesh = foldfill::read_mesh(path);
    benchmark::DoNotOptimize(mesh.positions.data());
  }
  state.counters["MB"] = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
}

void write_benchmark(benchmark::State& state, const FormatCase& format) {
  const Mesh& mesh = shared_grid();
  std::filesystem::create_directories(bench_dir());
  const std::string path = path_of(format, "output");
  for (auto _ : state) foldfill::write_mesh(mesh, path, {format.binary});
}

template <class Function>
void register_benchmark(const std::string& name, Function function, const FormatCase& format) {
  benchmark::RegisterBenchmark(name.c_str(), function, format)
      ->Iterations(1)
      ->Repetitions(3)
      ->ReportAggregatesOnly(true)
      ->Unit(benchmark::kMillisecond);
}

void register_benchmarks() {
  const FormatCase formats[] = {{"obj", "obj", false},
                                {"ply_binary", "ply", true},
                                {"ply_ascii", "ply", false},
                                {"off", "off", false},
                                {"stl_binary", "stl", true}};
  for (const FormatCase& format : formats) {
    register_benchmark("read/" + format.name, read_benchmark, format);
    register_benchmark("write/" + format.name, write_benchmark, format);
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  register_benchmarks();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::filesystem::remove_all(bench_dir());
  return 0;
}
