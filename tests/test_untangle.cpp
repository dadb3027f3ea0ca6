// Untangling a start that crosses something (untangle.h): the crossing
// curves' length and its gradient against finite differences, and patches
// pushed out of layers and spikes they were placed through until, by the
// exact test, nothing crosses.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "foldfill/arap.h"
#include "foldfill/contact.h"
#include "foldfill/metrics.h"
#include "foldfill/untangle.h"
#include "foldfill/vec3.h"
#include "lattice_domain.h"

namespace foldfill {
namespace {

EnergyOptions weights() {
  EnergyOptions options;
  options.lambda = 2e-4;
  return options;
}

// A flat square layer of cloth over the patch at height z (normalised units).
PatchScene layer_at(const EmbedDomain& domain, double z) {
  return testing::flat_layer(domain, z, 20);
}

// A thin four-sided spike from z = -3 up to its tip at (x, y, tip).
PatchScene spike_at(const EmbedDomain& domain, double x, double y, double tip) {
  PatchScene scene;
  const int first = domain.fixed_count;
  const double r = 0.6;
  scene.positions = {
      {x, y, tip}, {x - r, y - r, -3}, {x + r, y - r, -3}, {x + r, y + r, -3}, {x - r, y + r, -3}};
  for (int k = 0; k < 4; ++k)
    scene.faces.push_back({first, first + 1 + k, first + 1 + (k + 1) % 4});
  return scene;
}

double highest(const std::vector<Vec3>& positions) {
  double z = -1e9;
  for (const Vec3& p : positions) z = std::max(z, p[2]);
  return z;
}

TEST(Untangle, CurveLengthGradientMatchesFiniteDifferences) {
  // A bumpy patch through a layer at half its height: many crossing curves.
  const EmbedDomain domain = testing::lattice_domain(14, 12, [](const Vec2& uv) {
    return Vec3{0.7 * uv[0], 0.7 * uv[1], 0.3 * std::sin(uv[0]) * std::cos(0.8 * uv[1])};
  });
  const FabricEnergy energy(domain, weights());
  std::vector<Vec3> start = arap_embed(domain, {0.5, 30});
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  for (int v = domain.fixed_count; v < domain.vertex_count(); ++v) start[v][2] += jitter(random);
  const PatchContact contact(domain, layer_at(domain, 0.5 * highest(start)), {});
  const Eigen::VectorXd x = energy.variables(start);
  const std::vector<std::pair<int, int>> pairs = crossing_pairs(contact, x);
  ASSERT_GT(pairs.size(), 10u) << "the case does not test anything";
  Eigen::VectorXd gradient = Eigen::VectorXd::Zero(x.size());
  const double length = crossing_curve_length(contact, pairs, x, &gradient);
  EXPECT_GT(length, 1);
  EXPECT_GT(gradient.norm(), 0);
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd direction(x.size());
    for (Eigen::Index k = 0; k < x.size(); ++k) direction[k] = jitter(random);
    const double h = 1e-7;
    const double numeric = (crossing_curve_length(contact, pairs, x + h * direction, nullptr) -
                            crossing_curve_length(contact, pairs, x - h * direction, nullptr)) /
                           (2 * h);
    EXPECT_NEAR(gradient.dot(direction), numeric, 1e-5 * (1 + std::abs(numeric))) << trial;
  }
}

TEST(Untangle, PairsThatDoNotCrossAddNothing) {
  const EmbedDomain domain = testing::lattice_domain(10, 10, [](const Vec2& uv) {
    return Vec3{uv[0], uv[1], 0};
  });
  const FabricEnergy energy(domain, weights());
  const std::vector<Vec3> flat = arap_embed(domain, {1, 30});
  // The layer well above the flat patch: no pair crosses, the curves are empty.
  const PatchContact contact(domain, layer_at(domain, 2), {});
  const Eigen::VectorXd x = energy.variables(flat);
  EXPECT_TRUE(crossing_pairs(contact, x).empty());
  Eigen::VectorXd gradient = Eigen::VectorXd::Zero(x.size());
  EXPECT_EQ(
      crossing_curve_length(contact, {{domain.strip_face_count, contact.mesh().faces.size() - 1}},
                            x, &gradient),
      0.0);
  EXPECT_EQ(gradient.norm(), 0.0);
  // A clean start comes back as it is.
  const std::optional<Eigen::VectorXd> same = untangle(energy, contact, x, {}, {});
  ASSERT_TRUE(same.has_value());
  EXPECT_EQ(*same, x);
}

TEST(Untangle, ASpikeThroughTheFlatPatchEndsUnderIt) {
  const EmbedDomain domain = testing::lattice_domain(14, 12, [](const Vec2& uv) {
    return Vec3{uv[0], uv[1], 0};
  });
  const FabricEnergy energy(domain, weights());
  const std::vector<Vec3> flat = arap_embed(domain, {1, 30});
  Vec3 middle{0, 0, 0};
  for (const Vec3& p : domain.fixed_positions) middle = add(middle, p);
  middle = scaled(middle, 1.0 / domain.fixed_positions.size());
  const double tip = 0.8;
  const PatchContact contact(domain, spike_at(domain, middle[0], middle[1], tip), {});
  const Eigen::VectorXd x = energy.variables(flat);
  ASSERT_FALSE(crossing_pairs(contact, x).empty()) << "the case does not test anything";
  const std::optional<Eigen::VectorXd> untangled = untangle(energy, contact, x, {}, {});
  ASSERT_TRUE(untangled.has_value());
  EXPECT_TRUE(crossing_pairs(contact, *untangled).empty());
  EXPECT_TRUE(std::isfinite(contact.evaluate(*untangled, nullptr)));
  // The patch went over the tip, not through it.
  EXPECT_GT(highest(energy.positions(*untangled)), tip);
}

// A flat strip at z = 0 whose patch's bumps pass through a layer at 0.25
// over all of it.
struct BumpyPatch {
  static constexpr double kLayer = 0.25;
  EmbedDomain domain = testing::lattice_domain(16, 14, [](const Vec2& uv) {
    return Vec3{0.8 * uv[0], 0.8 * uv[1], 0};
  });
  FabricEnergy energy{domain, weights()};
  PatchContact contact{domain, layer_at(domain, kLayer), {}};
  Eigen::VectorXd start() const {
    std::vector<Vec3> positions = arap_embed(domain, {0.5, 30});
    for (int v = domain.fixed_count; v < domain.vertex_count(); ++v)
      positions[v][2] = 0.6 * std::sin(positions[v][0]) * std::sin(positions[v][1]);
    return energy.variables(positions);
  }
};

TEST(Untangle, ABumpyPatchThroughALayerEndsBelowIt) {
  // The bumps must come back under the layer.
  const BumpyPatch patch;
  const FabricEnergy& energy = patch.energy;
  const PatchContact& contact = patch.contact;
  const double layer = BumpyPatch::kLayer;
  const Eigen::VectorXd x = patch.start();
  ASSERT_GT(crossing_pairs(contact, x).size(), 10u) << "the case does not test anything";
  const std::optional<Eigen::VectorXd> untangled = untangle(energy, contact, x, {}, {});
  ASSERT_TRUE(untangled.has_value());
  EXPECT_TRUE(crossing_pairs(contact, *untangled).empty());
  EXPECT_LT(highest(energy.positions(*untangled)), layer);
}

// Each round's minimisation stops on the untangling's own tolerance
// (UntangleOptions::relative_energy_tol), not on the fill solver's default:
// a looser one cuts the rounds short and the patch ends elsewhere.
TEST(Untangle, ARoundStopsOnItsOwnTolerance) {
  const BumpyPatch patch;
  const FabricEnergy& energy = patch.energy;
  const PatchContact& contact = patch.contact;
  const Eigen::VectorXd x = patch.start();
  const std::optional<Eigen::VectorXd> strict = untangle(energy, contact, x, {}, {});
  UntangleOptions loose;
  loose.relative_energy_tol = 1e-1;
  const std::optional<Eigen::VectorXd> cut_short = untangle(energy, contact, x, loose, {});
  ASSERT_TRUE(strict.has_value() && cut_short.has_value());
  EXPECT_GT((*strict - *cut_short).lpNorm<Eigen::Infinity>(), 1e-6);
  EXPECT_TRUE(crossing_pairs(contact, *cut_short).empty());
}

// The crossing pairs are the crossings count_subset_crossings counts, each
// once, its patch face first, sorted, wherever the patch moves.
TEST(Untangle, CrossingPairsAreEveryCrossingOnce) {
  const EmbedDomain domain = testing::lattice_domain(14, 12, [](const Vec2& uv) {
    return Vec3{0.7 * uv[0], 0.7 * uv[1], 0.3 * std::sin(uv[0]) * std::cos(0.8 * uv[1])};
  });
  const FabricEnergy energy(domain, weights());
  std::vector<Vec3> start = arap_embed(domain, {0.5, 30});
  const PatchContact contact(domain, layer_at(domain, 0.5 * highest(start)), {});
  const int first = contact.first_patch_face(), end = contact.end_patch_face();
  std::vector<int> patch(end - first);
  std::iota(patch.begin(), patch.end(), first);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> jitter(-0.4, 0.4);
  size_t found = 0;
  for (int trial = 0; trial < 4; ++trial) {
    for (int v = domain.fixed_count; v < domain.vertex_count(); ++v) start[v][2] += jitter(random);
    const Eigen::VectorXd x = energy.variables(start);
    const auto pairs = crossing_pairs(contact, x);
    const SubsetCrossings counted =
        count_subset_crossings(contact.positions(x), contact.mesh().faces, patch, 0.0);
    EXPECT_EQ(static_cast<int>(pairs.size()), counted.within + counted.with_others) << trial;
    EXPECT_TRUE(std::is_sorted(pairs.begin(), pairs.end())) << trial;
    EXPECT_TRUE(std::adjacent_find(pairs.begin(), pairs.end()) == pairs.end()) << trial;
    for (const auto& [f, g] : pairs) {
      EXPECT_TRUE(f >= first && f < end) << trial;
      if (g >= first && g < end) {
        EXPECT_LT(f, g) << trial;
      }
    }
    found += pairs.size();
  }
  EXPECT_GT(found, 0u) << "the case does not test anything";
}

}  // namespace
}  // namespace foldfill
