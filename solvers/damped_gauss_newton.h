// The one damped Gauss-Newton (Levenberg-Marquardt) loop of the tree: every
// Gauss-Newton frame solver (Eq. 17's, solvers/gauss_newton_solver.h; the
// subspace ARAP energy's, solvers/arap_solver.h) runs its iterations here,
// on its own energy behind DampedGaussNewtonProblem and on a linear solver
// of solvers/gauss_newton_linear_solver.h.
//
// Each iteration solves (J^T J + mu D) delta = rhs (rhs = -g, or the
// energy's reduced form of it) and accepts x + delta when the cost
// decreases (or, where the problem says so, stays the same). GaussNewtonOptions sets the rest:
//   damping: kGaussNewton keeps mu at min_damping, x10 after a rejected step
//     with a fresh factorisation, /10 (to the floor) after an accepted one;
//     kLevenbergMarquardt starts at initial_damping and follows the gain
//     ratio (Nielsen);
//   factorization: a fresh factorisation every iteration, or one kept while
//     each accepted step shrinks max |g| by refactor_ratio (per frame, or
//     carried over from the last frame: DampedGaussNewtonState);
//   linear_solver: a direct one solves by the last factorisation; PCG
//     reassembles every iteration and stops at the forcing term.
// It stops on the StoppingRule: every linear solve counts as an iteration;
// max |g| <= gradient_tolerance; |delta| <= parameter_tolerance (|x| +
// parameter_tolerance) before a trial; an accepted decrease <=
// function_tolerance times the cost before it (not counted while the cost
// is at or below the energy's noise floor).

#ifndef MSDEFORM_SOLVERS_DAMPED_GAUSS_NEWTON_H_
#define MSDEFORM_SOLVERS_DAMPED_GAUSS_NEWTON_H_

#include <chrono>
#include <limits>

#include <Eigen/Core>

#include "msdeform/solvers/frame_solver.h"
#include "msdeform/solvers/gauss_newton_linear_solver.h"
#include "msdeform/solvers/gauss_newton_solver.h"

namespace msdeform {

// One frame's energy as the loop sees it: a current point x with its cost
// and gradient, the damped system at x, and trial steps.
class DampedGaussNewtonProblem {
 public:
  using SparseMatrix = GaussNewtonLinearSolver::SparseMatrix;
  virtual ~DampedGaussNewtonProblem() = default;

  virtual int num_variables() const = 0;
  // The cost (1/2 sum of squared residuals) and its gradient at x.
  virtual double cost() const = 0;
  virtual const Eigen::VectorXd& gradient() const = 0;
  virtual double x_norm() const = 0;
  // Writes J^T J + mu D at x into system().
  virtual void Assemble(double mu) = 0;
  virtual SparseMatrix& system() = 0;
  // The step's right-hand side at x (-gradient(), or its reduced form).
  virtual void StepRhs(Eigen::VectorXd* rhs) const = 0;
  // Levenberg-Marquardt's predicted decrease of the model for `delta`
  // (system() as last assembled, with damping mu).
  virtual double PredictedDecrease(const Eigen::VectorXd& delta, double mu) const = 0;
  // The cost at x + delta; Accept then moves x there.
  virtual double TrialCost(const Eigen::VectorXd& delta) = 0;
  // x = x + delta of the last TrialCost; cost and gradient there.
  virtual void Accept() = 0;
  // Costs at or below it are rounding: the function tolerance does not stop
  // there.
  virtual double noise_floor() const { return -std::numeric_limits<double>::infinity(); }
  // Whether a trial step whose cost equals the current one is accepted (a
  // step is accepted when it lowers the cost).
  virtual bool accepts_equal_cost() const { return false; }
};

// What carries over from one frame to the next within a handle layout.
struct DampedGaussNewtonState {
  bool factor_valid = false;  // a factorisation from an earlier iteration exists
  // The last frame ended wanting a new factorisation (its last step was
  // rejected, or did not shrink the gradient enough): a lagged factor is not
  // carried into the next frame then, so a small iteration budget cannot
  // keep reusing a factor that already failed.
  bool refactor_next = false;
};

// Runs the loop from the problem's current point; the caller gathers x
// before and scatters it after. `summary` gets the iterations,
// factorisations, costs, trace (times since `start`; its point 0 is the
// caller's), the stopping message and the failure flags.
void RunDampedGaussNewton(const GaussNewtonOptions& options, const StoppingRule& stopping,
                          std::chrono::steady_clock::time_point start,
                          GaussNewtonLinearSolver* linear_solver,
                          DampedGaussNewtonProblem* problem, DampedGaussNewtonState* state,
                          SolveSummary* summary);

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_DAMPED_GAUSS_NEWTON_H_
