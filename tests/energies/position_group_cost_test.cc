#include "msdeform/energies/position_group_cost.h"

#include <cmath>
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

// 1/2 sum_l |r_l|^2 in long double, r_l = s (sum_i w_li [R_i o_li + g_i + t_i] - q_l),
// q_l = handle * rest_l (or rest_l): the cost with about 1e-19 relative rounding.
long double ExactCost(const Group& group, const std::vector<Eigen::Matrix3d>& rotations,
                      const std::vector<Eigen::Vector3d>& translations,
                      const Eigen::Affine3d& handle, bool follows, double s) {
  using Vector3l = Eigen::Matrix<long double, 3, 1>;
  const Eigen::Matrix<long double, 3, 3> linear = handle.linear().cast<long double>();
  const Vector3l shift = handle.translation().cast<long double>();
  long double sum = 0.0L;
  for (size_t l = 0; l < group.rest.size(); ++l) {
    const Vector3l rest = group.rest[l].cast<long double>();
    Vector3l r = follows ? Vector3l(-(linear * rest + shift)) : Vector3l(-rest);
    for (size_t i = 0; i < rotations.size(); ++i) {
      const SkinningTerm& term = group.terms[l][i];
      r += static_cast<long double>(term.weight) *
           (rotations[i].cast<long double>() * term.offset.cast<long double>() +
            term.position.cast<long double>() + translations[i].cast<long double>());
    }
    sum += r.squaredNorm();
  }
  return 0.5L * static_cast<long double>(s) * static_cast<long double>(s) * sum;
}

// A group of 3,000 vertices on 3 nodes about 2e3 from the origin (spread
// about 1.5), residuals about 0.1-1 a vertex. The block's cost, what Ceres
// sees plus ConstantCost(), must be the exact sum of the per-vertex costs
// (long double) and the per-vertex costs summed in double (the ungrouped
// blocks) to 1e-12: rounding at the inputs' size (1e-16 of 2e3) against
// these residuals leaves the double sum up to 5e-13 off. The constant formed
// as 1/2 (sum_l |y_l|^2 - |b|^2) from expanded quadratics lost 1e-16 of
// s^2 N |2e3|^2 and was up to 9e-7 off.
TEST(PositionGroupCostTest, CostIsExactFarFromTheOrigin) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const Eigen::Vector3d far(1.1e3, -1.7e3, 0.6e3);
  const int kNodes = 3, kVertices = 3000;
  const double s = 7.0;
  std::vector<Eigen::Vector3d> nodes;
  for (int i = 0; i < kNodes; ++i)
    nodes.push_back(far + Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng)));
  Group group;
  for (int l = 0; l < kVertices; ++l) {
    const Eigen::Vector3d v = far + 1.5 * Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
    std::vector<SkinningTerm> terms;
    double sum = 0.0;
    for (int i = 0; i < kNodes; ++i) {
      terms.push_back({1.1 + uniform(rng), v - nodes[i], nodes[i]});
      sum += terms.back().weight;
    }
    for (auto& term : terms) term.weight /= sum;
    group.terms.push_back(terms);
    group.rest.push_back(v);
  }
  // Handles: a translation; a rotation of 0.3 rad about a point of the group.
  const Eigen::Vector3d move(0.25, -0.125, 0.375);
  Eigen::Affine3d turn = Eigen::Affine3d::Identity();
  turn.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, -2, 2).normalized()).toRotationMatrix();
  turn.translation() = far + move - turn.linear() * far;
  for (bool follows : {true, false}) {
    PositionGroupCost cost(group.terms, group.rest, follows, s);
    for (const Eigen::Affine3d& handle : {Eigen::Affine3d(Eigen::Translation3d(move)), turn}) {
      cost.SetHandle(handle);
      // Nodes at rest, then nodes that nearly follow the handle.
      for (double noise : {-1.0, 0.1}) {
        if (!follows && noise < 0.0) continue;  // the rest pose: cost 0
        std::vector<Eigen::Matrix3d> rotations;
        std::vector<Eigen::Vector3d> translations;
        std::vector<std::vector<double>> blocks;
        for (int i = 0; i < kNodes; ++i) {
          Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
          Eigen::Vector3d translation = Eigen::Vector3d::Zero();
          if (noise > 0.0 && follows) {
            rotation = handle.linear();
            translation = handle * nodes[i] - nodes[i];
          }
          if (noise > 0.0) {
            for (int k = 0; k < 9; ++k) rotation.data()[k] += noise * uniform(rng);
            for (int k = 0; k < 3; ++k) translation[k] += noise * uniform(rng);
          }
          rotations.push_back(rotation);
          translations.push_back(translation);
          blocks.emplace_back(rotation.data(), rotation.data() + 9);
          blocks.emplace_back(translation.data(), translation.data() + 3);
        }
        std::vector<const double*> parameters;
        for (const auto& block : blocks) parameters.push_back(block.data());
        Eigen::VectorXd r(cost.num_residuals());
        ASSERT_TRUE(cost.Evaluate(parameters.data(), r.data(), nullptr));
        const long double exact = ExactCost(group, rotations, translations, handle, follows, s);
        const long double block_cost =
            0.5L * static_cast<long double>(r.squaredNorm()) + cost.ConstantCost();
        double per_vertex = 0.0;
        for (size_t l = 0; l < group.rest.size(); ++l) {
          const Eigen::Vector3d target =
              follows ? Eigen::Vector3d(handle * group.rest[l]) : group.rest[l];
          PositionCostAnalytic vertex(group.terms[l], target, s);
          Eigen::Vector3d rv;
          vertex.Evaluate(parameters.data(), rv.data(), nullptr);
          per_vertex += 0.5 * rv.squaredNorm();
        }
        EXPECT_LT(std::abs(static_cast<double>((block_cost - exact) / exact)), 1e-12)
            << "follows " << follows << ", noise " << noise << ": cost " << static_cast<double>(exact)
            << ", off by " << static_cast<double>(block_cost - exact);
        EXPECT_LT(std::abs(static_cast<double>(block_cost) - per_vertex), 1e-12 * per_vertex);
      }
    }
  }
}

}  // namespace
}  // namespace msdeform
