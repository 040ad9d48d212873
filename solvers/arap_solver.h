// The local/global solver of the subspace ARAP energy (solvers/subspace_arap.h;
// docs/method.md §9), a FrameSolver (solvers/frame_solver.h) like the
// Gauss-Newton and Ceres backends of Eq. 17. Setup factorises the global
// step's matrix Q_vv once per layout (the same for the three coordinates);
// each iteration of a frame fits the cluster rotations (the local step, one
// closed-form 3x3 eigen-decomposition per cluster), then solves for the free nodes with three
// back-substitutions (the global step). Neither step reads the mesh: a frame
// costs O(clusters + nodes) until the skinning.
//
// This is Gauss-Newton with the rotations' dependence on the nodes left out
// of the Jacobian (the variable-projection gradient is exact, as the
// rotations are optimal): each iteration minimises exactly over the nodes,
// so the energy never rises. Damping: the matrix is Q_vv + D with
// D = 1e-9 diag(Q_vv) + 1e-12 mean(diag Q_vv) I (I when Q_vv = 0), and the right-hand side
// adds D times the previous iterate, so a fixed point is the undamped
// minimum and a slot no spoke reaches keeps its value.
//
// A frame's first global step is tried with the last frame's rotations (I
// on a layout's first frame) and kept where it ends lower than the start:
// the start's own rotations are fitted to a handle that has just jumped and
// bend the free region after it, while the last frame's carry it along (a
// translation of handle and free region is then one step).
//
// Stops on the StoppingRule: at most max_iterations global steps; converged
// when an iteration lowers the energy by at most function_tolerance times
// it, or moves the variables by at most parameter_tolerance (|x| +
// parameter_tolerance). The energy u^T Q u - 2 sum tr(R^T S) + C loses about
// 1e-15 C to cancellation (C = sum w |e|^2 over the active spokes), so below
// ArapEnergyNoiseFloor the function test is skipped (a rigid motion, energy
// 0, would otherwise stop on rounding near 1e-13) and the parameter test
// decides; so it is where the local/global energy rose (each of its steps
// minimises exactly, so a rise is rounding).

// ArapGaussNewtonSolver (arap.solver=gauss_newton) minimises the same
// energy by Gauss-Newton on the nodes and the cluster rotations jointly.
// With the rotations perturbed as R_c exp([omega_c]x), the residual of spoke
// s in cluster c, sqrt(w_s)(D_s u_d - R_c(d, :) e_s) per coordinate d, is
// linearised as sqrt(w_s)(D_s u - R_c e_s + R_c [e_s]x omega_c). The normal
// equations in (v, omega), F = 2 unit^2 E:
//   [Q_vv (x) I_3   B ] [dv]      [g_v]    g_v = Q_vv v + Q_vk k - sum_c K_c^T R_c rows
//   [B^T            D ] [dw]  = - [g_w]    g_w,c = vee(M_c^T - M_c), M_c = R_c^T S_c
// with D_c = sum_s w_s [e_s]x^T [e_s]x = tr(Cov_c) I - Cov_c (constant per
// layout) and B_c's row of variable (slot p, coordinate d) equal to
// R_c(d, :)^T x k_{c,p} (K_c's vector of slot p). Each omega_c is eliminated:
//   (Q_vv (x) I_3 - sum_c B_c D_c^-1 B_c^T) dv = -g_v + sum_c B_c D_c^-1 g_w,c,
// a 3 nv system whose coordinates the rotations couple; its pattern (Q_vv's
// and every pair of slots a cluster reaches, as 3x3 blocks) is analysed once
// per layout and factorised each iteration. The step is a Gauss-Newton step
// on v followed by the optimal local step (the rotations refitted, not
// R_c exp(omega_c)): the rotations stay optimal, so g_w = 0 but where a
// reflection was refused, and the energy compared is the one the
// local/global solver reports. The iterations are those of every
// Gauss-Newton solver here (solvers/damped_gauss_newton.h: the damping
// mu diag(Q_vv) + a floor on the Eq. 17 backend's schedule, GaussNewtonOptions'
// linear solver, refactorised every iteration): a step that does not lower the
// energy is refused, so the energy never rises. Stops on the StoppingRule as
// that loop does, the function test skipped below ArapEnergyNoiseFloor.

#ifndef MSDEFORM_SOLVERS_ARAP_SOLVER_H_
#define MSDEFORM_SOLVERS_ARAP_SOLVER_H_

#include <memory>
#include <string>
#include <vector>

#include <Eigen/SparseCholesky>

#include "msdeform/solvers/anderson_acceleration.h"
#include "msdeform/solvers/damped_gauss_newton.h"
#include "msdeform/solvers/frame_solver.h"
#include "msdeform/solvers/gauss_newton_linear_solver.h"
#include "msdeform/solvers/gauss_newton_solver.h"
#include "msdeform/solvers/subspace_arap.h"

namespace msdeform {

// 1e-12 C / (2 unit^2): energies below it are rounding.
double ArapEnergyNoiseFloor(const SubspaceArap& arap);

// The damping every solver of the energy adds to each diagonal of Q_vv:
// 1e-12 times its mean, so that a slot no spoke reaches keeps its value; 1
// where every diagonal is 0 (no vertex is skinned: the handle covers what the
// free nodes skin), where any positive floor does.
double ArapDampingFloor(const Eigen::VectorXd& diagonal);

class ArapLocalGlobalSolver : public FrameSolver {
 public:
  // `anderson_window` > 0 accelerates the iteration (ArapOptions::anderson_window).
  explicit ArapLocalGlobalSolver(const StoppingRule& stopping, int anderson_window = 0)
      : stopping_(stopping), anderson_window_(anderson_window) {}

