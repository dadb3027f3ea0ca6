// Collision work of one minimisation iteration (issue 17) on a free patch of
// 2k, 20k and 100k vertices just above a fixed layer: a wavy triangulated
// sheet of unit edges, the patch a copy of it lifted by `gap`, shifted and
// crumpled. The stages, as in collision.h's recipe: the pairs within dhat +
// skin (find_within, only when a vertex has moved skin / 2; find, the boxes'
// pairs alone, for comparison), the barrier potential with its gradient over
// them, the broad phase along the step (swept boxes) and the step bound
// (Additive CCD over those pairs); "all" adds the stages of the recipe. The
// step moves the patch by up to about one edge, partly through the layer.
// Prints markdown: medians in milliseconds. Then the cost of one triangle
// against an analytic obstacle (triangle_obstacle_distance, with and without
// its gradient, and triangle_obstacle_ccd), in nanoseconds per call, over
// random unit triangles within about one radius of a unit sphere, a cylinder
// and a plane, with steps of about one radius towards them.
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
#include "foldfill/obstacles.h"

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

// Nanoseconds per call of the obstacle queries on `count` random triangles
// with steps, for a sphere, a cylinder (capsule) and a plane. Returns a sum
// of the results, to keep the calls.
double bench_obstacles(int runs) {
  const int count = 4096;
  std::mt19937 random(23);
  std::uniform_real_distribution<double> uniform(-1, 1);
  const auto point = [&](double scale) {
    return Vec3{scale * uniform(random), scale * uniform(random), scale * uniform(random)};
  };
  std::vector<Obstacle> obstacles(3);
  obstacles[0].type = Obstacle::Type::Sphere;
  obstacles[0].radius = 1;
  obstacles[1].type = Obstacle::Type::Cylinder;
  obstacles[1].radius = 1;
  obstacles[1].height = 4;
  obstacles[1].axis = {0, 0.6, 0.8};
  obstacles[2].type = Obstacle::Type::Plane;
  obstacles[2].normal = {0, 0.6, 0.8};
  // Corners within 1 of a point at 2 from the origin; steps towards it.
  std::vector<std::array<Vec3, 6>> triangles(count);
  for (auto& t : triangles) {
    Vec3 centre = point(1);
    const double length =
        std::sqrt(centre[0] * centre[0] + centre[1] * centre[1] + centre[2] * centre[2]) + 1e-9;
    for (double& c : centre) c *= 2 / length;
    for (int k = 0; k < 3; ++k) {
      const Vec3 offset = point(0.6);
      t[k] = {centre[0] + offset[0], centre[1] + offset[1], centre[2] + offset[2]};
      const Vec3 jitter = point(0.3);
      t[3 + k] = {-0.8 * centre[0] + jitter[0], -0.8 * centre[1] + jitter[1],
                  -0.8 * centre[2] + jitter[2]};
    }
  }
  double sum = 0;
  std::printf(
      "\n| obstacle | distance ns | distance + gradient ns | ccd ns |\n|---|---|---|---|\n");
  const char* names[3] = {"sphere", "cylinder", "plane"};
  for (int type = 0; type < 3; ++type) {
    const Obstacle& o = obstacles[type];
    const double per_call = 1e6 / count;  // ms per sweep to ns per call
    const double distance_ns = per_call * bench::median_ms(runs, [&] {
                                 for (const auto& t : triangles)
                                   sum += triangle_obstacle_distance(o, t[0], t[1], t[2]);
                               });
    std::array<Vec3, 3> gradient;
    const double gradient_ns = per_call * bench::median_ms(runs, [&] {
                                 for (const auto& t : triangles) {
                                   sum +=
                                       triangle_obstacle_distance(o, t[0], t[1], t[2], &gradient);
                                   sum += gradient[0][0];
                                 }
                               });
    const double ccd_ns = per_call * bench::median_ms(runs, [&] {
                            for (const auto& t : triangles)
                              sum += triangle_obstacle_ccd(o, t[0], t[1], t[2], t[3], t[4], t[5]);
                          });
    std::printf("| %s | %.0f | %.0f | %.0f |\n", names[type], distance_ns, gradient_ns, ccd_ns);
  }
  return sum;
}

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
  if (!std::isfinite(bench_obstacles(runs))) return 1;
  return 0;
}
