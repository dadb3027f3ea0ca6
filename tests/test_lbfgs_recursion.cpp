// The fused two-loop recursion against the textbook's loops.
#include <gtest/gtest.h>

#include <deque>
#include <random>
#include <vector>

#include "embed/lbfgs_recursion.h"

namespace foldfill {
namespace {

using Eigen::VectorXd;

// Nocedal & Wright, algorithm 7.4, with gamma P^-1 as the initial inverse
// Hessian applied as P^-1 g - sum alpha_k P^-1 y_k: -H g.
VectorXd textbook_direction(const std::deque<CurvaturePair>& pairs, double gamma,
                            const VectorXd& gradient, const VectorXd& preconditioned) {
  const int count = static_cast<int>(pairs.size());
  std::vector<double> alpha(count);
  VectorXd q = gradient, d = preconditioned;
  for (int m = count; m-- > 0;) {
    alpha[m] = pairs[m].rho * pairs[m].s.dot(q);
    q -= alpha[m] * pairs[m].y;
    d -= alpha[m] * pairs[m].preconditioned_y;
  }
  d *= gamma;
  for (int m = 0; m < count; ++m) d += (alpha[m] - pairs[m].rho * pairs[m].y.dot(d)) * pairs[m].s;
  return -d;
}

TEST(LbfgsRecursion, MatchesTheTextbookLoops) {
  std::mt19937 random(7);
  std::normal_distribution<double> normal;
  // Sizes around the four-wide blocks of the passes, and 1 to 10 pairs.
  for (const int size : {3, 6, 9, 12, 15, 300, 3001 * 3}) {
    for (int count = 1; count <= 10; count += 3) {
      SCOPED_TRACE(testing::Message() << size << " variables, " << count << " pairs");
      auto random_vector = [&] {
        VectorXd v(size);
        for (double& c : v) c = normal(random);
        return v;
      };
      std::deque<CurvaturePair> pairs(count);
      for (CurvaturePair& pair : pairs) {
        pair.s = random_vector();
        pair.y = pair.s + 0.3 * random_vector();
        pair.preconditioned_y = 0.5 * pair.y + 0.1 * random_vector();
        pair.rho = 1 / pair.s.dot(pair.y);
      }
      const VectorXd gradient = random_vector();
      const VectorXd preconditioned = 0.5 * gradient + 0.1 * random_vector();
      const double gamma = 0.7;

      std::vector<double> alpha;
      VectorXd q, direction;
      const double slope =
          two_loop_recursion(pairs, gamma, gradient, preconditioned, alpha, q, direction);
      const VectorXd expected = textbook_direction(pairs, gamma, gradient, preconditioned);
      EXPECT_LT((direction - expected).norm(), 1e-12 * expected.norm());
      EXPECT_NEAR(slope, expected.dot(gradient), 1e-12 * std::abs(expected.dot(gradient)));
    }
  }
}

}  // namespace
}  // namespace foldfill
