#include "msdeform/core/skinning.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <gtest/gtest.h>

#include "msdeform/core/procedural_meshes.h"

namespace msdeform {
namespace {

struct Fixture {
  Mesh mesh;
  Lattice lattice;
  std::vector<DeformationGraph> graphs;
};

Fixture Build(Mesh mesh, double cell_width) {
  Fixture f;
  f.mesh = std::move(mesh);
  LatticeOptions lattice_options;
  lattice_options.cell_width = cell_width;
  std::string error;
  EXPECT_TRUE(Lattice::Build(f.mesh, lattice_options, &f.lattice, &error)) << error;
  GraphOptions options;
  options.nodes_per_scale = 10;
  EXPECT_TRUE(BuildMultiScaleGraphs(f.mesh, f.lattice, options, &f.graphs, &error)) << error;
  EXPECT_GE(f.graphs.size(), 3u);
  return f;
}

std::vector<Fixture> Fixtures() {
  std::vector<Fixture> fixtures;
  fixtures.push_back(Build(MakeSphere(1.0, 48, 24), 0.15));
  fixtures.push_back(Build(MakeComb(4, 5, 1.0, 4), 0.45));
  fixtures.push_back(Build(MakeTwoBars(8, 2, 1.0, 4), 0.4));
  return fixtures;
}

Eigen::Matrix3d RandomRotation(std::mt19937* rng) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(*rng), normal(*rng), normal(*rng), normal(*rng));
  return q.normalized().toRotationMatrix();
}

// Eq. 9 and Eq. 10 (R^{-T}) written out directly.
Eigen::Vector3d ReferencePosition(const DeformationGraph& graph, const NodeTransforms& transforms,
                                  const Eigen::Vector3d& v, int vertex) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i = 0; i < graph.weights.k(); ++i) {
    const int j = graph.weights.node(i, vertex);
    const Eigen::Vector3d g = graph.positions.col(j);
    sum += graph.weights.weight(i, vertex) *
           (transforms.rotation(j) * (v - g) + g + transforms.translations.col(j));
  }
  return sum;
}

Eigen::Vector3d ReferenceNormal(const DeformationGraph& graph, const NodeTransforms& transforms,
                                const Eigen::Vector3d& n, int vertex) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i = 0; i < graph.weights.k(); ++i) {
    const int j = graph.weights.node(i, vertex);
    const Eigen::Matrix3d r = transforms.rotation(j);
    sum += graph.weights.weight(i, vertex) * (r.inverse().transpose() * n);
  }
  return sum.normalized();
}

TEST(SkinningTest, IdentityTransformsReproduceTheRestMeshExactly) {
  for (const Fixture& f : Fixtures()) {
    const Eigen::Matrix3Xd normals = VertexNormals(f.mesh);
    for (const DeformationGraph& graph : f.graphs) {
      const NodeTransforms identity = NodeTransforms::Identity(graph.num_nodes());
      Eigen::Matrix3Xd deformed, deformed_normals;
      SkinPositions(f.mesh.vertices, graph, identity, &deformed);
      SkinNormals(normals, graph, identity, &deformed_normals);
      EXPECT_TRUE(deformed == f.mesh.vertices) << "positions differ at " << graph.num_nodes()
                                               << " nodes";
      EXPECT_LE((deformed_normals - normals).cwiseAbs().maxCoeff(), 4e-16);
    }
  }
}

