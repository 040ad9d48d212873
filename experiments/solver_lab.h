// The solver lab (issue 14, "The benchmark"): how fast each way of solving a
// frame (solvers/frame_solver.h) reaches the minimum of its energy: Eq. 17
// (energy ed) or the subspace ARAP energy (energy arap,
// solvers/subspace_arap.h). Every solver variant x every scenario x every
// per-frame iteration budget is one drag; the variants of one energy share it
// and the stopping rule and differ only in the solver. Each frame's energy
// E_f (at the frame's solution, evaluated by EvaluateEnergy for every backend
// alike) is compared with E*_f, the minimum a tightly converged reference run
// of the same drag and energy finds (ed: Gauss-Newton with a fresh
// factorisation every iteration; arap: the local/global solver; 500
// iterations, tolerances 1e-14): the energy at a frame depends only on that frame's
// handle target, so E*_f is that frame's minimum even though warm starts
// make the trajectories differ. (The backends' own reported costs carry
// rounding, once up to 2e-6 of E, enough to put a Ceres run "below" the
// Gauss-Newton reference; both now evaluate them from compressed residuals,
// within 4e-14 of E where measured. The cost_error column shows it.)
//
//   SolverLabOptions options;  // defaults: the full lab
//   options.out_dir = "experiments/results";
//   RunSolverLab(options, &error);
//
// Writes into out_dir:
//   solvers.csv         one row per scenario x variant x budget
//   solvers.md          the same table after three summaries: the winner at
//                       equal quality per scenario, iterations against the
//                       cost of an iteration per variant, the variant list
//   solver_traces.csv   per-iteration cost of frame 1 and of the last frame,
//                       budget "converged"
// (the CLI: msdeform_experiments --solver_lab [--quick]).

#ifndef MSDEFORM_EXPERIMENTS_SOLVER_LAB_H_
#define MSDEFORM_EXPERIMENTS_SOLVER_LAB_H_

#include <functional>
#include <string>
#include <vector>

#include "experiments/experiment_scenario.h"
#include "msdeform/scales/deformer_options.h"

namespace msdeform {

// The budget that stands for "until converged": the iteration cap of those
// runs (they stop on the default tolerances of StoppingRule long before).
constexpr int kConvergedBudget = 0;
constexpr int kConvergedMaxIterations = 200;
// "Equal quality": the largest relative energy gap over a drag's frames that
// still counts as the minimum for the summary's winner.
constexpr double kEqualQualityGap = 1e-3;
// Rows "at the minimum" (the summary's converged comparison).
constexpr double kMinimumGap = 1e-6;

// One solver variant: the energy it minimises and a change of the solver
// fields of DeformerOptions (backend, initial guess, Gauss-Newton or Ceres
// options), applied to the defaults. The stopping rule is the lab's, never
// the variant's.
struct SolverVariant {
  std::string name;
  std::function<void(DeformerOptions*)> apply;
  Energy energy = Energy::kEd;
};

// Every variant, in table order: gn_lagged (the default options), gn_exact,
// gn_per_frame, gn_lm, gn_pcg_jacobi, gn_pcg_ichol, gn_eigen_llt, gn_ldlt, gn_cholmod,
// gn_cold, gn_previous, gn_extrapolated, gn_exact_extrapolated,
// ceres_lm_<lib> and ceres_dogleg_<lib> for every lib of
// CeresSparseLibraries(), ceres_cgnr, ceres_lm_per_vertex (one position
// block per vertex) and ceres_lm_autodiff (CeresOptions::jacobians), all of
// energy ed; then arap_local_global (energy arap: ArapLocalGlobalSolver, the
// solver of --energy=arap with backend gauss_newton). Each changes the defaults in one
// respect (gn_exact_extrapolated: two), so a variant can repeat the defaults
// (gn_extrapolated while the default initial guess is extrapolated); the lab
// runs it anyway and says so in its header: the two rows differ by timing
// noise only.
std::vector<SolverVariant> SolverVariants();

// `base` with the solver fields set to DeformerOptions' defaults, the
// variant's energy, then changed by `variant`, and the stopping rule of
// `budget` (kConvergedBudget: kConvergedMaxIterations with the default
// tolerances).
DeformerOptions VariantOptions(const DeformerOptions& base, const SolverVariant& variant,
                               int budget);

// The reference run of base.energy: energy ed solved by Gauss-Newton with a
// factorisation every iteration, energy arap by the local/global solver
// (backend gauss_newton), from the previous frame's solution, at most 500
// iterations, function, gradient and parameter tolerance 1e-14.
DeformerOptions ReferenceOptions(const DeformerOptions& base);

// The solver of `options` in words, e.g. "Gauss-Newton; Cholesky (eigen_llt);
// factorisation lagged; damping gauss_newton; initial guess previous".
std::string DescribeSolver(const DeformerOptions& options);

// True when every step solves its linear system exactly (sparse Cholesky),
// so that a converged run reaches the minimum as tightly as the reference.
// False for the arap local/global solver: its steps minimise exactly over
// the nodes, but it converges linearly, and its default tolerances stop it
// short of the reference.
bool HasExactSteps(const DeformerOptions& options);

// "1", "2", ... or "converged".
std::string BudgetName(int budget);

struct SolverLabOptions {
  // Folder of the scenario entries (*.json), every one of which is run.
  std::string scenario_dir;
  // Where solvers.{csv,md} and solver_traces.csv go (created if missing).
  std::string out_dir;

  // Folder with scenarios/armadillo_claw.json and meshes/armadillo_104k.off,
  // meshes/armadillo_416k.off, for the claw drags claw_104k and claw_416k
  // (empty: DataDir() of core/build_info.h).
  std::string data_dir;
  // The CI subset: the cactus only, 5 frames, budgets {1, 3, converged}, no
  // large meshes, every variant (overrides budgets and large_meshes).
  bool quick = false;
  // Drag frames per scenario; 0 = the scenario's (quick: 5).
  int frames = 0;
  // Threads for Ceres and the skinning.
  int threads = 1;
  // Per-frame iteration budgets (StoppingRule::max_iterations);
  // kConvergedBudget = until converged.
  std::vector<int> budgets = {1, 2, 3, 5, 10, kConvergedBudget};
  // Also the claw drag on the 104K and 416K armadillo.
  bool large_meshes = true;
  // Only these scenario names (claw_104k and claw_416k included; empty: all).
  std::vector<std::string> only;
  // Only these variants (names of SolverVariants(); empty: all).
  std::vector<std::string> variants;
  // The energy's settings (method, weights, rigidity, ...); the solver fields
  // are the variants' and the stopping rule the budget's.
  DeformerOptions deformer;
  // Called with one line per scenario x variant (and per reference); may be
  // empty.
  std::function<void(const std::string&)> progress;

  bool Check(std::string* error) const;
};

// Runs the lab and writes its files into out_dir. A frame that fails is
// counted (failed_frames), not fatal; false with one line on a scenario that
// does not load, a deformer that does not set up, or a reference run that
// fails.
bool RunSolverLab(const SolverLabOptions& options, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_EXPERIMENTS_SOLVER_LAB_H_
