// The fabric energy on small grids built here: gradients against finite
// differences for every term, rest states, invariances and the bending Hessian.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <set>
#include <utility>

#include "foldfill/energy.h"
#include "foldfill/error.h"

namespace foldfill {
namespace {

using Embedding = std::function<Vec3(const Vec2&)>;

Vec3 flat(const Vec2& uv) { return {uv[0], uv[1], 0}; }

// The rest grid rolled onto a cylinder of radius `radius` around an axis along v.
Embedding rolled(double radius) {
  return [radius](const Vec2& uv) {
    return Vec3{radius * std::sin(uv[0] / radius), uv[1], radius * (1 - std::cos(uv[0] / radius))};
  };
}

// An n x n grid of unit spacing (the normalised unit) with alternating
// diagonals, counter-clockwise in rest_uv. The boundary ring comes first and
// is fixed at embed(uv); the interior vertices are free.
EmbedDomain grid_domain(int n, const Embedding& embed = flat) {
  std::vector<int> index(n * n);
  std::vector<Vec2> uv;
  const auto on_boundary = [n](int i, int j) {
    return i == 0 || j == 0 || i == n - 1 || j == n - 1;
  };
  for (bool boundary : {true, false}) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        if (on_boundary(i, j) != boundary) continue;
        index[j * n + i] = static_cast<int>(uv.size());
        uv.push_back({static_cast<double>(i), static_cast<double>(j)});
      }
    }
  }
  EmbedDomain domain;
  domain.rest_uv = uv;
  domain.fixed_count = domain.loop_size = 4 * (n - 1);
  for (int v = 0; v < domain.fixed_count; ++v) domain.fixed_positions.push_back(embed(uv[v]));
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const int a = index[j * n + i], b = index[j * n + i + 1];
      const int c = index[(j + 1) * n + i + 1], d = index[(j + 1) * n + i];
      if ((i + j) % 2 == 0) {
        domain.faces.push_back({a, b, c});
        domain.faces.push_back({a, c, d});
      } else {
        domain.faces.push_back({a, b, d});
        domain.faces.push_back({b, c, d});
      }
    }
  }
  return domain;
}

// The free variables of `domain` placed at embed(rest_uv).
Eigen::VectorXd embedded_variables(const EmbedDomain& domain, const Embedding& embed) {
  Eigen::VectorXd x(3 * domain.free_count());
  for (int v = 0; v < domain.free_count(); ++v) {
    const Vec3 p = embed(domain.rest_uv[domain.fixed_count + v]);
    for (int c = 0; c < 3; ++c) x[3 * v + c] = p[c];
  }
  return x;
}

Eigen::VectorXd perturbed(Eigen::VectorXd x, double amplitude, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> noise(-amplitude, amplitude);
  for (Eigen::Index k = 0; k < x.size(); ++k) x[k] += noise(random);
  return x;
}

EnergyOptions weights(double lambda, double repulsion, BendingModel bending) {
  EnergyOptions options;
  options.lambda = lambda;
  options.repulsion = repulsion;
  options.bending = bending;
  return options;
}

Eigen::VectorXd gradient_of(const FabricEnergy& energy, const Eigen::VectorXd& x) {
  Eigen::VectorXd g;
  energy.evaluate(x, &g);
  return g;
}

using Term = double EnergyTerms::*;

// Central finite differences of one term.
Eigen::VectorXd numeric_gradient(const FabricEnergy& energy, const Eigen::VectorXd& x, Term term) {
  const double h = 1e-6;
  Eigen::VectorXd g(x.size()), y = x;
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    y[k] = x[k] + h;
    const double plus = energy.evaluate(y).*term;
    y[k] = x[k] - h;
    const double minus = energy.evaluate(y).*term;
    y[k] = x[k];
    g[k] = (plus - minus) / (2 * h);
  }
  return g;
}

double relative_error(const Eigen::VectorXd& g, const Eigen::VectorXd& reference) {
  return (g - reference).norm() / reference.norm();
}

