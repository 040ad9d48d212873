#include "msdeform/solvers/gauss_newton_supernodal_cholesky.h"

#include <random>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>
#include <gtest/gtest.h>

namespace msdeform {
namespace {

using SparseMatrix = SupernodalCholesky::SparseMatrix;

// A random symmetric positive definite system shaped like the Gauss-Newton
// normal equations: `nodes` blocks of 12 or 9 variables, a dense block per
// node (the Rot term) and rows coupling two or three nodes on some of their
// variables (Coherence and Position terms), so J^T J, plus `shift` I.
SparseMatrix RandomBlockSystem(int nodes, unsigned seed, double shift) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<int> offset(nodes + 1, 0);
  for (int j = 0; j < nodes; ++j) offset[j + 1] = offset[j] + (j % 3 == 2 ? 9 : 12);
  const int n = offset[nodes];
  std::vector<Eigen::Triplet<double>> rows;
  int row = 0;
  for (int j = 0; j < nodes; ++j, ++row)  // one dense row per node
    for (int i = offset[j]; i < offset[j + 1]; ++i) rows.emplace_back(row, i, value(random));
  std::uniform_int_distribution<int> node(0, nodes - 1), coordinate(0, 2);
  for (int term = 0; term < 4 * nodes; ++term) {
    const int a = coordinate(random);
    for (int touched = 0; touched < 2 + term % 2; ++touched) {
      const int j = node(random);
      for (int c = 0; c < 3; ++c) rows.emplace_back(row, offset[j] + c * 3 + a, value(random));
      if (offset[j + 1] - offset[j] == 12) rows.emplace_back(row, offset[j] + 9 + a, value(random));
    }
    ++row;
  }
  SparseMatrix jacobian(row, n);
  jacobian.setFromTriplets(rows.begin(), rows.end());
  SparseMatrix identity(n, n);
  identity.setIdentity();
  SparseMatrix system = SparseMatrix(jacobian.transpose() * jacobian) + shift * identity;
  system.makeCompressed();
  return system;
}

// The solve of a dense LLT.
Eigen::VectorXd DenseSolve(const SparseMatrix& system, const Eigen::VectorXd& rhs) {
  return Eigen::MatrixXd(system).llt().solve(rhs);
}

TEST(SupernodalCholeskyTest, SolvesARandomBlockSystemLikeADenseLLT) {
  for (int nodes : {1, 2, 7, 40}) {
    int fundamental = 0;
    for (double relax : {0.0, 0.2, 1.0}) {
      const SparseMatrix system = RandomBlockSystem(nodes, 17u + nodes, 1e-2);
      const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(system.rows(), -1.0, 2.0);
      SupernodalCholesky cholesky(relax);
      cholesky.Analyze(system);
      ASSERT_TRUE(cholesky.Factorize(system));
      Eigen::VectorXd x;
      cholesky.Solve(rhs, &x);
      const Eigen::VectorXd expected = DenseSolve(system, rhs);
      EXPECT_LE((x - expected).norm(), 1e-12 * expected.norm())
          << nodes << " nodes, relax " << relax;
      // Relaxing merges supernodes, never splits them.
      if (relax == 0.0) fundamental = cholesky.num_supernodes();
      EXPECT_LE(cholesky.num_supernodes(), fundamental) << nodes << " nodes, relax " << relax;
      EXPECT_GE(cholesky.num_supernodes(), 1);
    }
  }
}

TEST(SupernodalCholeskyTest, RefactorisesNewValuesOnTheSamePattern) {
  const SparseMatrix first = RandomBlockSystem(30, 5u, 1e-2);
  SparseMatrix second = first;
  for (int k = 0; k < second.nonZeros(); ++k) second.valuePtr()[k] *= 0.5;
  for (int i = 0; i < second.rows(); ++i) second.coeffRef(i, i) += 1.0;
  SupernodalCholesky cholesky;
  cholesky.Analyze(first);
  ASSERT_TRUE(cholesky.Factorize(first));
  ASSERT_TRUE(cholesky.Factorize(second));
  const Eigen::VectorXd rhs = Eigen::VectorXd::Ones(second.rows());
  Eigen::VectorXd x;
  cholesky.Solve(rhs, &x);
  const Eigen::VectorXd expected = DenseSolve(second, rhs);
  EXPECT_LE((x - expected).norm(), 1e-12 * expected.norm());
}

TEST(SupernodalCholeskyTest, AnIndefiniteSystemDoesNotFactorise) {
  SparseMatrix system = RandomBlockSystem(10, 3u, 0.0);
  for (int i = 0; i < system.rows(); ++i) system.coeffRef(i, i) -= 1e3;
  SupernodalCholesky cholesky;
  cholesky.Analyze(system);
  EXPECT_FALSE(cholesky.Factorize(system));
}

TEST(SupernodalCholeskyDeathTest, AnotherPatternWithAsManyEntriesIsRefused) {
  // Two 3x3 tridiagonal-like patterns with 7 entries each: the (1, 0) pair
  // moved to (2, 0). Factorize would write the values to the wrong places.
  auto matrix = [](int far_row) {
    std::vector<Eigen::Triplet<double>> entries = {{0, 0, 4.0}, {1, 1, 4.0}, {2, 2, 4.0},
                                                   {2, 1, 1.0}, {1, 2, 1.0}};
    entries.emplace_back(far_row, 0, 1.0);
    entries.emplace_back(0, far_row, 1.0);
    SparseMatrix m(3, 3);
    m.setFromTriplets(entries.begin(), entries.end());
    m.makeCompressed();
    return m;
  };
  SupernodalCholesky cholesky;
  cholesky.Analyze(matrix(1));
  EXPECT_TRUE(cholesky.Factorize(matrix(1)));
  EXPECT_DEATH(cholesky.Factorize(matrix(2)), "another pattern");
}

}  // namespace
}  // namespace msdeform
