// The local/global solver of the subspace ARAP energy (scales/subspace_arap.h;
// docs/method.md §9), a FrameSolver (scales/frame_solver.h) like the
// Gauss-Newton and Ceres backends of Eq. 17. Setup factorises the global
// step's matrix Q_vv once per layout (the same for the three coordinates);
// each iteration of a frame fits the cluster rotations (the local step, one
// 3x3 SVD per cluster), then solves for the free nodes with three
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
// Stops on the StoppingRule: at most max_iterations global steps; converged
// when an iteration lowers the energy by at most function_tolerance times
// it, or moves the variables by at most parameter_tolerance (|x| +
// parameter_tolerance).

#ifndef MSDEFORM_SCALES_ARAP_SOLVER_H_
#define MSDEFORM_SCALES_ARAP_SOLVER_H_

#include <memory>
#include <string>

#include <Eigen/SparseCholesky>

#include "msdeform/scales/frame_solver.h"
#include "msdeform/scales/subspace_arap.h"

namespace msdeform {

class ArapLocalGlobalSolver : public FrameSolver {
 public:
  explicit ArapLocalGlobalSolver(const StoppingRule& stopping) : stopping_(stopping) {}

  // `energy` must hold a subspace ARAP energy (energy.arap) and no other
  // terms.
  bool Setup(const DeformationEnergy& energy, const NodeTransforms& transforms,
             std::string* error) override;
  SolveSummary Solve(const Eigen::Affine3d& handle, NodeTransforms* transforms) override;
  double Cost(const Eigen::Affine3d& handle, const NodeTransforms& transforms) override;
  int num_variables() const override { return arap_ ? arap_->num_variables() : 0; }

 private:
  StoppingRule stopping_;
  std::shared_ptr<const SubspaceArap> arap_;
  Eigen::VectorXd damping_;  // D's diagonal
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower,
                        Eigen::AMDOrdering<int>>
      factorization_;
};

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_ARAP_SOLVER_H_
