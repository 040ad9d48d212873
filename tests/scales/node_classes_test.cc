#include "msdeform/scales/node_classes.h"

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/lattice.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/nearest_nodes.h"
#include "msdeform/scales/scale_selection.h"

// Node classes on graphs built by hand, a few nodes each, with the classes
// derived by hand from the rules of scales/scale_selection.h and docs/method.md
// §4 (paper §4.2): Totally Free (T) holds a moveable-handle vertex, or has
// e' > T and no fixed-handle vertex; Half Free (H) holds a fixed-handle vertex
// (every one in the paper; by default only those next to a Totally Free
// node); Fixed (F) the rest, with the border ring, still components and
// pinned nodes on top. Each case states the derivation next to its answer.

namespace msdeform {
namespace {

constexpr NodeClass F = NodeClass::kFixed;
constexpr NodeClass H = NodeClass::kHalfFree;
constexpr NodeClass T = NodeClass::kTotallyFree;

CompressedLists Lists(const std::vector<std::vector<int>>& rows) {
  CompressedLists lists;
  for (const std::vector<int>& row : rows) {
    lists.values.insert(lists.values.end(), row.begin(), row.end());
    lists.offsets.push_back(static_cast<int64_t>(lists.values.size()));
  }
  return lists;
}

// A graph with the given DG1 members and neighbours per node (positions at
// the origin: the classes do not read them), and no skinning weights.
DeformationGraph Graph(const std::vector<std::vector<int>>& members,
                       const std::vector<std::vector<int>>& neighbors) {
  DeformationGraph graph;
  graph.positions = Eigen::Matrix3Xd::Zero(3, static_cast<int>(members.size()));
  graph.members = Lists(members);
  graph.neighbors = Lists(neighbors);
  for (size_t j = 0; j < neighbors.size(); ++j) {
    for (int k : neighbors[j]) {
      if (static_cast<int>(j) < k) graph.edges.emplace_back(static_cast<int>(j), k);
    }
  }
  return graph;
}

// DG1 as a chain 0 - 1 - ... - (n - 1): node j is DG1 node j.
DeformationGraph Chain(int n) {
  std::vector<std::vector<int>> members, neighbors;
  for (int j = 0; j < n; ++j) {
    members.push_back({j});
    neighbors.emplace_back();
    if (j > 0) neighbors.back().push_back(j - 1);
    if (j + 1 < n) neighbors.back().push_back(j + 1);
  }
  return Graph(members, neighbors);
}

// Skinning with two slots per vertex: vertex v by nodes[v] with weights[v].
SkinningWeights TwoSlotWeights(int num_nodes, const std::vector<std::pair<int, int>>& nodes,
                               const std::vector<std::pair<double, double>>& weights) {
  SkinningWeights skinning(2, static_cast<int>(nodes.size()), num_nodes);
  for (size_t v = 0; v < nodes.size(); ++v) {
    const int slot_nodes[2] = {nodes[v].first, nodes[v].second};
    const double slot_weights[2] = {weights[v].first, weights[v].second};
    skinning.SetVertex(static_cast<int>(v), slot_nodes, slot_weights);
  }
  return skinning;
}

// Handle nodes of `num_dg1` DG1 nodes: which hold fixed and moveable vertices.
HandleNodes Handles(int num_dg1, const std::vector<int>& fixed_dg1,
                    const std::vector<int>& moveable_dg1) {
  HandleNodes handles;
  handles.holds_fixed.assign(num_dg1, 0);
  handles.holds_moveable.assign(num_dg1, 0);
  for (int m : fixed_dg1) handles.holds_fixed[m] = 1;
  for (int m : moveable_dg1) handles.holds_moveable[m] = 1;
  return handles;
}

// The paper's rules: no pinning, every fixed-handle node Half Free, the
// border left Fixed.
ScaleSelectionOptions PaperRules() {
  ScaleSelectionOptions options;
  options.pin_fixed_region = false;
  options.half_free = HalfFreeRule::kEveryFixedHandleNode;
  options.border = BorderRule::kFixed;
  return options;
}

std::vector<NodeClass> Classify(const DeformationGraph& graph, int scale,
                                const std::vector<double>& dg1_extent,
                                const HandleNodes& handles, double threshold,
                                const ScaleSelectionOptions& options) {
  ScaleClasses classes;
  EXPECT_TRUE(
      ClassifyNodesAtScale(graph, scale, dg1_extent, handles, threshold, options, &classes));
  return classes.node_class;
}

// The chain of six DG1 nodes most cases below share: node 0 holds the fixed
// handle, node 5 the moveable one; e' is above T = 0.1 at nodes 2 and 4.
const std::vector<double> kChainExtent = {0.0, 0.05, 0.3, 0.05, 0.2, 0.9};
constexpr double kThreshold = 0.1;

TEST(NodeClassesTest, PaperRulesOnAChain) {
  // T: 2 (0.3 > 0.1), 4 (0.2 > 0.1), 5 (moveable; its e' is irrelevant).
  // H: 0 (holds the fixed handle: Half Free under the paper's rule).
  // F: 1 and 3 (e' <= T, no handle; the paper keeps the border Fixed).
  const std::vector<NodeClass> expected = {H, F, T, F, T, T};
  EXPECT_EQ(Classify(Chain(6), 1, kChainExtent, Handles(6, {0}, {5}), kThreshold, PaperRules()),
            expected);
}

TEST(NodeClassesTest, BorderRuleDecidesTheFixedNodesNextToTotallyFreeOnes) {
  // Before the border: T = {2, 4, 5} as above. Nodes 1 and 3 border node 2;
  // node 0 borders only node 1, Fixed before the border ring is applied, so
  // under kNextToTotallyFree it stays Fixed (no Totally Free neighbour).
  ScaleSelectionOptions options;
  options.pin_fixed_region = false;
  const HandleNodes handles = Handles(6, {0}, {5});
  options.border = BorderRule::kTotallyFree;  // the default: one more ring
  EXPECT_EQ(Classify(Chain(6), 1, kChainExtent, handles, kThreshold, options),
            std::vector<NodeClass>({F, T, T, T, T, T}));
  options.border = BorderRule::kHalfFree;  // a joint: rotation only
  EXPECT_EQ(Classify(Chain(6), 1, kChainExtent, handles, kThreshold, options),
            std::vector<NodeClass>({F, H, T, H, T, T}));
  options.border = BorderRule::kFixed;  // the paper
  EXPECT_EQ(Classify(Chain(6), 1, kChainExtent, handles, kThreshold, options),
            std::vector<NodeClass>({F, F, T, F, T, T}));
}

TEST(NodeClassesTest, HalfFreeRuleDecidesTheFixedHandleNodes) {
  // e'_1 = 0.5 > T makes node 1 Totally Free, so fixed-handle node 0 has a
  // Totally Free neighbour. Node 3 (0.05) borders nodes 2 and 4: border.
  const std::vector<double> extent = {0.0, 0.5, 0.3, 0.05, 0.2, 0.9};
  const HandleNodes handles = Handles(6, {0}, {5});
  ScaleSelectionOptions options;
  options.pin_fixed_region = false;
  options.border = BorderRule::kFixed;
  options.half_free = HalfFreeRule::kNextToTotallyFree;  // the default
  EXPECT_EQ(Classify(Chain(6), 1, extent, handles, kThreshold, options),
            std::vector<NodeClass>({H, T, T, F, T, T}));
  options.half_free = HalfFreeRule::kNone;  // fixed-handle nodes Fixed
  EXPECT_EQ(Classify(Chain(6), 1, extent, handles, kThreshold, options),
            std::vector<NodeClass>({F, T, T, F, T, T}));
  // Without a Totally Free neighbour node 0 is Half Free only under the
  // paper's rule (the first case: kChainExtent leaves node 1 Fixed).
  options.half_free = HalfFreeRule::kNextToTotallyFree;
  EXPECT_EQ(Classify(Chain(6), 1, kChainExtent, handles, kThreshold, options),
            std::vector<NodeClass>({F, F, T, F, T, T}));
}

TEST(NodeClassesTest, AFixedHandleNodeIsNeverTotallyFreeWhateverItsExtent) {
  // Node 0 holds the fixed handle and has e' = 0.9 > T: still Half Free
  // (paper's rule), not Totally Free.
  const std::vector<double> extent = {0.9, 0.05, 0.05};
  EXPECT_EQ(Classify(Chain(3), 1, extent, Handles(3, {0}, {2}), kThreshold, PaperRules()),
            std::vector<NodeClass>({H, F, T}));
}

TEST(NodeClassesTest, CoarseNodeExtentIsTheMaxOrTheMeanOfItsMembers) {
  // DG_2 of six DG1 nodes: {0, 1}, {2, 3}, {4, 5} in a chain; DG1 node 0
  // holds the fixed handle, DG1 node 5 the moveable one; T = 0.2.
  const DeformationGraph graph = Graph({{0, 1}, {2, 3}, {4, 5}}, {{1}, {0, 2}, {1}});
  const std::vector<double> dg1_extent = {0.0, 0.05, 0.3, 0.0, 0.05, 0.08};
  const HandleNodes handles = Handles(6, {0}, {5});
  ScaleSelectionOptions options;
  options.pin_fixed_region = false;
  ScaleClasses classes;

  // Max: e' = (0.05, 0.3, 0.08). T: node 1 (0.3 > 0.2) and node 2 (moveable).
  // Node 0 holds the fixed handle and borders node 1: Half Free.
  options.member_extent = MemberExtent::kMax;
  ASSERT_TRUE(ClassifyNodesAtScale(graph, 2, dg1_extent, handles, 0.2, options, &classes));
  EXPECT_EQ(classes.node_extent, std::vector<double>({0.05, 0.3, 0.08}));
  EXPECT_EQ(classes.node_class, std::vector<NodeClass>({H, T, T}));
  EXPECT_EQ(classes.num_pinned, 0);

  // Mean: e' = (0.025, 0.15, 0.065). T: node 2 only. Node 1 borders it: the
  // default border makes it Totally Free. Node 0's neighbour (node 1) was
  // Fixed before the border ring, so node 0 stays Fixed.
  options.member_extent = MemberExtent::kMean;
  ASSERT_TRUE(ClassifyNodesAtScale(graph, 2, dg1_extent, handles, 0.2, options, &classes));
  ASSERT_EQ(classes.node_extent.size(), 3u);
  EXPECT_DOUBLE_EQ(classes.node_extent[0], 0.025);
  EXPECT_DOUBLE_EQ(classes.node_extent[1], 0.15);
  EXPECT_DOUBLE_EQ(classes.node_extent[2], 0.065);
  EXPECT_EQ(classes.node_class, std::vector<NodeClass>({F, T, T}));
}

TEST(NodeClassesTest, ANodeHoldingFixedAndMoveableVerticesCannotServeTheLayout) {
  // DG_2 node 0 merges DG1 node 0 (fixed) and DG1 node 1 (moveable).
  const DeformationGraph graph = Graph({{0, 1}, {2, 3}}, {{1}, {0}});
  ScaleClasses classes;
  EXPECT_FALSE(ClassifyNodesAtScale(graph, 2, {0.0, 0.0, 0.0, 0.0}, Handles(4, {0}, {1}),
                                    kThreshold, ScaleSelectionOptions(), &classes));
  // On DG1 the two are apart and both serve: H (paper) and T.
  EXPECT_EQ(Classify(Chain(4), 1, {0.0, 0.0, 0.0, 0.0}, Handles(4, {0}, {1}), kThreshold,
                     PaperRules()),
            std::vector<NodeClass>({H, T, F, F}));
}

TEST(NodeClassesTest, StillNodesAreFixedWhateverTheirExtent) {
  // Two components: DG1 nodes 0 - 1 hold the moveable handle (node 1), DG1
  // nodes 2 - 3 are still (no moveable vertex in their component). Node 3's
  // e' = 0.9 > T would make it Totally Free; still, it is Fixed, and so is
  // node 2. Node 0 borders Totally Free node 1: the default border ring.
  const DeformationGraph graph = Graph({{0}, {1}, {2}, {3}}, {{1}, {0}, {3}, {2}});
  HandleNodes handles = Handles(4, {}, {1});
  handles.still = {0, 0, 1, 1};
  ScaleSelectionOptions options;
  options.pin_fixed_region = false;
  EXPECT_EQ(Classify(graph, 1, {0.0, 0.0, 0.05, 0.9}, handles, kThreshold, options),
            std::vector<NodeClass>({T, T, F, F}));
}

TEST(NodeClassesTest, NodesSkinningAFixedVertexArePinned) {
  // Vertex v sits in DG1 node v of a five-node chain and is skinned by nodes
  // v and v + 1 (vertex 4 by 4 and 3). Vertex 0 is fixed, vertex 4 moveable;
  // e' above T at node 2 only.
  DeformationGraph graph = Chain(5);
  graph.weights = TwoSlotWeights(5, {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 3}},
                                 {{0.6, 0.4}, {0.6, 0.4}, {0.6, 0.4}, {0.6, 0.4}, {0.6, 0.4}});
  const std::vector<double> extent = {0.0, 0.05, 0.3, 0.05, 0.0};
  HandleNodes handles = Handles(5, {0}, {4});
  handles.fixed_vertices = {0};
  handles.moveable_vertices = {4};
  ScaleSelectionOptions options;  // the defaults: pinned, border ring, joint

