// GaussNewtonOptions (solvers/gauss_newton_solver.h): Check and the enum names.

#include <cmath>
#include <string>

#include "msdeform/solvers/gauss_newton_solver.h"

namespace msdeform {

bool GaussNewtonOptions::Check(std::string* error) const {
  if (!(min_damping > 0.0) || !std::isfinite(min_damping)) {
    *error = "Gauss-Newton min_damping must be a finite number > 0";
    return false;
  }
  if (!(initial_damping > 0.0) || !std::isfinite(initial_damping)) {
    *error = "Gauss-Newton initial_damping must be a finite number > 0";
    return false;
  }
  if (!(forcing_term > 0.0 && forcing_term < 1.0)) {
    *error = "Gauss-Newton forcing_term must be in (0, 1)";
    return false;
  }
  if (!(refactor_ratio > 0.0) || !std::isfinite(refactor_ratio)) {
    *error = "Gauss-Newton refactor_ratio must be a finite number > 0";
    return false;
  }
  if (max_cg_iterations < 1) {
    *error = "Gauss-Newton max_cg_iterations must be >= 1";
    return false;
  }
  return true;
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

}  // namespace msdeform
