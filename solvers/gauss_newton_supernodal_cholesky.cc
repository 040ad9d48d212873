#include "msdeform/solvers/gauss_newton_supernodal_cholesky.h"

#include <algorithm>
#include <iterator>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/OrderingMethods>
#include <glog/logging.h>

namespace msdeform {
namespace {

using Panel = Eigen::Map<Eigen::MatrixXd>;

// local[r] -= sum_i column[i][r] * value[i] for r in [begin, end).
template <int W>
void SubtractColumns(const double* const* column, const double* value, int begin, int end,
                     double* local) {
  double v[W];  // copies, so that the stores to local need not reload them
  for (int i = 0; i < W; ++i) v[i] = value[i];
  for (int r = begin; r < end; ++r) {
    double update = column[0][r] * v[0];
    for (int i = 1; i < W; ++i) update += column[i][r] * v[i];
    local[r] -= update;
  }
}

// sum[i] = sum_r column[i][r] * local[r] for r in [begin, end).
template <int W>
void DotColumns(const double* const* column, const double* local, int begin, int end,
                double* sum) {
  double s[W] = {};  // in registers, not through `sum`
  for (int r = begin; r < end; ++r) {
    for (int i = 0; i < W; ++i) s[i] += column[i][r] * local[r];
  }
  for (int i = 0; i < W; ++i) sum[i] = s[i];
}

// L's column structures (each column's rows below the diagonal, ascending)
// and the elimination tree (parent[j], -1 at a root) of `matrix` permuted
// by `position`: the permuted lower triangle by column, then along the
// elimination tree a column's structure is its own rows and its
// children's, less the children.
void ColumnStructures(const Eigen::SparseMatrix<double, Eigen::ColMajor, int>& matrix,
                      const std::vector<int>& position,
                      std::vector<std::vector<int>>* structure_out,
                      std::vector<int>* parent_out) {
  const int n = static_cast<int>(position.size());
  std::vector<std::vector<int>> lower(n), children(n);
  std::vector<std::vector<int>>& structure = *structure_out;
  std::vector<int>& parent = *parent_out;
  structure.assign(n, {});
  parent.assign(n, -1);
  const int* outer = matrix.outerIndexPtr();
  const int* inner = matrix.innerIndexPtr();
  for (int c = 0; c < n; ++c) {
    for (int k = outer[c]; k < outer[c + 1]; ++k) {
      const int i = position[inner[k]], j = position[c];
      if (i > j) lower[j].push_back(i);
    }
  }
  std::vector<int> merged;
  for (int j = 0; j < n; ++j) {
    std::vector<int>& rows = structure[j];
    rows = std::move(lower[j]);
    std::sort(rows.begin(), rows.end());
    for (int child : children[j]) {
      const std::vector<int>& from = structure[child];
      merged.clear();
      std::set_union(rows.begin(), rows.end(), from.begin() + 1, from.end(),
                     std::back_inserter(merged));  // from[0] == j
      rows.swap(merged);
    }
    if (!rows.empty()) {
      parent[j] = rows.front();
      children[rows.front()].push_back(j);
    }
  }
}

// Supernodes from the column structures: extend the current run by column
// j when j is the parent of the run's last column and the explicit zeros
// stay within relax_fraction of its entries. Supernode s: columns
// first[s] .. first[s + 1] - 1, its rows rows[row_begin[s] ..
// row_begin[s + 1]) (its own columns, then the rows below).
void FindSupernodes(const std::vector<std::vector<int>>& structure,
                    const std::vector<int>& parent, double relax_fraction,
                    std::vector<int>* first, std::vector<int>* row_begin,
                    std::vector<int>* rows) {
  const int n = static_cast<int>(structure.size());
  first->assign(1, 0);
  row_begin->assign(1, 0);
  rows->clear();
  std::vector<int> merged;
  std::vector<int> below;  // the current run's rows below its last column
  auto close = [&](int end) {
    for (int col = first->back(); col < end; ++col) rows->push_back(col);
    rows->insert(rows->end(), below.begin(), below.end());
    first->push_back(end);
    row_begin->push_back(static_cast<int>(rows->size()));
  };
  int64_t zeros = 0;
  for (int j = 0; j < n; ++j) {
    const int width = j - first->back();
    if (width > 0 && parent[j - 1] == j) {
      merged.clear();
      std::set_union(below.begin() + 1, below.end(), structure[j].begin(), structure[j].end(),
                     std::back_inserter(merged));  // below[0] == j
      const int64_t size = static_cast<int64_t>(merged.size());
      const int64_t added = width * (size - static_cast<int64_t>(below.size() - 1)) +
                            (size - static_cast<int64_t>(structure[j].size()));
      const int64_t entries = (width + 1) * (width + 2) / 2 + (width + 1) * size;
      if (added == 0 || zeros + added <= relax_fraction * static_cast<double>(entries)) {
        zeros += added;
        below.swap(merged);
        continue;
      }
    }
    if (width > 0) close(j);
    below = structure[j];
    zeros = 0;
  }
  if (n > 0) close(n);
}

}  // namespace

void SupernodalCholesky::Analyze(const SparseMatrix& matrix) {
  CHECK_EQ(matrix.rows(), matrix.cols());
  CHECK(matrix.isCompressed());
  n_ = static_cast<int>(matrix.rows());
  pattern_outer_.assign(matrix.outerIndexPtr(), matrix.outerIndexPtr() + n_ + 1);
  pattern_inner_.assign(matrix.innerIndexPtr(), matrix.innerIndexPtr() + matrix.nonZeros());
  // The AMD ordering, as Eigen's SimplicialLLT takes it: its indices()[k]
  // is the row of `matrix` at place k.
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> ordering;
  Eigen::AMDOrdering<int>()(matrix, ordering);
  position_.resize(n_);
  std::vector<int> column_of_position(n_);
  for (int k = 0; k < n_; ++k) {
    position_[ordering.indices()[k]] = k;
    column_of_position[k] = ordering.indices()[k];
  }

  std::vector<std::vector<int>> structure;
  std::vector<int> parent;
  ColumnStructures(matrix, position_, &structure, &parent);
  FindSupernodes(structure, parent, relax_fraction_, &first_, &row_begin_, &rows_);

  // Each supernode's panel: its rows by its columns, column-major.
  const int num = num_supernodes();
  std::vector<int> supernode_of(n_);
  value_begin_.assign(1, 0);
  for (int s = 0; s < num; ++s) {
    for (int col = first_[s]; col < first_[s + 1]; ++col) supernode_of[col] = s;
    const int64_t ld = row_begin_[s + 1] - row_begin_[s];
    value_begin_.push_back(value_begin_.back() + ld * (first_[s + 1] - first_[s]));
  }
  values_.assign(value_begin_.back(), 0.0);

  const std::vector<std::vector<int>> updates_of = ScheduleUpdates(supernode_of);
  PlaceUpdatesAndEntries(matrix, column_of_position, updates_of);
  permuted_.resize(n_);
}

std::vector<std::vector<int>> SupernodalCholesky::ScheduleUpdates(
    const std::vector<int>& supernode_of) {
  const int num = num_supernodes();
  update_begin_.assign(1, 0);
  updates_.clear();
  size_t largest = 0;
  int largest_rows = 0;
  int relative_size = 0;
  std::vector<std::vector<int>> updates_of(num);  // per target: indices into updates_
  for (int s = 0; s < num; ++s) {
    const int k = first_[s + 1] - first_[s];
    const int* off = rows_.data() + row_begin_[s] + k;
    const int m = row_begin_[s + 1] - row_begin_[s] - k;
    largest = std::max(largest, static_cast<size_t>(m) * m);
    largest_rows = std::max(largest_rows, m + k);
    for (int q = 0; q < m;) {
      const int t = supernode_of[off[q]];
      int end = q;
      while (end < m && supernode_of[off[end]] == t) ++end;
      updates_of[t].push_back(static_cast<int>(updates_.size()));
      updates_.push_back({t, q, end, relative_size});
      relative_size += m - q;
      q = end;
    }
    update_begin_.push_back(static_cast<int>(updates_.size()));
  }
  scratch_.assign(largest, 0.0);
  relative_.assign(relative_size, 0);
  buffer_.resize(largest_rows);
  return updates_of;
}

void SupernodalCholesky::PlaceUpdatesAndEntries(
    const SparseMatrix& matrix, const std::vector<int>& column_of_position,
    const std::vector<std::vector<int>>& updates_of) {
  const int num = num_supernodes();
  const int* outer = matrix.outerIndexPtr();
  const int* inner = matrix.innerIndexPtr();
  std::vector<int> update_source(updates_.size());
  for (int s = 0; s < num; ++s)
    for (int u = update_begin_[s]; u < update_begin_[s + 1]; ++u) update_source[u] = s;
  std::vector<int> where(n_, -1);
  destination_.assign(matrix.nonZeros(), -1);
  for (int t = 0; t < num; ++t) {
    for (int r = row_begin_[t]; r < row_begin_[t + 1]; ++r) where[rows_[r]] = r - row_begin_[t];
    for (int u : updates_of[t]) {
      const int s = update_source[u];
      const int k = first_[s + 1] - first_[s];
      const int* off = rows_.data() + row_begin_[s] + k;
      const int m = row_begin_[s + 1] - row_begin_[s] - k;
      int* relative = relative_.data() + updates_[u].relative;
      for (int p = updates_[u].column_begin; p < m; ++p) {
        CHECK_GE(where[off[p]], 0) << "row " << off[p] << " not in supernode " << t;
        *relative++ = where[off[p]];
      }
    }
    // Where each stored entry of the lower triangle of t's columns goes in
    // its panel.
    const int ld = row_begin_[t + 1] - row_begin_[t];
    for (int j = first_[t]; j < first_[t + 1]; ++j) {
      const int c = column_of_position[j];  // the column of `matrix` that is column j here
      for (int k = outer[c]; k < outer[c + 1]; ++k) {
        const int i = position_[inner[k]];
        if (i < j) continue;
        CHECK_GE(where[i], 0) << "row " << i << " not in supernode " << t;
        destination_[k] = value_begin_[t] + static_cast<int64_t>(j - first_[t]) * ld + where[i];
      }
    }
    for (int r = row_begin_[t]; r < row_begin_[t + 1]; ++r) where[rows_[r]] = -1;
  }
}

bool SupernodalCholesky::Factorize(const SparseMatrix& matrix) {
  CHECK_EQ(static_cast<size_t>(matrix.nonZeros()), destination_.size()) << "Analyze first";
  CHECK(matrix.isCompressed() &&
        matrix.cols() + 1 == static_cast<Eigen::Index>(pattern_outer_.size()) &&
        std::equal(pattern_outer_.begin(), pattern_outer_.end(), matrix.outerIndexPtr()) &&
        std::equal(pattern_inner_.begin(), pattern_inner_.end(), matrix.innerIndexPtr()))
      << "Factorize got another pattern than Analyze";
  std::fill(values_.begin(), values_.end(), 0.0);
  const double* a = matrix.valuePtr();
  for (size_t e = 0; e < destination_.size(); ++e) {
    if (destination_[e] >= 0) values_[destination_[e]] = a[e];
  }
  for (int s = 0; s < num_supernodes(); ++s) {
    const int k = first_[s + 1] - first_[s];
    const int ld = row_begin_[s + 1] - row_begin_[s];
    const int m = ld - k;
    Panel panel(values_.data() + value_begin_[s], ld, k);
    // The diagonal block in place (LLT of a Ref factorises in place).
    Eigen::Ref<Eigen::MatrixXd> diagonal = panel.topRows(k);
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> llt(diagonal);
    if (llt.info() != Eigen::Success) return false;
    if (m == 0) continue;
    auto off = panel.bottomRows(m);
    diagonal.transpose().triangularView<Eigen::Upper>().solveInPlace<Eigen::OnTheRight>(off);
    // Its update off off^T (lower triangle) into the ancestors' panels.
    Panel update(scratch_.data(), m, m);
    update.triangularView<Eigen::Lower>().setZero();
    update.selfadjointView<Eigen::Lower>().rankUpdate(off);
    const int* rows = rows_.data() + row_begin_[s] + k;
    for (int u = update_begin_[s]; u < update_begin_[s + 1]; ++u) {
      const Update& to = updates_[u];
      const int target_ld = row_begin_[to.target + 1] - row_begin_[to.target];
      double* target = values_.data() + value_begin_[to.target];
      const int* relative = relative_.data() + to.relative - to.column_begin;
      for (int q = to.column_begin; q < to.column_end; ++q) {
        double* column =
            target + static_cast<int64_t>(rows[q] - first_[to.target]) * target_ld;
        const double* from = update.data() + static_cast<int64_t>(q) * m;
        for (int p = q; p < m; ++p) column[relative[p]] -= from[p];
      }
    }
  }
  return true;
}

void SupernodalCholesky::Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd* x) const {
  CHECK_EQ(rhs.size(), n_);
  for (int i = 0; i < n_; ++i) permuted_[position_[i]] = rhs[i];
  const int num = num_supernodes();
  double* y = permuted_.data();
  // By hand: the supernodes are narrow here (3 to 4 columns on average),
  // where a dense kernel's call costs more than its work. Each supernode
  // gathers its rows of y into `local` once, works on up to four of its
  // columns at a time (one pass over the rows below them instead of four;
  // four independent sums instead of one chain of additions), and scatters
  // them back.
  double* local = buffer_.data();
  for (int s = 0; s < num; ++s) {  // L z = P rhs
    const int k = first_[s + 1] - first_[s];
    const int ld = row_begin_[s + 1] - row_begin_[s];
    const double* panel = values_.data() + value_begin_[s];
    const int* rows = rows_.data() + row_begin_[s];
    for (int r = 0; r < ld; ++r) local[r] = y[rows[r]];
    for (int bottom = 0; bottom < k; bottom += 4) {
      const int top = std::min(k - 1, bottom + 3);
      const double* column[4];
      for (int c = bottom; c <= top; ++c) {
        column[c - bottom] = panel + static_cast<int64_t>(c) * ld;
        local[c] /= column[c - bottom][c];
        for (int r = c + 1; r <= top; ++r) local[r] -= column[c - bottom][r] * local[c];
      }
      switch (top - bottom) {
        case 3: SubtractColumns<4>(column, local + bottom, top + 1, ld, local); break;
        case 2: SubtractColumns<3>(column, local + bottom, top + 1, ld, local); break;
        case 1: SubtractColumns<2>(column, local + bottom, top + 1, ld, local); break;
        default: SubtractColumns<1>(column, local + bottom, top + 1, ld, local); break;
      }
    }
    for (int r = 0; r < ld; ++r) y[rows[r]] = local[r];
  }
  for (int s = num - 1; s >= 0; --s) {  // L^T w = z
    const int k = first_[s + 1] - first_[s];
    const int ld = row_begin_[s + 1] - row_begin_[s];
    const double* panel = values_.data() + value_begin_[s];
    const int* rows = rows_.data() + row_begin_[s];
    for (int r = 0; r < ld; ++r) local[r] = y[rows[r]];
    for (int top = k - 1; top >= 0; top -= 4) {
      const int bottom = std::max(0, top - 3);
      const double* column[4];
      for (int c = bottom; c <= top; ++c) column[c - bottom] = panel + static_cast<int64_t>(c) * ld;
      double sum[4] = {0.0, 0.0, 0.0, 0.0};
      switch (top - bottom) {
        case 3: DotColumns<4>(column, local, top + 1, ld, sum); break;
        case 2: DotColumns<3>(column, local, top + 1, ld, sum); break;
        case 1: DotColumns<2>(column, local, top + 1, ld, sum); break;
        default: DotColumns<1>(column, local, top + 1, ld, sum); break;
      }
      for (int c = top; c >= bottom; --c) {
        double value = local[c] - sum[c - bottom];
        for (int r = c + 1; r <= top; ++r) value -= column[c - bottom][r] * local[r];
        local[c] = value / column[c - bottom][c];
      }
    }
    for (int c = 0; c < k; ++c) y[first_[s] + c] = local[c];
  }
  x->resize(n_);
  for (int i = 0; i < n_; ++i) (*x)[i] = y[position_[i]];
}

}  // namespace msdeform
