// A sparse symmetric positive definite system factored once and solved for
// the three coordinates of every vertex at once (internal to the embed layer:
// ARAP's global step and the solver's preconditioner).
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "foldfill/error.h"

namespace foldfill {

// Right-hand sides and solutions are n x 3, row-major (x, y, z of a vertex
// contiguous), the layout of the solver's variables. Eigen's own solve walks
// the factor once per column; this one walks it once for all three, which
// halves the time of a solve on patches of a few thousand vertices and more.
class CoordinateLdlt {
 public:
  using Coordinates = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

  // Throws Error(FillFailed, failure) when `matrix` cannot be factored.
  CoordinateLdlt(const Eigen::SparseMatrix<double>& matrix, const char* failure) {
    ldlt_.compute(matrix);
    if (ldlt_.info() != Eigen::Success) throw Error(ErrorKind::FillFailed, failure);
    work_.resize(matrix.rows(), 3);
  }

  // solution = matrix^-1 rhs; `rhs` and `solution` may be the same object.
  template <typename Rhs, typename Solution>
  void solve(const Rhs& rhs, Solution& solution) const {
    const Eigen::Index n = work_.rows();
    const int* permutation = ldlt_.permutationP().indices().data();
    for (Eigen::Index i = 0; i < n; ++i) work_.row(permutation[i]) = rhs.row(i);
    const auto& lower = ldlt_.matrixL().nestedExpression();  // unit diagonal not stored
    const int* start = lower.outerIndexPtr();
    const int* row = lower.innerIndexPtr();
    const double* value = lower.valuePtr();
    double* y = work_.data();
    for (Eigen::Index j = 0; j < n; ++j) {  // L y = b, column by column
      const double yj[3] = {y[3 * j], y[3 * j + 1], y[3 * j + 2]};
      for (int p = start[j]; p < start[j + 1]; ++p) {
        double* yi = y + 3 * static_cast<Eigen::Index>(row[p]);
        yi[0] -= value[p] * yj[0];
        yi[1] -= value[p] * yj[1];
        yi[2] -= value[p] * yj[2];
      }
    }
    const auto& diagonal = ldlt_.vectorD();
    for (Eigen::Index j = 0; j < n; ++j) work_.row(j) /= diagonal[j];
    for (Eigen::Index j = n - 1; j >= 0; --j) {  // L^T y = D^-1 y, row by row of L^T
      double sum[3] = {y[3 * j], y[3 * j + 1], y[3 * j + 2]};
      for (int p = start[j]; p < start[j + 1]; ++p) {
        const double* yi = y + 3 * static_cast<Eigen::Index>(row[p]);
        sum[0] -= value[p] * yi[0];
        sum[1] -= value[p] * yi[1];
        sum[2] -= value[p] * yi[2];
      }
      y[3 * j] = sum[0];
      y[3 * j + 1] = sum[1];
      y[3 * j + 2] = sum[2];
    }
    for (Eigen::Index i = 0; i < n; ++i) solution.row(i) = work_.row(permutation[i]);
  }

 private:
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  mutable Coordinates work_;
};

}  // namespace foldfill
