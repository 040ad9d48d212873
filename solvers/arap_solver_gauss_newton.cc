// ArapGaussNewtonSolver (solvers/arap_solver.h): Gauss-Newton on the subspace
// ARAP energy's nodes and cluster rotations, the rotations eliminated per
// cluster.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#ifdef MSDEFORM_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif
#include <glog/logging.h>

#include "msdeform/core/timing.h"
#include "msdeform/solvers/arap_solver.h"

namespace msdeform {

struct ArapGaussNewtonSolver::Factorization {
#ifdef MSDEFORM_HAVE_CHOLMOD
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> cholesky;
#else
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>>
      cholesky;
#endif
};

ArapGaussNewtonSolver::ArapGaussNewtonSolver(const StoppingRule& stopping)
    : stopping_(stopping), factorization_(std::make_unique<Factorization>()) {}
ArapGaussNewtonSolver::~ArapGaussNewtonSolver() = default;

bool ArapGaussNewtonSolver::Setup(const DeformationEnergy& energy,
                                  const NodeTransforms& transforms, std::string* error) {
  (void)transforms;  // the constant slots are gathered from each frame's transforms
  if (!IsArapEnergyAlone(energy, "the subspace ARAP Gauss-Newton solver", error)) return false;
  arap_ = energy.arap;
  noise_floor_ = ArapEnergyNoiseFloor(*arap_);
  const SubspaceArap& arap = *arap_;
  const int nv = arap.num_slot_variables();
  const Eigen::SparseMatrix<double>& q = arap.system_matrix();
  const std::vector<int>& k_offsets = arap.k_offsets();
  const std::vector<int>& k_slots = arap.k_slots();

  // Each cluster's variables, and the slot-level pattern: the diagonal,
  // Q_vv's and every pair of variables one cluster reaches.
  cluster_variable_offsets_.assign(1, 0);
  cluster_variables_.clear();
  cluster_entries_.clear();
  std::vector<Eigen::Triplet<double>> pattern;
  for (int p = 0; p < nv; ++p) pattern.emplace_back(p, p, 1.0);  // a slot no spoke reaches too
  for (int col = 0; col < q.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(q, col); it; ++it)
      pattern.emplace_back(it.row(), col, 1.0);
  for (int c = 0; c < arap.num_clusters(); ++c) {
    const int first = static_cast<int>(cluster_variables_.size());
    for (int e = k_offsets[c]; e < k_offsets[c + 1]; ++e) {
      const int variable = arap.variable_of_slot(k_slots[e]);
      if (variable < 0) continue;
      cluster_variables_.push_back(variable);
      cluster_entries_.push_back(e);
    }
    const int last = static_cast<int>(cluster_variables_.size());
    for (int a = first; a < last; ++a)
      for (int b = first; b < last; ++b)
        pattern.emplace_back(cluster_variables_[a], cluster_variables_[b], 1.0);
    cluster_variable_offsets_.push_back(last);
  }
  Eigen::SparseMatrix<double> slots(nv, nv);
  slots.setFromTriplets(pattern.begin(), pattern.end());
  slots.makeCompressed();

  // The 3 nv pattern: each slot entry (p, q) a dense 3x3 block; in column
  // 3 q + d' the rows of a slot column's entries, 3 each, in order.
  const int n = 3 * nv;
  Eigen::SparseMatrix<double> matrix(n, n);
  Eigen::VectorXi column_sizes(n);
  column_stride_.assign(nv, 0);
  for (int col = 0; col < nv; ++col) {
    column_stride_[col] = 3 * (slots.outerIndexPtr()[col + 1] - slots.outerIndexPtr()[col]);
    for (int d = 0; d < 3; ++d) column_sizes[3 * col + d] = column_stride_[col];
  }
  matrix.reserve(column_sizes);
  for (int col = 0; col < nv; ++col)
    for (int d = 0; d < 3; ++d)
      for (Eigen::SparseMatrix<double>::InnerIterator it(slots, col); it; ++it)
        for (int r = 0; r < 3; ++r) matrix.insert(3 * it.row() + r, 3 * col + d) = 0.0;
  matrix.makeCompressed();
  matrix_ = std::move(matrix);
  // The value index of block (p, q)'s (0, 0) entry.
  auto block_index = [&](int p, int col) {
    const int* begin = slots.innerIndexPtr() + slots.outerIndexPtr()[col];
    const int* end = slots.innerIndexPtr() + slots.outerIndexPtr()[col + 1];
    const int* found = std::lower_bound(begin, end, p);
    CHECK(found != end && *found == p);
    const int index = matrix_.outerIndexPtr()[3 * col] + 3 * static_cast<int>(found - begin);
    CHECK_EQ(matrix_.innerIndexPtr()[index], 3 * p);
    return index;
  };
  base_values_ = Eigen::VectorXd::Zero(matrix_.nonZeros());
  for (int col = 0; col < nv; ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(q, col); it; ++it) {
      const int index = block_index(it.row(), col);
      for (int d = 0; d < 3; ++d) base_values_[index + d + d * column_stride_[col]] += it.value();
    }
  }
  diagonal_ = q.diagonal();
  diagonal_index_.resize(n);
  for (int p = 0; p < nv; ++p) {
    const int index = block_index(p, p);
    for (int d = 0; d < 3; ++d) diagonal_index_[3 * p + d] = index + d + d * column_stride_[p];
  }
  cluster_pair_offsets_.assign(1, 0);
  cluster_pair_index_.clear();
  for (int c = 0; c < arap.num_clusters(); ++c) {
    const int first = cluster_variable_offsets_[c], last = cluster_variable_offsets_[c + 1];
    for (int b = first; b < last; ++b)
      for (int a = first; a < last; ++a)
        cluster_pair_index_.push_back(block_index(cluster_variables_[a], cluster_variables_[b]));
    cluster_pair_offsets_.push_back(static_cast<int>(cluster_pair_index_.size()));
  }
  // D_c = tr(Cov_c) I - Cov_c = L L^T; clusters whose D_c is not positive
  // definite (all spokes on one line, or negative cotangent weights) keep
  // their rotation out of the coupling (L^-1 = 0).
  d_inverse_factor_.assign(arap.num_clusters(), Eigen::Matrix3d::Zero());
  for (int c = 0; c < arap.num_clusters(); ++c) {
    const Eigen::Matrix3d& cov = arap.cluster_covariances()[c];
    const Eigen::Matrix3d d = cov.trace() * Eigen::Matrix3d::Identity() - cov;
    const Eigen::LLT<Eigen::Matrix3d> llt(d);
    if (llt.info() != Eigen::Success) continue;
    const Eigen::Matrix3d l = llt.matrixL();
    if (!(l.diagonal().minCoeff() > 1e-8 * l.diagonal().maxCoeff())) continue;
    d_inverse_factor_[c] = l.inverse();
  }
  lambda_ = kMinLambda;
  if (n > 0) {
    matrix_.coeffs() = base_values_;
    factorization_->cholesky.analyzePattern(matrix_);
  }
  return true;
}