TEST(SkinningTest, OneRigidTransformMovesTheMeshRigidlyAtEveryScale) {
  std::mt19937 rng(4);
  for (const Fixture& f : Fixtures()) {
    const Eigen::Matrix3Xd normals = VertexNormals(f.mesh);
    const Eigen::Matrix3d rotation = RandomRotation(&rng);
    const Eigen::Vector3d translation(3.0, -1.5, 0.25);
    for (const DeformationGraph& graph : f.graphs) {
      // R (v - g) + g + t = R v + T for every node: t = T + R g - g.
      NodeTransforms transforms = NodeTransforms::Identity(graph.num_nodes());
      for (int j = 0; j < graph.num_nodes(); ++j) {
        transforms.rotation(j) = rotation;
        transforms.translations.col(j) =
            translation + rotation * graph.positions.col(j) - graph.positions.col(j);
      }
      Eigen::Matrix3Xd deformed, deformed_normals;
      SkinPositions(f.mesh.vertices, graph, transforms, &deformed);
      SkinNormals(normals, graph, transforms, &deformed_normals);
      const Eigen::Matrix3Xd expected = (rotation * f.mesh.vertices).colwise() + translation;
      EXPECT_LE((deformed - expected).cwiseAbs().maxCoeff(), 1e-12) << graph.num_nodes();
      EXPECT_LE((deformed_normals - rotation * normals).cwiseAbs().maxCoeff(), 1e-12)
          << graph.num_nodes();
    }
  }
}

TEST(SkinningTest, GeneralTransformsFollowEq9AndInverseTransposedNormals) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (const Fixture& f : Fixtures()) {
    const Eigen::Matrix3Xd normals = VertexNormals(f.mesh);
    for (const DeformationGraph& graph : f.graphs) {
      NodeTransforms transforms = NodeTransforms::Identity(graph.num_nodes());
      for (int j = 0; j < graph.num_nodes(); ++j) {
        // A rotation times a stretch and a shear: far from rigid, det > 0.
        Eigen::Matrix3d stretch = Eigen::Matrix3d::Identity();
        stretch.diagonal() << 1.5 + uniform(rng), 1.0, 0.7;
        stretch(0, 1) = 0.4 * uniform(rng);
        transforms.rotation(j) = RandomRotation(&rng) * stretch;
        transforms.translations.col(j) << uniform(rng), uniform(rng), uniform(rng);
      }
      Eigen::Matrix3Xd deformed, deformed_normals;
      SkinPositions(f.mesh.vertices, graph, transforms, &deformed);
      SkinNormals(normals, graph, transforms, &deformed_normals);
      for (int v = 0; v < f.mesh.num_vertices(); ++v) {
        ASSERT_LE((deformed.col(v) - ReferencePosition(graph, transforms, f.mesh.vertices.col(v), v))
                      .norm(),
                  1e-12)
            << "vertex " << v;
        ASSERT_LE((deformed_normals.col(v) - ReferenceNormal(graph, transforms, normals.col(v), v))
                      .norm(),
                  1e-12)
            << "vertex " << v;
        ASSERT_NEAR(deformed_normals.col(v).norm(), 1.0, 1e-14);
      }
    }
  }
}

TEST(SkinningTest, NormalsUseTheInverseTransposeNotTheMatrix) {
  // One anisotropic scale on all nodes: the plane x + y = const keeps its
  // normal direction under R^{-T} = diag(1/2, 1, 1), but not under R = diag(2, 1, 1).
  const Fixture f = Build(MakeSphere(1.0, 32, 16), 0.2);
  const DeformationGraph& graph = f.graphs[0];
  NodeTransforms transforms = NodeTransforms::Identity(graph.num_nodes());
  for (int j = 0; j < graph.num_nodes(); ++j) {
    transforms.rotation(j) = Eigen::Vector3d(2.0, 1.0, 1.0).asDiagonal();
  }
  Eigen::Matrix3Xd normals(3, f.mesh.num_vertices());
  normals.colwise() = Eigen::Vector3d(1.0, 1.0, 0.0).normalized();
  Eigen::Matrix3Xd deformed_normals;
  SkinNormals(normals, graph, transforms, &deformed_normals);
  // Tangent (1, -1, 0) maps to (2, -1, 0); the new normal is orthogonal to it.
  const Eigen::Vector3d expected = Eigen::Vector3d(0.5, 1.0, 0.0).normalized();
  for (int v = 0; v < f.mesh.num_vertices(); ++v) {
    ASSERT_LE((deformed_normals.col(v) - expected).norm(), 1e-14) << v;
    ASSERT_NEAR(deformed_normals.col(v).dot(Eigen::Vector3d(2.0, -1.0, 0.0)), 0.0, 1e-14);
  }
}

