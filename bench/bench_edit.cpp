// The edit tool of `foldfill serve`: the demo's sheet with its hole filled at
// a density that gives a patch of about 2,000 new vertices, then a handle near
// the patch's middle dragged up and around in `--moves` steps, each one
// update: first through the library (PatchEditor::drag), then through the
// server's API (POST /api/edit/move on an in-process server, the reply's
// positions included). Prints the patch size and the median and 90th
// percentile of the update times.
//
//   bench_edit [--density 2] [--moves 60] [--iterations 2 (the library part only)]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "foldfill/edit.h"
#include "foldfill/examples.h"
#include "foldfill/fill.h"
#include "foldfill/io.h"
#include "serve.h"

// After Eigen: <resolv.h>, which httplib.h includes, defines `_res`.
#include <httplib.h>

using namespace foldfill;
using Clock = std::chrono::steady_clock;

namespace {

double percentile(std::vector<double> values, double share) {
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<size_t>(share * values.size()))];
}

// The targets of the drag: up by a third of the hole's radius, then around
// a circle of that radius, starting from `p`.
std::vector<Vec3> path(const Vec3& p, int moves, double radius) {
  std::vector<Vec3> targets;
  for (int k = 1; k <= moves; ++k) {
    const double t = static_cast<double>(k) / moves;
    const double lift = std::min(1.0, 4 * t) * radius;
    const double angle = 2 * M_PI * t;
    targets.push_back({p[0] + 0.5 * radius * std::sin(angle),
                       p[1] + 0.5 * radius * (1 - std::cos(angle)), p[2] + lift});
  }
  return targets;
}

int handle_of(const Mesh& mesh, IndexRange range) {
  Vec3 centre{0, 0, 0};
  for (int v = range.first; v < range.end; ++v)
    for (int c = 0; c < 3; ++c) centre[c] += mesh.positions[v][c] / range.size();
  int best = range.first;
  double nearest = 1e300;
  for (int v = range.first; v < range.end; ++v) {
    double d = 0;
    for (int c = 0; c < 3; ++c) d += std::pow(mesh.positions[v][c] - centre[c], 2);
    if (d < nearest) {
      nearest = d;
      best = v;
    }
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  double density = 2;
  int moves = 60;
  EditOptions edit;  // the library's, as the server uses them
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--density")) density = std::atof(argv[i + 1]);
    if (!std::strcmp(argv[i], "--moves")) moves = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--iterations")) edit.max_iterations = std::atoi(argv[i + 1]);
  }
  const double radius = 0.7;
  const CutMesh cut = cut_disk_hole(make_folded_sheet(), {2.6, 1.5}, radius);
  const Mesh& input = cut.cut.mesh;
  FillRequest request;
  request.options.triangulate.density = density;
  const auto fill_start = Clock::now();
  FillOutput output = fill(input, request);
  const double fill_seconds = std::chrono::duration<double>(Clock::now() - fill_start).count();
  const HoleReport& hole = output.report.holes.at(0);
  std::printf("patch: %d new vertices, %d faces (density %g), fill %.2f s\n",
              hole.patch_vertex_count, hole.patch_face_count, density, fill_seconds);

  // The library.
  const auto build_start = Clock::now();
  PatchEditor editor(input, output, 0, output.loops.at(hole.loop_id), request.options, "sheet.obj",
                     edit);
  std::printf("editor built (the precompute) in %.1f ms\n",
              1e3 * std::chrono::duration<double>(Clock::now() - build_start).count());
  const int handle = handle_of(output.mesh, hole.new_vertices);
  const std::vector<Vec3> targets = path(output.mesh.positions[handle], moves, radius / 3);
  editor.grab(handle);
  std::vector<double> library;
  int iterations = 0;
  for (const Vec3& target : targets) {
    const DragResult moved = editor.drag(target);
    library.push_back(1e3 * moved.seconds);
    iterations += moved.iterations;
  }
  editor.release();
  std::printf("library drag(): median %.1f ms, 90%% %.1f ms, %.1f iterations per update\n",
              percentile(library, 0.5), percentile(library, 0.9),
              static_cast<double>(iterations) / moves);

  // The server's API.
  cli::Server server;
  const int port = server.bind(0);
  std::thread thread([&] { server.listen(); });
  httplib::Client client("127.0.0.1", port);
  client.set_read_timeout(600, 0);
  client.Post("/api/mesh?name=sheet.obj", serialize_mesh(input, MeshFormat::Obj), "text/plain");
  client.Post("/api/fill", nlohmann::json{{"density", density}}.dump(), "application/json");
  while (!nlohmann::json::parse(client.Get("/api/progress")->body)["done"].get<bool>())
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const auto began =
      client.Post("/api/edit/begin", nlohmann::json{{"vertex", handle}}.dump(), "application/json");
  if (!began || began->status != 200) {
    std::fprintf(stderr, "edit/begin failed: %s\n", began ? began->body.c_str() : "no answer");
    return 1;
  }
  std::vector<double> api;
  for (const Vec3& target : targets) {
    const auto start = Clock::now();
    const auto moved =
        client.Post("/api/edit/move",
                    nlohmann::json{{"x", target[0]}, {"y", target[1]}, {"z", target[2]}}.dump(),
                    "application/json");
    api.push_back(1e3 * std::chrono::duration<double>(Clock::now() - start).count());
    if (!moved || moved->status != 200) {
      std::fprintf(stderr, "edit/move failed\n");
      return 1;
    }
  }
  const auto ended = client.Post("/api/edit/end", "{}", "application/json");
  const nlohmann::json report = nlohmann::json::parse(ended->body)["report"];
  std::printf(
      "POST /api/edit/move: median %.1f ms, 90%% %.1f ms over %d updates; crossings after: %d\n",
      percentile(api, 0.5), percentile(api, 0.9), moves,
      report["holes"][0]["self_intersections"].get<int>());
  server.stop();
  thread.join();
  return 0;
}