// A rolled 7 x 7 grid with its interior shaken off the surface.
struct BentCase {
  EmbedDomain domain = grid_domain(7, rolled(3));
  Eigen::VectorXd x = perturbed(embedded_variables(domain, rolled(3)), 0.3, 7);
};

TEST(EnergyGradient, IsometricMatchesFiniteDifferences) {
  const BentCase bent;
  const FabricEnergy energy(bent.domain, weights(0, 0, BendingModel::Quadratic));
  const Eigen::VectorXd numeric = numeric_gradient(energy, bent.x, &EnergyTerms::isometric);
  EXPECT_GT(numeric.norm(), 1e-2);
  EXPECT_LT(relative_error(gradient_of(energy, bent.x), numeric), 1e-5);
}

// The bending gradient alone: the gradient with lambda = 1 minus the one with lambda = 0.
void check_bending_gradient(BendingModel model) {
  const BentCase bent;
  const FabricEnergy with(bent.domain, weights(1, 0, model));
  const FabricEnergy without(bent.domain, weights(0, 0, model));
  const Eigen::VectorXd numeric = numeric_gradient(with, bent.x, &EnergyTerms::bending);
  EXPECT_GT(numeric.norm(), 1e-2);
  const Eigen::VectorXd analytic = gradient_of(with, bent.x) - gradient_of(without, bent.x);
  EXPECT_LT(relative_error(analytic, numeric), 1e-5);
}

TEST(EnergyGradient, QuadraticBendingMatchesFiniteDifferences) {
  check_bending_gradient(BendingModel::Quadratic);
}

TEST(EnergyGradient, TwoRingBendingMatchesFiniteDifferences) {
  check_bending_gradient(BendingModel::TwoRing);
}

// The interior squeezed towards its centre so that vertices come closer than
// their repulsion radius.
struct SqueezedCase {
  EmbedDomain domain = grid_domain(7, rolled(3));
  Eigen::VectorXd x = squeeze(perturbed(embedded_variables(domain, rolled(3)), 0.1, 3));
  static Eigen::VectorXd squeeze(Eigen::VectorXd x) {
    const Eigen::Vector3d centre = x.reshaped(3, x.size() / 3).rowwise().mean();
    for (Eigen::Index k = 0; k < x.size(); ++k)
      x[k] = centre[k % 3] + 0.35 * (x[k] - centre[k % 3]);
    return x;
  }
};

TEST(EnergyGradient, RepulsionMatchesFiniteDifferences) {
  const SqueezedCase squeezed;
  const FabricEnergy with(squeezed.domain, weights(0, 1, BendingModel::Quadratic));
  const FabricEnergy without(squeezed.domain, weights(0, 0, BendingModel::Quadratic));
  EXPECT_GT(with.evaluate(squeezed.x).repulsion, 0.1);
  const Eigen::VectorXd numeric = numeric_gradient(with, squeezed.x, &EnergyTerms::repulsion);
  const Eigen::VectorXd analytic = gradient_of(with, squeezed.x) - gradient_of(without, squeezed.x);
  EXPECT_LT(relative_error(analytic, numeric), 1e-5);
}

TEST(EnergyGradient, TotalMatchesFiniteDifferences) {
  const SqueezedCase squeezed;
  for (BendingModel model : {BendingModel::Quadratic, BendingModel::TwoRing}) {
    const FabricEnergy energy(squeezed.domain, weights(0.3, 0.7, model));
    const EnergyTerms terms = energy.evaluate(squeezed.x);
    EXPECT_GT(terms.repulsion, 0);
    EXPECT_DOUBLE_EQ(terms.total, terms.isometric + 0.3 * terms.bending + 0.7 * terms.repulsion);
    const Eigen::VectorXd numeric = numeric_gradient(energy, squeezed.x, &EnergyTerms::total);
    EXPECT_LT(relative_error(gradient_of(energy, squeezed.x), numeric), 1e-5);
  }
}