TEST(SkinningTest, SingularMatricesGiveFiniteNormals) {
  const Fixture f = Build(MakeSphere(1.0, 32, 16), 0.2);
  const DeformationGraph& graph = f.graphs[0];
  NodeTransforms transforms = NodeTransforms::Identity(graph.num_nodes());
  for (int j = 0; j < graph.num_nodes(); ++j) {
    transforms.rotation(j) = Eigen::Vector3d(1.0, 1.0, 0.0).asDiagonal();  // Flattens z.
  }
  Eigen::Matrix3Xd deformed_normals;
  SkinNormals(VertexNormals(f.mesh), graph, transforms, &deformed_normals);
  ASSERT_TRUE(deformed_normals.allFinite());
  for (int v = 0; v < f.mesh.num_vertices(); ++v) {
    const double length = deformed_normals.col(v).norm();
    // The cofactor of diag(1, 1, 0) is diag(0, 0, 1): the flattened sheet's normal.
    EXPECT_TRUE(length == 0.0 || std::abs(std::abs(deformed_normals(2, v)) - 1.0) < 1e-12) << v;
  }
}

// On a mesh large enough for several threads and several chunks (ChunkPool in
// skinning.cc: 2,048-vertex chunks, one thread under 8,192 vertices): all
// vertices and a subset of them, on 1, 2 and 3 threads, bit for bit.
TEST(SkinningTest, ThreadCountDoesNotChangeTheResult) {
  std::mt19937 rng(6);
  const Fixture f = Build(MakeSphere(1.0, 160, 80), 0.1);
  ASSERT_GT(f.mesh.num_vertices(), 6 * 2048);
  const DeformationGraph& graph = f.graphs[1];
  NodeTransforms transforms = NodeTransforms::Identity(graph.num_nodes());
  for (int j = 0; j < graph.num_nodes(); ++j) {
    transforms.rotation(j) = RandomRotation(&rng);
    transforms.translations.col(j) = Eigen::Vector3d::Random();
  }
  const Eigen::Matrix3Xd normals = VertexNormals(f.mesh);
  // Every vertex but each fifth: more than 8,192, in runs with gaps.
  std::vector<int> subset;
  for (int v = 0; v < f.mesh.num_vertices(); ++v) {
    if (v % 5 != 0) subset.push_back(v);
  }
  ASSERT_GT(subset.size(), 4u * 2048);
  for (bool use_simd : {false, true}) {
    Eigen::Matrix3Xd positions[3], deformed_normals[3], fused_positions[3], fused_normals[3];
    Eigen::Matrix3Xd subset_positions[3], subset_normals[3];
    for (int threads : {1, 2, 3}) {
      SkinningOptions options;
      options.num_threads = threads;
      options.use_simd = use_simd;
      const int i = threads - 1;
      SkinPositions(f.mesh.vertices, graph, transforms, &positions[i], options);
      SkinNormals(normals, graph, transforms, &deformed_normals[i], options);
      SkinPositionsAndNormals(f.mesh.vertices, normals, graph, transforms, nullptr,
                              &fused_positions[i], &fused_normals[i], options);
      subset_positions[i] = f.mesh.vertices;
      subset_normals[i] = normals;
      SkinPositionsAndNormals(f.mesh.vertices, normals, graph, transforms, &subset,
                              &subset_positions[i], &subset_normals[i], options);
    }
    EXPECT_TRUE(subset_positions[0] != f.mesh.vertices) << "the subset should move";
    for (int i = 1; i < 3; ++i) {
      SCOPED_TRACE("use_simd " + std::to_string(use_simd) + ", " + std::to_string(i + 1) +
                   " threads");
      EXPECT_TRUE(positions[0] == positions[i]);
      EXPECT_TRUE(deformed_normals[0] == deformed_normals[i]);
      EXPECT_TRUE(fused_positions[0] == fused_positions[i]);
      EXPECT_TRUE(fused_normals[0] == fused_normals[i]);
      EXPECT_TRUE(subset_positions[0] == subset_positions[i]);
      EXPECT_TRUE(subset_normals[0] == subset_normals[i]);
    }
  }
}

