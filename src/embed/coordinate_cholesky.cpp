// CHOLMOD's supernodal Cholesky factorisation behind CoordinateCholesky.
//
// Why CHOLMOD: a factorisation column by column (Eigen's SimplicialLDLT) is
// several times slower on the preconditioners of large patches than
// CHOLMOD's supernodal one, which works on dense blocks with the BLAS. With
// METIS's ordering (nested dissection) the factor holds fewer entries than
// with AMD's, so that each solve is cheaper (docs/scale.md).
//
// Determinism: the factor must not depend on the number of threads filling
// holes at once, nor on their timing. So factorisations run one at a time
// (they take a small part of a fill):
// - METIS draws its random numbers from the C library's rand(), whose state
//   is global (it reseeds at each call): two analyses at once would share
//   the stream and could order differently;
// - the BLAS must be single-threaded (scripts/setup.sh installs OpenBLAS's
//   serial variant; a threaded OpenBLAS is told to use one thread), and
//   OpenBLAS's serial builds need not be safe to call from two threads;
// - CHOLMOD's supernodal factorisation opens OpenMP parallel regions of its
//   own (4 threads, compiled in) for its copies: outside the holes' parallel
//   loop they oversubscribe the cores, and the calling thread spins at their
//   barriers (a large share of a small fill's time on loaded cores), so they
//   run with no active level (the setting is restored after).
#include "embed/coordinate_cholesky.h"

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

// Below this many rows METIS's factor is hardly smaller than AMD's, and its
// analysis costs more than it saves (docs/benchmarks.md, "Figures behind the
// code's choices").
constexpr Eigen::Index kSmallestMetisOrdering = 10000;

// Columns of a panel of the factor's blocks (see coordinate_cholesky.h): the
// forward substitution updates each row of a supernode with this many
// columns at once, loading and storing its point once for them. Four
// columns' points (eight pairs of doubles) fit in SSE2's sixteen registers.
constexpr int kPanelWidth = 4;

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
    // when AMD fills in very much: it does not judge so on these meshes,
    // although METIS's factors are the smaller from about 10k vertices on,
    // and the solves the faster.
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

// Where row i of a panel's diagonal block starts in its strict lower triangle.
constexpr int triangle_row(int i) { return i * (i - 1) / 2; }

}  // namespace

