#include "msdeform/solvers/damped_gauss_newton.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace msdeform {
namespace {

using Factorization = GaussNewtonOptions::Factorization;
using Damping = GaussNewtonOptions::Damping;

double MillisecondsFrom(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// The damping schedule and the factorisation rule of GaussNewtonOptions.
class Schedule {
 public:
  explicit Schedule(const GaussNewtonOptions& options)
      : options_(options),
        levenberg_marquardt_(options.damping == Damping::kLevenbergMarquardt),
        mu_(levenberg_marquardt_ ? options.initial_damping : options.min_damping) {}

  bool levenberg_marquardt() const { return levenberg_marquardt_; }
  double mu() const { return mu_; }
  // The factorisation failed (or its solve, when `fresh`): damp more.
  void Failed() { mu_ *= 10.0; }
  void Accepted(double rho) {
    if (levenberg_marquardt_) {
      mu_ = std::max(mu_ * std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3)),
                     options_.min_damping);
      nu_ = 2.0;
    } else {
      mu_ = std::max(mu_ / 10.0, options_.min_damping);
    }
  }
  // A rejected step: Levenberg-Marquardt grows mu by nu; Gauss-Newton
  // refreshes a stale factorisation first and damps a fresh one more.
  void Rejected(bool fresh) {
    if (levenberg_marquardt_) {
      mu_ *= nu_;
      nu_ *= 2.0;
    } else if (fresh) {
      mu_ *= 10.0;
    }
  }
  // After an accepted step: Gauss-Newton proper and Levenberg-Marquardt
  // refactorise every iteration; the lagged variants keep the factorisation
  // while the gradient shrinks by refactor_ratio a step.
  bool RefactorAfter(double new_gradient_norm, double gradient_norm) const {
    return levenberg_marquardt_ || options_.factorization == Factorization::kEveryIteration ||
           new_gradient_norm > options_.refactor_ratio * gradient_norm;
  }

 private:
  const GaussNewtonOptions& options_;
  const bool levenberg_marquardt_;
  double mu_;
  double nu_ = 2.0;  // Levenberg-Marquardt's growth after a rejected step
};

}  // namespace

void RunDampedGaussNewton(const GaussNewtonOptions& options, const StoppingRule& stopping,
                          std::chrono::steady_clock::time_point start,
                          GaussNewtonLinearSolver* linear_solver,
                          DampedGaussNewtonProblem* problem, DampedGaussNewtonState* state,
                          SolveSummary* summary) {
  Schedule schedule(options);
  double cost = problem->cost();
  Eigen::VectorXd delta, rhs;
  bool done = problem->num_variables() == 0;
  double gradient_norm = problem->gradient().lpNorm<Eigen::Infinity>();
  const double forcing_reference = gradient_norm;  // max |g_0| of the frame
  if (!done && gradient_norm <= stopping.gradient_tolerance) {
    summary->converged = true;
    summary->message = "gradient tolerance";
    done = true;
  }
  // PCG multiplies by the current J^T J, so it reassembles every iteration
  // and only its preconditioner follows the factorisation rule.
  const bool cholesky = linear_solver->direct();
  bool need_factor = !state->factor_valid || state->refactor_next ||
                     options.factorization != Factorization::kLagged ||
                     schedule.levenberg_marquardt();
  bool fresh = false;  // the factorisation is of J^T J at the current x and mu
  // A frame fails when it ends on a system that could not be factorised
  // before any step was taken (the start would come back as a result), or
  // when even the largest damping does not make it factorisable.
  bool factor_failed = false;  // the last factorisation (or its solve) failed
  bool unfactorisable = false;
  int accepted_steps = 0;
  bool assembled = false;  // the system holds J^T J + mu D at the current x and mu
  while (!done && summary->iterations < stopping.max_iterations) {
    if (need_factor || !cholesky) {
      problem->Assemble(schedule.mu());
      assembled = true;
    }
    if (need_factor) {
      ++summary->factorizations;
      need_factor = false;
      state->factor_valid = linear_solver->Factorize(problem->system());
      fresh = true;
      factor_failed = !state->factor_valid;
      if (!state->factor_valid) {
        ++summary->iterations;
        summary->trace.push_back({MillisecondsFrom(start), cost});
        schedule.Failed();
        need_factor = true;
        if (schedule.mu() > 1e32) {
          unfactorisable = true;
          break;
        }
        continue;
      }
    }
    ++summary->iterations;
    const double eta = std::min(options.forcing_term,
                                std::sqrt(gradient_norm / std::max(forcing_reference, 1e-300)));
    problem->StepRhs(&rhs);
    if (!linear_solver->Solve(problem->system(), rhs, eta, &delta)) {
      summary->trace.push_back({MillisecondsFrom(start), cost});
      factor_failed = true;
      state->factor_valid = false;
      need_factor = true;
      if (fresh) schedule.Failed();
      continue;
    }
    factor_failed = false;
    if (delta.norm() <=
        stopping.parameter_tolerance * (problem->x_norm() + stopping.parameter_tolerance)) {
      summary->trace.push_back({MillisecondsFrom(start), cost});
      summary->converged = true;
      summary->message = "parameter tolerance";
      break;
    }
    const double new_cost = problem->TrialCost(delta);
    double rho = 1.0;  // gain ratio, Levenberg-Marquardt only
    if (schedule.levenberg_marquardt() && assembled) {
      const double predicted = problem->PredictedDecrease(delta, schedule.mu());
      rho = predicted > 0.0 ? (cost - new_cost) / predicted : -1.0;
    }
    if (new_cost < cost || (problem->accepts_equal_cost() && new_cost == cost)) {
      ++accepted_steps;
      const double decrease = cost - new_cost;
      problem->Accept();
      cost = problem->cost();
      summary->trace.push_back({MillisecondsFrom(start), cost});
      schedule.Accepted(rho);
      const double new_gradient_norm = problem->gradient().lpNorm<Eigen::Infinity>();
      if (cost > problem->noise_floor() &&
          decrease <= stopping.function_tolerance * (cost + decrease)) {
        summary->converged = true;
        summary->message = "function tolerance";
        break;
      }
      if (new_gradient_norm <= stopping.gradient_tolerance) {
        summary->converged = true;
        summary->message = "gradient tolerance";
        break;
      }
      fresh = false;
      need_factor = schedule.RefactorAfter(new_gradient_norm, gradient_norm);
      gradient_norm = new_gradient_norm;
    } else {
      summary->trace.push_back({MillisecondsFrom(start), cost});
      schedule.Rejected(fresh);
      need_factor = true;
    }
    assembled = false;
  }
  if (!done && summary->message.empty()) summary->message = "iteration cap";
  state->refactor_next = need_factor && !summary->converged;
  summary->final_cost = cost;
  if (unfactorisable || (factor_failed && accepted_steps == 0)) {
    summary->failed = true;
    summary->message = "the damped normal equations could not be factorised (" +
                       std::to_string(summary->factorizations) + " tries); " +
                       (accepted_steps == 0 ? std::string("the nodes were not moved")
                                            : "stopped after " + std::to_string(accepted_steps) +
                                                  " accepted steps");
  }
  if (!std::isfinite(cost)) {
    summary->failed = true;
    summary->message = "the cost is not finite";
  }
}

}  // namespace msdeform