TEST(EnergyRestState, FlatRestStateHasZeroEnergyAndGradient) {
  const EmbedDomain domain = grid_domain(6);
  const Eigen::VectorXd x = embedded_variables(domain, flat);
  for (BendingModel model : {BendingModel::Quadratic, BendingModel::TwoRing}) {
    const FabricEnergy energy(domain, weights(1, 1, model));
    Eigen::VectorXd g;
    const EnergyTerms terms = energy.evaluate(x, &g);
    EXPECT_NEAR(terms.isometric, 0, 1e-24);
    EXPECT_NEAR(terms.bending, 0, 1e-24);
    EXPECT_EQ(terms.repulsion, 0);  // radius 1/1.3 < the shortest non-edge distance sqrt(2)
    EXPECT_LT(g.norm(), 1e-12);
    // The same state shaken is not at rest.
    EXPECT_GT(energy.evaluate(perturbed(x, 0.2, 5)).total, 1e-4);
  }
}

// A rotation about a generic axis and a translation.
Vec3 rigid_motion(const Vec3& p) {
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d q =
      rotation * Eigen::Vector3d(p[0], p[1], p[2]) + Eigen::Vector3d(3, -1, 2);
  return {q[0], q[1], q[2]};
}

// The domain and variables with every position (fixed and free) moved rigidly.
void move_rigidly(EmbedDomain& domain, Eigen::VectorXd& x) {
  for (Vec3& p : domain.fixed_positions) p = rigid_motion(p);
  for (Eigen::Index v = 0; v < x.size() / 3; ++v) {
    const Vec3 q = rigid_motion({x[3 * v], x[3 * v + 1], x[3 * v + 2]});
    for (int c = 0; c < 3; ++c) x[3 * v + c] = q[c];
  }
}

TEST(EnergyRestState, RigidlyMovedFlatStateHasZeroBending) {
  EmbedDomain domain = grid_domain(6);
  Eigen::VectorXd x = embedded_variables(domain, flat);
  move_rigidly(domain, x);
  for (BendingModel model : {BendingModel::Quadratic, BendingModel::TwoRing}) {
    const EnergyTerms terms = FabricEnergy(domain, weights(1, 1, model)).evaluate(x);
    // p^T H p of a state in H's kernel cancels to rounding: eps |H| |p|^2 per vertex.
    EXPECT_NEAR(terms.bending, 0, 1e-10);
    EXPECT_NEAR(terms.isometric, 0, 1e-20);
  }
}

TEST(EnergyInvariance, RigidMotionKeepsEveryTerm) {
  SqueezedCase squeezed;
  for (BendingModel model : {BendingModel::Quadratic, BendingModel::TwoRing}) {
    const EnergyTerms before =
        FabricEnergy(squeezed.domain, weights(1, 1, model)).evaluate(squeezed.x);
    EmbedDomain moved_domain = squeezed.domain;
    Eigen::VectorXd moved_x = squeezed.x;
    move_rigidly(moved_domain, moved_x);
    const EnergyTerms after = FabricEnergy(moved_domain, weights(1, 1, model)).evaluate(moved_x);
    EXPECT_GT(before.repulsion, 0);
    EXPECT_NEAR(after.isometric, before.isometric, 1e-12 * before.isometric);
    EXPECT_NEAR(after.bending, before.bending, 1e-10 * before.bending);
    EXPECT_NEAR(after.repulsion, before.repulsion, 1e-12 * before.repulsion);
  }
}

double rolled_bending(double radius, double stretch = 1) {
  const Embedding embed = [&](const Vec2& uv) {
    const Vec3 p = rolled(radius)(uv);
    return Vec3{stretch * p[0], stretch * p[1], stretch * p[2]};
  };
  const EmbedDomain domain = grid_domain(9, embed);
  return FabricEnergy(domain, {}).evaluate(embedded_variables(domain, embed)).bending;
}

