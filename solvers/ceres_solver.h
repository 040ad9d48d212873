// The Ceres backend (solvers/frame_solver.h): Eq. 17 as a ceres::Problem of the
// cost functors in energies/ (analytic or autodiff, CeresOptions::jacobians)
// plus one residual block per DeformationEnergy::terms entry, node classes as
// parameter-block fixing (Totally Free: R and t vary, Half Free: R only,
// Fixed: none). The reference the
// Gauss-Newton backend (solvers/gauss_newton_solver.h) is tested against.
// The subspace ARAP energy (--energy=arap) runs as one residual block per
// rotation cluster, with the cluster rotations as extra parameter blocks
// (solvers/ceres_solver_arap.h).

#ifndef MSDEFORM_SOLVERS_CERES_SOLVER_H_
#define MSDEFORM_SOLVERS_CERES_SOLVER_H_

#include <memory>
#include <string>
#include <vector>

#include <ceres/types.h>

#include "msdeform/core/option_table.h"
#include "msdeform/solvers/frame_solver.h"

namespace msdeform {

struct CeresOptions {
  // Trust-region strategy: LEVENBERG_MARQUARDT or DOGLEG (TRADITIONAL_DOGLEG).
  ceres::TrustRegionStrategyType trust_region = ceres::LEVENBERG_MARQUARDT;
  // SPARSE_NORMAL_CHOLESKY (exact) or CGNR (conjugate gradients on the
  // normal equations, JACOBI preconditioner).
  ceres::LinearSolverType linear_solver = ceres::SPARSE_NORMAL_CHOLESKY;
  // The sparse Cholesky library of SPARSE_NORMAL_CHOLESKY. EIGEN_SPARSE is
  // 1.45-1.6x faster than SUITE_SPARSE here (docs/decisions/speed.md); the others
  // this Ceres has: SUITE_SPARSE, CX_SPARSE (CeresSparseLibraries()).
  ceres::SparseLinearAlgebraLibraryType sparse_library = ceres::EIGEN_SPARSE;
  // Handle vertices that share the same nodes become one exact
  // least-squares block (energies/position_group_cost.h) instead of one
  // residual block each. Same minimiser; false gives the per-vertex blocks.
  bool group_position_terms = true;
  // Which Jacobians the residual blocks use, both from the functors in
  // energies/: kAnalytic the hand-written ones (RotCostAnalytic, ...,
  // PositionGroupCost), kAutodiff ceres::AutoDiffCostFunction of the
  // templated functors (RotCost, CoherenceCost, GaugeCost, PositionCost), one
  // position block per handle vertex (group_position_terms does not apply:
  // the grouped block has no functor). Same minimum; autodiff is slower.
  // DeformationEnergy::terms follow it too (analytic where a term has one).
  enum class Jacobians { kAnalytic, kAutodiff };
  Jacobians jacobians = Jacobians::kAnalytic;

  bool Check(std::string* error) const;
};

// "levenberg_marquardt", "dogleg"; "sparse_normal_cholesky", "cgnr";
// "eigen_sparse", "suite_sparse", "cx_sparse" (Ceres's names, lower case).
std::string TrustRegionName(ceres::TrustRegionStrategyType type);
bool ParseTrustRegion(const std::string& name, ceres::TrustRegionStrategyType* type);
std::string CeresLinearSolverName(ceres::LinearSolverType type);
bool ParseCeresLinearSolver(const std::string& name, ceres::LinearSolverType* type);
std::string SparseLibraryName(ceres::SparseLinearAlgebraLibraryType type);
bool ParseSparseLibrary(const std::string& name, ceres::SparseLinearAlgebraLibraryType* type);
// "analytic", "autodiff".
const EnumNames<CeresOptions::Jacobians>& JacobiansNames();  // core/option_table.h
const char* JacobiansName(CeresOptions::Jacobians jacobians);
bool ParseJacobians(const std::string& name, CeresOptions::Jacobians* jacobians);
// "2.1.0": the Ceres msdeform is built against.
std::string CeresVersion();
// The sparse libraries this build of Ceres has, among those three.
std::vector<ceres::SparseLinearAlgebraLibraryType> CeresSparseLibraries();

class CeresSolver : public FrameSolver {
 public:
  // `num_threads`: Ceres's threads (Jacobian evaluation, linear algebra).
  CeresSolver(const CeresOptions& options, const StoppingRule& stopping, int num_threads);
  ~CeresSolver() override;

  bool Setup(const DeformationEnergy& energy, const NodeTransforms& transforms,
             std::string* error) override;
  SolveSummary Solve(const HandleTransforms& handles, NodeTransforms* transforms) override;
  double Cost(const HandleTransforms& handles, const NodeTransforms& transforms) override;
  int num_variables() const override { return num_variables_; }

 private:
  double SetHandles(const HandleTransforms& handles);

  struct Impl;
  std::unique_ptr<Impl> impl_;
  CeresOptions options_;
  StoppingRule stopping_;
  int num_threads_ = 1;
  int num_variables_ = 0;
};

// CeresOptions' rows (core/option_table.h), declared in its header beside the fields: a new field
// is the field above and its row here. CeresOptionTable() (ceres_solver.cc) builds the table from
// them once; a template, so that only that file compiles the rows.
template <typename Table>
void DeclareCeresOptionRows(Table& t) {
  using C = CeresOptions;
  t.Enum("trust_region", &C::trust_region,
         EnumNames<ceres::TrustRegionStrategyType>::FromFunction(
             {ceres::LEVENBERG_MARQUARDT, ceres::DOGLEG}, TrustRegionName),
         "Ceres: levenberg_marquardt or dogleg.");
  t.Enum("linear_solver", &C::linear_solver,
         EnumNames<ceres::LinearSolverType>::FromFunction(
             {ceres::SPARSE_NORMAL_CHOLESKY, ceres::CGNR}, CeresLinearSolverName),
         "Ceres: sparse_normal_cholesky or cgnr.");
  // Only the libraries this Ceres has.
  t.Enum("sparse_library", &C::sparse_library,
         EnumNames<ceres::SparseLinearAlgebraLibraryType>::FromFunction(
             CeresSparseLibraries(), SparseLibraryName),
         "Ceres's sparse Cholesky library: eigen_sparse, suite_sparse or cx_sparse (those "
         "this Ceres has).")
      .ChoiceWords("one this Ceres has: ");
  t.Bool("group_position_terms", &C::group_position_terms,
         "One exact least-squares block per group of handle vertices sharing nodes.");
  t.Enum("jacobians", &C::jacobians,
         JacobiansNames(),
         "Ceres's residual blocks: analytic (the functors' hand-written Jacobians) or autodiff "
         "(the same functors through ceres::AutoDiffCostFunction).");
}
const OptionTable<CeresOptions>& CeresOptionTable();

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_CERES_SOLVER_H_
