// A Gauss-Newton solver (Levenberg damping as a fallback) for the deformation
// energy of paper Eq. 17, the second backend beside Ceres (the paper solves with
// Gauss-Newton and sparse Cholesky; docs/method.md §6).
//
// The energy, with x the variables of the Totally Free (R_j, t_j: 12) and
// Half Free (R_j: 9) nodes and tau the 12 numbers of the handle transform
// (its 3x3 matrix column-major, then its translation):
//   F(x) = 1/2 |r_rot(x)|^2 + 1/2 |A x + c - P tau|^2,
// r_rot the six Rot residuals (Eq. 12) per free node, and the second term
// every Coherence (Eq. 14) and Position (Eq. 16) residual and the gauge terms
// (DeformationEnergy::Gauge), all linear in x.
// So J^T J = H + blockdiag(J_rot^T J_rot) with H = A^T A constant: H, its
// sparsity pattern with the 9x9 rotation blocks, and the symbolic Cholesky
// analysis are built once per handle layout (Setup); a frame only moves tau
// (g0 = A^T c - A^T P tau, O(#variables)), and an iteration only rewrites the
// rotation blocks and factorises numerically. The cost of an iteration does
// not depend on the number of handle vertices: they enter through H, A^T P
// (#variables by 12) and a 13x13 Gram matrix for the constant.
//
// Iteration: solve (J^T J + mu D) delta = -g (J^T J possibly lagged, see
// GaussNewtonOptions::hessian_reuse), D = diag(J^T J), mu starting at
// a 1e-9 floor (J^T J is positive definite once the gauge terms pin the spins
// Eq. 17 leaves free, so the floor is only a safeguard); accept if F decreases
// (then mu /= 10 down to the floor), else mu *= 10 and retry. Stops like
// Ceres: |dF| <= function_tolerance F, max |g| <= gradient_tolerance,
// |delta| <= parameter_tolerance (|x| + parameter_tolerance), or
// max_iterations (every linear solve counts).
// Costs are reported as Ceres does: 1/2 sum of squared residuals.

#ifndef MSDEFORM_SCALES_GAUSS_NEWTON_SOLVER_H_
#define MSDEFORM_SCALES_GAUSS_NEWTON_SOLVER_H_

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include "core/deformation_graph.h"
#include "energies/position_cost.h"
#include "scales/scale_selection.h"

namespace msdeform {

// The terms of Eq. 17 for one handle layout, independent of the backend.
// Lengths are already scaled into the sqrt weights.
struct DeformationEnergy {
  // Per node of the active graph: Totally Free varies R and t, Half Free R
  // only, Fixed nothing (values stay as given).
  std::vector<NodeClass> node_class;
  // Rot (Eq. 12) over these nodes, residual scale sqrt(w_rot).
  std::vector<int> rot_nodes;
  double sqrt_rot = 1.0;
  // Coherence (Eq. 14) of directed edge (j, k):
  //   sqrt_weight * (R_j e + g_j + t_j - g_k - t_k),  e = g_k - g_j.
  struct Coherence {
    int j, k;
    Eigen::Vector3d edge;  // g_k - g_j
    double sqrt_weight;
  };
  std::vector<Coherence> coherence;
  // Position (Eq. 16): sqrt_weight * (sum_i w_i [R_i o_i + g_i + t_i] - q),
  // q = handle * rest when follows_handle, else q = rest (the static
  // baselines' fixed handles). Nodes distinct, zero weights dropped.
  struct Position {
    std::vector<int> nodes;
    std::vector<SkinningTerm> terms;
    Eigen::Vector3d rest;
    bool follows_handle;
    double sqrt_weight;
  };
  std::vector<Position> positions;
  // Gauge fixing (energies/gauge_cost.h, docs/decisions.md "Gauge freedom"):
  //   sqrt_weight * axis^T omega(R_node),  omega(R) = 1/2 (R32 - R23, R13 - R31, R21 - R12),
  // one per unit axis along which Eq. 17 leaves R_node free (GaugeTerms).
  // Zero on a member of every such family of minima, so the minimum value
  // does not change; J^T J becomes non-singular.
  struct Gauge {
    int node;
    Eigen::Vector3d axis;  // unit
    double sqrt_weight;
  };
  std::vector<Gauge> gauge;

