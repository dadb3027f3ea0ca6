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
    // Scalars in registers: stores through y may alias value[], so the
    // factor's entries are read once into locals.
    for (Eigen::Index j = 0; j < n; ++j) {  // L y = b, column by column
      const double y0 = y[3 * j], y1 = y[3 * j + 1], y2 = y[3 * j + 2];
      for (int p = start[j], end = start[j + 1]; p < end; ++p) {
        const double l = value[p];
        double* yi = y + 3 * static_cast<Eigen::Index>(row[p]);
        yi[0] -= l * y0;
        yi[1] -= l * y1;
        yi[2] -= l * y2;
      }
    }
    const auto& diagonal = ldlt_.vectorD();
    for (Eigen::Index j = 0; j < n; ++j) work_.row(j) /= diagonal[j];
    for (Eigen::Index j = n - 1; j >= 0; --j) {  // L^T y = D^-1 y, row by row of L^T
      double s0 = y[3 * j], s1 = y[3 * j + 1], s2 = y[3 * j + 2];
      for (int p = start[j], end = start[j + 1]; p < end; ++p) {
        const double l = value[p];
        const double* yi = y + 3 * static_cast<Eigen::Index>(row[p]);
        s0 -= l * yi[0];
        s1 -= l * yi[1];
        s2 -= l * yi[2];
      }
      y[3 * j] = s0;
      y[3 * j + 1] = s1;
      y[3 * j + 2] = s2;
    }
    for (Eigen::Index i = 0; i < n; ++i) solution.row(i) = work_.row(permutation[i]);
  }

 private:
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  mutable Coordinates work_;
};

}  // namespace foldfill