void ArapGaussNewtonSolver::Assemble(const SubspaceArap::Slots& u,
                                     const SubspaceArap::Rotations& rotations,
                                     const SubspaceArap::Slots& gradient,
                                     SubspaceArap::Slots* rhs) {
  const SubspaceArap& arap = *arap_;
  const std::vector<int>& k_offsets = arap.k_offsets();
  const std::vector<int>& k_slots = arap.k_slots();
  const Eigen::Matrix3Xd& k_vectors = arap.k_vectors();
  assembled_ = base_values_;
  *rhs = -gradient;
  Eigen::Matrix<double, Eigen::Dynamic, 3> y;
  for (int c = 0; c < arap.num_clusters(); ++c) {
    const Eigen::Matrix3d& l_inverse = d_inverse_factor_[c];
    if (l_inverse(0, 0) == 0.0) continue;
    const int first = cluster_variable_offsets_[c];
    const int count = cluster_variable_offsets_[c + 1] - first;
    if (count == 0) continue;
    const Eigen::Matrix3d& r = rotations[c];
    Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
    for (int e = k_offsets[c]; e < k_offsets[c + 1]; ++e)
      s.noalias() += u.row(k_slots[e]).transpose() * k_vectors.col(e).transpose();
    const Eigen::Matrix3d m = r.transpose() * s;
    const Eigen::Matrix3d skew = m.transpose() - m;
    const Eigen::Vector3d z = l_inverse * Eigen::Vector3d(skew(2, 1), skew(0, 2), skew(1, 0));
    // Y = B_c L^-T: row (a, d) = (L^-1 (R(d, :)^T x k_a))^T.
    y.resize(3 * count, 3);
    for (int a = 0; a < count; ++a) {
      const Eigen::Vector3d k = k_vectors.col(cluster_entries_[first + a]);
      const int p = cluster_variables_[first + a];
      for (int d = 0; d < 3; ++d) {
        y.row(3 * a + d) = (l_inverse * r.row(d).transpose().cross(k)).transpose();
        (*rhs)(p, d) += y.row(3 * a + d).dot(z);
      }
    }
    const Eigen::MatrixXd block = y * y.transpose();
    const int* pair = cluster_pair_index_.data() + cluster_pair_offsets_[c];
    for (int b = 0; b < count; ++b) {
      const int stride = column_stride_[cluster_variables_[first + b]];
      for (int a = 0; a < count; ++a, ++pair) {
        for (int dc = 0; dc < 3; ++dc)
          for (int dr = 0; dr < 3; ++dr)
            assembled_[*pair + dr + dc * stride] -= block(3 * a + dr, 3 * b + dc);
      }
    }
  }
}