TEST(QuadraticBending, RolledGridScalesWithSquaredCurvature) {
  const double e10 = rolled_bending(10), e20 = rolled_bending(20);
  EXPECT_GT(e10, 0);
  EXPECT_NEAR(e10 / e20, 4, 0.04);  // E ~ area / R^2
  // Quadratic in the positions: scaling the whole state by s scales E by s^2.
  EXPECT_NEAR(rolled_bending(10, 2.5), 6.25 * e10, 1e-9 * e10);
}

// One hinge: rest edge (0,0)-(1,0), triangles of areas 0.4 (vertex 2, fixed)
// and 0.75 (vertex 3, free), the second wing folded by `angle` about the edge.
struct Hinge {
  EmbedDomain domain;
  Eigen::VectorXd x;
  explicit Hinge(double angle) {
    domain.rest_uv = {{0, 0}, {1, 0}, {0.3, 0.8}, {0.6, -1.5}};
    domain.faces = {{0, 1, 2}, {1, 0, 3}};
    domain.fixed_count = 3;
    domain.fixed_positions = {{0, 0, 0}, {1, 0, 0}, {0.3, 0.8, 0}};
    x = Eigen::Vector3d(0.6, -1.5 * std::cos(angle), 1.5 * std::sin(angle));
  }
};

// |K X| = |e| 2 sin(angle / 2) for an isometric fold, so E_B = 1/2 3 / (A0 + A1) |K X|^2.
TEST(QuadraticBending, HingeEnergyUsesBothFaceAreas) {
  const double angle = 0.7;
  const Hinge hinge(angle);
  const EnergyTerms terms = FabricEnergy(hinge.domain, {}).evaluate(hinge.x);
  const double expected = 0.5 * 3 / (0.4 + 0.75) * std::pow(2 * std::sin(angle / 2), 2);
  EXPECT_NEAR(terms.bending, expected, 1e-14);
  EXPECT_NEAR(terms.isometric, 0, 1e-28);
}

// Vertices 2 and 3 are the hinge's only two-ring pair.
TEST(TwoRingBending, HingeEnergyIsTheSpringBetweenTheWingTips) {
  const Hinge hinge(0.7);
  const EnergyTerms terms =
      FabricEnergy(hinge.domain, weights(1, 0, BendingModel::TwoRing)).evaluate(hinge.x);
  const double rest = std::hypot(0.3 - 0.6, 0.8 + 1.5);
  const double now = std::hypot(0.3 - hinge.x[0], 0.8 - hinge.x[1], hinge.x[2]);
  EXPECT_NEAR(terms.bending, 0.5 * (now - rest) * (now - rest), 1e-14);
}

// Two separate triangles: a fixed one of edge 2 and a free one of edge 1 whose
// vertex 3 comes within 0.2 of vertex 0. Radii: 2 / 1.3 and 1 / 1.3.
TEST(Repulsion, PairRadiusIsTheMeanOfTheVertexRadii) {
  EmbedDomain domain;
  const double h = std::sqrt(3.0) / 2;
  domain.rest_uv = {{0, 0}, {2, 0}, {1, 2 * h}, {10, 0}, {11, 0}, {10.5, h}};
  domain.faces = {{0, 1, 2}, {3, 4, 5}};
  domain.fixed_count = 3;
  domain.fixed_positions = {{0, 0, 0}, {2, 0, 0}, {1, 2 * h, 0}};
  const Eigen::VectorXd x = (Eigen::VectorXd(9) << 0, 0, 0.2, 0, 0, 5, 1, 0, 5).finished();
  const EnergyTerms terms =
      FabricEnergy(domain, weights(0, 1, BendingModel::Quadratic)).evaluate(x);
  EXPECT_NEAR(terms.repulsion, 0.5 * std::pow(1.5 / 1.3 - 0.2, 2), 1e-15);
}

