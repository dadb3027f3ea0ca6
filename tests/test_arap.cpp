// ARAP initialisation on hand-built domains: a triangular lattice whose two
// outer rings are the fixed strip, placed in 3D by a known map.
#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <string>

#include "foldfill/arap.h"
#include "foldfill/error.h"
#include "lattice_domain.h"

namespace foldfill {
namespace {

using testing::lattice_domain;

Vec3 rigid_motion(const Vec2& uv) {
  // Rotation by 0.7 rad about the unit axis (1, 2, 2) / 3, then a translation.
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 2) / 3).toRotationMatrix();
  const Eigen::Vector3d p = r * Eigen::Vector3d(uv[0], uv[1], 0) + Eigen::Vector3d(3, -1, 2);
  return {p.x(), p.y(), p.z()};
}

// Wraps u around a cylinder of radius `radius` with axis along v: isometric.
std::function<Vec3(const Vec2&)> onto_cylinder(double radius) {
  return [radius](const Vec2& uv) {
    return Vec3{radius * std::sin(uv[0] / radius), uv[1], radius * (1 - std::cos(uv[0] / radius))};
  };
}

double length(const Vec3& a, const Vec3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

// Mean of |x_i - x_j| / rest over the patch faces' edges.
double mean_length_ratio(const EmbedDomain& domain, const std::vector<Vec3>& x) {
  double sum = 0;
  int count = 0;
  for (size_t f = domain.strip_face_count; f < domain.faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int i = domain.faces[f][k], j = domain.faces[f][(k + 1) % 3];
      const Vec2& a = domain.rest_uv[i];
      const Vec2& b = domain.rest_uv[j];
      sum += length(x[i], x[j]) / std::hypot(a[0] - b[0], a[1] - b[1]);
      ++count;
    }
  }
  return sum / count;
}

double max_abs_length_error(const EmbedDomain& domain, const std::vector<Vec3>& x) {
  double worst = 0;
  for (size_t f = domain.strip_face_count; f < domain.faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int i = domain.faces[f][k], j = domain.faces[f][(k + 1) % 3];
      const Vec2& a = domain.rest_uv[i];
      const Vec2& b = domain.rest_uv[j];
      worst = std::max(worst, std::abs(length(x[i], x[j]) - std::hypot(a[0] - b[0], a[1] - b[1])));
    }
  }
  return worst;
}

TEST(Arap, LatticeDomainIsConsistent) {
  const EmbedDomain domain = lattice_domain(8, 7, rigid_motion);
  EXPECT_EQ(domain.vertex_count(), 56);
  EXPECT_EQ(domain.fixed_count, 26 + 18);
  EXPECT_EQ(domain.loop_size, 18);
  EXPECT_EQ(domain.faces.size(), 2u * 7 * 6);
  // Consecutive loop vertices are one rest edge apart.
  for (int k = 0; k < domain.loop_size; ++k) {
    const Vec2& a = domain.rest_uv[k];
    const Vec2& b = domain.rest_uv[(k + 1) % domain.loop_size];
    EXPECT_NEAR(std::hypot(a[0] - b[0], a[1] - b[1]), 1.0, 1e-12) << k;
  }
}

TEST(Arap, RigidlyMovedBoundaryGivesTheRigidlyMovedPatch) {
  const EmbedDomain domain = lattice_domain(12, 11, rigid_motion);
  const std::vector<Vec3> x = arap_embed(domain, {1.0, 30});
  ASSERT_EQ(x.size(), domain.rest_uv.size());
  for (int i = domain.fixed_count; i < domain.vertex_count(); ++i) {
    const Vec3 expected = rigid_motion(domain.rest_uv[i]);
    EXPECT_LT(length(x[i], expected), 1e-8) << i;
  }
}

// The mirror image of the flat domain (v -> -v) is the flat domain turned
// over: rotations alone must reach it, without reflections creeping in.
TEST(Arap, MirroredBoundaryGivesTheMirroredPatch) {
  const auto mirrored = [](const Vec2& uv) { return rigid_motion({uv[0], -uv[1]}); };
  const EmbedDomain domain = lattice_domain(12, 11, mirrored);
  const std::vector<Vec3> x = arap_embed(domain, {1.0, 30});
  for (int i = domain.fixed_count; i < domain.vertex_count(); ++i)
    EXPECT_LT(length(x[i], mirrored(domain.rest_uv[i])), 1e-8) << i;
}

