// A supernodal sparse Cholesky factorisation A = P^T L L^T P for the
// Gauss-Newton backend's normal equations (solvers/gauss_newton_linear_solver.h,
// GaussNewtonOptions::Cholesky::kSupernodal), small enough to read in one
// sitting: CHOLMOD's method without its BLAS calls.
//
// Analyze, once per pattern: the AMD ordering (Eigen's), the elimination
// tree, the structure of each column of L, and supernodes: runs of columns
// j, j + 1, ... with parent(j) = j + 1 whose rows below the run are the same
// (fundamental), widened by relaxed amalgamation to runs whose union of rows
// stores at most `relax_fraction` explicit zeros. Each supernode is one dense
// column-major panel (its rows by its columns), so the numeric work is dense
// kernels (Eigen's LLT, triangular solve, matrix product) on panels instead
// of one scalar column at a time, and the scatter of each supernode's update
// into its ancestors' panels goes through relative indices computed here.
//
// Factorize, per set of values on that pattern: copies A's lower triangle
// into the panels (indices computed in Analyze) and factorises right-looking,
// supernode by supernode. Solve: forward and back substitution, a small
// triangular solve and a matrix-vector product per supernode.
//
// On the 104K claw drag (1,188 variables, 99 nodes; L has 58.7K entries by
// AMD, the same as CHOLMOD's choice) this factorises in 0.56 ms against 1.2-1.4
// ms for Eigen's scalar SimplicialLLT and solves in 0.038 ms against 0.064 ms
// (docs/decisions/supernodal-cholesky.md, "The Gauss-Newton solve").

#ifndef MSDEFORM_SOLVERS_GAUSS_NEWTON_SUPERNODAL_CHOLESKY_H_
#define MSDEFORM_SOLVERS_GAUSS_NEWTON_SUPERNODAL_CHOLESKY_H_

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace msdeform {

class SupernodalCholesky {
 public:
  using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  // Explicit zeros a relaxed supernode may store, as a fraction of its
  // entries (0: fundamental supernodes only).
  explicit SupernodalCholesky(double relax_fraction = 0.2) : relax_fraction_(relax_fraction) {}

  // `matrix`: square, compressed, its pattern symmetric with both triangles
  // stored (the lower one is read). Factorize must get the same pattern
  // (checked).
  void Analyze(const SparseMatrix& matrix);
  // False when the matrix is not (numerically) positive definite.
  bool Factorize(const SparseMatrix& matrix);
  // x with A x = rhs, by the last Factorize, which must have succeeded (a
  // failed one leaves the factor unusable until the next success).
  void Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd* x) const;

  int num_supernodes() const { return static_cast<int>(first_.size()) - 1; }
  // Entries of L's panels, explicit zeros included.
  int64_t factor_entries() const { return static_cast<int64_t>(values_.size()); }

 private:
  // Supernode s: columns first_[s] .. first_[s + 1] - 1 of the permuted
  // matrix; its rows (its own columns first, then the rows below, ascending)
  // are rows_[row_begin_[s] .. row_begin_[s + 1]); its panel, column-major
  // with that many rows, starts at values_[value_begin_[s]].
  struct Update {
    int target;        // the supernode whose columns receive the update
    int column_begin;  // this supernode's off-diagonal rows in `target`'s columns:
    int column_end;    // [column_begin, column_end), counted from its first off row
    int relative;      // start in relative_: rows column_begin.. as positions in target
  };

  // Analyze's last steps. Each supernode's updates, grouped by the
  // supernode of the column they land in (update_begin_, updates_; the
  // sizes of scratch_, relative_ and buffer_); returned: per target
  // supernode, the indices of its updates in updates_.
  std::vector<std::vector<int>> ScheduleUpdates(const std::vector<int>& supernode_of);
  // Then, target by target, the positions there of each update's rows
  // (relative_) and of each stored entry of `matrix` (destination_).
  void PlaceUpdatesAndEntries(const SparseMatrix& matrix,
                              const std::vector<int>& column_of_position,
                              const std::vector<std::vector<int>>& updates_of);

  double relax_fraction_;
  int n_ = 0;
  std::vector<int> position_;  // position_[i]: row i's place in the permuted order
  // The pattern Analyze saw (outer and inner indices), checked by Factorize.
  std::vector<int> pattern_outer_, pattern_inner_;
  std::vector<int> first_, row_begin_, rows_;
  std::vector<int64_t> value_begin_;
  std::vector<int> update_begin_;  // per supernode into updates_
  std::vector<Update> updates_;
  std::vector<int> relative_;
  std::vector<int64_t> destination_;  // per stored entry of A: index into values_, or -1
  std::vector<double> values_;
  std::vector<double> scratch_;  // one supernode's update
  mutable Eigen::VectorXd permuted_, buffer_;  // Solve's
};

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_GAUSS_NEWTON_SUPERNODAL_CHOLESKY_H_
