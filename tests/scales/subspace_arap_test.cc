// The subspace ARAP energy (scales/subspace_arap.h) and its local/global
// solver (scales/arap_solver.h) against answers known without the reduced
// algebra: a full-mesh evaluation written from the energy's definition (skin
// every vertex, set the exact constraints, then per rotation cluster the best
// rotation by SVD and the cotangent-weighted spokes), a rigid edit whose
// optimum lies inside the subspace (energy 0, every vertex at H * rest), the
// solver's energy never rising, and the options' errors.

#include "msdeform/scales/subspace_arap.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <gflags/gflags.h>
#include <gtest/gtest.h>

#include "msdeform/core/skinning.h"
#include "experiments/metrics.h"
#include "msdeform/scales/arap_solver.h"
#include "msdeform/scales/deformer_flags.h"
#include "tests/scales/deformer_test_util.h"

namespace msdeform {
namespace {

constexpr RotationClusters kAllClusters[] = {RotationClusters::kWeights, RotationClusters::kNodes,
                                             RotationClusters::kVertices};
constexpr ArapConstraints kAllConstraints[] = {ArapConstraints::kExact, ArapConstraints::kSoft};

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
  Eigen::Matrix3Xd Positions(const NodeTransforms& transforms, const Eigen::Affine3d& handle) const {
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
        if (!IsStill(v)) total += options.soft_weight * (x.col(v) - mesh->vertices.col(v)).squaredNorm();
    }
    return 0.5 * total / (unit * unit);
  }
};

// Random transforms: Fixed nodes the identity (as every layout holds them),
// the others a random linear map near I and a random translation (Half Free
// translations too: the energy reads them from the transforms).
NodeTransforms RandomTransforms(const std::vector<NodeClass>& node_class, double size,
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

Eigen::Affine3d RandomRigid(double size, std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const Eigen::Vector3d axis =
      Eigen::Vector3d(uniform(*rng), uniform(*rng), uniform(*rng)).normalized();
  Eigen::Affine3d h = Eigen::Affine3d::Identity();
  h.linear() = Eigen::AngleAxisd(1.5 * uniform(*rng), axis).toRotationMatrix();
  h.translation() = 0.5 * size * Eigen::Vector3d(uniform(*rng), uniform(*rng), uniform(*rng));
  return h;
}

DeformerOptions ArapOptionsFor(Method method, RotationClusters clusters,
                               ArapConstraints constraints) {
  DeformerOptions options = OptionsFor(method);
  options.energy = Energy::kArap;
  options.arap.clusters = clusters;
  options.arap.num_clusters = 17;  // several vertices per cluster on these meshes
  options.arap.constraints = constraints;
  return options;
}

std::unique_ptr<Deformer> MakeDeformer(const Mesh& mesh, const DeformerOptions& options,
                                       const HandleLayout& handles) {
  auto deformer = std::make_unique<Deformer>();
  std::string error;
  EXPECT_TRUE(deformer->Init(mesh, options, &error)) << error;
  EXPECT_TRUE(deformer->SetHandles(handles, &error)) << error;
  return deformer;
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
      if (y > 1.0) bar1.push_back(v);
    }
  }
  Mesh mesh;
  HandleLayout layout;
  std::vector<int> bar1;
};

// The reduced energy at random transforms and a random handle equals the
// full-mesh evaluation to 1e-12 relative, for every cluster option and both
// constraint kinds, on the layouts the Deformer makes (one mesh with a still
// second component) and with hand-made node classes that mix Totally Free,
// Half Free and Fixed nodes (and a length unit that is not the diagonal).
TEST(SubspaceArapTest, ReducedEnergyEqualsTheFullMeshEvaluation) {
  const BarEdit bar(12, 4);
  const TwoBarEdit two_bars(/*fix_bar0=*/true);
  std::mt19937 rng(29);
  for (const auto& [mesh, handles] : {std::make_pair(&bar.mesh, &bar.layout),
                                      std::make_pair(&two_bars.mesh, &two_bars.layout)}) {
    for (Method method : {Method::kMultiScale, Method::kStatic}) {
      for (RotationClusters clusters : kAllClusters) {
        for (ArapConstraints constraints : kAllConstraints) {
          const DeformerOptions options = ArapOptionsFor(method, clusters, constraints);
          const std::unique_ptr<Deformer> deformer = MakeDeformer(*mesh, options, *handles);
          const Layout& layout = *deformer->layout();
          const double diagonal = deformer->diagonal();
          // Hand-made classes: Totally Free, Half Free and Fixed in turn.
          std::vector<NodeClass> mixed(layout.graph().num_nodes());
          for (size_t j = 0; j < mixed.size(); ++j)
            mixed[j] = j % 3 == 0 ? NodeClass::kTotallyFree
                       : j % 3 == 1 ? NodeClass::kHalfFree
                                    : NodeClass::kFixed;
          SubspaceArapInput input;
          input.mesh = &layout.precompute().mesh();
          input.cotangent = &layout.precompute().cotangent();
          input.graph = &layout.graph();
          input.node_class = &mixed;
          input.handles = &layout.handles();
          input.still_vertices = &layout.still_vertices();
          input.length_unit = 0.37 * diagonal;
          const std::shared_ptr<const SubspaceArap> hand = SubspaceArap::Build(input, options.arap);

          struct Case {
            const SubspaceArap* arap;
            const std::vector<NodeClass>* classes;
            double unit;
          };
          for (const Case& c : {Case{layout.energy().arap.get(), &layout.node_classes(), diagonal},
                                Case{hand.get(), &mixed, 0.37 * diagonal}}) {
            ASSERT_NE(c.arap, nullptr);
            const FullMesh full{&layout.precompute().mesh(), &layout.precompute().cotangent(),
                                &layout.graph(), &layout.handles(), &layout.still_vertices(),
                                c.unit, options.arap};
            for (int trial = 0; trial < 3; ++trial) {
              const NodeTransforms transforms = RandomTransforms(*c.classes, diagonal, &rng);
              const Eigen::Affine3d handle = RandomRigid(diagonal, &rng);
              SubspaceArap::Slots u;
              c.arap->Gather(transforms, handle, &u);
              const double reduced = c.arap->Cost(u);
              const double expected =
                  full.Energy(full.Positions(transforms, handle), handle, c.arap->cluster_of_vertex());
              EXPECT_GT(expected, 0.0);
              EXPECT_NEAR(reduced, expected, 1e-12 * expected)
                  << MethodName(method) << " " << RotationClustersNames().Name(clusters) << " "
                  << ArapConstraintsNames().Name(constraints) << " trial " << trial
                  << (c.arap == hand.get() ? " (mixed classes)" : "");
            }
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace msdeform
