// The Gauss-Newton backend (solvers/frame_solver.h) for the deformation
// energy of paper Eq. 17 (solvers/deformation_energy.h); the paper solves with
// Gauss-Newton and sparse Cholesky (docs/method.md §6). Ceres is the other
// backend (solvers/ceres_solver.h).
//
// The energy, with x the variables of the Totally Free (R_j, t_j: 12) and
// Half Free (R_j: 9) nodes and tau the 12 numbers of the handle transform
// (its 3x3 matrix column-major, then its translation):
//   F(x) = 1/2 |r_rot(x)|^2 + 1/2 |A x + c - P tau|^2,
// r_rot the six Rot residuals (Eq. 12) per free node, and the second term
// every Coherence (Eq. 14) and Position (Eq. 16) residual and the gauge terms,
// all linear in x (solvers/gauss_newton_linear_terms.h). The terms of
// DeformationEnergy::terms join the one or the other by their `linear` flag
// (solvers/gauss_newton_terms.h): a linear one becomes rows of A, a nonlinear
// one is evaluated like r_rot, through its own residual and Jacobian, on
// J^T J entries that join the pattern once per layout.
// So J^T J = H + blockdiag(J_rot^T J_rot) with H = A^T A constant: H, its
// sparsity pattern with the 9x9 rotation blocks, and the symbolic Cholesky
// analysis are built once per handle layout (Setup); a frame only moves tau
// (g0 = A^T c - A^T P tau, O(#variables)), and an iteration only rewrites the
// rotation blocks and factorises numerically. The cost of an iteration does
// not depend on the number of handle vertices: they enter through H, A^T P
// (#variables by 12) and at most 3 (4 k + 7) compressed residuals per group
// of position terms on the same k nodes: costs are not taken from the
// expanded quadratic 1/2 (x^T H x + 2 g0^T x + |c - P tau|^2), which loses
// about 1e-16 of |c - P tau|^2 (4e-7 of the energy on the 416K claw), but
// from the linear residuals kept compressed (A's Coherence and gauge rows,
// and per group of position terms the R of a QR of their rows: the same sum
// of squares), at the start of a frame and after each accepted step; a
// trial step adds the change of the quadratic to the last of those.
//
// Iteration: solve (J^T J + mu D) delta = -g, D = diag(J^T J), by sparse
// Cholesky or by preconditioned conjugate gradients (GaussNewtonOptions);
// accept if F decreases. Damping::kGaussNewton keeps mu at a 1e-9 floor
// (J^T J is positive definite once the gauge terms pin the spins Eq. 17
// leaves free, so the floor is only a safeguard) and grows it 10x only after
// a rejected step; Damping::kLevenbergMarquardt adapts mu from the gain ratio
// every step. Stops on the StoppingRule (every linear solve counts as an
// iteration). Costs are reported as Ceres does: 1/2 sum of squared residuals.
// A frame fails (SolveSummary::failed, with a message) when its cost is not
// finite, when it ends on a system that could not be factorised before any
// step was accepted, or when no damping up to 1e32 makes it factorisable.

#ifndef MSDEFORM_SOLVERS_GAUSS_NEWTON_SOLVER_H_
#define MSDEFORM_SOLVERS_GAUSS_NEWTON_SOLVER_H_

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msdeform/core/option_table.h"
#include "msdeform/solvers/frame_solver.h"

