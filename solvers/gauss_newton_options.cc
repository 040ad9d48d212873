// GaussNewtonOptions (solvers/gauss_newton_solver.h): Check and the enum names.

#include <cmath>
#include <string>

#include "msdeform/solvers/gauss_newton_solver.h"

namespace msdeform {

bool GaussNewtonOptions::Check(std::string* error) const {
  // The rows' ranges (GaussNewtonOptionTable(), gauss_newton_solver.h).
  return GaussNewtonOptionTable().CheckRanges(*this, error);
}

using LinearSolver = GaussNewtonOptions::LinearSolver;
using Cholesky = GaussNewtonOptions::Cholesky;
using Factorization = GaussNewtonOptions::Factorization;
using Damping = GaussNewtonOptions::Damping;

const EnumNames<LinearSolver>& LinearSolverNames() {
  static const EnumNames<LinearSolver> names{
      {LinearSolver::kCholesky, "cholesky"},
      {LinearSolver::kPcgJacobi, "pcg_jacobi"},
      {LinearSolver::kPcgIncompleteCholesky, "pcg_incomplete_cholesky"}};
  return names;
}

const EnumNames<Cholesky>& CholeskyNames() {
  static const EnumNames<Cholesky> names{{Cholesky::kSupernodal, "supernodal"},
                                         {Cholesky::kEigenLLT, "eigen_llt"},
                                         {Cholesky::kEigenLDLT, "eigen_ldlt"},
                                         {Cholesky::kCholmod, "cholmod"}};
  return names;
}

const EnumNames<Factorization>& FactorizationNames() {
  static const EnumNames<Factorization> names{{Factorization::kEveryIteration, "every_iteration"},
                                              {Factorization::kPerFrame, "per_frame"},
                                              {Factorization::kLagged, "lagged"}};
  return names;
}

const EnumNames<Damping>& DampingNames() {
  static const EnumNames<Damping> names{{Damping::kGaussNewton, "gauss_newton"},
                                        {Damping::kLevenbergMarquardt, "levenberg_marquardt"}};
  return names;
}

const char* LinearSolverName(LinearSolver solver) { return LinearSolverNames().Name(solver); }
bool ParseLinearSolver(const std::string& name, LinearSolver* solver) {
  return LinearSolverNames().Parse(name, solver);
}
const char* CholeskyName(Cholesky cholesky) { return CholeskyNames().Name(cholesky); }
bool ParseCholesky(const std::string& name, Cholesky* cholesky) {
  return CholeskyNames().Parse(name, cholesky);
}
const char* FactorizationName(Factorization factorization) {
  return FactorizationNames().Name(factorization);
}
bool ParseFactorization(const std::string& name, Factorization* factorization) {
  return FactorizationNames().Parse(name, factorization);
}
const char* DampingName(Damping damping) { return DampingNames().Name(damping); }
bool ParseDamping(const std::string& name, Damping* damping) {
  return DampingNames().Parse(name, damping);
}

bool GaussNewtonHasCholmod() {
#ifdef MSDEFORM_HAVE_CHOLMOD
  return true;
#else
  return false;
#endif
}

const OptionTable<GaussNewtonOptions>& GaussNewtonOptionTable() {
  static const OptionTable<GaussNewtonOptions>& table =
      MakeOptionTable<GaussNewtonOptions>([](auto& t) { DeclareGaussNewtonOptionRows(t); });
  return table;
}

}  // namespace msdeform
