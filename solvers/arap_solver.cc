#include "msdeform/solvers/arap_solver.h"

#include <chrono>
#include <cmath>
#include <memory>
#include <utility>

#include "msdeform/core/timing.h"
#include "msdeform/solvers/anderson_acceleration.h"
#include "msdeform/solvers/subspace_arap_terms.h"

namespace msdeform {

double ArapEnergyNoiseFloor(const SubspaceArap& arap) {
  double spokes = 0.0;  // C = sum_c tr(Cov_c)
  for (const Eigen::Matrix3d& cov : arap.cluster_covariances()) spokes += std::abs(cov.trace());
  return 1e-12 * 0.5 * spokes / (arap.length_unit() * arap.length_unit());
}

double ArapDampingFloor(const Eigen::VectorXd& diagonal) {
  const double mean = diagonal.size() > 0 ? diagonal.mean() : 0.0;
  return mean > 0.0 ? 1e-12 * mean : 1.0;
}

bool ArapLocalGlobalSolver::Setup(const DeformationEnergy& energy,
                                  const NodeTransforms& transforms, std::string* error) {
  (void)transforms;  // the constant slots are gathered from each frame's transforms
  if (!IsArapEnergyAlone(energy, "the local/global solver", error)) return false;
  arap_ = FindSubspaceArap(energy);
  noise_floor_ = ArapEnergyNoiseFloor(*arap_);
  const Eigen::SparseMatrix<double>& q = arap_->system_matrix();
  const int n = q.rows();
  damping_.resize(n);
  if (n == 0) return true;
  damping_ = Eigen::VectorXd::Constant(n, ArapDampingFloor(q.diagonal()));
  Eigen::SparseMatrix<double> matrix = q;
  for (int i = 0; i < n; ++i) matrix.coeffRef(i, i) += damping_[i];
  factorization_.compute(matrix);
  if (factorization_.info() != Eigen::Success) {
    *error = "the subspace ARAP global step's matrix could not be factorised";
    return false;
  }
  // The layout starts at rest: every cluster's rotation is I.
  previous_rotations_.assign(arap_->num_clusters(), Eigen::Matrix3d::Identity());
  return true;
}

SolveSummary ArapLocalGlobalSolver::Solve(const HandleTransforms& handles,
                                          NodeTransforms* transforms) {
  const auto start = std::chrono::steady_clock::now();
  SolveSummary summary;
  SubspaceArap::Slots u, v, rhs, next;
  SubspaceArap::Rotations rotations;
  arap_->Gather(*transforms, handles, &u);
  double energy = arap_->EnergyFromTrace(u, arap_->FitRotations(u, &rotations));
  summary.initial_cost = energy;
  summary.trace.push_back({0.0, energy});
  summary.message = "iteration budget";
  if (!std::isfinite(energy)) {
    summary.failed = true;
    summary.final_cost = energy;
    summary.message = "the energy is not finite at the initial guess";
    return summary;
  }
  arap_->Variables(u, &v);
  // The first global step may take the last frame's rotations instead of
  // those fitted to this frame's start, whose handle has jumped: kept when it
  // ends lower than the fitted ones' step would start (a rigid motion of
  // handle and free region is then one step from its optimum).
  bool first_step_with_previous = previous_rotations_.size() == rotations.size() &&
                                  stopping_.max_iterations > 0 && v.rows() > 0;
  std::unique_ptr<AndersonAcceleration> anderson;
  if (anderson_window_ > 0 && v.rows() > 0) {
    anderson = std::make_unique<AndersonAcceleration>(static_cast<int>(v.size()), anderson_window_);
  }
  SubspaceArap::Slots accelerated_next;
  double trial_energy = 0.0;
  for (int iteration = 0; iteration < stopping_.max_iterations && v.rows() > 0; ++iteration) {
    if (first_step_with_previous) {
      first_step_with_previous = false;
      arap_->GlobalRhs(u, previous_rotations_, &rhs);
      rhs += damping_.asDiagonal() * v;
      SubspaceArap::Slots trial_v = factorization_.solve(rhs);
      SubspaceArap::Slots trial_u = u;
      arap_->SetVariables(trial_v, &trial_u);
      SubspaceArap::Rotations trial_rotations;
      const double trial =
          arap_->EnergyFromTrace(trial_u, arap_->FitRotations(trial_u, &trial_rotations));
      if (std::isfinite(trial) && trial < energy) {
        ++summary.iterations;
        v = std::move(trial_v);
        u = std::move(trial_u);
        rotations = std::move(trial_rotations);
        energy = trial;
        summary.trace.push_back({MillisecondsSince(start), energy});
        continue;
      }
    }
    arap_->GlobalRhs(u, rotations, &rhs);
    rhs += damping_.asDiagonal() * v;
    next = factorization_.solve(rhs);
    ++summary.iterations;
    // Anderson's step from the plain one, G(v) = next; kept where the energy
    // falls below the last iterate's, else the plain step (the safeguard).
    bool accelerated = false;
    if (anderson != nullptr) {
      accelerated = Accelerate(v, next, energy, anderson.get(), &accelerated_next, &u,
                               &rotations, &trial_energy);
    }
    const SubspaceArap::Slots& step_to = accelerated ? accelerated_next : next;
    const double step = (step_to - v).norm();
    const double size = v.norm();
    v = step_to;
    const double previous = energy;
    if (accelerated) {
      energy = trial_energy;  // u and rotations are the accelerated iterate's
    } else {
      arap_->SetVariables(v, &u);
      energy = arap_->EnergyFromTrace(u, arap_->FitRotations(u, &rotations));
    }
    summary.trace.push_back({MillisecondsSince(start), energy});
    if (!std::isfinite(energy)) {
      summary.failed = true;
      summary.message = "the energy is not finite";
      break;
    }
    // Each step minimises exactly, so a rise is rounding: no evidence of
    // convergence (the parameter test decides). Only a plain step's small
    // change says the iteration has converged: an extrapolation can land
    // close to the last iterate while the plain step would still go far.
    const double decrease = previous - energy;
    const bool small_decrease = energy > noise_floor_ && decrease >= 0.0 &&
                                decrease <= stopping_.function_tolerance * previous;
    const bool small_step =
        step <= stopping_.parameter_tolerance * (size + stopping_.parameter_tolerance);
    if (accelerated) {
      if (small_decrease || small_step) anderson->Reset();
      continue;
    }
    if (small_decrease) {
      summary.converged = true;
      summary.message = "function tolerance";
      break;
    }
    if (small_step) {
      summary.converged = true;
      summary.message = "parameter tolerance";
      break;
    }
  }
  summary.factorizations = 0;  // one per layout, in Setup
  summary.final_cost = energy;
  if (!summary.failed) {
    arap_->Scatter(u, transforms);
    previous_rotations_ = std::move(rotations);
  }
  return summary;
}

bool ArapLocalGlobalSolver::Accelerate(const SubspaceArap::Slots& v,
                                       const SubspaceArap::Slots& plain, double energy,
                                       AndersonAcceleration* anderson, SubspaceArap::Slots* next,
                                       SubspaceArap::Slots* u, SubspaceArap::Rotations* rotations,
                                       double* next_energy) const {
  const int64_t n = v.size();
  Eigen::VectorXd accelerated;
  anderson->Compute(Eigen::Map<const Eigen::VectorXd>(v.data(), n),
                    Eigen::Map<const Eigen::VectorXd>(plain.data(), n), &accelerated);
  if (anderson->history() == 0) return false;  // nothing to combine yet: the plain step
  next->resize(v.rows(), 3);
  Eigen::Map<Eigen::VectorXd>(next->data(), n) = accelerated;
  SubspaceArap::Slots trial_u = *u;
  arap_->SetVariables(*next, &trial_u);
  SubspaceArap::Rotations trial_rotations;
  const double trial =
      arap_->EnergyFromTrace(trial_u, arap_->FitRotations(trial_u, &trial_rotations));
  if (!(trial < energy)) {  // the safeguard (non-finite included)
    anderson->Reset();
    return false;
  }
  *u = std::move(trial_u);
  *rotations = std::move(trial_rotations);
  *next_energy = trial;
  return true;
}

double ArapLocalGlobalSolver::Cost(const HandleTransforms& handles,
                                   const NodeTransforms& transforms) {
  SubspaceArap::Slots u;
  arap_->Gather(transforms, handles, &u);
  return arap_->Cost(u);
}

}  // namespace msdeform