  // `energy` must hold a subspace ARAP energy (solvers/subspace_arap_terms.h)
  // and no other terms.
  bool Setup(const DeformationEnergy& energy, const NodeTransforms& transforms,
             std::string* error) override;
  SolveSummary Solve(const HandleTransforms& handles, NodeTransforms* transforms) override;
  double Cost(const HandleTransforms& handles, const NodeTransforms& transforms) override;
  int num_variables() const override { return arap_ ? arap_->num_variables() : 0; }

 private:
  // Anderson's step from the variables v and the plain step's `plain`: when
  // the history has differences to combine and the accelerated iterate's
  // energy is below `energy`, writes that iterate to *next, its slots to *u,
  // its rotations and energy, and returns true. Else returns false (the
  // history reset after a refused step) and leaves u and rotations as given.
  bool Accelerate(const SubspaceArap::Slots& v, const SubspaceArap::Slots& plain, double energy,
                  AndersonAcceleration* anderson, SubspaceArap::Slots* next,
                  SubspaceArap::Slots* u, SubspaceArap::Rotations* rotations,
                  double* next_energy) const;

  StoppingRule stopping_;
  int anderson_window_ = 0;
  std::shared_ptr<const SubspaceArap> arap_;
  double noise_floor_ = 0.0;
  Eigen::VectorXd damping_;  // D's diagonal
  // The last frame's cluster rotations (I after Setup), for the first step.
  SubspaceArap::Rotations previous_rotations_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower,
                        Eigen::AMDOrdering<int>>
      factorization_;
};

// Gauss-Newton on the nodes and the cluster rotations jointly, the
// rotations eliminated per cluster, iterated by the damped Gauss-Newton loop
// of solvers/damped_gauss_newton.h with the linear solver, damping and
// damping of `options` (the Eq. 17 backend's), a fresh factorisation every
// iteration, and CHOLMOD for its sparse Cholesky (Eigen's LLT without it):
// D is Q_vv's diagonal, plus ArapDampingFloor.
class ArapGaussNewtonSolver : public FrameSolver {
 public:
  ArapGaussNewtonSolver(const GaussNewtonOptions& options, const StoppingRule& stopping);
  ~ArapGaussNewtonSolver() override;

  // As ArapLocalGlobalSolver::Setup.
  bool Setup(const DeformationEnergy& energy, const NodeTransforms& transforms,
             std::string* error) override;
  SolveSummary Solve(const HandleTransforms& handles, NodeTransforms* transforms) override;
  double Cost(const HandleTransforms& handles, const NodeTransforms& transforms) override;
  int num_variables() const override { return arap_ ? arap_->num_variables() : 0; }

 private:
  class Frame;  // one frame's problem for the damped Gauss-Newton loop

  // The reduced Gauss-Newton matrix at u with rotations R (no damping) into
  // assembled_, and the right-hand side -g_v + sum B D^-1 g_w (one row per
  // variable slot, one column per coordinate) from g_v (`gradient`).
  void Assemble(const SubspaceArap::Slots& u, const SubspaceArap::Rotations& rotations,
                const SubspaceArap::Slots& gradient, SubspaceArap::Slots* rhs);

  GaussNewtonOptions options_;
  StoppingRule stopping_;
  std::shared_ptr<const SubspaceArap> arap_;
  double noise_floor_ = 0.0;
  // 3 nv by 3 nv, variable (slot p, coordinate d) at 3 p + d; full symmetric.
  Eigen::SparseMatrix<double> matrix_;
  Eigen::VectorXd base_values_;  // Q_vv (x) I_3 in matrix_'s value order
  Eigen::VectorXd diagonal_;     // Q_vv's diagonal, per slot
  double damping_floor_ = 0.0;   // ArapDampingFloor(diagonal_)
  std::vector<int> diagonal_index_;  // matrix_'s value of (i, i), per row i
  // Per cluster: its variables (slot variables), and for each pair (a, b) of
  // them the first value of their 3x3 block (column 3 b, row 3 a) in matrix_;
  // column 3 b + d' is at that plus d' column_stride_[b].
  std::vector<int> cluster_variable_offsets_, cluster_variables_, cluster_entries_;
  std::vector<int> cluster_pair_offsets_, cluster_pair_index_;
  std::vector<int> column_stride_;
  std::vector<Eigen::Matrix3d> d_inverse_factor_;  // L^-1 with D_c = L L^T (0 if none)
  Eigen::VectorXd assembled_;  // Assemble's values of matrix_
  std::unique_ptr<GaussNewtonLinearSolver> linear_solver_;  // of options_
  DampedGaussNewtonState state_;
};

// The solver of arap.solver: ArapLocalGlobalSolver (with arap.anderson_window)
// or ArapGaussNewtonSolver (with `gauss_newton`'s linear solver, damping and
// factorisation rule).
std::unique_ptr<FrameSolver> MakeArapSolver(
    ArapSolver solver, const StoppingRule& stopping,
    const GaussNewtonOptions& gauss_newton = GaussNewtonOptions(), int anderson_window = 0);

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_ARAP_SOLVER_H_