  int num_variables() const;
};

// The gauge terms `energy` needs, from its Rot, Coherence and Position terms
// (energy.gauge is ignored). R_j of a node in rot_nodes enters Eq. 17 through
// Rot, which depends on R_j^T R_j only, and through R_j u for the vectors u of
// its terms: the edge of each Coherence term with j as source, the offset of
// each Position term's share of j. Spinning R_j about a unit axis n
// (R_j -> Q R_j, Q a rotation about R_j n; = R_j Q_n for a rotation R_j)
// changes none of these when every u is parallel to n. With S the sum of
// u u^T over those vectors scaled as in J (sqrt weight, times w_i for a
// Position share):
//   S = 0 (no such term): axes x, y and z;
//   S of rank one (second eigenvalue <= 1e-12 times the first, a relative
//   test): its leading eigenvector, the common direction of the edges;
//   otherwise none (the terms pin R_j).
// Weight sqrt_rot (the Rot residuals' scale, so the term is as stiff as the
// Rot terms that pin R_j's other directions); none when sqrt_rot is 0.
std::vector<DeformationEnergy::Gauge> GaugeTerms(const DeformationEnergy& energy);

// 1/2 sum of squared residuals of `energy` at `transforms` with the handle at
// `handle` (deformed_from_rest), evaluated term by term (the reference).
double EvaluateEnergy(const DeformationEnergy& energy, const NodeTransforms& transforms,
                      const Eigen::Affine3d& handle);

struct GaussNewtonOptions {
  enum class LinearSolver {
    kEigenLLT,   // Eigen::SimplicialLLT, AMD ordering
    kEigenLDLT,  // Eigen::SimplicialLDLT, AMD ordering
    kCholmod,    // CHOLMOD (SuiteSparse) supernodal LLT; kEigenLLT when not built in
  };
  LinearSolver linear_solver = LinearSolver::kEigenLLT;
  // When J^T J is factorised. Every iteration: Gauss-Newton proper. Per frame:
  // at the first iteration of each Solve, kept while the gradient's max norm
  // shrinks at least 4x per accepted step. Lagged: the same, but the
  // factorisation also carries over from the last frame. Any rejected step
  // with a stale factorisation refactorises before damping grows. All three
  // stop on the same tests, so they reach the same minimum.
  enum class HessianReuse { kEveryIteration, kPerFrame, kLagged };
  HessianReuse hessian_reuse = HessianReuse::kLagged;
  int max_iterations = 20;            // linear solves per Solve
  double function_tolerance = 1e-8;   // |dF| / F
  double gradient_tolerance = 1e-10;  // max |g|
  double parameter_tolerance = 1e-10;  // |delta| / (|x| + tol)
  double min_damping = 1e-9;          // mu floor, relative to diag(J^T J)

  bool Check(std::string* error) const;
};

struct GaussNewtonSummary {
  int iterations = 0;  // linear solves
  int factorizations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  bool converged = false;
  std::string message;
};

// True when CHOLMOD support was compiled in.
bool GaussNewtonHasCholmod();

class GaussNewtonSolver {
 public:
  GaussNewtonSolver();
  ~GaussNewtonSolver();

  // Once per handle layout: variables, H, A^T c, A^T P, the pattern and the
  // symbolic factorisation. `transforms` gives the values of the constant
  // blocks (Fixed nodes, Half Free translations); they must not change later.
  bool Setup(const DeformationEnergy& energy, const NodeTransforms& transforms,
             const GaussNewtonOptions& options, std::string* error);

  // Solves for the handle at `handle`, warm-started from *transforms, which
  // it updates in place.
  GaussNewtonSummary Solve(const Eigen::Affine3d& handle, NodeTransforms* transforms);

  int num_variables() const { return num_variables_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int num_variables_ = 0;
};

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_GAUSS_NEWTON_SOLVER_H_