TEST(SkinningTest, FusedPassEqualsSeparatePassesOnAllVerticesAndSubsets) {
  std::mt19937 rng(7);
  const Fixture f = Build(MakeSphere(1.0, 96, 48), 0.1);
  const DeformationGraph& graph = f.graphs[1];
  NodeTransforms transforms = NodeTransforms::Identity(graph.num_nodes());
  for (int j = 0; j < graph.num_nodes(); ++j) {
    transforms.rotation(j) = RandomRotation(&rng) * (1.0 + 0.1 * j / graph.num_nodes());
    transforms.translations.col(j) = Eigen::Vector3d::Random();
  }
  const Eigen::Matrix3Xd normals = VertexNormals(f.mesh);
  for (bool use_simd : {false, true}) {
    SCOPED_TRACE(use_simd ? "use_simd" : "portable");
    SkinningOptions separate_options;
    separate_options.use_simd = use_simd;
    Eigen::Matrix3Xd positions, deformed_normals;
    SkinPositions(f.mesh.vertices, graph, transforms, &positions, separate_options);
    SkinNormals(normals, graph, transforms, &deformed_normals, separate_options);
    for (int threads : {1, 2}) {
      SkinningOptions options;
      options.num_threads = threads;
      options.use_simd = use_simd;
      Eigen::Matrix3Xd fused_positions, fused_normals;
      SkinPositionsAndNormals(f.mesh.vertices, normals, graph, transforms, nullptr,
                              &fused_positions, &fused_normals, options);
      EXPECT_TRUE(fused_positions == positions);
      EXPECT_TRUE(fused_normals == deformed_normals);
      // Every third vertex: those change, the others keep what was there.
      std::vector<int> subset;
      for (int v = 0; v < f.mesh.num_vertices(); v += 3) subset.push_back(v);
      Eigen::Matrix3Xd sub_positions = Eigen::Matrix3Xd::Zero(3, f.mesh.num_vertices());
      Eigen::Matrix3Xd sub_normals = Eigen::Matrix3Xd::Zero(3, f.mesh.num_vertices());
      SkinPositionsAndNormals(f.mesh.vertices, normals, graph, transforms, &subset, &sub_positions,
                              &sub_normals, options);
      for (int v = 0; v < f.mesh.num_vertices(); ++v) {
        if (v % 3 == 0) {
          EXPECT_TRUE(sub_positions.col(v) == positions.col(v)) << v;
          EXPECT_TRUE(sub_normals.col(v) == deformed_normals.col(v)) << v;
        } else {
          EXPECT_TRUE(sub_positions.col(v).isZero(0.0)) << v;
          EXPECT_TRUE(sub_normals.col(v).isZero(0.0)) << v;
        }
      }
    }
  }
}

