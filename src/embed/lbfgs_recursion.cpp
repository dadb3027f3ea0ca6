#include "embed/lbfgs_recursion.h"

namespace foldfill {

using Eigen::VectorXd;

namespace {

// The passes of two_loop_recursion over flat arrays: element i of q and d
// stays in registers between the operations on it, and the dot product the
// next step needs is formed on the way, in four partial sums (a fixed
// order, which the compiler can vectorise; it may not reorder one sum).

// q -= a y, d -= a P^-1 y; returns next_s . q.
double subtract_pair(Eigen::Index size, double a, const double* __restrict y,
                     const double* __restrict preconditioned_y, const double* __restrict next_s,
                     double* __restrict q, double* __restrict d) {
  double sum[4] = {0, 0, 0, 0};
  Eigen::Index i = 0;
  for (; i + 4 <= size; i += 4)
    for (int k = 0; k < 4; ++k) {
      q[i + k] -= a * y[i + k];
      d[i + k] -= a * preconditioned_y[i + k];
      sum[k] += next_s[i + k] * q[i + k];
    }
  for (; i < size; ++i) {
    q[i] -= a * y[i];
    d[i] -= a * preconditioned_y[i];
    sum[0] += next_s[i] * q[i];
  }
  return (sum[0] + sum[1]) + (sum[2] + sum[3]);
}

// d = scale d + c v; returns next . d.
double scale_and_add(Eigen::Index size, double scale, double c, const double* __restrict v,
                     const double* __restrict next, double* __restrict d) {
  double sum[4] = {0, 0, 0, 0};
  Eigen::Index i = 0;
  for (; i + 4 <= size; i += 4)
    for (int k = 0; k < 4; ++k) {
      d[i + k] = scale * d[i + k] + c * v[i + k];
      sum[k] += next[i + k] * d[i + k];
    }
  for (; i < size; ++i) {
    d[i] = scale * d[i] + c * v[i];
    sum[0] += next[i] * d[i];
  }
  return (sum[0] + sum[1]) + (sum[2] + sum[3]);
}

}  // namespace

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
                          const VectorXd& gradient, const VectorXd& preconditioned,
                          std::vector<double>& alpha, VectorXd& q, VectorXd& direction) {
  const int count = static_cast<int>(pairs.size());
  const Eigen::Index size = gradient.size();
  alpha.resize(count);
  q = gradient;
  VectorXd& d = direction;
  d = preconditioned;
  // First loop, newest pair first. The oldest pair's pass leaves q alone (it
  // is not needed any more) and forms y_0 . d for the second loop.
  double s_dot_q = pairs.back().s.dot(gradient);
  for (int m = count - 1; m > 0; --m) {
    const CurvaturePair& pair = pairs[m];
    alpha[m] = pair.rho * s_dot_q;
    s_dot_q = subtract_pair(size, alpha[m], pair.y.data(), pair.preconditioned_y.data(),
                            pairs[m - 1].s.data(), q.data(), d.data());
  }
  alpha[0] = pairs[0].rho * s_dot_q;
  double y_dot_d = scale_and_add(size, 1, -alpha[0], pairs[0].preconditioned_y.data(),
                                 pairs[0].y.data(), d.data());
  // Second loop, oldest pair first; its first pass scales d by gamma, the
  // newest pair's negates the result and forms its slope along g.
  y_dot_d *= gamma;
  double scale = gamma;
  for (int m = 0; m + 1 < count; ++m) {
    const CurvaturePair& pair = pairs[m];
    const double c = alpha[m] - pair.rho * y_dot_d;
    y_dot_d = scale_and_add(size, scale, c, pair.s.data(), pairs[m + 1].y.data(), d.data());
    scale = 1;
  }
  const CurvaturePair& newest = pairs.back();
  const double c = alpha[count - 1] - newest.rho * y_dot_d;
  return scale_and_add(size, -scale, -c, newest.s.data(), gradient.data(), d.data());
}

}  // namespace foldfill
