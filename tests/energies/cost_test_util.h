// Shared checks for the cost-function tests (tests/energies/*_cost_test.cc and
// the example terms' tests): Jacobians against numeric differentiation, and an
// analytic cost function against its autodiff twin.

#ifndef MSDEFORM_TESTS_ENERGIES_COST_TEST_UTIL_H_
#define MSDEFORM_TESTS_ENERGIES_COST_TEST_UTIL_H_

#include <random>
#include <vector>

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

namespace msdeform {

// Random parameter blocks sized for `cost`, entries in [-1, 1].
inline std::vector<std::vector<double>> RandomBlocks(const ceres::CostFunction& cost,
                                                     std::mt19937* random) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<std::vector<double>> blocks;
  for (int size : cost.parameter_block_sizes()) {
    blocks.emplace_back(size);
    for (double& value : blocks.back()) value = uniform(*random);
  }
  return blocks;
}

inline std::vector<const double*> Pointers(const std::vector<std::vector<double>>& blocks) {
  std::vector<const double*> pointers;
  for (const auto& block : blocks) pointers.push_back(block.data());
  return pointers;
}

inline void ExpectJacobianMatchesNumeric(const ceres::CostFunction& cost,
                                         const std::vector<std::vector<double>>& blocks) {
  ceres::NumericDiffOptions options;
  ceres::GradientChecker checker(
      &cost, static_cast<const std::vector<const ceres::Manifold*>*>(nullptr), options);
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(Pointers(blocks).data(), 1e-8, &results)) << results.error_log;
}

// Residuals and every Jacobian block of `a` and `b` agree to `tolerance`.
inline void ExpectSameCost(const ceres::CostFunction& a, const ceres::CostFunction& b,
                           const std::vector<std::vector<double>>& blocks, double tolerance) {
  ASSERT_EQ(a.num_residuals(), b.num_residuals());
  ASSERT_EQ(a.parameter_block_sizes(), b.parameter_block_sizes());
  const int m = a.num_residuals();
  std::vector<double> residuals_a(m), residuals_b(m);
  std::vector<std::vector<double>> jacobian_a, jacobian_b;
  std::vector<double*> pointers_a, pointers_b;
  for (int size : a.parameter_block_sizes()) {
    jacobian_a.emplace_back(m * size, 0.0);
    jacobian_b.emplace_back(m * size, 0.0);
  }
  for (size_t i = 0; i < jacobian_a.size(); ++i) {
    pointers_a.push_back(jacobian_a[i].data());
    pointers_b.push_back(jacobian_b[i].data());
  }
  ASSERT_TRUE(a.Evaluate(Pointers(blocks).data(), residuals_a.data(), pointers_a.data()));
  ASSERT_TRUE(b.Evaluate(Pointers(blocks).data(), residuals_b.data(), pointers_b.data()));
  for (int r = 0; r < m; ++r) EXPECT_NEAR(residuals_a[r], residuals_b[r], tolerance) << r;
  for (size_t i = 0; i < jacobian_a.size(); ++i)
    for (size_t e = 0; e < jacobian_a[i].size(); ++e)
      EXPECT_NEAR(jacobian_a[i][e], jacobian_b[i][e], tolerance) << "block " << i << " entry " << e;
}

// `trials` times: random blocks (RandomBlocks with `random`), both Jacobians
// against numeric differentiation, and the analytic residuals and Jacobians
// equal to the autodiff ones to `tolerance`.
inline void ExpectAnalyticMatchesAutodiff(const ceres::CostFunction& analytic,
                                          const ceres::CostFunction& autodiff, int trials,
                                          double tolerance, std::mt19937* random) {
  for (int trial = 0; trial < trials; ++trial) {
    SCOPED_TRACE(testing::Message() << "trial " << trial);
    const auto blocks = RandomBlocks(analytic, random);
    ExpectJacobianMatchesNumeric(autodiff, blocks);
    ExpectJacobianMatchesNumeric(analytic, blocks);
    ExpectSameCost(analytic, autodiff, blocks, tolerance);
  }
}

inline std::vector<double> Residuals(const ceres::CostFunction& cost,
                                     const std::vector<std::vector<double>>& blocks) {
  std::vector<double> residuals(cost.num_residuals());
  EXPECT_TRUE(cost.Evaluate(Pointers(blocks).data(), residuals.data(), nullptr));
  return residuals;
}

}  // namespace msdeform

#endif  // MSDEFORM_TESTS_ENERGIES_COST_TEST_UTIL_H_