template <typename Value>
CoordinateCholesky<Value>::CoordinateCholesky(const Eigen::SparseMatrix<double>& matrix,
                                              OrderingEffort effort, const char* failure) {
  use_one_blas_thread();
  CholmodFactor cholmod(effort, matrix.rows());
  const cholmod_factor* l = cholmod.factor(matrix);
  if (!l) throw FillFailedError(failure);
  const size_t supernodes = l->nsuper;
  permutation_ = copy_ints(l->Perm, l->n);
  first_column_ = copy_ints(l->super, supernodes + 1);
  pattern_start_ = copy_ints(l->pi, supernodes + 1);
  rows_ = copy_ints(l->s, static_cast<size_t>(pattern_start_[supernodes]));
  // CHOLMOD keeps each supernode's whole rectangle, column after column.
  const int* cholmod_value_start = static_cast<const int*>(l->px);
  const double* cholmod_values = static_cast<const double*>(l->x);
  // Calls visit_panel(entry, q, width, row_count) for each panel of each
  // supernode in turn, entry(i, j) being the supernode's L(i, j) as kept.
  auto for_each_panel = [&](auto visit_panel) {
    for (size_t s = 0; s < supernodes; ++s) {
      const int columns = first_column_[s + 1] - first_column_[s];
      const int row_count = pattern_start_[s + 1] - pattern_start_[s];
      const double* block = cholmod_values + cholmod_value_start[s];
      auto entry = [&](int i, int j) {
        return static_cast<Value>(block[static_cast<std::ptrdiff_t>(j) * row_count + i]);
      };
      for (int q = 0; q < columns; q += kPanelWidth)
        visit_panel(entry, q, std::min(kPanelWidth, columns - q), row_count);
    }
  };
  first_panel_.resize(supernodes + 1);
  first_panel_[0] = 0;
  size_t tallest = 0;
  for (size_t s = 0; s < supernodes; ++s) {
    const int columns = first_column_[s + 1] - first_column_[s];
    first_panel_[s + 1] = first_panel_[s] + (columns + kPanelWidth - 1) / kPanelWidth;
    tallest = std::max(tallest, static_cast<size_t>(pattern_start_[s + 1] - pattern_start_[s]));
  }
  // The runs of rows below each panel's diagonal block with a nonzero entry
  // in the panel, and how many values the panels keep.
  run_start_.reserve(static_cast<size_t>(first_panel_[supernodes]) + 1);
  run_start_.push_back(0);
  size_t value_count = 0;
  for_each_panel([&](auto entry, int q, int width, int row_count) {
    value_count += static_cast<size_t>(triangle_row(width));
    for (int i = q + width; i < row_count; ++i) {
      bool zero = true;
      for (int j = q; j < q + width; ++j) zero = zero && entry(i, j) == 0;
      if (zero) continue;
      value_count += static_cast<size_t>(width);
      const bool extends_run = static_cast<int>(nonzero_runs_.size()) > run_start_.back() &&
                               nonzero_runs_.back().end == i;
      if (extends_run)
        ++nonzero_runs_.back().end;
      else
        nonzero_runs_.push_back({i, i + 1});
    }
    run_start_.push_back(static_cast<int>(nonzero_runs_.size()));
  });
  values_.reserve(value_count);
  panel_value_start_.reserve(run_start_.size());
  const RowRun* run = nonzero_runs_.data();
  inverse_diagonal_.reserve(l->n);
  for_each_panel([&](auto entry, int q, int width, int) {
    // The solve multiplies by the inverse of the diagonal entry as kept.
    for (int j = q; j < q + width; ++j)
      inverse_diagonal_.push_back(1 / static_cast<double>(entry(j, j)));
    panel_value_start_.push_back(static_cast<std::ptrdiff_t>(values_.size()));
    for (int i = q + 1; i < q + width; ++i)
      for (int j = q; j < i; ++j) values_.push_back(entry(i, j));
    const RowRun* runs_end = nonzero_runs_.data() + run_start_[panel_value_start_.size()];
    for (; run != runs_end; ++run)
      for (int i = run->begin; i < run->end; ++i)
        for (int j = q; j < q + width; ++j) values_.push_back(entry(i, j));
  });
  panel_value_start_.push_back(static_cast<std::ptrdiff_t>(values_.size()));
  work_.resize(l->n);
  buffer_.resize(tallest);
}

namespace {

// rows[i] -= sum over j of panel[k * Width + j] x[j] for the k-th row i of
// the runs [run, runs_end), the columns j in increasing order.
template <int Width, typename Value, typename Point, typename Run>
void subtract_panel_columns(const Value* panel, const Point* x, Point* rows, const Run* run,
                            const Run* runs_end) {
  Point column_x[Width];  // in registers: for the compiler, `rows` may alias `x`
  std::copy(x, x + Width, column_x);
  for (; run != runs_end; ++run) {
    for (int i = run->begin; i < run->end; ++i, panel += Width) {
      Point row = rows[i];
      for (int j = 0; j < Width; ++j) row -= static_cast<double>(panel[j]) * column_x[j];
      rows[i] = row;
    }
  }
}

// The same for a panel of `width` columns, fixed at compile time so that the
// columns' points stay in registers.
template <typename Value, typename Point, typename Run>
void subtract_panel_columns(int width, const Value* panel, const Point* x, Point* rows,
                            const Run* run, const Run* runs_end) {
  static_assert(kPanelWidth == 4, "one case per panel width");
  switch (width) {
    case 1:
      return subtract_panel_columns<1>(panel, x, rows, run, runs_end);
    case 2:
      return subtract_panel_columns<2>(panel, x, rows, run, runs_end);
    case 3:
      return subtract_panel_columns<3>(panel, x, rows, run, runs_end);
    default:
      return subtract_panel_columns<4>(panel, x, rows, run, runs_end);
  }
}

}  // namespace

