// The seam between the stages (scales/) and the backends that minimise Eq. 17 each
// frame (solvers/deformation_energy.h): the Gauss-Newton solver
// (solvers/gauss_newton_solver.h) and Ceres (solvers/ceres_solver.h).
//
//   std::unique_ptr<FrameSolver> solver = MakeGaussNewtonSolver(options, stopping);
//   solver->Setup(energy, transforms, &error);      // once per handle layout
//   solver->Solve(handle, &transforms);             // once per frame, warm-started
//
// Every backend stops on the same StoppingRule and reports the same
// SolveSummary, so variants can be compared at equal quality.

#ifndef MSDEFORM_SOLVERS_FRAME_SOLVER_H_
#define MSDEFORM_SOLVERS_FRAME_SOLVER_H_

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/option_table.h"
#include "msdeform/solvers/deformation_energy.h"

namespace msdeform {

// When a frame's solve stops (Ceres's three tests, which the Gauss-Newton
// backend applies the same way): |dF| <= function_tolerance F after an
// accepted step, max |gradient| <= gradient_tolerance, |step| <=
// parameter_tolerance (|x| + parameter_tolerance), or max_iterations linear
// solves (the per-frame iteration budget).
struct StoppingRule {
  int max_iterations = 20;
  double function_tolerance = 1e-8;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-10;

  // Messages name the fields ("max_iterations must be >= 0").
  bool Check(std::string* error) const;
};

// One point of a frame's convergence trace: the cost after an iteration and
// the time since the solve began (point 0: the initial cost at time 0).
struct TracePoint {
  double ms = 0.0;
  double cost = 0.0;
};

struct SolveSummary {
  int iterations = 0;      // linear solves (Ceres: iterations, accepted or not)
  int factorizations = 0;  // numeric factorisations (Ceres: linear solver calls)
  double initial_cost = 0.0;
  double final_cost = 0.0;
  bool converged = false;  // a tolerance test stopped it, not the budget
  bool failed = false;     // no usable result (a factorisation that never succeeded, NaN)
  std::string message;     // why it stopped
  std::vector<TracePoint> trace;
};

class FrameSolver {
 public:
  virtual ~FrameSolver() = default;

  // Once per handle layout. `transforms` gives the values of the constant
  // blocks (Fixed nodes, Half Free translations); they must not change until
  // the next Setup.
  virtual bool Setup(const DeformationEnergy& energy, const NodeTransforms& transforms,
                     std::string* error) = 0;

  // Minimises the energy with the handle at `handle` (deformed_from_rest),
  // starting from *transforms, which it updates in place.
  virtual SolveSummary Solve(const HandleTransforms& handles, NodeTransforms* transforms) = 0;

  // The energy (1/2 sum of squared residuals, as Solve reports it) with the
  // handle at `handle` and the nodes at `transforms`; the free blocks are
  // read from `transforms`, the constant ones are Setup's. For choosing
  // between initial guesses: cheaper than a solve.
  virtual double Cost(const HandleTransforms& handles, const NodeTransforms& transforms) = 0;

  virtual int num_variables() const = 0;
};

// StoppingRule's rows (core/option_table.h), declared in its header beside the fields: a new field
// is the field above and its row here. StoppingRuleTable() (frame_solver.cc) builds the table from
// them once; a template, so that only that file compiles the rows.
template <typename Table>
void DeclareStoppingRuleRows(Table& t) {
  t.Int("max_iterations", &StoppingRule::max_iterations,
        "Iteration budget per frame (linear solves), >= 1.")
      .Range(1, kOptionIntMax,
             "an integer >= 1 (a frame with no iteration leaves the handle behind)");
  t.Double("function_tolerance", &StoppingRule::function_tolerance,
           "Stop when |cost change| / cost falls to this.")
      .AtLeast(0, "a finite number >= 0");
  t.Double("gradient_tolerance", &StoppingRule::gradient_tolerance,
           "Stop when the gradient's max norm falls to this.")
      .AtLeast(0, "a finite number >= 0");
  t.Double("parameter_tolerance", &StoppingRule::parameter_tolerance,
           "Stop when |step| <= this * (|x| + this).")
      .AtLeast(0, "a finite number >= 0");
}
const OptionTable<StoppingRule>& StoppingRuleTable();

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_FRAME_SOLVER_H_