  // Before pinning: T = {2, 4}. Vertex 0 is skinned by nodes 0 and 1: both
  // pinned (Fixed). The moveable vertex's nodes (3, 4) are not pinned.
  // Border ring: node 3 borders 2 and 4 -> Totally Free; node 1 borders 2
  // but is pinned; node 0 is pinned.
  ScaleClasses classes;
  ASSERT_TRUE(ClassifyNodesAtScale(graph, 1, extent, handles, kThreshold, options, &classes));
  EXPECT_EQ(classes.node_class, std::vector<NodeClass>({F, F, T, T, T}));
  EXPECT_EQ(classes.num_pinned, 2);

  // Unpinned, node 1 joins the border ring, and node 0 (fixed handle; its
  // neighbour 1 was Fixed before the ring) stays Fixed.
  options.pin_fixed_region = false;
  ASSERT_TRUE(ClassifyNodesAtScale(graph, 1, extent, handles, kThreshold, options, &classes));
  EXPECT_EQ(classes.node_class, std::vector<NodeClass>({F, T, T, T, T}));
  EXPECT_EQ(classes.num_pinned, 0);
}

TEST(NodeClassesTest, APinnedNodeThatSkinsTheHandleMovesTheSelectionFiner) {
  // Three nodes; fixed vertex 0 is skinned by nodes 0 and 1, moveable vertex
  // 2 by nodes 2 and 1: node 1 would be pinned and serves the handle.
  DeformationGraph graph = Chain(3);
  graph.weights = TwoSlotWeights(3, {{0, 1}, {1, 0}, {2, 1}}, {{0.5, 0.5}, {1.0, 0.0}, {0.5, 0.5}});
  HandleNodes handles = Handles(3, {0}, {2});
  handles.fixed_vertices = {0};
  handles.moveable_vertices = {2};
  const std::vector<double> extent = {0.0, 0.0, 0.0};
  ScaleClasses classes;
  // At a coarse scale: refused, the selection moves finer.
  EXPECT_FALSE(ClassifyNodesAtScale(graph, 2, extent, handles, kThreshold,
                                    ScaleSelectionOptions(), &classes));
  // On DG1 node 1 is left unpinned: T (2, moveable), then node 1 borders it
  // (the ring: T); node 0 is pinned (F).
  ASSERT_TRUE(ClassifyNodesAtScale(graph, 1, extent, handles, kThreshold,
                                   ScaleSelectionOptions(), &classes));
  EXPECT_EQ(classes.node_class, std::vector<NodeClass>({F, T, T}));
  EXPECT_EQ(classes.num_pinned, 1);
}

TEST(NodeClassesTest, StillVerticesAreThoseOfComponentsWithoutAMoveableVertex) {
  Components components;
  components.component_of_vertex = {0, 0, 1, 1, 1, 2};
  components.count = 3;
  HandleLayout layout;
  layout.fixed = {0, 2};
  layout.moveable = {1};
  EXPECT_EQ(StillVertices(components, layout), std::vector<char>({0, 0, 1, 1, 1, 1}));
  components.component_of_vertex = {0, 0, 0};
  components.count = 1;
  EXPECT_TRUE(StillVertices(components, layout).empty());
}

TEST(NodeClassesTest, StillNodesNeedEveryMemberStill) {
  const DeformationGraph graph = Graph({{0, 1}, {2, 3}, {}}, {{1}, {0}, {}});
  EXPECT_EQ(StillNodes(graph, {0, 1, 1, 1}), std::vector<char>({0, 1, 0}));
  EXPECT_EQ(StillNodes(graph, {}), std::vector<char>({0, 0, 0}));
}

TEST(NodeClassesTest, StaticBaselinesAreTotallyFreeButStillNodes) {
  const DeformationGraph graph = Graph({{0}, {1, 2}, {3}}, {{1}, {0, 2}, {1}});
  EXPECT_EQ(StaticGraphNodeClasses(graph, {0, 1, 1, 0}), std::vector<NodeClass>({T, F, T}));
  EXPECT_EQ(StaticGraphNodeClasses(graph, {}), std::vector<NodeClass>({T, T, T}));
}

TEST(NodeClassesTest, AVertexMovesOnlyThroughAFreeNodeOfNonZeroWeight) {
  // Vertex 0: Fixed node 0 (1.0) and free node 1 with weight 0; vertex 1:
  // half on each; vertex 2: Fixed node 0 and Half Free node 2.
  const SkinningWeights weights =
      TwoSlotWeights(3, {{0, 1}, {0, 1}, {0, 2}}, {{1.0, 0.0}, {0.5, 0.5}, {0.5, 0.5}});
  const std::vector<NodeClass> classes = {F, T, H};
  EXPECT_FALSE(SkinnedByAFreeNode(weights, classes, 0));
  EXPECT_TRUE(SkinnedByAFreeNode(weights, classes, 1));
  EXPECT_TRUE(SkinnedByAFreeNode(weights, classes, 2));
  EXPECT_EQ(FirstVertexSkinnedOnlyByFixedNodes(weights, classes, {1, 2, 0}), 0);
  EXPECT_EQ(FirstVertexSkinnedOnlyByFixedNodes(weights, classes, {2, 1}), -1);
}

}  // namespace
}  // namespace msdeform