// The two vertex kernels (AVX2+FMA when the CPU has it, and the portable one)
// against Eq. 9 and the normal formula written out, for general transforms
// (rotation x stretch x shear, some with a reflection), all vertices and
// subsets whose size leaves every remainder of the 4-vertex blocks.
TEST(SkinningTest, BothKernelsFollowTheReferenceForGeneralTransforms) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  SCOPED_TRACE(SkinningSimdAvailable() ? "AVX2 kernel available" : "portable kernel only");
  for (const Fixture& f : Fixtures()) {
    const Eigen::Matrix3Xd normals = VertexNormals(f.mesh);
    const double diagonal =
        (f.mesh.vertices.rowwise().maxCoeff() - f.mesh.vertices.rowwise().minCoeff()).norm();
    for (const DeformationGraph* graph : {&f.graphs.front(), &f.graphs.back()}) {
      NodeTransforms transforms = NodeTransforms::Identity(graph->num_nodes());
      for (int j = 0; j < graph->num_nodes(); ++j) {
        Eigen::Matrix3d stretch = Eigen::Matrix3d::Identity();
        stretch.diagonal() << 1.5 + uniform(rng), 1.0, j % 5 == 0 ? -0.7 : 0.7;
        stretch(0, 1) = 0.4 * uniform(rng);
        transforms.rotation(j) = RandomRotation(&rng) * stretch;
        transforms.translations.col(j) = diagonal * Eigen::Vector3d::Random();
      }
      for (int size : {-1, 1, 2, 3, 4, 5, 6, 7, 9, 4 * 97 + 3}) {  // -1: all vertices
        std::vector<int> subset;
        for (int v = 0;
             size >= 0 && v < f.mesh.num_vertices() && static_cast<int>(subset.size()) < size;
             v += 2) {
          subset.push_back(v);
        }
        Eigen::Matrix3Xd results[2][2];  // [use_simd][positions, normals]
        for (bool use_simd : {false, true}) {
          SkinningOptions options;
          options.use_simd = use_simd;
          Eigen::Matrix3Xd& positions = results[use_simd][0];
          Eigen::Matrix3Xd& unit_normals = results[use_simd][1];
          positions.setZero(3, f.mesh.num_vertices());
          unit_normals.setZero(3, f.mesh.num_vertices());
          SkinPositionsAndNormals(f.mesh.vertices, normals, *graph, transforms,
                                  size >= 0 ? &subset : nullptr, &positions, &unit_normals,
                                  options);
          std::vector<char> in_subset(f.mesh.num_vertices(), size < 0);
          for (int v : subset) in_subset[v] = 1;
          for (int v = 0; v < f.mesh.num_vertices(); ++v) {
            if (!in_subset[v]) {
              ASSERT_TRUE(positions.col(v).isZero(0.0) && unit_normals.col(v).isZero(0.0))
                  << "vertex " << v << " is not in the subset";
              continue;
            }
            ASSERT_LE((positions.col(v) -
                       ReferencePosition(*graph, transforms, f.mesh.vertices.col(v), v))
                          .norm(),
                      1e-12 * diagonal)
                << "use_simd " << use_simd << " subset " << size << " vertex " << v;
            ASSERT_LE((unit_normals.col(v) - ReferenceNormal(*graph, transforms, normals.col(v), v))
                          .norm(),
                      1e-12)
                << "use_simd " << use_simd << " subset " << size << " vertex " << v;
          }
        }
        // The kernels differ only by FMA rounding (in a normal, amplified by
        // cancellation where the blended R^{-T} n is short: 1e-14 seen with
        // random rotations on the 104K armadillo).
        EXPECT_LE((results[0][0] - results[1][0]).cwiseAbs().maxCoeff(), 1e-14 * diagonal);
        EXPECT_LE((results[0][1] - results[1][1]).cwiseAbs().maxCoeff(), 1e-13);
      }
    }
  }
}

// The weights of `weights` stored again for a graph of `width_nodes` nodes
// (which picks the id width), each first passed through `change`.
template <typename Change>
SkinningWeights Restored(const SkinningWeights& weights, int width_nodes, Change change) {
  SkinningWeights restored(weights.k(), weights.num_vertices(), width_nodes);
  std::vector<int> nodes(weights.k());
  std::vector<double> values(weights.k());
  for (int v = 0; v < weights.num_vertices(); ++v) {
    for (int slot = 0; slot < weights.k(); ++slot) {
      nodes[slot] = weights.node(slot, v);
      values[slot] = weights.weight(slot, v);
    }
    change(&values);
    restored.SetVertex(v, nodes.data(), values.data());
  }
  return restored;
}

// General transforms: random rotations times stretches (one in five
// reflecting), translations up to the diagonal.
NodeTransforms GeneralTransforms(int num_nodes, double diagonal, std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  NodeTransforms transforms = NodeTransforms::Identity(num_nodes);
  for (int j = 0; j < num_nodes; ++j) {
    Eigen::Matrix3d stretch = Eigen::Matrix3d::Identity();
    stretch.diagonal() << 1.5 + uniform(*rng), 1.0, j % 5 == 0 ? -0.7 : 0.7;
    stretch(0, 1) = 0.4 * uniform(*rng);
    transforms.rotation(j) = RandomRotation(rng) * stretch;
    transforms.translations.col(j) = diagonal * Eigen::Vector3d(uniform(*rng), uniform(*rng),
                                                                uniform(*rng));
  }
  return transforms;
}

