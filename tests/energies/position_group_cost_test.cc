#include "msdeform/energies/position_group_cost.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "msdeform/energies/position_cost.h"

namespace msdeform {
namespace {

// A group of vertices sharing `num_nodes` nodes, with random weights/offsets.
struct Group {
  std::vector<std::vector<SkinningTerm>> terms;
  std::vector<Eigen::Vector3d> rest;
};

Group RandomGroup(int num_vertices, int num_nodes, std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(0.1, 1.0);
  std::vector<Eigen::Vector3d> nodes(num_nodes);
  for (auto& g : nodes) g = 3.0 * Eigen::Vector3d::Random();
  Group group;
  for (int l = 0; l < num_vertices; ++l) {
    const Eigen::Vector3d v = 3.0 * Eigen::Vector3d::Random();
    std::vector<SkinningTerm> terms;
    double sum = 0.0;
    for (int i = 0; i < num_nodes; ++i) {
      terms.push_back({uniform(*rng), v - nodes[i], nodes[i]});
      sum += terms.back().weight;
    }
    for (auto& term : terms) term.weight /= sum;
    group.terms.push_back(terms);
    group.rest.push_back(v);
  }
  return group;
}

// The group block's 1/2 |L x - b|^2 + constant, and its gradient, equal the
// sum of the per-vertex PositionCostAnalytic costs and gradients, for groups
// smaller (rank-deficient G) and larger than the 12 m variables.
TEST(PositionGroupCostTest, EqualsTheSumOfPerVertexCosts) {
  std::mt19937 rng(3);
  for (int num_vertices : {1, 3, 40}) {
    for (int num_nodes : {1, 4}) {
      for (bool follows : {true, false}) {
        const Group group = RandomGroup(num_vertices, num_nodes, &rng);
        const double sqrt_weight = 7.0;
        PositionGroupCost cost(group.terms, group.rest, follows, sqrt_weight);
        Eigen::Affine3d handle = Eigen::Affine3d::Identity();
        handle.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())
                              .toRotationMatrix() * 1.1;
        handle.translation() = Eigen::Vector3d(0.5, -1.0, 2.0);
        cost.SetHandle(handle);
        std::vector<std::vector<double>> blocks;
        for (int i = 0; i < num_nodes; ++i) {
          blocks.emplace_back(9);
          for (double& value : blocks.back()) value = std::uniform_real_distribution<>(-1, 1)(rng);
          blocks.emplace_back(3);
          for (double& value : blocks.back()) value = std::uniform_real_distribution<>(-1, 1)(rng);
        }
        std::vector<const double*> parameters;
        for (const auto& block : blocks) parameters.push_back(block.data());
        const int n = 12 * num_nodes;

        // Reference: the per-vertex costs.
        double reference_cost = 0.0;
        Eigen::VectorXd reference_gradient = Eigen::VectorXd::Zero(n);
        for (int l = 0; l < num_vertices; ++l) {
          const Eigen::Vector3d target = follows ? Eigen::Vector3d(handle * group.rest[l])
                                                 : group.rest[l];
          PositionCostAnalytic vertex(group.terms[l], target, sqrt_weight);
          Eigen::Vector3d r;
          std::vector<std::vector<double>> jacobians;
          std::vector<double*> jacobian_pointers;
          for (int size : vertex.parameter_block_sizes()) {
            jacobians.emplace_back(3 * size);
            jacobian_pointers.push_back(jacobians.back().data());
          }
          ASSERT_TRUE(vertex.Evaluate(parameters.data(), r.data(), jacobian_pointers.data()));
          reference_cost += 0.5 * r.squaredNorm();
          int column = 0;
          for (size_t b = 0; b < jacobians.size(); ++b) {
            const int size = vertex.parameter_block_sizes()[b];
            for (int p = 0; p < size; ++p)
              for (int a = 0; a < 3; ++a)
                reference_gradient[column + p] += jacobians[b][a * size + p] * r[a];
            column += size;
          }
        }

        const int rank = cost.num_residuals();
        EXPECT_LE(rank, std::min(n, 3 * num_vertices));
        Eigen::VectorXd r(rank);
        std::vector<std::vector<double>> jacobians;
        std::vector<double*> jacobian_pointers;
        for (int size : cost.parameter_block_sizes()) {
          jacobians.emplace_back(rank * size);
          jacobian_pointers.push_back(jacobians.back().data());
        }
        ASSERT_TRUE(cost.Evaluate(parameters.data(), r.data(), jacobian_pointers.data()));
        const double group_cost = 0.5 * r.squaredNorm() + cost.ConstantCost();
        EXPECT_NEAR(group_cost, reference_cost, 1e-9 * (1.0 + reference_cost))
            << num_vertices << " vertices, " << num_nodes << " nodes";
        Eigen::VectorXd gradient = Eigen::VectorXd::Zero(n);
        int column = 0;
        for (size_t b = 0; b < jacobians.size(); ++b) {
          const int size = cost.parameter_block_sizes()[b];
          for (int p = 0; p < size; ++p)
            for (int a = 0; a < rank; ++a) gradient[column + p] += jacobians[b][a * size + p] * r[a];
          column += size;
        }
        EXPECT_LT((gradient - reference_gradient).norm(),
                  1e-8 * (1.0 + reference_gradient.norm()));
      }
    }
  }
}

}  // namespace
}  // namespace msdeform
