// A sparse symmetric positive definite system factored once and solved for
// the three coordinates of every vertex at once (internal to the embed layer:
// ARAP's global step and the solver's preconditioner).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstddef>
#include <vector>

namespace foldfill {

// How hard to look for a fill-reducing ordering: AMD alone (Quick), or also
// METIS on matrices of 10k rows and more, keeping the ordering whose
// factorisation takes fewer flops (Thorough). METIS's analysis costs much
// more than AMD's; its smaller factor pays that back over the hundreds of
// solves of a minimisation on large matrices, not over ARAP's 30 iterations.
enum class OrderingEffort { Quick, Thorough };

// A Cholesky factor P A P^T = L L^T computed by CHOLMOD (supernodal, with
// AMD's or METIS's fill-reducing ordering), kept in its own arrays and solved
// by the loops of coordinate_cholesky.cpp rather than by CHOLMOD's solve.
// Right-hand sides and solutions are n x 3, row-major (x, y, z of a vertex
// contiguous), the layout of the solver's variables; one pass over the
// factor serves all three columns. `Value` is the type the factor's entries
// are kept in: double, or float where an approximate inverse will do (the
// solver's preconditioner), which halves the memory a solve streams through.
// The arithmetic is double either way. Results do not depend on the number
// of threads (see coordinate_cholesky.cpp).
template <typename Value>
class CoordinateCholesky {
 public:
  using Coordinates = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

  // Throws FillFailedError(failure) when `matrix` cannot be factored (it
  // is not positive definite).
  CoordinateCholesky(const Eigen::SparseMatrix<double>& matrix, OrderingEffort effort,
                     const char* failure);

  // solution = matrix^-1 rhs; `rhs` and `solution` may be the same object.
  template <typename Rhs, typename Solution>
  void solve(const Rhs& rhs, Solution& solution) const {
    const size_t n = work_.size();
    for (size_t k = 0; k < n; ++k) {
      const Eigen::Index from = permutation_[k];
      work_[k] = Point(rhs(from, 0), rhs(from, 1), rhs(from, 2), 0);
    }
    solve_permuted();
    for (size_t k = 0; k < n; ++k)
      for (int c = 0; c < 3; ++c) solution(permutation_[k], c) = work_[k][c];
  }

 private:
  // x, y, z of a vertex and a zero, so that the arithmetic on a point runs
  // on two pairs of doubles (SSE2's width) rather than on three doubles.
  using Point = Eigen::Array4d;

  // Rows [begin, end) of a supernode, counted from its first row.
  struct RowRun {
    int begin, end;
  };

  // Row k of the factored system is row permutation_[k] of the matrix.
  std::vector<int> permutation_;
  // Supernode s: columns [first_column_[s], first_column_[s + 1]), rows
  // rows_[pattern_start_[s] ...  pattern_start_[s + 1]) (the columns first),
  // and its block in panels of four columns (fewer in the last), panels
  // [first_panel_[s], first_panel_[s + 1]).
  std::vector<int> first_column_, pattern_start_, rows_, first_panel_;
  // Panel p: from values_[panel_value_start_[p]], row after row, the strict
  // lower triangle of its diagonal block (the diagonal is in
  // inverse_diagonal_), then the rows below it, all of the panel's columns,
  // but only those of the runs nonzero_runs_[run_start_[p] ...
  // run_start_[p + 1]): CHOLMOD's relaxed supernodes keep explicit zeros,
  // and whole rows of a panel that are zero (a sizeable share of the
  // entries) are left out of the solves. That changes no
  // result for finite right-hand sides (the solver's gradients, ARAP's
  // rotated edges): 0 x is then a zero, and subtracting a zero changes no
  // value (at most the sign of a zero: -0 - -0 = +0).
  std::vector<std::ptrdiff_t> panel_value_start_;
  std::vector<int> run_start_;
  std::vector<RowRun> nonzero_runs_;
  std::vector<Value> values_;
  std::vector<double> inverse_diagonal_;  // 1 / L(k, k)
  mutable std::vector<Point> work_;
  mutable std::vector<Point> buffer_;  // the rows of one supernode

  // work_ = (L L^T)^-1 work_.
  void solve_permuted() const;
  // Supernode s's part of L y = b, and of L^T x = y, on its rows gathered
  // into buffer_.
  void forward_supernode(int s) const;
  void backward_supernode(int s) const;
};

extern template class CoordinateCholesky<double>;
extern template class CoordinateCholesky<float>;

}  // namespace foldfill