// The spatial hash finds every close pair: compare with all pairs on a
// squeezed grid (unit rest edges, so every radius is 1 / 1.3).
TEST(Repulsion, MatchesAllPairsSearch) {
  const EmbedDomain domain = grid_domain(14, rolled(4));
  const Eigen::VectorXd x =
      SqueezedCase::squeeze(perturbed(embedded_variables(domain, rolled(4)), 0.2, 9));
  const FabricEnergy energy(domain, weights(0, 1, BendingModel::Quadratic));
  const std::vector<Vec3> p = energy.positions(x);
  std::set<std::pair<int, int>> edges;
  for (const Tri& t : domain.faces) {
    for (int k = 0; k < 3; ++k) {
      edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
    }
  }
  double expected = 0;
  int close_pairs = 0;
  for (int i = 0; i < domain.vertex_count(); ++i) {
    for (int j = std::max(i + 1, domain.fixed_count); j < domain.vertex_count(); ++j) {
      const double d = std::hypot(p[i][0] - p[j][0], p[i][1] - p[j][1], p[i][2] - p[j][2]);
      if (d < 1 / 1.3 && !edges.count({i, j})) {
        expected += 0.5 * std::pow(1 / 1.3 - d, 2);
        ++close_pairs;
      }
    }
  }
  EXPECT_GT(close_pairs, 50);
  EXPECT_NEAR(energy.evaluate(x).repulsion, expected, 1e-12 * expected);
}

// The candidate pairs found at one state are reused while vertices move
// little: along a path of small steps from the rolled state to a squeezed one,
// and after a jump back, the energy and its gradient are bit for bit those of
// a fresh object, which searches all pairs at that very state.
TEST(Repulsion, ReusedCandidatesGiveTheEnergyOfAFreshSearch) {
  const EmbedDomain domain = grid_domain(14, rolled(4));
  const Eigen::VectorXd start = embedded_variables(domain, rolled(4));
  const Eigen::VectorXd squeezed = SqueezedCase::squeeze(perturbed(start, 0.2, 9));
  const EnergyOptions options = weights(0.1, 1, BendingModel::Quadratic);
  const FabricEnergy reused(domain, options);
  std::vector<Eigen::VectorXd> path;
  for (int k = 0; k <= 40; ++k) path.push_back(start + (k / 40.0) * (squeezed - start));
  path.push_back(start);
  for (const Eigen::VectorXd& x : path) {
    Eigen::VectorXd g_reused, g_fresh;
    const EnergyTerms terms = reused.evaluate(x, &g_reused);
    const EnergyTerms fresh = FabricEnergy(domain, options).evaluate(x, &g_fresh);
    EXPECT_EQ(terms.repulsion, fresh.repulsion);
    EXPECT_EQ(terms.total, fresh.total);
    EXPECT_TRUE(g_reused == g_fresh);
  }
  EXPECT_GT(reused.evaluate(squeezed).repulsion, 0.1);
}

// The repulsion from all pairs (i > j, i free, not joined by an edge): the
// candidates, those closer than their radius plus the skin, in (i, j) order,
// and the energy summed in that order as FabricEnergy sums its candidates, so
// equal bit for bit when its list holds every close pair. `close` counts the
// pairs closer than their radius, `wide` those with a fixed end of radius
// above `wide_radius`.
struct AllPairs {
  std::vector<FabricEnergy::RepulsionPair> candidates;
  double repulsion = 0;
  int close = 0, wide = 0;
};