// Compact weights (floats on the 2^-24 grid, nearest_nodes.h) against the
// double weights they are rounded from: the deformed mesh moves by less than
// 1e-6 of the diagonal (the bound the storage was chosen for), even with
// node transforms far apart.
TEST(SkinningTest, CompactWeightsStayWithinAMillionthOfTheDiagonalOfDoubleWeights) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(0.5, 1.5);
  for (const Fixture& f : Fixtures()) {
    const double diagonal =
        (f.mesh.vertices.rowwise().maxCoeff() - f.mesh.vertices.rowwise().minCoeff()).norm();
    for (const DeformationGraph* graph : {&f.graphs.front(), &f.graphs.back()}) {
      // Double weights off the grid: the graph's, jittered and renormalised.
      std::vector<std::vector<double>> doubles;
      DeformationGraph compact = *graph;
      compact.weights = Restored(graph->weights, graph->num_nodes(), [&](std::vector<double>* w) {
        double sum = 0.0;
        for (double& value : *w) sum += (value *= jitter(rng));
        for (double& value : *w) value /= sum;
        doubles.push_back(*w);
      });
      const NodeTransforms transforms = GeneralTransforms(graph->num_nodes(), diagonal, &rng);
      for (bool use_simd : {false, true}) {
        SkinningOptions options;
        options.use_simd = use_simd;
        Eigen::Matrix3Xd deformed;
        SkinPositions(f.mesh.vertices, compact, transforms, &deformed, options);
        double largest = 0.0;
        for (int v = 0; v < f.mesh.num_vertices(); ++v) {
          Eigen::Vector3d expected = Eigen::Vector3d::Zero();  // Eq. 9 with the doubles
          for (int slot = 0; slot < compact.weights.k(); ++slot) {
            const int j = compact.weights.node(slot, v);
            const Eigen::Vector3d g = graph->positions.col(j);
            expected += doubles[v][slot] * (transforms.rotation(j) * (f.mesh.vertices.col(v) - g) +
                                            g + transforms.translations.col(j));
          }
          largest = std::max(largest, (deformed.col(v) - expected).norm());
        }
        EXPECT_LT(largest, 1e-6 * diagonal) << "use_simd " << use_simd;
        EXPECT_GT(largest, 0.0) << "the jittered weights are off the grid";
      }
    }
  }
}

// The 32-bit ids of a graph of more than 65,536 nodes give the same numbers
// as the 16-bit ones.
TEST(SkinningTest, SixteenAndThirtyTwoBitIdsGiveTheSameNumbers) {
  std::mt19937 rng(12);
  const Fixture f = Build(MakeSphere(1.0, 48, 24), 0.15);
  const Eigen::Matrix3Xd normals = VertexNormals(f.mesh);
  const DeformationGraph& graph = f.graphs.front();
  DeformationGraph wide = graph;
  wide.weights = Restored(graph.weights, kMaxNodesFor16BitIds + 1, [](std::vector<double>*) {});
  ASSERT_TRUE(graph.weights.has_16bit_ids());
  ASSERT_FALSE(wide.weights.has_16bit_ids());
  const NodeTransforms transforms = GeneralTransforms(graph.num_nodes(), 2.0, &rng);
  for (bool use_simd : {false, true}) {
    SkinningOptions options;
    options.use_simd = use_simd;
    Eigen::Matrix3Xd positions[2], unit_normals[2];
    SkinPositionsAndNormals(f.mesh.vertices, normals, graph, transforms, nullptr, &positions[0],
                            &unit_normals[0], options);
    SkinPositionsAndNormals(f.mesh.vertices, normals, wide, transforms, nullptr, &positions[1],
                            &unit_normals[1], options);
    EXPECT_EQ(positions[0], positions[1]) << "use_simd " << use_simd;
    EXPECT_EQ(unit_normals[0], unit_normals[1]) << "use_simd " << use_simd;
  }
}

