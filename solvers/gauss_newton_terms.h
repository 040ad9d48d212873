// The Gauss-Newton backend's side of DeformationEnergy::terms
// (energies/energy_term.h): what solvers/gauss_newton_solver.cc asks of a term
// it knows nothing else about.
//   Linear terms: evaluated once per layout at x = 0, their residual c and
//   constant Jacobian A become rows of the backend's A (so of H = A^T A and
//   the compressed residuals), like Coherence.
//   Nonlinear terms: their J^T J blocks between their variable blocks join
//   the pattern of J^T J once per layout (so the symbolic factorisation stays
//   per layout); each iteration evaluates each term's own residual and
//   Jacobian, adds J^T r to the gradient and J^T J to those entries.
// A term's blocks that the node classes keep constant are read from the
// layout's transforms and get no Jacobian.

#ifndef MSDEFORM_SOLVERS_GAUSS_NEWTON_TERMS_H_
#define MSDEFORM_SOLVERS_GAUSS_NEWTON_TERMS_H_

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <ceres/cost_function.h>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/energies/energy_term.h"

namespace msdeform {

class GaussNewtonTerms {
 public:
  using Triplet = Eigen::Triplet<double, int>;
  using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  // `offset[j]`: node j's first variable (R_j: 9, then t_j: 3 when
  // totally_free[j]), -1 for a Fixed node. `transforms`: the constant blocks.
  bool Setup(const std::vector<EnergyTerm>& terms, const std::vector<int>& offset,
             const std::vector<char>& totally_free, const NodeTransforms& transforms,
             std::string* error);

  // The linear terms' rows r = A x + c: A's entries from row *row on, c into
  // `constant` (resized); *row advances past them.
  void AppendLinearRows(std::vector<Triplet>* a_entries, std::vector<double>* constant,
                        int* row) const;

  // The entries of J^T J the nonlinear terms write (both triangles), to join
  // the pattern; then, once the pattern is compressed, IndexValues finds them.
  void AppendPattern(std::vector<Triplet>* entries) const;
  void IndexValues(const SparseMatrix& system);

  // 1/2 |r|^2 of the nonlinear terms at x. With gradient != nullptr also adds
  // J^T r to *gradient and writes their J^T J entries to *values (in
  // IndexValues' order) for AddValues.
  double Cost(const Eigen::VectorXd& x, Eigen::VectorXd* gradient,
              std::vector<double>* values) const;
  void AddValues(const std::vector<double>& values, double* system_values) const;

  bool has_nonlinear() const { return !nonlinear_.empty(); }

 private:
  struct Term {
    std::unique_ptr<ceres::CostFunction> cost;
    std::vector<int> variable;          // per block: first variable, or -1 (constant)
    std::vector<const double*> constant;  // per block: its value when constant
    std::vector<int> size;               // per block: 9 or 3
  };
  Term Prepare(const EnergyTerm& term) const;
  // Residuals and the Jacobians of the variable blocks (row-major) at x.
  void Evaluate(const Term& term, const Eigen::VectorXd& x, double* residuals,
                std::vector<std::vector<double>>* jacobians) const;

  std::vector<int> offset_;
  std::vector<char> totally_free_;
  NodeTransforms constants_;
  std::vector<Term> linear_, nonlinear_;
  std::vector<int> value_index_;  // per entry of `values`
};

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_GAUSS_NEWTON_TERMS_H_
