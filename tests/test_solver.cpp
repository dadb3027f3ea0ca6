// The energy minimisation on hand-built domains: a lattice whose fixed strip
// is compressed and waved in 3D, so that the free part must fold.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "foldfill/arap.h"
#include "foldfill/error.h"
#include "foldfill/solver.h"
#include "lattice_domain.h"

namespace foldfill {
namespace {

using testing::lattice_domain;

// The strip squeezed to 80% along u and waved out of plane, so the patch has
// more material than room and must fold.
Vec3 squeezed_wave(const Vec2& uv) {
  return {0.8 * uv[0], uv[1], 0.6 * std::sin(0.9 * uv[0]) * std::cos(0.3 * uv[1])};
}

struct Problem {
  EmbedDomain domain;
  FabricEnergy energy;
  std::vector<Vec3> start;
  Problem(int columns, int rows)
      : domain(lattice_domain(columns, rows, squeezed_wave)),
        energy(domain, EnergyOptions{}),
        start(arap_embed(domain)) {}
};

double rms_gradient(const FabricEnergy& energy, const std::vector<Vec3>& positions) {
  const Eigen::VectorXd x = energy.variables(positions);
  Eigen::VectorXd g(x.size());
  energy.evaluate(x, &g);
  return std::sqrt(3.0 * g.squaredNorm() / g.size());
}

double total_energy(const FabricEnergy& energy, const std::vector<Vec3>& positions) {
  return energy.evaluate(energy.variables(positions)).total;
}

TEST(Solver, Probe) {
  for (int size : {16, 55}) {
    Problem problem(size, size);
    std::printf("free %d start E %g\n", problem.domain.free_count(), total_energy(problem.energy, problem.start));
    for (SolverKind kind : {SolverKind::GradientDescent, SolverKind::Fast}) {
      SolverOptions options;
      options.kind = kind;
      options.max_iterations = 200000;
      const auto t0 = std::chrono::steady_clock::now();
      const SolverResult r = minimize_energy(problem.energy, {}, problem.start, options);
      const std::chrono::duration<double> dt = std::chrono::steady_clock::now() - t0;
      std::printf("%s: %d its %s %.3fs E %.10g g %g\n", kind == SolverKind::Fast ? "fast" : "gd",
                  r.iterations, r.stop_reason.c_str(), dt.count(), total_energy(problem.energy, r.positions),
                  rms_gradient(problem.energy, r.positions));
    }
  }
}

}  // namespace
}  // namespace foldfill
