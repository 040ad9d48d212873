#include "core/skinning.h"

#include <cmath>

#include <Eigen/LU>
#include <glog/logging.h>
#include <omp.h>

namespace msdeform {
namespace {

using Matrix12Xd = Eigen::Matrix<double, 12, Eigen::Dynamic>;
using Vector12d = Eigen::Matrix<double, 12, 1>;

void CheckInputs(const Eigen::Matrix3Xd& rest, const DeformationGraph& graph,
                 const NodeTransforms& transforms, const SkinningOptions& options) {
  std::string error;
  CHECK(options.Check(&error)) << error;
  CHECK_EQ(transforms.rotations.cols(), graph.num_nodes());
  CHECK_EQ(transforms.translations.cols(), graph.num_nodes());
  CHECK_EQ(graph.weights.nodes.cols(), rest.cols()) << "the graph was built for another mesh";
  CHECK_EQ(graph.weights.weights.cols(), rest.cols());
  CHECK_EQ(graph.weights.nodes.rows(), graph.weights.k);
  CHECK_EQ(graph.weights.weights.rows(), graph.weights.k);
}

int NumThreads(const SkinningOptions& options) {
  return options.num_threads > 0 ? options.num_threads : omp_get_max_threads();
}

// Sum over the k nearest nodes of vertex v of w_j * per_node.col(j).
template <int Rows>
Eigen::Matrix<double, Rows, 1> Blend(const SkinningWeights& weights,
                                     const Eigen::Matrix<double, Rows, Eigen::Dynamic>& per_node,
                                     int v) {
  const int* nodes = weights.nodes.col(v).data();
  const double* w = weights.weights.col(v).data();
  Eigen::Matrix<double, Rows, 1> sum = w[0] * per_node.col(nodes[0]);
  for (int i = 1; i < weights.k; ++i) sum += w[i] * per_node.col(nodes[i]);
  return sum;
}

}  // namespace

bool SkinningOptions::Check(std::string* error) const {
  if (num_threads < 0) {
    *error = "num_threads must be >= 0 (0: OpenMP default), got " + std::to_string(num_threads);
    return false;
  }
  return true;
}

void SkinPositions(const Eigen::Matrix3Xd& rest_vertices, const DeformationGraph& graph,
                   const NodeTransforms& transforms, Eigen::Matrix3Xd* deformed,
                   const SkinningOptions& options) {
  CHECK(deformed != nullptr);
  CHECK_NE(deformed, &rest_vertices);
  CheckInputs(rest_vertices, graph, transforms, options);
  const int num_nodes = graph.num_nodes();
  const int num_vertices = static_cast<int>(rest_vertices.cols());
  deformed->resize(3, num_vertices);
  // Column j: M_j = R_j - I (column-major), then c_j = t_j - M_j g_j.
  Matrix12Xd affine(12, num_nodes);
#pragma omp parallel num_threads(NumThreads(options))
  {
#pragma omp for schedule(static)
    for (int j = 0; j < num_nodes; ++j) {
      const Eigen::Matrix3d m = transforms.rotation(j) - Eigen::Matrix3d::Identity();
      Eigen::Map<Eigen::Matrix3d>(affine.col(j).data()) = m;
      affine.col(j).tail<3>() = transforms.translations.col(j) - m * graph.positions.col(j);
    }
#pragma omp for schedule(static)
    for (int v = 0; v < num_vertices; ++v) {
      const Vector12d blend = Blend<12>(graph.weights, affine, v);
      const Eigen::Vector3d p = rest_vertices.col(v);
      deformed->col(v) = p + (Eigen::Map<const Eigen::Matrix3d>(blend.data()) * p +
                              blend.tail<3>());
    }
  }
}

void SkinNormals(const Eigen::Matrix3Xd& rest_normals, const DeformationGraph& graph,
                 const NodeTransforms& transforms, Eigen::Matrix3Xd* deformed_normals,
                 const SkinningOptions& options) {
  CHECK(deformed_normals != nullptr);
  CHECK_NE(deformed_normals, &rest_normals);
  CheckInputs(rest_normals, graph, transforms, options);
  const int num_nodes = graph.num_nodes();
  const int num_vertices = static_cast<int>(rest_normals.cols());
  deformed_normals->resize(3, num_vertices);
  Eigen::Matrix<double, 9, Eigen::Dynamic> inverse_transposed(9, num_nodes);
#pragma omp parallel num_threads(NumThreads(options))
  {
#pragma omp for schedule(static)
    for (int j = 0; j < num_nodes; ++j) {
      const Eigen::Matrix3d r = transforms.rotation(j);
      // Cofactor matrix: cofactor = det(R) R^{-T}.
      Eigen::Matrix3d cofactor;
      cofactor.col(0) = r.col(1).cross(r.col(2));
      cofactor.col(1) = r.col(2).cross(r.col(0));
      cofactor.col(2) = r.col(0).cross(r.col(1));
      const double det = r.col(0).dot(cofactor.col(0));
      Eigen::Map<Eigen::Matrix3d> q(inverse_transposed.col(j).data());
      q = std::abs(det) >= 1e-12 ? Eigen::Matrix3d(cofactor / det) : cofactor;
    }
#pragma omp for schedule(static)
    for (int v = 0; v < num_vertices; ++v) {
      const Eigen::Matrix<double, 9, 1> blend = Blend<9>(graph.weights, inverse_transposed, v);
      const Eigen::Vector3d n = Eigen::Map<const Eigen::Matrix3d>(blend.data()) *
                                rest_normals.col(v);
      const double length = n.norm();
      deformed_normals->col(v) =
          length > 0.0 && std::isfinite(length) ? Eigen::Vector3d(n / length)
                                                : Eigen::Vector3d::Zero();
    }
  }
}

}  // namespace msdeform
