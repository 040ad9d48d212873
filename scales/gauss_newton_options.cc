// GaussNewtonOptions (scales/gauss_newton_solver.h): Check and the enum names.

#include <cmath>
#include <string>

#include "msdeform/scales/gauss_newton_solver.h"

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

namespace {

template <typename Enum, size_t N>
bool ParseByName(const std::string& name, const Enum (&values)[N], const char* (*to_name)(Enum),
                 Enum* value) {
  for (Enum candidate : values) {
    if (name == to_name(candidate)) {
      *value = candidate;
      return true;
    }
  }
  return false;
}

using LinearSolver = GaussNewtonOptions::LinearSolver;
using Cholesky = GaussNewtonOptions::Cholesky;
using Factorization = GaussNewtonOptions::Factorization;
using Damping = GaussNewtonOptions::Damping;

}  // namespace

const char* LinearSolverName(LinearSolver solver) {
  switch (solver) {
    case LinearSolver::kCholesky:
      return "cholesky";
    case LinearSolver::kPcgJacobi:
      return "pcg_jacobi";
    case LinearSolver::kPcgIncompleteCholesky:
      return "pcg_incomplete_cholesky";
  }
  return "unknown";
}

bool ParseLinearSolver(const std::string& name, LinearSolver* solver) {
  static constexpr LinearSolver kAll[] = {LinearSolver::kCholesky, LinearSolver::kPcgJacobi,
                                          LinearSolver::kPcgIncompleteCholesky};
  return ParseByName(name, kAll, LinearSolverName, solver);
}

const char* CholeskyName(Cholesky cholesky) {
  switch (cholesky) {
    case Cholesky::kEigenLLT:
      return "eigen_llt";
    case Cholesky::kEigenLDLT:
      return "eigen_ldlt";
    case Cholesky::kCholmod:
      return "cholmod";
  }
  return "unknown";
}

bool ParseCholesky(const std::string& name, Cholesky* cholesky) {
  static constexpr Cholesky kAll[] = {Cholesky::kEigenLLT, Cholesky::kEigenLDLT,
                                      Cholesky::kCholmod};
  return ParseByName(name, kAll, CholeskyName, cholesky);
}

const char* FactorizationName(Factorization factorization) {
  switch (factorization) {
    case Factorization::kEveryIteration:
      return "every_iteration";
    case Factorization::kPerFrame:
      return "per_frame";
    case Factorization::kLagged:
      return "lagged";
  }
  return "unknown";
}

bool ParseFactorization(const std::string& name, Factorization* factorization) {
  static constexpr Factorization kAll[] = {Factorization::kEveryIteration,
                                           Factorization::kPerFrame, Factorization::kLagged};
  return ParseByName(name, kAll, FactorizationName, factorization);
}

const char* DampingName(Damping damping) {
  switch (damping) {
    case Damping::kGaussNewton:
      return "gauss_newton";
    case Damping::kLevenbergMarquardt:
      return "levenberg_marquardt";
  }
  return "unknown";
}

bool ParseDamping(const std::string& name, Damping* damping) {
  static constexpr Damping kAll[] = {Damping::kGaussNewton, Damping::kLevenbergMarquardt};
  return ParseByName(name, kAll, DampingName, damping);
}

bool GaussNewtonHasCholmod() {
#ifdef MSDEFORM_HAVE_CHOLMOD
  return true;
#else
  return false;
#endif
}

}  // namespace msdeform
