// The position constraints (paper Eq. 16) of a group of handle vertices that
// share the same nodes, as one small exact least-squares block.
//
// For vertex l of the group, residual r_l = s (sum_i w_li [R_i o_li + g_i + t_i] - q_l).
// Its component a involves only row a of each R_i and component a of each t_i,
// with the same coefficients for every a. With c the group's mean rest
// position and the handle q = A p + u written as q_l = A (p_l - c) + d + c,
// d = (A - I) c + u (d = 0 when the targets stay at rest):
//   r_la = m_l^T [x_a; -A_a; -d_a; e_a],
//   m_l = s [w_l1 o_l1, w_l1, ..., w_lk o_lk, w_lk, p_l - c, 1, blended_l - c],
// x_a = [R_1(a, :), t_1(a), ..., R_k(a, :), t_k(a)], A_a row a of A, e_a the
// a-th unit 3-vector, blended_l = sum_i w_li g_i. The rows m_l^T stack into M,
// #vertices by 4 k + 7, and a Householder QR gives M = Q U with sum_l |r_l|^2 =
// sum_a |U z_a|^2 for every z_a. U's first 4 k rows are the block's residuals
// (3 of them per row, one per axis); its last 7 columns' trailing rows hold the
// part no x can change, 1/2 sum_a |U_22 [-A_a; -d_a; e_a]|^2 (ConstantCost(),
// for reporting the true Eq. 17 cost). The QR is backward stable and every
// entry is relative to the group (c), so the cost is exact to the rounding
// of the residuals themselves, however far from the origin the group lies.
// A group of at most 4 k vertices keeps its rows M as they are.
//
// Parameter blocks: R_1, t_1, ..., R_k, t_k (9 doubles column-major, and 3).
// Residuals: 3 min(4 k, #vertices), ordered axis by axis.

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
  // The part of the group's Eq. 17 cost that no node transform changes, for
  // the current handle: the group's cost is this plus the cost Ceres sees.
  double ConstantCost() const { return constant_cost_; }
  int num_nodes() const { return num_nodes_; }

 private:
  int num_nodes_ = 0;
  bool follows_handle_ = true;
  Eigen::Vector3d center_ = Eigen::Vector3d::Zero();  // c
  // U's leading rows: rows by 4 k (the nodes' columns) and rows by 7.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> factor_;
  Eigen::Matrix<double, Eigen::Dynamic, 7> factor_handle_;
  Eigen::Matrix<double, Eigen::Dynamic, 7> constant_factor_;  // U_22: trailing rows by 7
  Eigen::Matrix<double, Eigen::Dynamic, 3> offset_;  // per axis a: factor_handle_ z_a
  double constant_cost_ = 0.0;
};

}  // namespace msdeform

#endif  // MSDEFORM_ENERGIES_POSITION_GROUP_COST_H_