AllPairs all_pairs(const FabricEnergy& energy, const Eigen::VectorXd& x, double wide_radius) {
  const EmbedDomain& domain = energy.domain();
  const int n = domain.vertex_count();
  std::vector<double> radius(n, HUGE_VAL);
  std::set<std::pair<int, int>> edges;
  for (const Tri& t : domain.faces) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      const double length = std::hypot(domain.rest_uv[a][0] - domain.rest_uv[b][0],
                                       domain.rest_uv[a][1] - domain.rest_uv[b][1]);
      radius[a] = std::min(radius[a], length);
      radius[b] = std::min(radius[b], length);
      edges.insert(std::minmax(a, b));
    }
  }
  for (double& r : radius) r *= energy.options().repulsion_radius;
  const double skin = energy.repulsion_skin();
  const std::vector<Vec3> p = energy.positions(x);
  AllPairs all;
  double sum = 0;
  for (int i = domain.fixed_count; i < n; ++i) {
    for (int j = 0; j < i; ++j) {
      const double r = 0.5 * (radius[i] + radius[j]);
      const double d[3] = {p[i][0] - p[j][0], p[i][1] - p[j][1], p[i][2] - p[j][2]};
      const double distance_sq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      if (!(distance_sq < (r + skin) * (r + skin)) || edges.count({j, i})) continue;
      all.candidates.push_back({i, j, r});
      if (!(distance_sq < r * r)) continue;
      const double overlap = r - std::sqrt(distance_sq);
      sum += overlap * overlap;
      ++all.close;
      all.wide += radius[j] > wide_radius;
    }
  }
  all.repulsion = 0.5 * sum;
  return all;
}

bool same_pairs(const std::vector<FabricEnergy::RepulsionPair>& a,
                const std::vector<FabricEnergy::RepulsionPair>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const auto& p, const auto& q) {
    return p.i == q.i && p.j == q.j && p.radius == q.radius;
  });
}

// An n x n grid with rest positions shaken by up to `shake` (so radii differ),
// plus fixed equilateral triangles of edge 1.5 (radius 1.5 / 1.3, more than
// 1.25 times any free vertex's) at the front of the fixed vertices, flat at
// each of `wide_at`.
EmbedDomain uneven_domain(int n, double shake, const std::vector<Vec3>& wide_at) {
  EmbedDomain grid = grid_domain(n);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> noise(-shake, shake);
  for (int v = grid.fixed_count; v < grid.vertex_count(); ++v) {
    for (int c = 0; c < 2; ++c) grid.rest_uv[v][c] += noise(random);
  }
  EmbedDomain domain;
  const int added = 3 * static_cast<int>(wide_at.size());
  const Vec2 corner[3] = {{0, 0}, {1.5, 0}, {0.75, 0.75 * std::sqrt(3.0)}};
  for (size_t t = 0; t < wide_at.size(); ++t) {
    const int first = static_cast<int>(domain.rest_uv.size());
    for (const Vec2& c : corner) {
      domain.rest_uv.push_back({c[0] + 10.0 * n * (t + 1), c[1]});
      domain.fixed_positions.push_back({wide_at[t][0] + c[0], wide_at[t][1] + c[1], wide_at[t][2]});
    }
    domain.faces.push_back({first, first + 1, first + 2});
  }
  domain.rest_uv.insert(domain.rest_uv.end(), grid.rest_uv.begin(), grid.rest_uv.end());
  domain.fixed_positions.insert(domain.fixed_positions.end(), grid.fixed_positions.begin(),
                                grid.fixed_positions.end());
  for (Tri t : grid.faces) {
    for (int& v : t) v += added;
    domain.faces.push_back(t);
  }
  domain.fixed_count = added + grid.fixed_count;
  domain.loop_size = grid.loop_size;
  return domain;
}