namespace msdeform {

struct GaussNewtonOptions {
  // How each step's linear system is solved.
  enum class LinearSolver {
    kCholesky,  // sparse Cholesky (`cholesky`), exact
    kPcgJacobi,  // conjugate gradients, diagonal preconditioner, inexact
    kPcgIncompleteCholesky,  // conjugate gradients, incomplete Cholesky preconditioner
  };
  LinearSolver linear_solver = LinearSolver::kCholesky;
  // The sparse Cholesky of LinearSolver::kCholesky.
  enum class Cholesky {
    kSupernodal,  // our supernodal LLT, AMD ordering (solvers/gauss_newton_supernodal_cholesky.h)
    kEigenLLT,   // Eigen::SimplicialLLT, AMD ordering
    kEigenLDLT,  // Eigen::SimplicialLDLT, AMD ordering
    kCholmod,    // CHOLMOD (SuiteSparse) supernodal LLT; kEigenLLT when not built in
  };
  // Supernodal: the same ordering and factor as Eigen's scalar LLT, with
  // dense kernels per supernode: about 2.3x faster to factorise and 1.7x to
  // solve on the 104K claw (docs/decisions/supernodal-cholesky.md, "The
  // Gauss-Newton solve").
  Cholesky cholesky = Cholesky::kSupernodal;
  // When J^T J is factorised (the Cholesky factor, or the PCG preconditioner).
  // Every iteration: Gauss-Newton proper. Per frame: at the first iteration of
  // each Solve, then kept while each accepted step shrinks the gradient's max
  // norm by at least refactor_ratio. Lagged: the same, but the factorisation
  // also carries over from the last frame. A rejected step with a stale
  // factorisation refactorises before damping grows. A stale factor makes the
  // step inexact (a chord step), not the minimum: all stop on the same tests.
  enum class Factorization { kEveryIteration, kPerFrame, kLagged };
  Factorization factorization = Factorization::kLagged;
  // A factorisation costs about five to ten chord steps here, and
  // Gauss-Newton on Eq. 17 converges linearly even with a fresh one, so
  // refactorising whenever a step shrinks the gradient less than 4x (0.25,
  // the rule before 2026-11-23) bought few iterations for many
  // factorisations; refactorising only when it grows (1) lets a stale factor
  // crawl (the cactus with the paper's fixed border: 3,045 iterations and
  // stuck at 45x the minimum's energy). 0.8 keeps both in check
  // (docs/decisions/solver-seam.md).
  double refactor_ratio = 0.8;
  // kGaussNewton: mu at min_damping, x10 after a rejected step, /10 after an
  // accepted one. kLevenbergMarquardt: mu from initial_damping, updated from
  // the gain ratio rho of each step (Nielsen: mu *= max(1/3, 1 - (2 rho - 1)^3)
  // when accepted, mu *= nu, nu *= 2 when not); a new mu needs a new
  // factorisation, so it refactorises every iteration.
  enum class Damping { kGaussNewton, kLevenbergMarquardt };
  Damping damping = Damping::kGaussNewton;
  double min_damping = 1e-9;      // mu floor, relative to diag(J^T J)
  double initial_damping = 1e-4;  // Levenberg-Marquardt's first mu
  // PCG: stop when |J^T J delta + g| <= eta |g|, the forcing term
  // eta = min(forcing_term, sqrt(max|g| / max|g_0|)), g_0 the frame's first
  // gradient (Eisenstat-Walker-style: loose far from the minimum, tight near
  // it), or after max_cg_iterations.
  double forcing_term = 0.1;
  int max_cg_iterations = 200;

  bool Check(std::string* error) const;
};

// "cholesky", "pcg_jacobi", "pcg_incomplete_cholesky".
// The names of the enums above (core/option_table.h), and Name/Parse by them.
const EnumNames<GaussNewtonOptions::LinearSolver>& LinearSolverNames();
const EnumNames<GaussNewtonOptions::Cholesky>& CholeskyNames();
const EnumNames<GaussNewtonOptions::Factorization>& FactorizationNames();
const EnumNames<GaussNewtonOptions::Damping>& DampingNames();
const char* LinearSolverName(GaussNewtonOptions::LinearSolver solver);
bool ParseLinearSolver(const std::string& name, GaussNewtonOptions::LinearSolver* solver);
// "supernodal", "eigen_llt", "eigen_ldlt", "cholmod".
const char* CholeskyName(GaussNewtonOptions::Cholesky cholesky);
bool ParseCholesky(const std::string& name, GaussNewtonOptions::Cholesky* cholesky);
// "every_iteration", "per_frame", "lagged".
const char* FactorizationName(GaussNewtonOptions::Factorization factorization);
bool ParseFactorization(const std::string& name, GaussNewtonOptions::Factorization* factorization);
// "gauss_newton", "levenberg_marquardt".
const char* DampingName(GaussNewtonOptions::Damping damping);
bool ParseDamping(const std::string& name, GaussNewtonOptions::Damping* damping);

// True when CHOLMOD support was compiled in.
bool GaussNewtonHasCholmod();

// How an iteration's assembly of the Rot terms (residuals, J^T r into the
// gradient, the 9x9 blocks of J^T J) splits over threads: fixed chunks of
// `chunk_size` rot nodes, each chunk's cost summed alone and the chunk sums
// added in chunk order, so the bits do not depend on num_threads. Parallel
// only from `min_parallel_terms` rot nodes: a term takes about 80 ns, and a
// frame's ~100 nodes (the claw at any mesh size) are far below what pays for
// a parallel region (a few microseconds on a busy machine).
struct GaussNewtonThreads {
  int num_threads = 1;
  int chunk_size = 512;
  int min_parallel_terms = 8192;
  // Setup's QR of the position groups (solvers/gauss_newton_linear_terms.h)
  // in parallel from this many position rows in all.
  int min_parallel_rows = 4096;
};

class GaussNewtonSolver : public FrameSolver {
 public:
  GaussNewtonSolver(const GaussNewtonOptions& options, const StoppingRule& stopping,
                    const GaussNewtonThreads& threads = GaussNewtonThreads());
  ~GaussNewtonSolver() override;