// A boundary collapsed onto a line gives one-rings whose fit has rank one
// (any rotation about the line fits equally): the patch must still come out
// finite and near the line, not thrown off by an arbitrary frame.
TEST(Arap, BoundaryCollapsedOntoALineStaysNearIt) {
  const EmbedDomain domain = lattice_domain(9, 8, [](const Vec2& uv) { return Vec3{uv[0], 0, 0}; });
  const std::vector<Vec3> x = arap_embed(domain, {0.5, 30});
  for (int i = domain.fixed_count; i < domain.vertex_count(); ++i) {
    ASSERT_TRUE(std::isfinite(x[i][0]) && std::isfinite(x[i][1]) && std::isfinite(x[i][2])) << i;
    EXPECT_GT(x[i][0], 0.0) << i;
    EXPECT_LT(x[i][0], 8.5) << i;
    EXPECT_LT(std::hypot(x[i][1], x[i][2]), 3.0) << i;
  }
}

TEST(Arap, FixedVerticesAreReturnedBitForBit) {
  const EmbedDomain domain = lattice_domain(10, 9, onto_cylinder(2.0));
  const std::vector<Vec3> x = arap_embed(domain, {0.5, 10});
  for (int i = 0; i < domain.fixed_count; ++i) EXPECT_EQ(x[i], domain.fixed_positions[i]) << i;
}

TEST(Arap, BentBoundaryGivesANearlyIsometricPatchOnTheCylinder) {
  const double radius = 2.5;
  const EmbedDomain domain = lattice_domain(14, 12, onto_cylinder(radius));
  const std::vector<Vec3> x = arap_embed(domain, {1.0, 30});
  EXPECT_LT(max_abs_length_error(domain, x), 0.03);
  for (int i = domain.fixed_count; i < domain.vertex_count(); ++i) {
    const double distance_to_axis = std::hypot(x[i][0], x[i][2] - radius);
    EXPECT_NEAR(distance_to_axis, radius, 0.025 * radius) << i;
  }
  // The flat start alone is far from the cylinder: ARAP did the bending.
  const std::vector<Vec3> start = arap_embed(domain, {1.0, 0});
  double worst_start = 0;
  for (int i = domain.fixed_count; i < domain.vertex_count(); ++i)
    worst_start =
        std::max(worst_start, std::abs(std::hypot(start[i][0], start[i][2] - radius) - radius));
  EXPECT_GT(worst_start, 0.1 * radius);
}

TEST(Arap, StopsWhenItsBudgetIsSpent) {
  const EmbedDomain domain = lattice_domain(10, 9, onto_cylinder(2.0));
  std::atomic<bool> cancel{true};
  EXPECT_EQ(arap_embed(domain, {1.0, 30}, Budget(0, &cancel)), arap_embed(domain, {1.0, 0}));
  EXPECT_EQ(arap_embed(domain, {1.0, 30}, Budget(1e-9)), arap_embed(domain, {1.0, 0}));
  cancel = false;
  EXPECT_EQ(arap_embed(domain, {1.0, 30}, Budget(1e6, &cancel)), arap_embed(domain, {1.0, 30}));
}

TEST(Arap, ShrunkRestShapeGivesShorterEdges) {
  const EmbedDomain domain = lattice_domain(14, 12, onto_cylinder(2.5));
  const double full = mean_length_ratio(domain, arap_embed(domain, {1.0, 30}));
  const double shrunk = mean_length_ratio(domain, arap_embed(domain, {0.5, 30}));
  EXPECT_NEAR(full, 1.0, 0.01);
  EXPECT_LT(shrunk, full - 0.05);
}

// How many iterations `options` ran: the run is deterministic, so its result
// is bit for bit that of the same number of iterations without early stop
// (-1 if none matches).
int iterations_run(const EmbedDomain& domain, const ArapOptions& options) {
  const std::vector<Vec3> result = arap_embed(domain, options);
  for (int k = 0; k <= options.iterations; ++k)
    if (arap_embed(domain, {options.shrink, k, 0.0}) == result) return k;
  return -1;
}

double largest_distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, length(a[i], b[i]));
  return worst;
}

// A rigidly placed boundary is fitted by the start itself: the first
// iteration moves nothing, and there is nothing left to iterate for.
TEST(Arap, StopsAtOnceWhenTheStartIsTheAnswer) {
  const EmbedDomain domain = lattice_domain(12, 11, rigid_motion);
  EXPECT_EQ(iterations_run(domain, {1.0, 30}), 1);
}

