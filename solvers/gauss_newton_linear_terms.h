// The Gauss-Newton backend's linear terms (solvers/gauss_newton_solver.h),
// assembled once per handle layout: every Coherence (Eq. 14), Position
// (Eq. 16) and gauge residual and the linear DeformationEnergy::terms, all
// affine in the variables x and the handle groups' 12 numbers each, tau,
//   r = A x + c - P tau,
// kept as H = A^T A, A^T c, A^T P and a compressed form of the residuals
// with the same sum of squares (the cost is taken from it, not from the
// expanded quadratic; solvers/gauss_newton_solver.h says why).

#ifndef MSDEFORM_SOLVERS_GAUSS_NEWTON_LINEAR_TERMS_H_
#define MSDEFORM_SOLVERS_GAUSS_NEWTON_LINEAR_TERMS_H_

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/solvers/deformation_energy.h"
#include "msdeform/solvers/gauss_newton_terms.h"

namespace msdeform {

struct LinearTerms {
  using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  using RowSparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
  SparseMatrix hessian;             // H = A^T A, #variables square
  Eigen::VectorXd linear_gradient;  // A^T c
  int num_handle_groups = 1;       // G
  SparseMatrix handle_gradient;     // A^T P, #variables by 12 G
  // |root x + root_handle [tau; 1]|^2 = |A x + c - P tau|^2: A's Coherence,
  // gauge and linear-term rows as they are; per group of position terms with
  // the same variable nodes, the triangular factor of a QR of their rows.
  RowSparseMatrix root;         // m by #variables
  RowSparseMatrix root_handle;  // m by 12 G + 1
};

// `offset[j]`: node j's first variable (R_j, then t_j for a Totally Free
// node), -1 for a Fixed node; `n` the number of variables; `transforms` the
// values of the constant blocks; `terms` the energy's extra terms.
// The QR of each group of position terms (a third of this call on the 1.66M
// claw: 12 groups of 1,300 rows) runs on `num_threads` threads, one group
// per thread at a time, once the groups have `min_parallel_rows` rows in
// all; each group's factor is the same whichever thread computes it, so the
// output is the same bits for any thread count.
void AssembleLinearTerms(const DeformationEnergy& energy, const NodeTransforms& transforms,
                         const std::vector<int>& offset, const GaussNewtonTerms& terms, int n,
                         LinearTerms* out, int num_threads = 1, int min_parallel_rows = 4096);

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_GAUSS_NEWTON_LINEAR_TERMS_H_