// Forward substitution, panel by panel: the panel's columns are solved in
// its diagonal block, then subtracted from every row below. Each row thus
// receives its columns' terms in increasing order, as it would column by
// column. The rows left out, where the panel is zero, would only have
// subtracted zeros (see nonzero_runs_ in coordinate_cholesky.h).
template <typename Value>
void CoordinateCholesky<Value>::forward_supernode(int s) const {
  const int first = first_column_[s];
  const int columns = first_column_[s + 1] - first;
  Point* b = buffer_.data();
  for (int q = 0, p = first_panel_[s]; q < columns; q += kPanelWidth, ++p) {
    const int width = std::min(kPanelWidth, columns - q);
    const Value* panel = values_.data() + panel_value_start_[p];
    for (int i = 0; i < width; ++i) {
      Point row = b[q + i];
      const Value* entry = panel + triangle_row(i);
      for (int j = 0; j < i; ++j) row -= static_cast<double>(entry[j]) * b[q + j];
      b[q + i] = row * inverse_diagonal_[first + q + i];
    }
    subtract_panel_columns(width, panel + triangle_row(width), b + q, b,
                           nonzero_runs_.data() + run_start_[p],
                           nonzero_runs_.data() + run_start_[p + 1]);
  }
}

// Back substitution, column by column from the last: x_j = (y_j - sum over
// the rows i below j, in increasing order, of L(i, j) x_i) / L(j, j). Each
// sum is one chain of dependent subtractions, so this half runs at their
// latency. Running the panel's sums side by side, row by row (as the forward
// substitution does), would be faster but would change the order of the
// sums, hence the rounding, and with it the minimisations' paths.
template <typename Value>
void CoordinateCholesky<Value>::backward_supernode(int s) const {
  const int first = first_column_[s];
  const int columns = first_column_[s + 1] - first;
  Point* b = buffer_.data();
  const int last_panel = (columns - 1) / kPanelWidth;
  for (int q = last_panel * kPanelWidth, p = first_panel_[s] + last_panel; q >= 0;
       q -= kPanelWidth, --p) {
    const int width = std::min(kPanelWidth, columns - q);
    const Value* panel = values_.data() + panel_value_start_[p];
    const Value* below = panel + triangle_row(width);
    const RowRun* runs_begin = nonzero_runs_.data() + run_start_[p];
    const RowRun* runs_end = nonzero_runs_.data() + run_start_[p + 1];
    for (int j = width - 1; j >= 0; --j) {
      Point sum = b[q + j];
      for (int i = j + 1; i < width; ++i)
        sum -= static_cast<double>(panel[triangle_row(i) + j]) * b[q + i];
      const Value* entry = below + j;
      for (const RowRun* run = runs_begin; run != runs_end; ++run) {
        // Two rows an iteration: fewer instructions for the loop, same sum.
#pragma GCC unroll 2
        for (int i = run->begin; i < run->end; ++i, entry += width)
          sum -= static_cast<double>(*entry) * b[i];
      }
      b[q + j] = sum * inverse_diagonal_[first + q + j];
    }
  }
}

// L y = b, then L^T x = y, supernode by supernode. Each supernode gathers
// the rows of work_ it touches into a small contiguous buffer, works on
// that, and scatters them back: work_ is read and written once per
// supernode instead of once per entry of the factor, and the inner loops
// run over contiguous memory.
template <typename Value>
void CoordinateCholesky<Value>::solve_permuted() const {
  Point* y = work_.data();
  Point* buffer = buffer_.data();
  const int supernodes = static_cast<int>(first_column_.size()) - 1;
  auto gather = [&](const int* row, int count) {
    for (int i = 0; i < count; ++i) buffer[i] = y[row[i]];
  };
  auto scatter = [&](const int* row, int count) {
    for (int i = 0; i < count; ++i) y[row[i]] = buffer[i];
  };
  for (int s = 0; s < supernodes; ++s) {
    const int row_count = pattern_start_[s + 1] - pattern_start_[s];
    const int* row = rows_.data() + pattern_start_[s];
    gather(row, row_count);
    forward_supernode(s);
    scatter(row, row_count);
  }
  for (int s = supernodes - 1; s >= 0; --s) {
    const int columns = first_column_[s + 1] - first_column_[s];
    const int row_count = pattern_start_[s + 1] - pattern_start_[s];
    const int* row = rows_.data() + pattern_start_[s];
    gather(row, row_count);
    backward_supernode(s);
    scatter(row, columns);
  }
}

template class CoordinateCholesky<double>;
template class CoordinateCholesky<float>;

}  // namespace foldfill
