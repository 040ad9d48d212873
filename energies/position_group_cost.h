// The position constraints (paper Eq. 16) of a group of handle vertices that
// share the same nodes, as one small exact least-squares block.
//
// For vertex l of the group, residual r_l = s (sum_i w_li [R_i o_li + g_i + t_i] - q_l)
// is linear in x = [R_1 (9, column-major), t_1 (3), ..., R_m, t_m]:
// r_l = J_l x - y_l with y_l = s (q_l - sum_i w_li g_i). So
//   sum_l |r_l|^2 = x^T G x - 2 x^T h + sum_l |y_l|^2,  G = sum J_l^T J_l,  h = sum J_l^T y_l.
// With G = V Lambda V^T (eigenvalues above 1e-12 lambda_max kept, which loses
// nothing: h lies in the range of G), L = Lambda^{1/2} V^T and
// b = Lambda^{-1/2} V^T h, this equals |L x - b|^2 + sum_l |y_l|^2 - |b|^2:
// the same minimiser, gradient and Gauss-Newton Hessian, with rank(G) <= 12 m
// residuals however many vertices the group holds. q_l = handle * rest_l is
// linear in the handle's 12 numbers tau, so a frame sets b = D [tau; 1] and
// the dropped constant 1/2 (sum_l |y_l|^2 - |b|^2) (ConstantCost(), for
// reporting the true Eq. 17 cost) from precomputed 13-column matrices.
//
// Parameter blocks: R_1, t_1, ..., R_m, t_m (9 and 3 doubles). Residuals: rank(G).

#ifndef MSDEFORM_ENERGIES_POSITION_GROUP_COST_H_
#define MSDEFORM_ENERGIES_POSITION_GROUP_COST_H_

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <ceres/cost_function.h>

#include "msdeform/energies/position_cost.h"

namespace msdeform {

class PositionGroupCost : public ceres::CostFunction {
 public:
  // vertex_terms[l][i]: vertex l's share of node i (same nodes, same order for
  // every l; zero weights allowed). rest[l]: its rest position. When
  // follows_handle is false the targets stay at rest whatever SetHandle gets.
  PositionGroupCost(const std::vector<std::vector<SkinningTerm>>& vertex_terms,
                    const std::vector<Eigen::Vector3d>& rest, bool follows_handle,
                    double sqrt_weight);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // Moves the targets to handle * rest (a drag frame).
  void SetHandle(const Eigen::Affine3d& handle);
  // 1/2 (sum_l |y_l|^2 - |b|^2) for the current handle: the Eq. 17 cost of
  // the group is this plus the cost Ceres sees.
  double ConstantCost() const { return constant_cost_; }
  int num_nodes() const { return num_nodes_; }

 private:
  int num_nodes_ = 0;
  bool follows_handle_ = true;
  Eigen::MatrixXd factor_;      // L, rank by 12 m
  Eigen::MatrixXd target_map_;  // D, rank by 13: b = D [tau; 1]
  Eigen::Matrix<double, 13, 13> gram_;  // sum_l Y_l^T Y_l, y_l = Y_l [tau; 1]
  Eigen::VectorXd target_;      // b
  double constant_cost_ = 0.0;
};

}  // namespace msdeform

#endif  // MSDEFORM_ENERGIES_POSITION_GROUP_COST_H_