TEST(SkinningTest, BothKernelsGiveTheRestPositionsBitForBitUnderIdentity) {
  for (const Fixture& f : Fixtures()) {
    const Eigen::Matrix3Xd normals = VertexNormals(f.mesh);
    for (const DeformationGraph& graph : f.graphs) {
      const NodeTransforms identity = NodeTransforms::Identity(graph.num_nodes());
      for (bool use_simd : {false, true}) {
        SkinningOptions options;
        options.use_simd = use_simd;
        Eigen::Matrix3Xd deformed, deformed_normals;
        SkinPositionsAndNormals(f.mesh.vertices, normals, graph, identity, nullptr, &deformed,
                                &deformed_normals, options);
        EXPECT_TRUE(deformed == f.mesh.vertices)
            << "use_simd " << use_simd << ", " << graph.num_nodes() << " nodes";
        EXPECT_LE((deformed_normals - normals).cwiseAbs().maxCoeff(), 4e-16);
        SkinPositions(f.mesh.vertices, graph, identity, &deformed, options);
        EXPECT_TRUE(deformed == f.mesh.vertices) << "use_simd " << use_simd;
      }
    }
  }
}

// Normals of zero or non-finite length come out as zero vectors, in every
// position of a 4-vertex block, while their neighbours stay unit vectors.
TEST(SkinningTest, BothKernelsZeroNormalsOfZeroOrNonFiniteLength) {
  const Fixture f = Build(MakeSphere(1.0, 32, 16), 0.2);
  const DeformationGraph& graph = f.graphs[0];
  std::mt19937 rng(9);
  NodeTransforms transforms = NodeTransforms::Identity(graph.num_nodes());
  for (int j = 0; j < graph.num_nodes(); ++j) transforms.rotation(j) = RandomRotation(&rng);
  Eigen::Matrix3Xd normals = VertexNormals(f.mesh);
  const double kNaN = std::numeric_limits<double>::quiet_NaN();
  const double kInf = std::numeric_limits<double>::infinity();
  std::vector<char> bad(f.mesh.num_vertices(), 0);
  for (int v = 0; v < f.mesh.num_vertices(); v += 7) {
    bad[v] = 1;
    const Eigen::Vector3d bad_normals[4] = {
        Eigen::Vector3d::Zero(), Eigen::Vector3d(kNaN, 0.0, 0.0), Eigen::Vector3d(0.0, kInf, 1.0),
        Eigen::Vector3d(1e300, 1e300, 0.0)};  // the last: |n|^2 overflows
    normals.col(v) = bad_normals[v % 4];
  }
  for (bool use_simd : {false, true}) {
    SkinningOptions options;
    options.use_simd = use_simd;
    Eigen::Matrix3Xd deformed, deformed_normals;
    SkinPositionsAndNormals(f.mesh.vertices, normals, graph, transforms, nullptr, &deformed,
                            &deformed_normals, options);
    for (int v = 0; v < f.mesh.num_vertices(); ++v) {
      if (bad[v]) {
        EXPECT_TRUE(deformed_normals.col(v).isZero(0.0)) << "use_simd " << use_simd << " " << v;
      } else {
        EXPECT_NEAR(deformed_normals.col(v).norm(), 1.0, 1e-14) << use_simd << " " << v;
      }
    }
    EXPECT_TRUE(deformed.allFinite());
  }
}

TEST(SkinningTest, OptionsCheck) {
  SkinningOptions options;
  std::string error;
  EXPECT_TRUE(options.Check(&error));
  options.num_threads = kMaxThreads;
  EXPECT_TRUE(options.Check(&error));
  for (int threads : {-1, kMaxThreads + 1, 100000}) {
    options.num_threads = threads;
    EXPECT_FALSE(options.Check(&error));
    EXPECT_EQ(error, "num_threads must be in 0..1024 (0: OpenMP default), got " +
                         std::to_string(threads));
  }
}

}  // namespace
}  // namespace msdeform