  // Variables, H, A^T c, A^T P, the pattern and the symbolic factorisation.
  bool Setup(const DeformationEnergy& energy, const NodeTransforms& transforms,
             std::string* error) override;
  SolveSummary Solve(const HandleTransforms& handles, NodeTransforms* transforms) override;
  double Cost(const HandleTransforms& handles, const NodeTransforms& transforms) override;
  int num_variables() const override { return num_variables_; }

 private:
  struct Impl;
  class Frame;  // one frame's problem for the damped Gauss-Newton loop
  std::unique_ptr<Impl> impl_;
  GaussNewtonOptions options_;
  StoppingRule stopping_;
  GaussNewtonThreads threads_;
  int num_variables_ = 0;
};

// GaussNewtonOptions' rows (core/option_table.h), declared in its header beside the fields: a new
// field is the field above and its row here. GaussNewtonOptionTable() (gauss_newton_options.cc)
// builds the table from them once; a template, so that only that file compiles the rows.
// The energy helper's solver files keep their Name/Parse functions; the
// names here are read from them.
template <typename Table>
void DeclareGaussNewtonOptionRows(Table& t) {
  using GN = GaussNewtonOptions;
  t.Enum("linear_solver", &GN::linear_solver,
         LinearSolverNames(),
         "Gauss-Newton step: cholesky (exact), pcg_jacobi or pcg_incomplete_cholesky "
         "(inexact, forcing-term stop).");
  t.Enum("cholesky", &GN::cholesky,
         CholeskyNames(),
         "Gauss-Newton sparse Cholesky: supernodal, eigen_llt, eigen_ldlt or cholmod.");
  t.Enum("factorization", &GN::factorization,
         FactorizationNames(),
         "When Gauss-Newton refactorises J^T J: every_iteration, per_frame or lagged (kept "
         "while the gradient falls 4x a step, also across frames).");
  t.Double("refactor_ratio", &GN::refactor_ratio,
           "Lagged and per-frame factorisation: refactorise after a step that shrank the "
           "gradient by less than this factor (1: only when it grew).")
      .Above(0, "a number > 0");
  t.Enum("damping", &GN::damping,
         DampingNames(),
         "Gauss-Newton damping: gauss_newton (a 1e-9 floor, raised only after a rejected "
         "step) or levenberg_marquardt (adapted every step).");
  t.Double("min_damping", &GN::min_damping, "mu floor, relative to diag(J^T J).")
      .Above(0, "a finite number > 0");
  t.Double("initial_damping", &GN::initial_damping, "Levenberg-Marquardt's first mu.")
      .Above(0, "a finite number > 0");
  t.Double("forcing_term", &GN::forcing_term, "PCG's relative residual bound, at most.")
      .Range(0, 1, "a number in (0, 1)", /*high_open=*/true)
      .lo_open = true;
  t.Int("max_cg_iterations", &GN::max_cg_iterations, "PCG iterations per step, at most.")
      .Range(1, kOptionIntMax, "an integer >= 1");
}
const OptionTable<GaussNewtonOptions>& GaussNewtonOptionTable();

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_GAUSS_NEWTON_SOLVER_H_
