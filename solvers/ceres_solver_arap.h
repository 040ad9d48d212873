// The Ceres backend's problem for the subspace ARAP energy
// (solvers/subspace_arap.h; used by solvers/ceres_solver.cc): one residual
// block per rotation cluster (energies/arap_cluster_cost.h) over the nodes'
// R_j and t_j blocks (constant by node class, as for Eq. 17), the handle as
// a constant 12-double block set each frame (its four slots' values, as
// SubspaceArap::Gather forms them), and the cluster's rotation R_c
// (9 doubles on RotationMatrixManifold), started each frame at its best fit.
// Each block's residuals are 3 times the rank of the cluster's 4x4-blocked
// Gram matrix G_c (built once per layout), whatever its vertex count; one
// more block over the same kind of factor holds the soft constraint terms.

#ifndef MSDEFORM_SOLVERS_CERES_SOLVER_ARAP_H_
#define MSDEFORM_SOLVERS_CERES_SOLVER_ARAP_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/problem.h>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/solvers/subspace_arap.h"

namespace msdeform {

class CeresArapProblem {
 public:
  // Adds the blocks to `problem`; `parameters` holds R_j and t_j (kept by
  // the caller), `ensure_blocks(j)` adds node j's two parameter blocks with
  // their class's constancy.
  CeresArapProblem(std::shared_ptr<const SubspaceArap> arap, NodeTransforms* parameters,
                   const std::function<void(int)>& ensure_blocks, ceres::Problem* problem);

  // Before a solve or an evaluation at `parameters`: the handle blocks and
  // each cluster's rotation at its best fit.
  void SetFrame(const HandleTransforms& handles, const NodeTransforms& parameters);

  int num_clusters() const { return static_cast<int>(rotations_.size()); }

 private:
  std::shared_ptr<const SubspaceArap> arap_;
  std::vector<Eigen::Matrix3d> rotations_;  // R_c blocks
  // Per handle group g: slot 4 (n + g) + m, coordinate d at 3 m + d. Sized
  // once (the problem holds pointers into it).
  std::vector<Eigen::Matrix<double, 12, 1>> handles_;
};

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_CERES_SOLVER_ARAP_H_
