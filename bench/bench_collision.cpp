// Collision work of one minimisation iteration (issue 17) on a free patch of
// 2k, 20k and 100k vertices just above a fixed layer: a wavy triangulated
// sheet of unit edges, the patch a copy of it lifted by `gap`, shifted and
// crumpled. The stages, as in collision.h's recipe: the pairs within dhat +
// skin (find_within, only when a vertex has moved skin / 2; find, the boxes'
// pairs alone, for comparison), the barrier potential with its gradient over
// them, the broad phase along the step (swept boxes) and the step bound
// (Additive CCD over those pairs); "all" adds the stages of the recipe. The
// step moves the patch by up to about one edge, partly through the layer.
// Prints markdown: medians in milliseconds.
//
//   build/bench/bench_collision [--runs N] [--threads N] [--dhat D] [--skin S]
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

#include "bench_timing.h"
#include "foldfill/collision.h"

namespace {

using namespace foldfill;

struct Scene {
  std::vector<Vec3> positions, step;
  CollisionMesh mesh;
};

double wave(double x, double y) { return 2 * std::sin(0.15 * x) * std::cos(0.11 * y); }

// Two n x n sheets: the fixed layer first, then the free patch.
Scene make_scene(int n, double gap) {
  Scene scene;
  std::vector<Tri> faces;
  std::mt19937 random(17);
  std::uniform_real_distribution<double> noise(-0.1, 0.1);
  for (int sheet = 0; sheet < 2; ++sheet) {
    const int first = static_cast<int>(scene.positions.size());
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        if (sheet == 0) {
          scene.positions.push_back({double(i), double(j), wave(i, j)});
        } else {
          const double x = i + 0.3 + noise(random), y = j + 0.2 + noise(random);
          scene.positions.push_back({x, y, wave(x, y) + gap + noise(random)});
        }
      }
    }
    for (int j = 0; j + 1 < n; ++j) {
      for (int i = 0; i + 1 < n; ++i) {
        const int a = first + j * n + i, b = a + 1, c = a + n + 1, d = a + n;
        faces.push_back({a, b, c});
        faces.push_back({a, c, d});
      }
    }
  }
  const int fixed = n * n;
  scene.step.assign(scene.positions.size(), Vec3{0, 0, 0});
  for (int v = fixed; v < 2 * fixed; ++v) {
    const Vec3& p = scene.positions[v];
    scene.step[v] = {0.3 * std::cos(0.2 * p[1]), 0.2 * std::sin(0.13 * p[0]),
                     -0.5 * (1 + std::sin(0.3 * p[0] + 0.2 * p[1]))};
  }
  scene.mesh = make_collision_mesh(faces, 2 * fixed, fixed);
  return scene;
}

const double* flat(const std::vector<Vec3>& v) { return v.data()->data(); }

}  // namespace

int main(int argc, char** argv) {
  int runs = 7;
  double dhat = 0.2, skin = 0.1, gap = 0.3;
  for (int k = 1; k + 1 < argc; k += 2) {
    if (!std::strcmp(argv[k], "--runs")) runs = std::atoi(argv[k + 1]);
    if (!std::strcmp(argv[k], "--threads")) omp_set_num_threads(std::atoi(argv[k + 1]));
    if (!std::strcmp(argv[k], "--dhat")) dhat = std::atof(argv[k + 1]);
    if (!std::strcmp(argv[k], "--skin")) skin = std::atof(argv[k + 1]);
  }
  std::printf(
      "medians of %d runs, %d threads; unit edges, dhat %.2f, skin %.2f, layers %.1f apart\n\n",
      runs, omp_get_max_threads(), dhat, skin, gap);
  std::printf(
      "| patch vertices | setup ms | pairs in boxes | find ms | pairs within dhat + skin | "
      "find_within ms | barrier + gradient ms | swept pairs | swept find ms | step bound ms | step "
      "bound | all ms |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const int n : {45, 142, 317}) {
    const Scene scene = make_scene(n, gap);
    const double* x = flat(scene.positions);
    const double* dx = flat(scene.step);
    CollisionBroadPhase broad;
    const double setup_ms =
        bench::median_ms(1, [&] { broad = CollisionBroadPhase(scene.mesh, x); });
    CollisionCandidates boxed, near, swept;
    std::vector<double> gradient(3 * scene.positions.size());
    double potential = 0, bound = 0;
    const double find_ms =
        bench::median_ms(runs, [&] { broad.find(x, nullptr, dhat + skin, boxed); });
    const double within_ms =
        bench::median_ms(runs, [&] { broad.find_within(x, dhat + skin, near); });
    const double barrier_ms = bench::median_ms(runs, [&] {
      std::fill(gradient.begin(), gradient.end(), 0.0);
      potential = barrier_potential(scene.mesh, x, near, dhat, 1, gradient.data());
    });
    const double swept_ms = bench::median_ms(runs, [&] { broad.find(x, dx, 0, swept); });
    const double bound_ms =
        bench::median_ms(runs, [&] { bound = collision_step_bound(scene.mesh, x, dx, swept); });
    std::printf(
        "| %d | %.1f | %zu | %.2f | %zu | %.2f | %.2f | %zu | %.2f | %.2f | %.3f | %.1f |\n", n * n,
        setup_ms, boxed.size(), find_ms, near.size(), within_ms, barrier_ms, swept.size(), swept_ms,
        bound_ms, bound, within_ms + barrier_ms + swept_ms + bound_ms);
    std::fflush(stdout);
    if (!(potential >= 0)) return 1;
  }
  return 0;
}
