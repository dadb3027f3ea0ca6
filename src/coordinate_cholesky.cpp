// CHOLMOD's supernodal Cholesky factorisation behind CoordinateCholesky.
//
// Why CHOLMOD (measurements in docs/scale.md): Eigen's SimplicialLDLT, used
// before, factors column by column; on the preconditioner of a 120k-vertex
// patch with its bending block it took 5.5 to 7 s of CPU. CHOLMOD's
// supernodal factorisation works on dense blocks with the BLAS: 0.6 s with
// AMD's ordering, 1.2 s with METIS's (nested dissection), whose factor holds
// 106 entries per vertex instead of 153, so that each solve is cheaper.
//
// Determinism: the factor must not depend on the number of threads filling
// holes at once, nor on their timing. So factorisations run one at a time
// (they take a small part of a fill: 0.2 s of the 5 s of a 30k-vertex one):
// - METIS draws its random numbers from the C library's rand(), whose state
//   is global (it reseeds at each call): two analyses at once would share
//   the stream and could order differently;
// - the BLAS must be single-threaded (scripts/setup.sh installs OpenBLAS's
//   serial variant; a threaded OpenBLAS is told to use one thread), and
//   OpenBLAS's serial builds need not be safe to call from two threads;
// - CHOLMOD's supernodal factorisation opens OpenMP parallel regions of its
//   own (4 threads, compiled in) for its copies: outside the holes' parallel
//   loop they oversubscribed the cores, and the calling thread spun at their
//   barriers (half the time of a 2k-vertex fill on 2 loaded cores), so they
//   run with no active level (the setting is restored after).
#include "coordinate_cholesky.h"

#include <cholmod.h>
#include <omp.h>

#include <algorithm>
#include <mutex>
#include <new>

#include "foldfill/error.h"

// Defined by OpenBLAS (any variant), absent from other BLAS libraries.
extern "C" void openblas_set_num_threads(int) __attribute__((weak));

namespace foldfill {
namespace {

// Below this many rows METIS's factor is hardly smaller than AMD's (71
// instead of 86 entries per row on a 10k preconditioner, 30 instead of 34
// without the bending block) and its analysis costs more than it saves.
constexpr Eigen::Index kSmallestMetisOrdering = 10000;

std::mutex& factorisation_mutex() {
  static std::mutex mutex;
  return mutex;
}

void use_one_blas_thread() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (openblas_set_num_threads) openblas_set_num_threads(1);
  });
}

// CHOLMOD's workspace and factor, freed on every path.
class CholmodFactor {
 public:
  CholmodFactor(OrderingEffort effort, Eigen::Index rows) {
    cholmod_start(&common_);
    common_.print = 0;  // failures are reported by exceptions
    common_.supernodal = CHOLMOD_SUPERNODAL;
    // Chosen here rather than by CHOLMOD's default, which tries METIS only
    // when AMD fills in very much: it never judged so on these meshes,
    // although METIS's factors are the smaller from about 10k vertices on
    // (20% faster solves at 120k).
    const bool try_metis = effort == OrderingEffort::Thorough && rows >= kSmallestMetisOrdering;
    common_.nmethods = try_metis ? 2 : 1;
    common_.method[0].ordering = CHOLMOD_AMD;
    common_.method[1].ordering = CHOLMOD_METIS;
  }
  ~CholmodFactor() {
    cholmod_free_factor(&factor_, &common_);
    cholmod_finish(&common_);
  }
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  // Returns the factor of `matrix`, or null when it is not positive definite.
  const cholmod_factor* factor(const Eigen::SparseMatrix<double>& matrix) {
    cholmod_sparse a = upper_triangle_view(matrix);
    const std::lock_guard<std::mutex> lock(factorisation_mutex());
    factor_ = cholmod_analyze(&a, &common_);
    if (factor_) {
      const int active_levels = omp_get_max_active_levels();
      omp_set_max_active_levels(0);  // CHOLMOD's regions get one thread
      cholmod_factorize(&a, factor_, &common_);
      omp_set_max_active_levels(active_levels);
    }
    if (common_.status == CHOLMOD_OUT_OF_MEMORY) throw std::bad_alloc();
    const bool factored = factor_ && common_.status == CHOLMOD_OK && factor_->minor == factor_->n;
    return factored ? factor_ : nullptr;
  }

 private:
  cholmod_common common_;
  cholmod_factor* factor_ = nullptr;

  // `matrix` as CHOLMOD sees it, without a copy: only its upper triangle is read.
  static cholmod_sparse upper_triangle_view(const Eigen::SparseMatrix<double>& matrix) {
    cholmod_sparse view{};
    view.nrow = static_cast<size_t>(matrix.rows());
    view.ncol = static_cast<size_t>(matrix.cols());
    view.nzmax = static_cast<size_t>(matrix.nonZeros());
    view.p = const_cast<int*>(matrix.outerIndexPtr());
    view.i = const_cast<int*>(matrix.innerIndexPtr());
    view.nz = const_cast<int*>(matrix.innerNonZeroPtr());
    view.x = const_cast<double*>(matrix.valuePtr());
    view.stype = 1;
    view.itype = CHOLMOD_INT;
    view.xtype = CHOLMOD_REAL;
    view.dtype = CHOLMOD_DOUBLE;
    view.sorted = 1;
    view.packed = matrix.isCompressed();
    return view;
  }
};

std::vector<int> copy_ints(const void* data, size_t count) {
  const int* begin = static_cast<const int*>(data);
  return std::vector<int>(begin, begin + count);
}

}  // namespace

