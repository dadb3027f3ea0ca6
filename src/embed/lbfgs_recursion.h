// The two-loop recursion of L-BFGS (internal to the embed layer: the fast
// solver's search direction, solver.cpp).
#pragma once

#include <Eigen/Core>
#include <deque>
#include <vector>

namespace foldfill {

// One curvature pair of L-BFGS.
struct CurvaturePair {
  Eigen::VectorXd s, y, preconditioned_y;  // x and gradient changes, P^-1 y
  double rho = 0;                          // 1 / (y . s)
};

// direction = -H g by the two-loop recursion (Nocedal & Wright, algorithm
// 7.4) over `pairs` (oldest first, at least one) with gamma P^-1 as the
// initial inverse Hessian, where P^-1 q = P^-1 g - sum alpha_k P^-1 y_k;
// returns direction . g. Each step of either loop is one pass over the
// vectors that also forms the dot product the next step needs: the first
// loop updates q and d = P^-1 q for pair m and forms s_{m-1} . q, the second
// adds pair m's s to d and forms y_{m+1} . d: two passes per pair instead of
// the textbook's five, whose passes over the vectors weigh in a large
// patch's fill. Only the order of the dot products' sums differs from the
// textbook's: gamma, the final negation and the step's updates round alike.
double two_loop_recursion(const std::deque<CurvaturePair>& pairs, double gamma,
                          const Eigen::VectorXd& gradient, const Eigen::VectorXd& preconditioned,
                          std::vector<double>& alpha, Eigen::VectorXd& q,
                          Eigen::VectorXd& direction);

}  // namespace foldfill
