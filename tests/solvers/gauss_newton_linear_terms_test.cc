#include "msdeform/solvers/gauss_newton_linear_terms.h"

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "msdeform/core/procedural_meshes.h"
#include "msdeform/methods/graph_method.h"

namespace msdeform {
namespace {

// The stored arrays of a compressed sparse matrix, for a bitwise comparison.
template <typename Matrix>
void ExpectSameBits(const Matrix& a, const Matrix& b, const std::string& what) {
  ASSERT_EQ(a.rows(), b.rows()) << what;
  ASSERT_EQ(a.cols(), b.cols()) << what;
  ASSERT_EQ(a.nonZeros(), b.nonZeros()) << what;
  const Matrix ca = a, cb = b;  // compressed copies
  EXPECT_TRUE(std::equal(ca.valuePtr(), ca.valuePtr() + ca.nonZeros(), cb.valuePtr())) << what;
  EXPECT_TRUE(std::equal(ca.innerIndexPtr(), ca.innerIndexPtr() + ca.nonZeros(),
                         cb.innerIndexPtr()))
      << what;
  EXPECT_TRUE(std::equal(ca.outerIndexPtr(), ca.outerIndexPtr() + ca.outerSize() + 1,
                         cb.outerIndexPtr()))
      << what;
}

// The position groups' QR on 1, 2 and 3 threads (parallel from one row):
// H, A^T c, A^T P and the compressed residuals are the same bits.
TEST(GaussNewtonLinearTermsTest, ParallelGroupQrIsTheSameForAnyThreadCount) {
  const Mesh mesh = MakeBar(12, 1.0, 4);
  HandleLayout layout;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.vertices(0, v) <= 1.0) layout.fixed.push_back(v);
    if (mesh.vertices(0, v) >= 11.0) layout.moveable.push_back(v);
  }
  DeformerOptions options;
  options.num_threads = 1;
  GraphMethod deformer(options.method);
  std::string error;
  ASSERT_TRUE(deformer.Precompute(mesh, options, &error)) << error;
  ASSERT_TRUE(deformer.SetHandles(layout, &error)) << error;
  const DeformationEnergy& energy = deformer.energy();
  const NodeTransforms transforms = NodeTransforms::Identity(deformer.active().num_nodes());

  // The variables as GaussNewtonSolver::Setup numbers them.
  std::vector<int> offset(energy.node_class.size(), -1);
  std::vector<char> totally_free(energy.node_class.size(), 0);
  int n = 0;
  for (size_t j = 0; j < energy.node_class.size(); ++j) {
    if (energy.node_class[j] == NodeClass::kFixed) continue;
    offset[j] = n;
    totally_free[j] = energy.node_class[j] == NodeClass::kTotallyFree;
    n += totally_free[j] ? 12 : 9;
  }
  GaussNewtonTerms terms;
  ASSERT_TRUE(terms.Setup(energy.terms, offset, totally_free, transforms, &error)) << error;

  // At least two groups of position terms (variable nodes, and whether they
  // follow the handle), so that the parallel loop has work to split.
  std::set<std::vector<int>> groups;
  for (const DeformationEnergy::Position& term : energy.positions) {
    std::vector<int> key;
    for (int j : term.nodes)
      if (offset[j] >= 0) key.push_back(j);
    std::sort(key.begin(), key.end());
    key.push_back(term.handle_group);
    groups.insert(key);
  }
  ASSERT_GE(groups.size(), 2u);

  std::vector<LinearTerms> results(3);
  for (int threads = 1; threads <= 3; ++threads) {
    AssembleLinearTerms(energy, transforms, offset, terms, n, &results[threads - 1], threads, 1);
  }
  for (int t = 1; t < 3; ++t) {
    const std::string what = std::to_string(t + 1) + " threads";
    ExpectSameBits(results[t].hessian, results[0].hessian, what + ": H");
    ExpectSameBits(results[t].handle_gradient, results[0].handle_gradient, what + ": A^T P");
    ExpectSameBits(results[t].root, results[0].root, what + ": root");
    ExpectSameBits(results[t].root_handle, results[0].root_handle, what + ": root_handle");
    EXPECT_TRUE(results[t].linear_gradient == results[0].linear_gradient) << what << ": A^T c";
  }
  EXPECT_GT(results[0].root.rows(), 0);
}

}  // namespace
}  // namespace msdeform
