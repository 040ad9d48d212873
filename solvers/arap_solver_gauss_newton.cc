// ArapGaussNewtonSolver (solvers/arap_solver.h): Gauss-Newton on the subspace
// ARAP energy's nodes and cluster rotations, the rotations eliminated per
// cluster.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include <Eigen/Cholesky>
#include <glog/logging.h>

#include "msdeform/solvers/arap_solver.h"
#include "msdeform/solvers/subspace_arap_terms.h"

namespace msdeform {

ArapGaussNewtonSolver::ArapGaussNewtonSolver(const GaussNewtonOptions& options,
                                             const StoppingRule& stopping)
    : options_(options), stopping_(stopping) {
  // The reduced matrix changes with the cluster rotations at every step: a
  // kept factorisation gives chord steps, whose small decreases stop the
  // function test short of the minimum (the bent bar with soft
  // constraints of tests/solvers/arap_backends_test.cc: 8.37e-6 of the
  // diagonal from the local/global solver's vertices, 8.12e-6 allowed).
  options_.factorization = GaussNewtonOptions::Factorization::kEveryIteration;
  // CHOLMOD's supernodal LLT (Eigen's LLT without it), as before the loop
  // was shared: the matrix fills in (clusters reach many nodes), and with
  // the supernodal Cholesky of the Eq. 17 backend the soft-constraint case
  // of that test ends outside its 8.12e-6 by rounding.
  if (options_.linear_solver == GaussNewtonOptions::LinearSolver::kCholesky)
    options_.cholesky = GaussNewtonOptions::Cholesky::kCholmod;
}
ArapGaussNewtonSolver::~ArapGaussNewtonSolver() = default;

bool ArapGaussNewtonSolver::Setup(const DeformationEnergy& energy,
                                  const NodeTransforms& transforms, std::string* error) {
  (void)transforms;  // the constant slots are gathered from each frame's transforms
  if (!options_.Check(error) || !stopping_.Check(error)) return false;
  if (!IsArapEnergyAlone(energy, "the subspace ARAP Gauss-Newton solver", error)) return false;
  arap_ = FindSubspaceArap(energy);
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
  damping_floor_ = ArapDampingFloor(diagonal_);
  state_ = DampedGaussNewtonState();
  linear_solver_ = MakeGaussNewtonLinearSolver(options_);
  if (n > 0) {
    matrix_.coeffs() = base_values_;
    linear_solver_->Analyze(matrix_);
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

// One frame of the subspace ARAP energy for the damped Gauss-Newton loop:
// the variables v (x = v flattened, variable (slot p, coordinate d) at
// 3 p + d), u and the optimal rotations at them, the reduced system and its
// right-hand side. The system and the right-hand side are in Q's scale
// (2 unit^2 E); the cost and the gradient in the energy's.
class ArapGaussNewtonSolver::Frame : public DampedGaussNewtonProblem {
 public:
  Frame(ArapGaussNewtonSolver* solver, const HandleTransforms& handles,
        const NodeTransforms& transforms)
      : solver_(*solver), arap_(*solver->arap_) {
    arap_.Gather(transforms, handles, &u_);
    energy_ = arap_.EnergyFromTrace(u_, arap_.FitRotations(u_, &rotations_));
    arap_.Variables(u_, &v_);
    if (std::isfinite(energy_)) Linearize();
  }

  const SubspaceArap::Slots& u() const { return u_; }
  int num_variables() const override { return 3 * arap_.num_slot_variables(); }
  double cost() const override { return energy_; }
  const Eigen::VectorXd& gradient() const override { return gradient_; }
  double x_norm() const override { return v_.norm(); }
  void Assemble(double mu) override {
    solver_.matrix_.coeffs() = solver_.assembled_;
    for (int i = 0; i < num_variables(); ++i) {
      solver_.matrix_.coeffs()[solver_.diagonal_index_[i]] +=
          mu * solver_.diagonal_[i / 3] + solver_.damping_floor_;
    }
  }
  SparseMatrix& system() override { return solver_.matrix_; }
  void StepRhs(Eigen::VectorXd* rhs) const override { *rhs = rhs_; }
  // 1/2 delta^T (mu D delta + rhs), in the energy's scale.
  double PredictedDecrease(const Eigen::VectorXd& delta, double mu) const override {
    double damped = 0.0;
    for (int i = 0; i < num_variables(); ++i)
      damped += delta[i] * delta[i] * mu * solver_.diagonal_[i / 3];
    const double unit2 = arap_.length_unit() * arap_.length_unit();
    return 0.5 * (damped + delta.dot(rhs_)) / unit2;
  }
  double TrialCost(const Eigen::VectorXd& delta) override {
    trial_v_ = v_;
    for (int p = 0; p < arap_.num_slot_variables(); ++p)
      for (int d = 0; d < 3; ++d) trial_v_(p, d) += delta[3 * p + d];
    trial_u_ = u_;
    arap_.SetVariables(trial_v_, &trial_u_);
    trial_energy_ =
        arap_.EnergyFromTrace(trial_u_, arap_.FitRotations(trial_u_, &trial_rotations_));
    return trial_energy_;
  }
  void Accept() override {
    std::swap(v_, trial_v_);
    std::swap(u_, trial_u_);
    std::swap(rotations_, trial_rotations_);
    energy_ = trial_energy_;
    Linearize();
  }
  double noise_floor() const override { return solver_.noise_floor_; }
  // Near the minimum the refitted rotations often give a trial the same
  // energy to the last bit; accepting it keeps the nodes moving along the
  // flat valley (refusing it ends 1.3e-5 of the diagonal from the
  // local/global solver's vertices on that bent bar, 8.12e-6 allowed).
  bool accepts_equal_cost() const override { return true; }

 private:
  // The gradient, the reduced matrix (solver_.assembled_) and the
  // right-hand side at u.
  void Linearize() {
    const int nv = arap_.num_slot_variables();
    // g_v = Q_vv v + Q_vk k - sum_c K_c^T R_c rows; the energy's gradient in
    // v is g_v / unit^2.
    SubspaceArap::Slots g, rhs;
    arap_.GlobalRhs(u_, rotations_, &g);
    g = arap_.system_matrix() * v_ - g;
    solver_.Assemble(u_, rotations_, g, &rhs);
    const double unit2 = arap_.length_unit() * arap_.length_unit();
    gradient_.resize(3 * nv);
    rhs_.resize(3 * nv);
    for (int p = 0; p < nv; ++p) {
      for (int d = 0; d < 3; ++d) {
        gradient_[3 * p + d] = g(p, d) / unit2;
        rhs_[3 * p + d] = rhs(p, d);
      }
    }
  }

  ArapGaussNewtonSolver& solver_;
  const SubspaceArap& arap_;
  SubspaceArap::Slots u_, v_, trial_u_, trial_v_;
  SubspaceArap::Rotations rotations_, trial_rotations_;
  double energy_ = 0.0, trial_energy_ = 0.0;
  Eigen::VectorXd gradient_, rhs_;
};

SolveSummary ArapGaussNewtonSolver::Solve(const HandleTransforms& handles,
                                          NodeTransforms* transforms) {
  const auto start = std::chrono::steady_clock::now();
  Frame frame(this, handles, *transforms);
  SolveSummary summary;
  summary.initial_cost = frame.cost();
  summary.trace.push_back({0.0, frame.cost()});
  if (!std::isfinite(frame.cost())) {
    summary.failed = true;
    summary.final_cost = frame.cost();
    summary.message = "the energy is not finite at the initial guess";
    return summary;
  }
  RunDampedGaussNewton(options_, stopping_, start, linear_solver_.get(), &frame, &state_,
                       &summary);
  arap_->Scatter(frame.u(), transforms);
  return summary;
}

double ArapGaussNewtonSolver::Cost(const HandleTransforms& handles,
                                   const NodeTransforms& transforms) {
  SubspaceArap::Slots u;
  arap_->Gather(transforms, handles, &u);
  return arap_->Cost(u);
}

std::unique_ptr<FrameSolver> MakeArapSolver(ArapSolver solver, const StoppingRule& stopping,
                                            const GaussNewtonOptions& gauss_newton,
                                            int anderson_window) {
  if (solver == ArapSolver::kGaussNewton)
    return std::make_unique<ArapGaussNewtonSolver>(gauss_newton, stopping);
  return std::make_unique<ArapLocalGlobalSolver>(stopping, anderson_window);
}

}  // namespace msdeform