template <typename Value>
CoordinateCholesky<Value>::CoordinateCholesky(const Eigen::SparseMatrix<double>& matrix,
                                              OrderingEffort effort, const char* failure)
    : work_(matrix.rows(), 3) {
  use_one_blas_thread();
  CholmodFactor cholmod(effort, matrix.rows());
  const cholmod_factor* l = cholmod.factor(matrix);
  if (!l) throw Error(ErrorKind::FillFailed, failure);
  const size_t supernodes = l->nsuper;
  permutation_ = copy_ints(l->Perm, l->n);
  first_column_ = copy_ints(l->super, supernodes + 1);
  pattern_start_ = copy_ints(l->pi, supernodes + 1);
  rows_ = copy_ints(l->s, static_cast<size_t>(pattern_start_[supernodes]));
  // CHOLMOD keeps each supernode's whole rectangle, the zeros above the
  // diagonal included; only the lower triangle is copied.
  const int* cholmod_value_start = static_cast<const int*>(l->px);
  const double* cholmod_values = static_cast<const double*>(l->x);
  value_start_.resize(supernodes + 1);
  value_start_[0] = 0;
  size_t tallest = 0;
  for (size_t s = 0; s < supernodes; ++s) {
    const std::ptrdiff_t columns = first_column_[s + 1] - first_column_[s];
    const std::ptrdiff_t row_count = pattern_start_[s + 1] - pattern_start_[s];
    value_start_[s + 1] = value_start_[s] + columns * row_count - columns * (columns - 1) / 2;
    tallest = std::max(tallest, static_cast<size_t>(row_count));
  }
  values_.reserve(static_cast<size_t>(value_start_[supernodes]));
  for (size_t s = 0; s < supernodes; ++s) {
    const int columns = first_column_[s + 1] - first_column_[s];
    const int row_count = pattern_start_[s + 1] - pattern_start_[s];
    for (int j = 0; j < columns; ++j) {
      const double* column =
          cholmod_values + cholmod_value_start[s] + static_cast<std::ptrdiff_t>(j) * row_count;
      for (int i = j; i < row_count; ++i) values_.push_back(static_cast<Value>(column[i]));
    }
  }
  buffer_.resize(3 * tallest);
}

// L y = b, then L^T x = y, supernode by supernode. Each supernode gathers
// the rows of work_ it touches into a small contiguous buffer, works on
// that, and scatters them back: work_ is read and written once per
// supernode instead of once per entry of the factor, and the inner loops
// run over contiguous memory.
template <typename Value>
void CoordinateCholesky<Value>::solve_permuted() const {
  double* y = work_.data();
  double* buffer = buffer_.data();
  const int supernodes = static_cast<int>(first_column_.size()) - 1;
  auto gather = [&](const int* row, int count) {
    for (int i = 0; i < count; ++i)
      for (int c = 0; c < 3; ++c)
        buffer[3 * i + c] = y[3 * static_cast<std::ptrdiff_t>(row[i]) + c];
  };
  auto scatter = [&](const int* row, int count) {
    for (int i = 0; i < count; ++i)
      for (int c = 0; c < 3; ++c)
        y[3 * static_cast<std::ptrdiff_t>(row[i]) + c] = buffer[3 * i + c];
  };
  // Column j of a supernode with r rows starts j r - j (j - 1) / 2 values
  // into its block and holds rows j .. r - 1.
  auto column_of = [&](int s, int j, int row_count) {
    return values_.data() + value_start_[s] + static_cast<std::ptrdiff_t>(j) * row_count -
           static_cast<std::ptrdiff_t>(j) * (j - 1) / 2;
  };
  for (int s = 0; s < supernodes; ++s) {
    const int columns = first_column_[s + 1] - first_column_[s];
    const int row_count = pattern_start_[s + 1] - pattern_start_[s];
    const int* row = rows_.data() + pattern_start_[s];
    gather(row, row_count);
    for (int j = 0; j < columns; ++j) {
      const Value* column = column_of(s, j, row_count) - j;  // column[i]: row i
      const double inverse = 1 / static_cast<double>(column[j]);
      const double x0 = buffer[3 * j] * inverse, x1 = buffer[3 * j + 1] * inverse,
                   x2 = buffer[3 * j + 2] * inverse;
      buffer[3 * j] = x0;
      buffer[3 * j + 1] = x1;
      buffer[3 * j + 2] = x2;
      for (int i = j + 1; i < row_count; ++i) {
        const double entry = column[i];
        buffer[3 * i] -= entry * x0;
        buffer[3 * i + 1] -= entry * x1;
        buffer[3 * i + 2] -= entry * x2;
      }
    }
    scatter(row, row_count);
  }
  for (int s = supernodes - 1; s >= 0; --s) {
    const int columns = first_column_[s + 1] - first_column_[s];
    const int row_count = pattern_start_[s + 1] - pattern_start_[s];
    const int* row = rows_.data() + pattern_start_[s];
    gather(row, row_count);
    for (int j = columns - 1; j >= 0; --j) {
      const Value* column = column_of(s, j, row_count) - j;
      double s0 = buffer[3 * j], s1 = buffer[3 * j + 1], s2 = buffer[3 * j + 2];
      for (int i = j + 1; i < row_count; ++i) {
        const double entry = column[i];
        s0 -= entry * buffer[3 * i];
        s1 -= entry * buffer[3 * i + 1];
        s2 -= entry * buffer[3 * i + 2];
      }
      const double inverse = 1 / static_cast<double>(column[j]);
      buffer[3 * j] = s0 * inverse;
      buffer[3 * j + 1] = s1 * inverse;
      buffer[3 * j + 2] = s2 * inverse;
    }
    scatter(row, columns);
  }
}

template class CoordinateCholesky<double>;
template class CoordinateCholesky<float>;

}  // namespace foldfill
