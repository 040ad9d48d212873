// The linear solvers of the Gauss-Newton backend (solvers/gauss_newton_solver.h):
// each step solves (J^T J + mu D) delta = -g on a pattern fixed per handle
// layout. One class per way of solving it, behind one interface; the backend
// only calls Analyze once per layout, Factorize when its factorisation rule
// asks, and Solve every iteration.
//
// Adding one (docs/extending.md, "Adding a Gauss-Newton linear solver"): a
// class in this file's .cc (or a file of its own) and its case in
// MakeGaussNewtonLinearSolver, plus its value and name in
// GaussNewtonOptions::LinearSolver (or Cholesky) and LinearSolverNames().

#ifndef MSDEFORM_SOLVERS_GAUSS_NEWTON_LINEAR_SOLVER_H_
#define MSDEFORM_SOLVERS_GAUSS_NEWTON_LINEAR_SOLVER_H_

#include <memory>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "msdeform/solvers/gauss_newton_solver.h"

namespace msdeform {

class GaussNewtonLinearSolver {
 public:
  using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  virtual ~GaussNewtonLinearSolver() = default;

  // Once per layout: `system` holds the pattern of J^T J (both triangles).
  virtual void Analyze(const SparseMatrix& system) = 0;
  // The numeric factorisation (or preconditioner) of `system`'s current
  // values; false when it is not (numerically) positive definite.
  virtual bool Factorize(const SparseMatrix& system) = 0;
  // delta with system * delta = rhs: by the last factorisation (direct), or
  // iteratively on `system`'s current values to the relative residual `eta`.
  virtual bool Solve(const SparseMatrix& system, const Eigen::VectorXd& rhs, double eta,
                     Eigen::VectorXd* delta) = 0;
  // True when Solve uses only the last factorisation (a stale one gives a
  // chord step, and `system` need not be reassembled between
  // factorisations); false when it multiplies by `system` (PCG).
  virtual bool direct() const = 0;
};

// The solver `options` name (linear_solver, and cholesky for kCholesky;
// CHOLMOD falls back to Eigen's LLT when it is not built in).
std::unique_ptr<GaussNewtonLinearSolver> MakeGaussNewtonLinearSolver(
    const GaussNewtonOptions& options);

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_GAUSS_NEWTON_LINEAR_SOLVER_H_
