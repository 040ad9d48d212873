#include "msdeform/scales/scale_selection.h"
#include "msdeform/scales/node_classes.h"

#include <numeric>

#include <gtest/gtest.h>

namespace msdeform {
namespace {

// DG1 of `d1` nodes on a line (spacing 1, edges between neighbours) and
// coarser scales DG_i made of runs of i consecutive DG1 nodes.
std::vector<DeformationGraph> LineGraphs(int d1, int num_scales) {
  std::vector<DeformationGraph> graphs;
  for (int scale = 1; scale <= num_scales; ++scale) {
    DeformationGraph graph;
    const int n = (d1 + scale - 1) / scale;
    graph.positions = Eigen::Matrix3Xd::Zero(3, n);
    graph.node_of_dg1.resize(d1);
    graph.members.offsets.assign(1, 0);
    for (int j = 0; j < n; ++j) {
      graph.positions(0, j) = j * scale;
      for (int m = j * scale; m < std::min(d1, (j + 1) * scale); ++m) {
        graph.members.values.push_back(m);
        graph.node_of_dg1[m] = j;
      }
      graph.members.offsets.push_back(static_cast<int>(graph.members.values.size()));
    }
    graph.neighbors.offsets.assign(1, 0);
    for (int j = 0; j < n; ++j) {
      if (j > 0) graph.neighbors.values.push_back(j - 1);
      if (j + 1 < n) graph.neighbors.values.push_back(j + 1);
      graph.neighbors.offsets.push_back(static_cast<int>(graph.neighbors.values.size()));
      if (j + 1 < n) graph.edges.emplace_back(j, j + 1);
    }
    graphs.push_back(std::move(graph));
  }
  return graphs;
}

HandleNodes NoHandles(int d1) {
  return {std::vector<char>(d1, 0), std::vector<char>(d1, 0), {}, {}, {}};
}

ScaleSelection Select(const std::vector<DeformationGraph>& graphs, const std::vector<double>& e,
                      const HandleNodes& handles, ScaleSelectionOptions options = {},
                      double diagonal = 1e9, int nodes_per_scale = 100) {
  ScaleSelection selection;
  std::string error;
  EXPECT_TRUE(SelectScale(graphs, e, handles, nodes_per_scale, diagonal, options, &selection,
                          &error))
      << error;
  return selection;
}

TEST(ScaleSelectionTest, Eq7ThresholdFromFixedHandleNodes) {
  const auto graphs = LineGraphs(10, 1);
  std::vector<double> e = {1.0, 0.9, 0.8, 0.3, 0.45, 0.7, 0.2, 0.1, 0.05, 0.0};
  HandleNodes handles = NoHandles(10);
  handles.holds_moveable[0] = 1;
  EXPECT_DOUBLE_EQ(Select(graphs, e, handles).threshold, 0.5);  // no fixed node
  handles.holds_fixed[3] = handles.holds_fixed[4] = handles.holds_fixed[5] = 1;
  // max{e' < 0.5 over fixed nodes} = 0.45; 0.7 does not count.
  EXPECT_DOUBLE_EQ(Select(graphs, e, handles).threshold, 0.45);
  handles = NoHandles(10);
  handles.holds_moveable[0] = 1;
  handles.holds_fixed[8] = 1;  // e' = 0.05 -> T = max(0.1, 0.05)
  EXPECT_DOUBLE_EQ(Select(graphs, e, handles).threshold, 0.1);
  handles.holds_fixed[8] = 0;
  handles.holds_fixed[5] = 1;  // only e' = 0.7 >= 0.5: as if none.
  EXPECT_DOUBLE_EQ(Select(graphs, e, handles).threshold, 0.5);
}

// Nodes of a component that nothing moves (HandleNodes::still) are Fixed
// before the border ring and the alpha weights: they neither free their
// neighbours nor widen the omega range, whatever their extent.
TEST(ScaleSelectionTest, StillNodesAreFixedBeforeBorderAndAlpha) {
  const auto graphs = LineGraphs(10, 1);
  const std::vector<double> e = {1.0, 0.6, 0.4, 0.0, 0.0, 0.0, 0.9, 0.95, 0.9, 0.9};
  HandleNodes handles = NoHandles(10);
  handles.holds_moveable[0] = 1;
  handles.holds_fixed[3] = 1;
  handles.still.assign(10, 0);
  for (int i = 6; i < 10; ++i) handles.still[i] = 1;
  // A diagonal of 1: the fixed node, 3 away, is not a local-detail edit.
  const ScaleSelection selection = Select(graphs, e, handles, {}, /*diagonal=*/1.0);
  EXPECT_DOUBLE_EQ(selection.threshold, 0.1);
  using C = NodeClass;
  const std::vector<NodeClass> expected = {C::kTotallyFree, C::kTotallyFree, C::kTotallyFree,
                                           C::kHalfFree,    C::kFixed,       C::kFixed,
                                           C::kFixed,       C::kFixed,       C::kFixed,
                                           C::kFixed};
  EXPECT_EQ(selection.node_class, expected);
  EXPECT_EQ(selection.num_totally_free, 3);
  EXPECT_EQ(selection.num_half_free, 1);
  EXPECT_EQ(selection.num_fixed, 6);
  // omega over e' in [0.4, 1]: 4, 1 + 3 * 0.2 / 0.6 = 2, 1.
  EXPECT_DOUBLE_EQ(selection.omega[0], 4.0);
  EXPECT_DOUBLE_EQ(selection.omega[1], 2.0);
  EXPECT_DOUBLE_EQ(selection.omega[2], 1.0);
  EXPECT_DOUBLE_EQ(selection.Alpha(0, 1), 2.0);
  EXPECT_DOUBLE_EQ(selection.Alpha(5, 6), 1.0);
  // A node of a coarse scale is still only when all its members are.
  const std::vector<char> coarse = StillNodes(LineGraphs(10, 3)[2], handles.still);
  EXPECT_EQ(coarse, std::vector<char>({0, 0, 1, 1}));  // members {0-2} {3-5} {6-8} {9}
  EXPECT_EQ(StillNodes(graphs[0], {}), std::vector<char>(10, 0));
}

// A vertex moves only through a non-Fixed node of non-zero weight.
TEST(ScaleSelectionTest, VertexSkinnedOnlyByFixedNodesIsFound) {
  using C = NodeClass;
  const std::vector<NodeClass> classes = {C::kTotallyFree, C::kFixed, C::kHalfFree};
  SkinningWeights weights(/*k=*/2, /*num_vertices=*/3, /*num_nodes=*/3);
  const int nodes0[] = {1, 0}, nodes1[] = {1, 2}, nodes2[] = {0, 1};
  const double weights0[] = {1.0, 0.0}, weights1[] = {0.5, 0.5}, weights2[] = {0.25, 0.75};
  weights.SetVertex(0, nodes0, weights0);  // its free node has weight 0
  weights.SetVertex(1, nodes1, weights1);  // a Half Free node
  weights.SetVertex(2, nodes2, weights2);  // a Totally Free node
  EXPECT_EQ(FirstVertexSkinnedOnlyByFixedNodes(weights, classes, {1, 2}), -1);
  EXPECT_EQ(FirstVertexSkinnedOnlyByFixedNodes(weights, classes, {2, 0, 1}), 0);
  EXPECT_EQ(FirstVertexSkinnedOnlyByFixedNodes(weights, classes, {}), -1);
  const std::vector<NodeClass> all_fixed(3, C::kFixed);
  EXPECT_EQ(FirstVertexSkinnedOnlyByFixedNodes(weights, all_fixed, {2, 1}), 2);
}

TEST(ScaleSelectionTest, Eq6ScaleIsSmallestIWithP1BelowIP) {
  const int d1 = 1000;
  const auto graphs = LineGraphs(d1, 10);  // N = floor(1000 / 100)
  HandleNodes handles = NoHandles(d1);
  handles.holds_moveable[0] = 1;
  for (const auto& [p1, expected] : std::vector<std::pair<int, int>>{
           {1, 1}, {99, 1}, {100, 2}, {250, 3}, {999, 10}, {1000, 10}}) {
    std::vector<double> e(d1, 0.0);
    for (int i = 0; i < p1; ++i) e[i] = 0.9;
    const ScaleSelection selection = Select(graphs, e, handles);
    EXPECT_EQ(selection.group1_size, p1);
    EXPECT_EQ(selection.eq6_scale, expected) << "P1 = " << p1;
    EXPECT_EQ(selection.scale, expected) << "P1 = " << p1;
  }
}

TEST(ScaleSelectionTest, ClassesAndVariableCount) {
  // DG_2 over 8 DG1 nodes: nodes {0,1} {2,3} {4,5} {6,7}.
  const auto graphs = LineGraphs(8, 2);
  std::vector<double> e = {1.0, 0.8, 0.6, 0.05, 0.3, 0.02, 0.01, 0.0};
  HandleNodes handles = NoHandles(8);
  handles.holds_moveable[0] = 1;
  handles.holds_fixed[7] = 1;
  // P = 2: P1 = 4 -> s = 3, clamped to N = 2.
  const ScaleSelection selection = Select(graphs, e, handles, {}, 1e9, /*nodes_per_scale=*/2);
  EXPECT_DOUBLE_EQ(selection.threshold, 0.1);
  EXPECT_EQ(selection.group1_size, 4);  // 1.0, 0.8, 0.6, 0.3
  ASSERT_EQ(selection.scale, 2);
  EXPECT_EQ(selection.node_class,
            (std::vector<NodeClass>{NodeClass::kTotallyFree, NodeClass::kTotallyFree,
                                    NodeClass::kTotallyFree, NodeClass::kHalfFree}));
  // Node e' is the max over members.
  EXPECT_EQ(selection.node_extent, (std::vector<double>{1.0, 0.6, 0.3, 0.01}));
  EXPECT_EQ(selection.num_totally_free, 3);
  EXPECT_EQ(selection.num_half_free, 1);
  EXPECT_EQ(selection.num_variables(), 12 * 3 + 9 * 1);

  ScaleSelectionOptions options;
  options.member_extent = MemberExtent::kMean;
  const ScaleSelection mean = Select(graphs, e, handles, options, 1e9, /*nodes_per_scale=*/2);
  EXPECT_NEAR(mean.node_extent[2], 0.16, 1e-12);
  EXPECT_EQ(mean.node_class[2], NodeClass::kTotallyFree);
  EXPECT_NEAR(mean.node_extent[1], 0.325, 1e-12);
}

TEST(ScaleSelectionTest, OnlyFixedHandleNodesNextToTheFreeRegionAreHalfFree) {
  // A line of 10 DG1 nodes: the handle at 0, nodes 1-2 deform, nodes 3-9
  // hold the fixed handle. Only node 3 touches a Totally Free node; the
  // others cannot move and get no variables, however long the fixed part.
  const auto graphs = LineGraphs(10, 1);
  const std::vector<double> e = {1.0, 0.7, 0.4, 0, 0, 0, 0, 0, 0, 0};
  HandleNodes handles = NoHandles(10);
  handles.holds_moveable[0] = 1;
  for (int i = 3; i < 10; ++i) handles.holds_fixed[i] = 1;
  const NodeClass kT = NodeClass::kTotallyFree, kH = NodeClass::kHalfFree,
                  kF = NodeClass::kFixed;
  ScaleSelectionOptions options;
  EXPECT_EQ(Select(graphs, e, handles, options).node_class,
            (std::vector<NodeClass>{kT, kT, kT, kH, kF, kF, kF, kF, kF, kF}));
  options.half_free = HalfFreeRule::kEveryFixedHandleNode;  // the paper
  const ScaleSelection paper = Select(graphs, e, handles, options);
  EXPECT_EQ(paper.node_class, (std::vector<NodeClass>{kT, kT, kT, kH, kH, kH, kH, kH, kH, kH}));
  EXPECT_EQ(paper.num_variables(), 3 * 12 + 7 * 9);
  options.half_free = HalfFreeRule::kNone;  // Deformed 3
  EXPECT_EQ(Select(graphs, e, handles, options).node_class,
            (std::vector<NodeClass>{kT, kT, kT, kF, kF, kF, kF, kF, kF, kF}));
}

TEST(ScaleSelectionTest, BorderRuleDecidesTheFixedNodesNextToTheFreeRegion) {
  // Node 3 is rigid (e' < T) and holds no handle: it borders the free region.
  // Node 4 holds the fixed handle but borders only node 3.
  const auto graphs = LineGraphs(8, 1);
  const std::vector<double> e = {1.0, 0.7, 0.4, 0.05, 0, 0, 0, 0};
  HandleNodes handles = NoHandles(8);
  handles.holds_moveable[0] = 1;
  for (int i = 4; i < 8; ++i) handles.holds_fixed[i] = 1;
  const NodeClass kT = NodeClass::kTotallyFree, kH = NodeClass::kHalfFree,
                  kF = NodeClass::kFixed;
  ScaleSelectionOptions options;
  options.border = BorderRule::kFixed;
  EXPECT_EQ(Select(graphs, e, handles, options).node_class,
            (std::vector<NodeClass>{kT, kT, kT, kF, kF, kF, kF, kF}));
  options.border = BorderRule::kHalfFree;
  EXPECT_EQ(Select(graphs, e, handles, options).node_class,
            (std::vector<NodeClass>{kT, kT, kT, kH, kF, kF, kF, kF}));
  options.border = BorderRule::kTotallyFree;
  EXPECT_EQ(Select(graphs, e, handles, options).node_class,
            (std::vector<NodeClass>{kT, kT, kT, kT, kF, kF, kF, kF}));
  // Names round-trip.
  for (BorderRule rule : {BorderRule::kFixed, BorderRule::kHalfFree, BorderRule::kTotallyFree}) {
    BorderRule parsed = BorderRule::kFixed;
    EXPECT_TRUE(ParseBorderRule(BorderRuleName(rule), &parsed));
    EXPECT_EQ(parsed, rule);
  }
  for (HalfFreeRule rule : {HalfFreeRule::kNextToTotallyFree,
                            HalfFreeRule::kEveryFixedHandleNode, HalfFreeRule::kNone}) {
    HalfFreeRule parsed = HalfFreeRule::kNone;
    EXPECT_TRUE(ParseHalfFreeRule(HalfFreeRuleName(rule), &parsed));
    EXPECT_EQ(parsed, rule);
  }
}

TEST(ScaleSelectionTest, NodeHoldingBothHandlesMovesToFinerScale) {
  const auto graphs = LineGraphs(400, 4);
  std::vector<double> e(400, 0.0);
  for (int i = 0; i < 350; ++i) e[i] = 0.9;  // P1 = 350 -> s = 4
  HandleNodes handles = NoHandles(400);
  handles.holds_moveable[0] = 1;
  handles.holds_fixed[2] = 1;  // same DG_4 and DG_3 node as 0, not DG_2's... node {2,3}
  const ScaleSelection selection = Select(graphs, e, handles);
  EXPECT_EQ(selection.eq6_scale, 4);
  EXPECT_EQ(selection.scale, 2);
  handles.holds_fixed[2] = 0;
  handles.holds_fixed[0] = 1;
  ScaleSelection failed;
  std::string error;
  EXPECT_FALSE(SelectScale(graphs, e, handles, 100, 1e9, {}, &failed, &error));
  EXPECT_NE(error.find("cell"), std::string::npos) << error;
}

// Gives every graph of LineGraphs skinning weights over d1 vertices, vertex i
// at DG1 node i: at scale s it has k = 2 nodes, its run's node p = i / s
// (weight 3/4) and the next one, p + 1 (the previous one for the last run;
// weight 1/4).
void AddLineWeights(std::vector<DeformationGraph>* graphs, int d1) {
  for (DeformationGraph& graph : *graphs) {
    const int n = graph.num_nodes();
    graph.weights = SkinningWeights(2, d1, n);
    for (int i = 0; i < d1; ++i) {
      const int p = graph.node_of_dg1[i];
      const int nodes[] = {p, p + 1 < n ? p + 1 : p - 1};
      const double weights[] = {0.75, 0.25};
      graph.weights.SetVertex(i, nodes, weights);
    }
  }
}

TEST(ScaleSelectionTest, NodesSkinningAFixedVertexArePinned) {
  // ClassesAndVariableCount's edit with vertices: the fixed vertex 7 is
  // skinned at scale 2 by node 3 (which holds it: Half Free unpinned) and
  // node 2 (e' 0.3: Totally Free unpinned). Pinned, both are Fixed, and the
  // border ring leaves node 2 Fixed.
  auto graphs = LineGraphs(8, 2);
  AddLineWeights(&graphs, 8);
  std::vector<double> e = {1.0, 0.8, 0.6, 0.05, 0.3, 0.02, 0.01, 0.0};
  HandleNodes handles = NoHandles(8);
  handles.holds_moveable[0] = 1;
  handles.holds_fixed[7] = 1;
  handles.moveable_vertices = {0};
  handles.fixed_vertices = {7};
  using C = NodeClass;
  const ScaleSelection pinned = Select(graphs, e, handles, {}, 1e9, /*nodes_per_scale=*/2);
  ASSERT_EQ(pinned.scale, 2);
  EXPECT_EQ(pinned.node_class,
            (std::vector<NodeClass>{C::kTotallyFree, C::kTotallyFree, C::kFixed, C::kFixed}));
  EXPECT_EQ(pinned.num_pinned, 2);
  EXPECT_EQ(pinned.num_variables(), 12 * 2);
  // Every node skinning vertex 7 is Fixed: it stays at rest.
  EXPECT_EQ(FirstVertexSkinnedOnlyByFixedNodes(graphs[1].weights, pinned.node_class, {7}), 7);
  ScaleSelectionOptions paper;
  paper.pin_fixed_region = false;
  const ScaleSelection unpinned = Select(graphs, e, handles, paper, 1e9, 2);
  EXPECT_EQ(unpinned.node_class,
            (std::vector<NodeClass>{C::kTotallyFree, C::kTotallyFree, C::kTotallyFree,
                                    C::kHalfFree}));
  EXPECT_EQ(unpinned.num_pinned, 0);
}

TEST(ScaleSelectionTest, PinnedNodeSkinningTheHandleMovesToFinerScale) {
  // Fixed vertex 3: at scale 2 node 1 ({2, 3}) skins it and also skins the
  // handle vertex 0 (weight 1/4): a conflict, so scale 1, where vertex 0's
  // nodes (0, 1) and vertex 3's (3, 4) are apart.
  auto graphs = LineGraphs(8, 2);
  AddLineWeights(&graphs, 8);
  std::vector<double> e = {1.0, 0.8, 0.6, 0.5, 0.3, 0.02, 0.01, 0.0};
  HandleNodes handles = NoHandles(8);
  handles.holds_moveable[0] = 1;
  handles.holds_fixed[3] = 1;
  handles.moveable_vertices = {0};
  handles.fixed_vertices = {3};
  const ScaleSelection pinned = Select(graphs, e, handles, {}, 1e9, /*nodes_per_scale=*/2);
  EXPECT_EQ(pinned.eq6_scale, 2);
  EXPECT_EQ(pinned.scale, 1);
  EXPECT_EQ(pinned.node_class[3], NodeClass::kFixed);
  EXPECT_EQ(pinned.node_class[4], NodeClass::kFixed);
  EXPECT_EQ(pinned.num_pinned, 2);
  ScaleSelectionOptions paper;
  paper.pin_fixed_region = false;
  EXPECT_EQ(Select(graphs, e, handles, paper, 1e9, 2).scale, 2);
}

TEST(ScaleSelectionTest, OnDg1APinnedNodeSkinningTheHandleStaysFree) {
  // Fixed vertex 1 is skinned by nodes 1 and 2; node 1 also skins the handle
  // vertex 0, so on DG1 (no finer scale) it is not pinned: vertex 1 keeps a
  // non-Fixed node (held by a Position term, not exactly).
  auto graphs = LineGraphs(6, 1);
  AddLineWeights(&graphs, 6);
  const std::vector<double> e = {1.0, 0.2, 0.0, 0.0, 0.0, 0.0};
  HandleNodes handles = NoHandles(6);
  handles.holds_moveable[0] = 1;
  handles.holds_fixed[1] = 1;
  handles.moveable_vertices = {0};
  handles.fixed_vertices = {1};
  const ScaleSelection selection = Select(graphs, e, handles);
  using C = NodeClass;
  EXPECT_EQ(selection.node_class,
            (std::vector<NodeClass>{C::kTotallyFree, C::kHalfFree, C::kFixed, C::kFixed,
                                    C::kFixed, C::kFixed}));
  EXPECT_EQ(selection.num_pinned, 1);
  EXPECT_EQ(FirstVertexSkinnedOnlyByFixedNodes(graphs[0].weights, selection.node_class, {1}), -1);
}

TEST(ScaleSelectionTest, AlphaMapsExtentToOmegaAndTakesTheMin) {
  const auto graphs = LineGraphs(5, 1);
  const std::vector<double> e = {1.0, 0.6, 0.2, 0.0, 0.0};
  HandleNodes handles = NoHandles(5);
  handles.holds_moveable[0] = 1;
  handles.holds_fixed[4] = 1;  // 4 DG1 edges (length 1) away
  ScaleSelectionOptions options;
  options.border = BorderRule::kFixed;  // node 3 stays Fixed (e' 0 would set e_l)
  const ScaleSelection selection = Select(graphs, e, handles, options, /*diagonal=*/10.0);
  EXPECT_FALSE(selection.local_detail_edit);  // 4 > 0.1 * 10
  // Totally Free: nodes 0, 1, 2 with e' 1.0, 0.6, 0.2 -> omega 4, 2.5, 1.
  EXPECT_DOUBLE_EQ(selection.omega[0], 4.0);
  EXPECT_DOUBLE_EQ(selection.omega[1], 2.5);
  EXPECT_DOUBLE_EQ(selection.omega[2], 1.0);
  EXPECT_DOUBLE_EQ(selection.Alpha(0, 1), 2.5);
  EXPECT_DOUBLE_EQ(selection.Alpha(1, 0), 2.5);
  EXPECT_DOUBLE_EQ(selection.Alpha(2, 3), 1.0);  // 3 is Fixed
  options.alpha_all_one = true;
  EXPECT_DOUBLE_EQ(Select(graphs, e, handles, options, 10.0).Alpha(0, 1), 1.0);
}

TEST(ScaleSelectionTest, LocalDetailEditOnDg1HasUnitAlpha) {
  const auto graphs = LineGraphs(5, 1);
  const std::vector<double> e = {1.0, 0.6, 0.2, 0.0, 0.0};
  HandleNodes handles = NoHandles(5);
  handles.holds_moveable[0] = 1;
  handles.holds_fixed[4] = 1;
  // Geodesic distance 4 along DG1 edges, below 0.1 * 100.
  const ScaleSelection selection = Select(graphs, e, handles, {}, /*diagonal=*/100.0);
  EXPECT_TRUE(selection.local_detail_edit);
  EXPECT_DOUBLE_EQ(selection.Alpha(0, 1), 1.0);
}

}  // namespace
}  // namespace msdeform
