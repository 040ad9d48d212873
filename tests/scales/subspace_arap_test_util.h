// Shared by the subspace ARAP tests (subspace_arap_test.cc): the energy
// evaluated on the whole mesh straight from its definition (no reduced
// algebra), random and rigid node transforms, and small edits whose ARAP
// optimum lies inside every subspace.

#ifndef MSDEFORM_TESTS_SCALES_SUBSPACE_ARAP_TEST_UTIL_H_
#define MSDEFORM_TESTS_SCALES_SUBSPACE_ARAP_TEST_UTIL_H_

#include <algorithm>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <gtest/gtest.h>

#include "msdeform/core/skinning.h"
#include "msdeform/methods/graph_method.h"
#include "msdeform/scales/handle_setup.h"
#include "msdeform/scales/subspace_arap_build.h"
#include "tests/scales/deformer_test_util.h"

namespace msdeform {

inline constexpr RotationClusters kAllClusters[] = {
    RotationClusters::kWeights, RotationClusters::kNodes, RotationClusters::kVertices};
inline constexpr ArapConstraints kAllConstraints[] = {ArapConstraints::kExact,
                                                      ArapConstraints::kSoft};

// What the full-mesh evaluation reads: the rest mesh, its weights, the graph,
// the handles and still vertices, and the energy's options.
struct FullMesh {
  const Mesh* mesh;
  const CotangentWeights* cotangent;
  const DeformationGraph* graph;
  const HandleLayout* handles;
  const std::vector<char>* still;
  double unit;
  ArapOptions options;

  bool IsStill(int v) const { return !still->empty() && (*still)[v]; }

  // Every vertex skinned by the graph (Eq. 9); still vertices at rest; with
  // exact constraints, moveable-handle vertices at H * rest and fixed ones at
  // rest.
  Eigen::Matrix3Xd Positions(const NodeTransforms& transforms,
                             const Eigen::Affine3d& handle) const {
    Eigen::Matrix3Xd x;
    SkinningOptions skinning;
    skinning.num_threads = 1;
    SkinPositions(mesh->vertices, *graph, transforms, &x, skinning);
    for (int v = 0; v < mesh->num_vertices(); ++v)
      if (IsStill(v)) x.col(v) = mesh->vertices.col(v);
    if (options.constraints == ArapConstraints::kExact) {
      for (int v : handles->moveable)
        if (!IsStill(v)) x.col(v) = handle * Eigen::Vector3d(mesh->vertices.col(v));
      for (int v : handles->fixed)
        if (!IsStill(v)) x.col(v) = mesh->vertices.col(v);
    }
    return x;
  }

  // The size of the sums the reduced energy is a difference of:
  // 1/(2 unit^2) sum_i sum_k w_ik (|x'_i|^2 + |x'_k|^2 + |x_i|^2 + |x_k|^2)
  // (its slots hold positions, not edges), plus the soft terms' size
  // soft_weight (|x'_i|^2 + |q_i|^2). Its rounding error is a small multiple
  // of 1e-16 times this.
  double Magnitude(const Eigen::Matrix3Xd& x, const Eigen::Affine3d& handle) const {
    const VertexAdjacency& adjacency = cotangent->adjacency;
    double total = 0.0;
    for (int i = 0; i < mesh->num_vertices(); ++i) {
      for (int p = adjacency.offsets[i]; p < adjacency.offsets[i + 1]; ++p) {
        const int k = adjacency.neighbors[p];
        total += cotangent->weight[p] *
                 (x.col(i).squaredNorm() + x.col(k).squaredNorm() +
                  mesh->vertices.col(i).squaredNorm() + mesh->vertices.col(k).squaredNorm());
      }
    }
    if (options.constraints == ArapConstraints::kSoft) {
      for (int v : handles->moveable)
        total +=
            options.soft_weight * (x.col(v).squaredNorm() +
                                   (handle * Eigen::Vector3d(mesh->vertices.col(v))).squaredNorm());
      for (int v : handles->fixed)
        total +=
            options.soft_weight * (x.col(v).squaredNorm() + mesh->vertices.col(v).squaredNorm());
    }
    return 0.5 * total / (unit * unit);
  }

