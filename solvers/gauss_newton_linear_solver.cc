#include "msdeform/solvers/gauss_newton_linear_solver.h"

#include "msdeform/solvers/gauss_newton_supernodal_cholesky.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#ifdef MSDEFORM_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

namespace msdeform {
namespace {

using SparseMatrix = GaussNewtonLinearSolver::SparseMatrix;

// Sparse Cholesky (Eigen's simplicial LLT or LDLT, or CHOLMOD's supernodal
// LLT); `Positive` adds the check an LDLT needs (D > 0).
template <typename Factorization>
class SparseCholesky : public GaussNewtonLinearSolver {
 public:
  void Analyze(const SparseMatrix& system) override { factorization_.analyzePattern(system); }
  bool Factorize(const SparseMatrix& system) override {
    factorization_.factorize(system);
    return factorization_.info() == Eigen::Success && Positive();
  }
  bool Solve(const SparseMatrix&, const Eigen::VectorXd& rhs, double,
             Eigen::VectorXd* delta) override {
    *delta = factorization_.solve(rhs);
    return delta->allFinite();
  }
  bool direct() const override { return true; }

 private:
  bool Positive() const;
  Factorization factorization_;
};

using EigenLLT = Eigen::SimplicialLLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>>;
using EigenLDLT = Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>>;

template <>
bool SparseCholesky<EigenLLT>::Positive() const {
  return true;
}
template <>
bool SparseCholesky<EigenLDLT>::Positive() const {
  return (factorization_.vectorD().array() > 0.0).all();
}
#ifdef MSDEFORM_HAVE_CHOLMOD
using CholmodLLT = Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower>;
template <>
bool SparseCholesky<CholmodLLT>::Positive() const {
  return true;
}
#endif

// SupernodalCholesky (solvers/gauss_newton_supernodal_cholesky.h).
class Supernodal : public GaussNewtonLinearSolver {
 public:
  void Analyze(const SparseMatrix& system) override { cholesky_.Analyze(system); }
  bool Factorize(const SparseMatrix& system) override { return cholesky_.Factorize(system); }
  bool Solve(const SparseMatrix&, const Eigen::VectorXd& rhs, double,
             Eigen::VectorXd* delta) override {
    cholesky_.Solve(rhs, delta);
    return delta->allFinite();
  }
  bool direct() const override { return true; }

 private:
  SupernodalCholesky cholesky_;
};

// Preconditioned conjugate gradients on the current system; Factorize
// builds the preconditioner.
class Pcg : public GaussNewtonLinearSolver {
 public:
  explicit Pcg(int max_iterations) : max_iterations_(max_iterations) {}
  void Analyze(const SparseMatrix&) override {}
  bool Solve(const SparseMatrix& system, const Eigen::VectorXd& rhs, double eta,
             Eigen::VectorXd* delta) override {
    delta->setZero(rhs.size());
    Eigen::VectorXd r = rhs, z = Precondition(r), p = z, q;
    double rz = r.dot(z);
    const double target = eta * rhs.norm();
    for (int it = 0; it < max_iterations_ && r.norm() > target; ++it) {
      q.noalias() = system * p;
      const double pq = p.dot(q);
      if (!(pq > 0.0)) break;
      const double step = rz / pq;
      *delta += step * p;
      r -= step * q;
      z = Precondition(r);
      const double rz_new = r.dot(z);
      p = z + (rz_new / rz) * p;
      rz = rz_new;
    }
    return delta->allFinite();
  }
  bool direct() const override { return false; }

 protected:
  virtual Eigen::VectorXd Precondition(const Eigen::VectorXd& r) const = 0;

 private:
  const int max_iterations_;
};

class PcgJacobi : public Pcg {
 public:
  using Pcg::Pcg;
  bool Factorize(const SparseMatrix& system) override {
    inverse_diagonal_ = system.diagonal().cwiseInverse();
    return inverse_diagonal_.allFinite() && (inverse_diagonal_.array() > 0.0).all();
  }

 protected:
  Eigen::VectorXd Precondition(const Eigen::VectorXd& r) const override {
    return inverse_diagonal_.cwiseProduct(r);
  }

 private:
  Eigen::VectorXd inverse_diagonal_;
};

class PcgIncompleteCholesky : public Pcg {
 public:
  using Pcg::Pcg;
  bool Factorize(const SparseMatrix& system) override {
    incomplete_.compute(system);
    return incomplete_.info() == Eigen::Success;
  }

 protected:
  Eigen::VectorXd Precondition(const Eigen::VectorXd& r) const override {
    return incomplete_.solve(r);
  }

 private:
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::AMDOrdering<int>> incomplete_;
};

}  // namespace

std::unique_ptr<GaussNewtonLinearSolver> MakeGaussNewtonLinearSolver(
    const GaussNewtonOptions& options) {
  using LinearSolver = GaussNewtonOptions::LinearSolver;
  using Cholesky = GaussNewtonOptions::Cholesky;
  switch (options.linear_solver) {
    case LinearSolver::kPcgJacobi:
      return std::make_unique<PcgJacobi>(options.max_cg_iterations);
    case LinearSolver::kPcgIncompleteCholesky:
      return std::make_unique<PcgIncompleteCholesky>(options.max_cg_iterations);
    case LinearSolver::kCholesky:
      break;
  }
  if (options.cholesky == Cholesky::kSupernodal) return std::make_unique<Supernodal>();
  if (options.cholesky == Cholesky::kEigenLDLT) return std::make_unique<SparseCholesky<EigenLDLT>>();
#ifdef MSDEFORM_HAVE_CHOLMOD
  if (options.cholesky == Cholesky::kCholmod) return std::make_unique<SparseCholesky<CholmodLLT>>();
#endif
  return std::make_unique<SparseCholesky<EigenLLT>>();
}

}  // namespace msdeform