// The bent, shrunk patch converges linearly: early stop ends well before the
// cap, close to where many more iterations end (the lattice's edges are 1).
TEST(Arap, EarlyStopEndsNearTheConvergedEmbedding) {
  const EmbedDomain domain = lattice_domain(14, 12, onto_cylinder(2.5));
  const ArapOptions early{0.5, 30};
  const int iterations = iterations_run(domain, early);
  EXPECT_GT(iterations, 3);
  EXPECT_LT(iterations, 30);
  const std::vector<Vec3> converged = arap_embed(domain, {0.5, 300, 0.0});
  EXPECT_LT(largest_distance(arap_embed(domain, early), converged), 2 * early.tolerance);
  // A tenth of the tolerance takes more iterations and ends nearer.
  const ArapOptions tighter{0.5, 30, 0.1 * early.tolerance};
  EXPECT_GT(iterations_run(domain, tighter), iterations);
  EXPECT_LT(largest_distance(arap_embed(domain, tighter), converged),
            largest_distance(arap_embed(domain, early), converged));
}

// The tolerance is in rest edge lengths: the same domain ten times larger
// stops after the same number of iterations.
TEST(Arap, ToleranceIsRelativeToTheEdgeLength) {
  const EmbedDomain domain = lattice_domain(14, 12, onto_cylinder(2.5));
  EmbedDomain larger = domain;
  for (Vec2& p : larger.rest_uv) p = {10 * p[0], 10 * p[1]};
  for (Vec3& p : larger.fixed_positions) p = {10 * p[0], 10 * p[1], 10 * p[2]};
  EXPECT_EQ(iterations_run(larger, {0.5, 30}), iterations_run(domain, {0.5, 30}));
}

// Iterations stop at the cap, converged or not.
TEST(Arap, StopsAtTheCap) {
  const EmbedDomain domain = lattice_domain(14, 12, onto_cylinder(2.5));
  EXPECT_EQ(iterations_run(domain, {0.5, 4}), 4);
  EXPECT_NE(arap_embed(domain, {0.5, 4}), arap_embed(domain, {0.5, 5}));
}

TEST(Arap, IsDeterministic) {
  const EmbedDomain domain = lattice_domain(10, 9, onto_cylinder(2.0));
  EXPECT_EQ(arap_embed(domain, {0.5, 20}), arap_embed(domain, {0.5, 20}));
}

// Large enough for the parallel local step and right-hand side (5,776 free
// vertices, over arap.cpp's kSmallestParallelDomain).
TEST(Arap, GivesTheSameBitsWhateverTheThreadCount) {
  const EmbedDomain domain = lattice_domain(80, 80, onto_cylinder(20.0));
  ASSERT_GE(domain.free_count(), 5000);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const std::vector<Vec3> serial = arap_embed(domain, {0.5, 8});
  for (int count : {2, 3}) {
    omp_set_num_threads(count);
    EXPECT_EQ(arap_embed(domain, {0.5, 8}), serial) << count << " threads";
  }
  omp_set_num_threads(threads);
}

TEST(Arap, RejectsInconsistentDomains) {
  EmbedDomain domain = lattice_domain(6, 6, rigid_motion);
  domain.fixed_positions.pop_back();
  EXPECT_THROW(arap_embed(domain), Error);
  domain = lattice_domain(6, 6, rigid_motion);
  domain.fixed_positions[0][1] = std::nan("");
  EXPECT_THROW(arap_embed(domain), Error);
  domain = lattice_domain(6, 6, rigid_motion);
  EXPECT_THROW(arap_embed(domain, {0.0, 30}), Error);
  EXPECT_THROW(arap_embed(domain, {0.5, 30, -1.0}), Error);
}

// A free vertex in no face is tied to nothing: the global step's matrix is
// singular, which the factorisation reports.
TEST(Arap, RefusesAFreeVertexNotConnectedToTheStrip) {
  EmbedDomain domain = lattice_domain(6, 6, rigid_motion);
  domain.rest_uv.push_back({100, 100});
  try {
    arap_embed(domain);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::FillFailed);
    EXPECT_NE(std::string(e.what()).find("not connected"), std::string::npos);
  }
}

}  // namespace
}  // namespace foldfill
