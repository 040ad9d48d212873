// Shared by the deformer tests (deformer_test.cc, deformer_robustness_test.cc):
// the methods, small-graph options for small procedural meshes, and a
// vertex distance.

#ifndef MSDEFORM_TESTS_SCALES_DEFORMER_TEST_UTIL_H_
#define MSDEFORM_TESTS_SCALES_DEFORMER_TEST_UTIL_H_

#include <Eigen/Core>

#include "msdeform/scales/deformer.h"

namespace msdeform {

inline constexpr Method kAllMethods[] = {Method::kMultiScale, Method::kStatic,
                                         Method::kStaticDense};

// `method` with graphs small enough for a few hundred vertices: 20 nodes per
// scale, a 40-node static graph, one thread.
inline DeformerOptions OptionsFor(Method method) {
  DeformerOptions options;
  options.method = method;
  options.static_nodes = 40;
  options.graph.nodes_per_scale = 20;
  options.num_threads = 1;
  return options;
}

// Largest distance between corresponding columns.
inline double MaxDistance(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return (a - b).colwise().norm().maxCoeff();
}

}  // namespace msdeform

#endif  // MSDEFORM_TESTS_SCALES_DEFORMER_TEST_UTIL_H_
