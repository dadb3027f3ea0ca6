// CoordinateCholesky against Eigen's SimplicialLDLT on weighted grid
// Laplacians plus a diagonal (the shape of ARAP's matrix and of the solver's
// preconditioner), whose supernodes have from one to dozens of columns.
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <ostream>
#include <random>
#include <vector>

#include "embed/coordinate_cholesky.h"
#include "foldfill/error.h"

namespace foldfill {
namespace {

using Coordinates = CoordinateCholesky<double>::Coordinates;

// A side x side grid whose vertices are joined to those within `reach`
// steps in x and in y, with random weights, plus `shift` (times a random
// factor) on the diagonal: symmetric positive definite for shift > 0.
Eigen::SparseMatrix<double> grid_laplacian(int side, int reach, double shift, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> weight(0.1, 1.0);
  const int n = side * side;
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<double> diagonal(n, 0.0);
  for (int a = 0; a < n; ++a) {
    for (int dy = 0; dy <= reach; ++dy) {
      for (int dx = -reach; dx <= reach; ++dx) {
        const int x = a % side + dx, y = a / side + dy;
        if ((dy == 0 && dx <= 0) || x < 0 || x >= side || y >= side) continue;
        const int b = y * side + x;
        const double w = weight(random);
        entries.emplace_back(a, b, -w);
        entries.emplace_back(b, a, -w);
        diagonal[a] += w;
        diagonal[b] += w;
      }
    }
  }
  for (int a = 0; a < n; ++a) entries.emplace_back(a, a, diagonal[a] + shift * weight(random));
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

Coordinates random_coordinates(Eigen::Index rows, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  Coordinates points(rows, 3);
  for (Eigen::Index k = 0; k < points.size(); ++k) points.data()[k] = normal(random);
  return points;
}

// Largest difference between CoordinateCholesky's and SimplicialLDLT's
// solutions, relative to the largest entry of the latter.
template <typename Value>
double relative_difference(const Eigen::SparseMatrix<double>& matrix, OrderingEffort effort) {
  const CoordinateCholesky<Value> factor(matrix, effort, "not positive definite");
  const Coordinates rhs = random_coordinates(matrix.rows(), 7);
  Coordinates solution(matrix.rows(), 3);
  factor.solve(rhs, solution);
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> reference(matrix);
  const Eigen::MatrixXd expected = reference.solve(Eigen::MatrixXd(rhs));
  return (solution - expected).cwiseAbs().maxCoeff() / expected.cwiseAbs().maxCoeff();
}

struct GridCase {
  int side, reach;
};

void PrintTo(const GridCase& grid, std::ostream* out) {
  *out << grid.side << " x " << grid.side << ", reach " << grid.reach;
}

class CoordinateCholeskyGrid : public ::testing::TestWithParam<GridCase> {};

TEST_P(CoordinateCholeskyGrid, DoubleFactorSolvesAsSimplicialLdlt) {
  const Eigen::SparseMatrix<double> matrix =
      grid_laplacian(GetParam().side, GetParam().reach, 0.1, 1);
  EXPECT_LT(relative_difference<double>(matrix, OrderingEffort::Quick), 1e-12);
}

TEST_P(CoordinateCholeskyGrid, FloatFactorSolvesAsSimplicialLdltToFloatPrecision) {
  const Eigen::SparseMatrix<double> matrix =
      grid_laplacian(GetParam().side, GetParam().reach, 0.1, 2);
  EXPECT_LT(relative_difference<float>(matrix, OrderingEffort::Thorough), 1e-4);
}

// From one vertex to supernodes of dozens of columns (a dense 9 x 9 grid
// is a single supernode of 81 columns), and METIS's ordering from 10k rows.
INSTANTIATE_TEST_SUITE_P(Sizes, CoordinateCholeskyGrid,
                         ::testing::Values(GridCase{1, 1}, GridCase{2, 1}, GridCase{5, 2},
                                           GridCase{9, 8}, GridCase{31, 1}, GridCase{30, 2},
                                           GridCase{101, 1}));

TEST(CoordinateCholesky, SolvesInPlace) {
  const Eigen::SparseMatrix<double> matrix = grid_laplacian(12, 2, 0.1, 3);
  const CoordinateCholesky<double> factor(matrix, OrderingEffort::Quick, "not positive definite");
  const Coordinates rhs = random_coordinates(matrix.rows(), 4);
  Coordinates solution(matrix.rows(), 3);
  factor.solve(rhs, solution);
  Coordinates points = rhs;
  factor.solve(points, points);
  EXPECT_EQ(points, solution);
}

TEST(CoordinateCholesky, SolvesBlocksOfRows) {
  const Eigen::SparseMatrix<double> matrix = grid_laplacian(10, 2, 0.1, 5);
  const CoordinateCholesky<double> factor(matrix, OrderingEffort::Quick, "not positive definite");
  Coordinates rhs(matrix.rows() + 2, 3), solution(matrix.rows() + 2, 3), expected(matrix.rows(), 3);
  rhs.bottomRows(matrix.rows()) = random_coordinates(matrix.rows(), 6);
  auto rows = solution.bottomRows(matrix.rows());
  factor.solve(rhs.bottomRows(matrix.rows()), rows);
  factor.solve(Coordinates(rhs.bottomRows(matrix.rows())), expected);
  EXPECT_EQ(Coordinates(rows), expected);
  EXPECT_LT((matrix * expected - rhs.bottomRows(matrix.rows())).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(CoordinateCholesky, RefusesAMatrixThatIsNotPositiveDefinite) {
  // A Laplacian minus a positive diagonal: indefinite (the constant vector
  // has a negative energy).
  const Eigen::SparseMatrix<double> matrix = grid_laplacian(6, 1, -1, 8);
  try {
    const CoordinateCholesky<float> factor(matrix, OrderingEffort::Quick, "singular");
    FAIL() << "factored a singular matrix";
  } catch (const Error& error) {
    EXPECT_EQ(error.kind(), ErrorKind::FillFailed);
    EXPECT_STREQ(error.what(), "singular");
  }
}

}  // namespace
}  // namespace foldfill