// The candidate search (a grid, plus wider searches around long-edged fixed
// vertices) against all pairs, bit for bit: on a crumpled sheet (few occupied
// cells) and on a wide wavy one (many), with fixed triangles of long edges
// lying across each, and on a crumpled sheet of equal radii (where many pairs
// are as far apart as the grid must reach). Along a path the candidates found
// at an earlier state give the energy of all pairs; a fresh object finds
// exactly all candidates.
TEST(Repulsion, CandidatesAreAllPairsWithinReach) {
  struct Sheet {
    int n;
    double shake, squeeze;  // squeeze: of x and y towards the centre
    std::vector<Vec3> wide_at;
  };
  for (const Sheet& sheet :
       {Sheet{14, 0.2, 0.3, {{4.5, 4.5, 0}, {5, 6, 0.3}}},
        Sheet{48, 0.2, 1, {{20, 20, 0}, {30, 10, 0.5}, {5, 40, -0.2}}}, Sheet{16, 0, 0.4, {}}}) {
    const EmbedDomain domain = uneven_domain(sheet.n, sheet.shake, sheet.wide_at);
    const EnergyOptions options = weights(0.1, 1, BendingModel::Quadratic);
    const FabricEnergy reused(domain, options);
    const double centre = 0.5 * (sheet.n - 1);
    Eigen::VectorXd start(3 * domain.free_count());
    for (int v = 0; v < domain.free_count(); ++v) {
      const Vec2& uv = domain.rest_uv[domain.fixed_count + v];
      for (int c = 0; c < 2; ++c) start[3 * v + c] = centre + sheet.squeeze * (uv[c] - centre);
      start[3 * v + 2] = 0.3 * std::sin(uv[0]) * std::cos(0.7 * uv[1]);
    }
    const Eigen::VectorXd end = perturbed(start, 0.5, 13);
    int close = 0, wide = 0;
    for (int k = 0; k <= 10; ++k) {
      const Eigen::VectorXd x = start + (k / 10.0) * (end - start);
      const AllPairs all = all_pairs(reused, x, 1.4 / 1.3);
      EXPECT_EQ(reused.evaluate(x).repulsion, all.repulsion) << sheet.n << " step " << k;
      const FabricEnergy fresh(domain, options);
      EXPECT_EQ(fresh.evaluate(x).repulsion, all.repulsion) << sheet.n << " step " << k;
      EXPECT_TRUE(same_pairs(fresh.repulsion_candidates(), all.candidates))
          << sheet.n << " step " << k;
      close += all.close;
      wide += all.wide;
    }
    EXPECT_GT(close, 100) << sheet.n;
    EXPECT_EQ(wide > 0, !sheet.wide_at.empty()) << sheet.n;
  }
}

// Far-flung points (as a diverging line search tries) keep every close pair:
// cell coordinates saturate rather than wrap or collide.
TEST(Repulsion, FarPointsKeepTheirClosePairs) {
  const EmbedDomain domain = uneven_domain(8, 0.2, {{2, 2, 0}});
  for (double far : {1e6, 1e12, 1e20, -1e300}) {
    const FabricEnergy energy(domain, weights(0, 1, BendingModel::Quadratic));
    Eigen::VectorXd x = perturbed(embedded_variables(domain, flat), 0.3, 17);
    // Two free vertices not joined by an edge (the first and the last) 0.1
    // apart far away; the same point beyond 1e16.
    const Eigen::Index last = x.size() - 3;
    x.segment<3>(0) << far, far, far;
    x.segment<3>(last) << far, far, far + 0.1;
    const AllPairs all = all_pairs(energy, x, 1.4 / 1.3);
    EXPECT_EQ(energy.evaluate(x).repulsion, all.repulsion) << far;
    EXPECT_TRUE(same_pairs(energy.repulsion_candidates(), all.candidates)) << far;
    EXPECT_GT(all.close, 0) << far;
  }
}

TEST(QuadraticBending, HessianIsSymmetricPositiveSemidefinite) {
  const EmbedDomain domain = grid_domain(7);
  const FabricEnergy energy(domain, {});
  const Eigen::SparseMatrix<double>& hessian = energy.bending_hessian();
  ASSERT_EQ(hessian.rows(), domain.vertex_count());
  ASSERT_GT(hessian.nonZeros(), 0);
  const Eigen::SparseMatrix<double> transpose = hessian.transpose();
  EXPECT_EQ((hessian - transpose).norm(), 0);
  std::mt19937 random(11);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::VectorXd v(hessian.rows());
    for (Eigen::Index k = 0; k < v.size(); ++k) v[k] = normal(random);
    EXPECT_GE(v.dot(hessian * v), -1e-12 * v.squaredNorm());
  }
  // Affine functions of the rest state (flat states) are in its kernel.
  Eigen::VectorXd u(hessian.rows()), ones = Eigen::VectorXd::Ones(hessian.rows());
  for (int v = 0; v < domain.vertex_count(); ++v) u[v] = domain.rest_uv[v][0];
  EXPECT_LT((hessian * u).norm(), 1e-12);
  EXPECT_LT((hessian * ones).norm(), 1e-12);
  EXPECT_EQ(FabricEnergy(domain, weights(1, 0, BendingModel::TwoRing)).bending_hessian().size(), 0);
}