  // 1/(2 unit^2) [sum over groups of min_R sum_{i in group} sum_k
  // w_ik |x'_i - x'_k - R (x_i - x_k)|^2 (+ soft terms)]. The groups are the
  // clusters of `cluster_of_vertex`, and each vertex outside them alone.
  double Energy(const Eigen::Matrix3Xd& x, const Eigen::Affine3d& handle,
                const std::vector<int>& cluster_of_vertex) const {
    const int n = mesh->num_vertices();
    const int num_clusters =
        1 + *std::max_element(cluster_of_vertex.begin(), cluster_of_vertex.end());
    std::vector<std::vector<int>> groups(num_clusters);
    for (int v = 0; v < n; ++v) {
      if (cluster_of_vertex[v] >= 0) {
        groups[cluster_of_vertex[v]].push_back(v);
      } else {
        groups.push_back({v});
      }
    }
    const VertexAdjacency& adjacency = cotangent->adjacency;
    double total = 0.0;
    for (const std::vector<int>& group : groups) {
      Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
      for (int i : group) {
        for (int p = adjacency.offsets[i]; p < adjacency.offsets[i + 1]; ++p) {
          const int k = adjacency.neighbors[p];
          s += cotangent->weight[p] * (x.col(i) - x.col(k)) *
               (mesh->vertices.col(i) - mesh->vertices.col(k)).transpose();
        }
      }
      Eigen::JacobiSVD<Eigen::Matrix3d> svd(s, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
      flip(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
      const Eigen::Matrix3d r = svd.matrixU() * flip * svd.matrixV().transpose();
      for (int i : group) {
        for (int p = adjacency.offsets[i]; p < adjacency.offsets[i + 1]; ++p) {
          const int k = adjacency.neighbors[p];
          total += cotangent->weight[p] *
                   (x.col(i) - x.col(k) - r * (mesh->vertices.col(i) - mesh->vertices.col(k)))
                       .squaredNorm();
        }
      }
    }
    if (options.constraints == ArapConstraints::kSoft) {
      for (int v : handles->moveable)
        if (!IsStill(v))
          total += options.soft_weight *
                   (x.col(v) - handle * Eigen::Vector3d(mesh->vertices.col(v))).squaredNorm();
      for (int v : handles->fixed)
        if (!IsStill(v))
          total += options.soft_weight * (x.col(v) - mesh->vertices.col(v)).squaredNorm();
    }
    return 0.5 * total / (unit * unit);
  }
};

// Random transforms: Fixed nodes the identity (as every layout holds them),
// the others a random linear map near I and a random translation (Half Free
// translations too: the energy reads them from the transforms).
inline NodeTransforms RandomTransforms(const std::vector<NodeClass>& node_class, double size,
                                       std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  NodeTransforms transforms = NodeTransforms::Identity(static_cast<int>(node_class.size()));
  for (int j = 0; j < transforms.num_nodes(); ++j) {
    if (node_class[j] == NodeClass::kFixed) continue;
    for (int e = 0; e < 9; ++e) transforms.rotations(e, j) += 0.4 * uniform(*rng);
    for (int d = 0; d < 3; ++d) transforms.translations(d, j) = 0.3 * size * uniform(*rng);
  }
  return transforms;
}

inline Eigen::Affine3d RandomRigid(double size, std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const Eigen::Vector3d axis =
      Eigen::Vector3d(uniform(*rng), uniform(*rng), uniform(*rng)).normalized();
  Eigen::Affine3d h = Eigen::Affine3d::Identity();
  h.linear() = Eigen::AngleAxisd(1.5 * uniform(*rng), axis).toRotationMatrix();
  h.translation() = 0.5 * size * Eigen::Vector3d(uniform(*rng), uniform(*rng), uniform(*rng));
  return h;
}

inline DeformerOptions ArapOptionsFor(Method method, RotationClusters clusters,
                                      ArapConstraints constraints) {
  DeformerOptions options = OptionsFor(method);
  options.energy = Energy::kArap;
  options.arap.clusters = clusters;
  options.arap.num_clusters = 17;  // several vertices per cluster on these meshes
  options.arap.constraints = constraints;
  return options;
}

// A graph method with its handles set.
inline std::unique_ptr<GraphMethod> MakeDeformer(const Mesh& mesh, const DeformerOptions& options,
                                                 const HandleLayout& handles) {
  auto deformer = std::make_unique<GraphMethod>(options.method);
  std::string error;
  EXPECT_TRUE(deformer->Precompute(mesh, options, &error)) << error;
  EXPECT_TRUE(deformer->SetHandles(handles, &error)) << error;
  return deformer;
}

inline std::string Name(Method method, RotationClusters clusters, ArapConstraints constraints) {
  return std::string(MethodName(method)) + " " + RotationClustersNames().Name(clusters) + " " +
         ArapConstraintsNames().Name(constraints);
}

// Totally Free, Half Free and Fixed nodes in turn.
inline std::vector<NodeClass> MixedClasses(int num_nodes) {
  std::vector<NodeClass> classes(num_nodes);
  for (int j = 0; j < num_nodes; ++j)
    classes[j] = j % 3 == 0   ? NodeClass::kTotallyFree
                 : j % 3 == 1 ? NodeClass::kHalfFree
                              : NodeClass::kFixed;
  return classes;
}

// The subspace energy of `setup`'s mesh, graph and handles with other node
// classes and length unit.
inline std::shared_ptr<const SubspaceArap> BuildWithClasses(const HandleSetup& setup,
                                                            const std::vector<NodeClass>& classes,
                                                            double unit,
                                                            const ArapOptions& options) {
  SubspaceArapInput input;
  input.mesh = &setup.precompute().mesh();
  input.cotangent = &setup.precompute().cotangent();
  input.graph = &setup.graph();
  input.node_class = &classes;
  input.handles = &setup.handles();
  input.still_vertices = &setup.still_vertices();
  input.length_unit = unit;
  return BuildSubspaceArap(input, options);
}

inline FullMesh FullMeshOf(const HandleSetup& setup, double unit, const ArapOptions& options) {
  return FullMesh{&setup.precompute().mesh(),
                  &setup.precompute().cotangent(),
                  &setup.graph(),
                  &setup.handles(),
                  &setup.still_vertices(),
                  unit,
                  options};
}

// Two bars 8 x 1 x 1 voxels, 3 apart along y: bar 0 (y < 1) with its last
// voxel the handle and, when `fix_bar0`, its first voxel fixed; bar 1 with its
// first voxel fixed, a still component (it holds no handle vertex).
struct TwoBarEdit {
  explicit TwoBarEdit(bool fix_bar0) : mesh(MakeTwoBars(8, 3, 1.0, 3)) {
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const double x = mesh.vertices(0, v), y = mesh.vertices(1, v);
      if (y <= 1.0 && x >= 7.0) layout.moveable.push_back(v);
      if (y <= 1.0 && x <= 1.0 && fix_bar0) layout.fixed.push_back(v);
      if (y > 1.0 && x <= 1.0) layout.fixed.push_back(v);
    }
  }
  Mesh mesh;
  HandleLayout layout;
};

// Node transforms that move every vertex they skin by H: R_j = A_H,
// t_j = H g_j - g_j, Fixed nodes the identity.
inline NodeTransforms RigidTransforms(const DeformationGraph& graph,
                                      const std::vector<NodeClass>& classes,
                                      const Eigen::Affine3d& h) {
  NodeTransforms transforms = NodeTransforms::Identity(graph.num_nodes());
  for (int j = 0; j < graph.num_nodes(); ++j) {
    if (classes[j] == NodeClass::kFixed) continue;
    transforms.rotation(j) = h.linear();
    transforms.translations.col(j) =
        h * Eigen::Vector3d(graph.positions.col(j)) - graph.positions.col(j);
  }
  return transforms;
}

// Largest distance of a vertex from H * rest (still vertices: from rest), over
// the diagonal.
inline double DistanceFromRigid(const HandleSetup& setup, const Eigen::Matrix3Xd& x,
                                const Eigen::Affine3d& h) {
  const Mesh& mesh = setup.precompute().mesh();
  const std::vector<char>& still = setup.still_vertices();
  double distance = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d rest = mesh.vertices.col(v);
    const Eigen::Vector3d target = !still.empty() && still[v] ? rest : Eigen::Vector3d(h * rest);
    distance = std::max(distance, (x.col(v) - target).norm());
  }
  return distance / setup.precompute().diagonal();
}

// The two meshes whose ARAP optimum lies inside every subspace: a bar with
// no fixed vertex, and a bar beside a still bar (whose fixed vertices hold
// it). Moving the handle rigidly, the optimum moves every free vertex by H.
struct FreeEdit {
  const Mesh* mesh;
  const HandleLayout* handles;
};
inline std::vector<FreeEdit> FreeEdits(const BarEdit& free_bar, const TwoBarEdit& two_bars) {
  return {{&free_bar.mesh, &free_bar.layout}, {&two_bars.mesh, &two_bars.layout}};
}

inline Eigen::Affine3d Turn() {
  Eigen::Affine3d h = Eigen::Affine3d::Identity();
  h.linear() = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  h.translation() << 1.0, -2.0, 0.5;
  return h;
}

}  // namespace msdeform

#endif  // MSDEFORM_TESTS_SCALES_SUBSPACE_ARAP_TEST_UTIL_H_