SolveSummary ArapGaussNewtonSolver::Solve(const Eigen::Affine3d& handle,
                                          NodeTransforms* transforms) {
  const auto start = std::chrono::steady_clock::now();
  const SubspaceArap& arap = *arap_;
  SolveSummary summary;
  SubspaceArap::Slots u, v, rhs, gradient, trial_u, trial_v;
  SubspaceArap::Rotations rotations, trial_rotations;
  arap.Gather(*transforms, handle, &u);
  double energy = arap.EnergyFromTrace(u, arap.FitRotations(u, &rotations));
  summary.initial_cost = energy;
  summary.trace.push_back({0.0, energy});
  summary.message = "iteration budget";
  if (!std::isfinite(energy)) {
    summary.failed = true;
    summary.final_cost = energy;
    summary.message = "the energy is not finite at the initial guess";
    return summary;
  }
  arap.Variables(u, &v);
  const int nv = arap.num_slot_variables();
  const double unit2 = arap.length_unit() * arap.length_unit();
  const double floor = ArapDampingFloor(diagonal_);
  Eigen::VectorXd b(3 * nv), step(3 * nv);
  bool done = nv == 0;
  while (!done && summary.iterations < stopping_.max_iterations) {
    // g_v = Q_vv v + Q_vk k - sum_c K_c^T R_c rows; the energy's gradient
    // in v is g_v / unit^2.
    arap.GlobalRhs(u, rotations, &gradient);
    gradient = arap.system_matrix() * v - gradient;
    if (gradient.cwiseAbs().maxCoeff() / unit2 <= stopping_.gradient_tolerance) {
      summary.converged = true;
      summary.message = "gradient tolerance";
      break;
    }
    Assemble(u, rotations, gradient, &rhs);
    for (int p = 0; p < nv; ++p)
      for (int d = 0; d < 3; ++d) b[3 * p + d] = rhs(p, d);
    bool accepted = false;
    while (!accepted && summary.iterations < stopping_.max_iterations) {
      matrix_.coeffs() = assembled_;
      for (int i = 0; i < 3 * nv; ++i)
        matrix_.coeffs()[diagonal_index_[i]] += lambda_ * diagonal_[i / 3] + floor;
      factorization_->cholesky.factorize(matrix_);
      ++summary.iterations;
      ++summary.factorizations;
      if (factorization_->cholesky.info() != Eigen::Success) {
        lambda_ *= 10.0;
        summary.trace.push_back({MillisecondsSince(start), energy});
        continue;
      }
      step = factorization_->cholesky.solve(b);
      trial_v = v;
      for (int p = 0; p < nv; ++p)
        for (int d = 0; d < 3; ++d) trial_v(p, d) += step[3 * p + d];
      trial_u = u;
      arap.SetVariables(trial_v, &trial_u);
      const double trial =
          arap.EnergyFromTrace(trial_u, arap.FitRotations(trial_u, &trial_rotations));
      if (std::isfinite(trial) && trial <= energy) {
        accepted = true;
        lambda_ = std::max(kMinLambda, 0.1 * lambda_);
        const double previous = energy;
        const double size = v.norm();
        energy = trial;
        std::swap(v, trial_v);
        std::swap(u, trial_u);
        std::swap(rotations, trial_rotations);
        summary.trace.push_back({MillisecondsSince(start), energy});
        if (energy > noise_floor_ &&
            previous - energy <= stopping_.function_tolerance * previous) {
          summary.converged = true;
          summary.message = "function tolerance";
          done = true;
        } else if (step.norm() <=
                   stopping_.parameter_tolerance * (size + stopping_.parameter_tolerance)) {
          summary.converged = true;
          summary.message = "parameter tolerance";
          done = true;
        }
      } else {
        lambda_ *= 10.0;
        summary.trace.push_back({MillisecondsSince(start), energy});
      }
    }
  }
  summary.final_cost = energy;
  arap.Scatter(u, transforms);
  return summary;
}

double ArapGaussNewtonSolver::Cost(const Eigen::Affine3d& handle,
                                   const NodeTransforms& transforms) {
  SubspaceArap::Slots u;
  arap_->Gather(transforms, handle, &u);
  return arap_->Cost(u);
}

std::unique_ptr<FrameSolver> MakeArapSolver(ArapSolver solver, const StoppingRule& stopping) {
  if (solver == ArapSolver::kGaussNewton)
    return std::make_unique<ArapGaussNewtonSolver>(stopping);
  return std::make_unique<ArapLocalGlobalSolver>(stopping);
}

}  // namespace msdeform