TEST(Energy, EvaluationIsDeterministic) {
  const SqueezedCase squeezed;
  const FabricEnergy energy(squeezed.domain, weights(0.2, 0.5, BendingModel::Quadratic));
  const FabricEnergy twin(squeezed.domain, weights(0.2, 0.5, BendingModel::Quadratic));
  Eigen::VectorXd g1, g2, g3;
  const EnergyTerms t1 = energy.evaluate(squeezed.x, &g1);
  const EnergyTerms t2 = energy.evaluate(squeezed.x, &g2);
  const EnergyTerms t3 = twin.evaluate(squeezed.x, &g3);
  EXPECT_EQ(t1.total, t2.total);
  EXPECT_EQ(t1.repulsion, t3.repulsion);
  EXPECT_EQ(t1.total, t3.total);
  EXPECT_TRUE(g1 == g2);
  EXPECT_TRUE(g1 == g3);
  EXPECT_EQ(energy.evaluate(squeezed.x).total, t1.total);  // with or without gradient
}

TEST(Energy, SpringsCoverEdgesWithAFreeEnd) {
  const EmbedDomain domain = grid_domain(5);
  const FabricEnergy energy(domain, {});
  // A 5 x 5 grid has 4 * 5 * 2 + 16 = 56 edges, 16 of them on the fixed boundary ring.
  EXPECT_EQ(energy.springs().size(), 40u);
  for (const auto& s : energy.springs()) {
    EXPECT_TRUE(s.i >= domain.fixed_count || s.j >= domain.fixed_count);
    const double du = domain.rest_uv[s.i][0] - domain.rest_uv[s.j][0];
    const double dv = domain.rest_uv[s.i][1] - domain.rest_uv[s.j][1];
    EXPECT_DOUBLE_EQ(s.rest_length, std::hypot(du, dv));
  }
}

TEST(Energy, PositionsAndVariablesRoundTrip) {
  const BentCase bent;
  const FabricEnergy energy(bent.domain, {});
  const std::vector<Vec3> positions = energy.positions(bent.x);
  ASSERT_EQ(static_cast<int>(positions.size()), bent.domain.vertex_count());
  EXPECT_EQ(positions[0], bent.domain.fixed_positions[0]);
  EXPECT_EQ(positions[bent.domain.fixed_count][1], bent.x[1]);
  EXPECT_TRUE(energy.variables(positions) == bent.x);
}

// A diverged solver state must give a non-finite energy, not a crash or a hang.
TEST(Energy, NonFinitePositionsGiveNonFiniteEnergy) {
  const BentCase bent;
  const FabricEnergy energy(bent.domain, weights(0.1, 0.1, BendingModel::Quadratic));
  for (double bad : {std::nan(""), HUGE_VAL, 1e300}) {
    Eigen::VectorXd x = bent.x, g;
    x[4] = bad;
    EXPECT_FALSE(std::isfinite(energy.evaluate(x, &g).total)) << bad;
  }
}

TEST(Energy, RejectsBadInput) {
  const EmbedDomain domain = grid_domain(4);
  const FabricEnergy energy(domain, {});
  EXPECT_THROW(energy.evaluate(Eigen::VectorXd::Zero(5)), Error);
  EnergyOptions negative;
  negative.lambda = -1;
  try {
    FabricEnergy(domain, negative);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Usage);
  }
  EmbedDomain flipped = domain;
  std::swap(flipped.faces[3][1], flipped.faces[3][2]);
  try {
    FabricEnergy(flipped, {});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::FillFailed);
  }
}

}  // namespace
}  // namespace foldfill
