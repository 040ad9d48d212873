// Rigid cells (Botsch, Pauly, Wicke, Gross 2007, "Adaptive space
// deformations based on rigid cells", the paper's [15]) as an editing method.
//
// The cells are the particles of msdeform's lattice (core/lattice.h, with
// options.deformer.lattice but rigid_cells.cells_per_diagonal cells per
// diagonal): surface pieces and interior cells, cubes of side w. Cell k moves
// rigidly, T_k(x) = R_k (x - c_k) + p_k (a unit quaternion and a position:
// one pair of Ceres parameter blocks). Neighbouring cells (the lattice's
// particle adjacency, split pieces of one cell included) are coupled by the
// paper's volumetric energy
//   E = sum over neighbours i~j of 1/w^3 integral over C_i u C_j |T_i(x) - T_j(x)|^2 dx,
// evaluated in closed form (energies/rigid_cell_coupling_cost.h has the
// formula and its derivation).
//
// Handles. The cells holding moveable-handle vertices follow the handle
// transform, those holding fixed vertices stay at rest (a cell holding both
// stays at rest): their blocks are constant in the Ceres problem, so the
// constraints are exact rather than the high-weight soft terms the paper also
// allows (docs/decisions/rigid-cells.md). Each Drag minimises E over the free
// cells with Ceres' Levenberg-Marquardt, warm-started from the last frame.
//
// Surface. The cells' motion reaches the mesh by the paper's triharmonic RBF
// with a linear polynomial: with one centre r_k per cell (a surface piece's
// vertex centroid, an interior cell's centre; pieces of one cell have
// distinct centroids where the cell centre is shared),
//   u(x) = sum_k w_k |x - r_k|^3 + a + B x,   u(r_k) = T_k(r_k) - r_k,
// and vertex v goes to x_v + u(x_v). The dense (#cells + 1 + axes) square system
// depends only on the rest centres: it is factorised once in Precompute;
// each frame solves it for three right-hand sides and evaluates u at every
// vertex (#V x #cells kernel terms: the cost the paper calls "several
// seconds for large meshes"). A linear polynomial is reproduced exactly, so a
// rigid motion of every cell moves every vertex by that motion. The handle
// and fixed vertices are then set to their targets exactly; how far the RBF
// had them (constraint_gap()) is the seam that leaves inside their cells.

#ifndef MSDEFORM_METHODS_RIGID_CELLS_H_
#define MSDEFORM_METHODS_RIGID_CELLS_H_

#include <memory>
#include <string>
#include <vector>

#include <ceres/ceres.h>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "msdeform/core/lattice.h"
#include "msdeform/methods/method.h"

namespace msdeform {

struct RigidCellsOptions {
  // Cells per bounding-box diagonal of the method's lattice, replacing
  // deformer.lattice.cells_per_diagonal (a deformer.lattice.cell_width > 0
  // still wins). The RBF system is dense in the cells and the solve slows
  // steeply with them, so the lattice is coarser than the graph methods' 48:
  // 16 gives 170-270 cells on the cactus, man and armadillo. 32 gives
  // 700-1,300 there and a lower ARAP energy (on the man's foot drag 16 gave
  // 3.1x that of 32), but 2,757 cells and 22 s a frame on hand_finger
  // (docs/decisions/rigid-cells.md). In [2, 64].
  double cells_per_diagonal = 16.0;
  // The most cells (RBF centres) accepted: the factorised dense system takes
  // about 8 #cells^2 bytes (6,000: 290 MB). In [1, 20000].
  int max_cells = 6000;
  // Each frame's solve (num_threads is set from deformer.num_threads):
  // Levenberg-Marquardt, SPARSE_NORMAL_CHOLESKY on SUITE_SPARSE (faster
  // than EIGEN_SPARSE on these 26-neighbour lattices in a first comparison;
  // docs/decisions/rigid-cells.md), at most 50 iterations, stopping at a
  // relative cost change of 1e-10 (a rigid motion is then reached to 4e-15
  // of the diagonal; the scenarios' frames take 4-13 iterations), silent.
  ceres::Solver::Options solver = DefaultSolverOptions();

  bool Check(std::string* error) const;
  static ceres::Solver::Options DefaultSolverOptions();
};

class RigidCells : public EditingMethod {
 public:
  RigidCells() : EditingMethod("rigid_cells") {}

  const Eigen::Matrix3Xd& deformed_vertices() const override { return deformed_vertices_; }
  // Free cells (neither driven nor fixed), 6 degrees of freedom each.
  int nodes_optimized() const override { return num_free_; }
  int variables() const override { return 6 * num_free_; }
  double precompute_ms() const override { return precompute_ms_; }
  double setup_ms() const override { return setup_ms_; }
  StageTimes stages() const override { return stages_; }
  const Lattice* lattice() const override { return &lattice_; }

  // Each cell's rigid motion T_k after the last Drag.
  Eigen::Affine3d cell_transform(int cell) const;
  // The RBF centres r_k, 3 by #cells.
  const Eigen::Matrix3Xd& rbf_centres() const { return rbf_centres_; }
  // Largest distance, over the handle and fixed vertices, between where the
  // RBF put them in the last Drag and their targets (where they are put).
  double constraint_gap() const { return constraint_gap_; }

 protected:
  bool DoPrecompute(const Mesh& mesh, const MethodOptions& options, std::string* error) override;
  bool DoSetHandles(const HandleLayout& layout, std::string* error) override;
  bool DoDrag(const HandleTransforms& deformed_from_rest, MethodStats* stats,
              std::string* error) override;

 private:
  enum class Kind : char { kFree, kFixed, kDriven };
  // Solves the RBF system for the cells' displacements and moves the mesh.
  void Interpolate(const HandleTransforms& deformed_from_rest);

  RigidCellsOptions options_;
  int num_threads_ = 1;
  Mesh mesh_;
  Lattice lattice_;
  Eigen::Matrix3Xd rbf_centres_;                 // r_k, 3 by #cells
  Eigen::Vector3d rbf_origin_;                   // the centres are shifted by this
  double rbf_scale_ = 1.0;                       // and divided by this
  // The polynomial's linear part is over these orthonormal axes of the scaled
  // centres (3 by r): all three, or fewer where the centres are coplanar or
  // collinear and the full linear polynomial would make the system singular.
  Eigen::Matrix3Xd rbf_axes_;
  Eigen::PartialPivLU<Eigen::MatrixXd> rbf_lu_;  // (#cells + 1 + r) square
  Eigen::MatrixXd rbf_matrix_;                   // the system, for one refinement step
  std::vector<Kind> kind_;                       // per cell
  std::vector<char> vertex_kind_;                // per vertex: Kind of its constraint
  std::vector<int> vertex_group_;                // per vertex: its handle group, or -1
  std::vector<int> driven_group_;                // per cell: HandleGroupOfParticles (scales/rigidity.h)
  int num_free_ = 0;
  // Parameter blocks: quaternions 4 by #cells (x, y, z, w), positions 3 by #cells.
  Eigen::Matrix4Xd rotations_;
  Eigen::Matrix3Xd positions_;
  std::unique_ptr<ceres::Problem> problem_;
  Eigen::Matrix3Xd deformed_vertices_;
  double constraint_gap_ = 0.0;
  double precompute_ms_ = 0.0;
  double setup_ms_ = 0.0;
  StageTimes precompute_stages_;
  StageTimes stages_;  // precompute_stages_ and the layout's
};

}  // namespace msdeform

#endif  // MSDEFORM_METHODS_RIGID_CELLS_H_
