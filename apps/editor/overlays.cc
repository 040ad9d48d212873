#include "apps/editor/overlays.h"

#include <algorithm>
#include <cmath>

namespace msdeform {
namespace editor {

Rgb LabelColor(VertexLabel label) {
  if (label == VertexLabel::kFixed) return kFixedColor;
  if (IsHandle(label)) return HandleGroupColor(HandleGroupOf(label));
  return kFreeColor;
}

Rgb HandleGroupColor(int group) {
  // Group 0 the handle's red, then reds and pinks that neither the labels,
  // the node classes (orange, magenta, grey) nor e''s viridis map use.
  static const Rgb kOthers[] = {{240, 100, 170}, {140, 80, 30}, {120, 0, 50}, {255, 190, 220}};
  return group == 0 ? kHandleColor : kOthers[(group - 1) % 4];
}

Rgb NodeClassColor(NodeClass node_class) {
  switch (node_class) {
    case NodeClass::kTotallyFree:
      return kTotallyFreeColor;
    case NodeClass::kHalfFree:
      return kHalfFreeColor;
    case NodeClass::kFixed:
      break;
  }
  return kFixedNodeColor;
}

Rgb RigidityColor(double e_prime) {
  // Viridis at 0, 0.1, ..., 1 (matplotlib's table).
  static constexpr std::uint8_t kStops[11][3] = {{68, 1, 84},    {72, 36, 117},  {65, 68, 135},
                                                 {53, 95, 141},  {42, 120, 142}, {33, 145, 140},
                                                 {34, 168, 132}, {68, 191, 112}, {122, 209, 81},
                                                 {189, 223, 38}, {253, 231, 37}};
  const double x = std::clamp(std::isfinite(e_prime) ? e_prime : 0.0, 0.0, 1.0) * 10.0;
  const int i = std::min(static_cast<int>(x), 9);
  const double f = x - i;
  Rgb color;
  for (int c = 0; c < 3; ++c) {
    color[c] =
        static_cast<std::uint8_t>(std::lround((1.0 - f) * kStops[i][c] + f * kStops[i + 1][c]));
  }
  return color;
}

Eigen::VectorXd VertexRigidity(const GraphMethod& graph_method) {
  const RigidityEstimate& rigidity = graph_method.rigidity();
  if (graph_method.graphs().empty() || rigidity.relative_extent.size() == 0) return {};
  const DeformationGraph& dg1 = graph_method.graphs()[0];
  if (rigidity.relative_extent.size() < dg1.num_nodes()) return {};
  const SkinningWeights& weights = dg1.weights;
  Eigen::VectorXd per_vertex = Eigen::VectorXd::Zero(weights.num_vertices());
  for (int v = 0; v < weights.num_vertices(); ++v) {
    for (int slot = 0; slot < weights.k(); ++slot) {
      per_vertex[v] += weights.weight(slot, v) * rigidity.relative_extent[weights.node(slot, v)];
    }
  }
  return per_vertex;
}

std::vector<Rgb> VertexColors(const std::vector<VertexLabel>& labels,
                              const Eigen::VectorXd& rigidity) {
  std::vector<Rgb> colors(labels.size());
  const bool by_rigidity = rigidity.size() == static_cast<Eigen::Index>(labels.size());
  for (size_t v = 0; v < labels.size(); ++v) {
    colors[v] = by_rigidity && labels[v] == VertexLabel::kFree ? RigidityColor(rigidity[v])
                                                                : LabelColor(labels[v]);
  }
  return colors;
}

Eigen::Matrix3Xd DeformedNodePositions(const GraphMethod& graph_method) {
  const DeformationGraph& graph = graph_method.active();
  const NodeTransforms& transforms = graph_method.transforms();
  Eigen::Matrix3Xd positions = graph.positions;
  if (transforms.num_nodes() == graph.num_nodes()) positions += transforms.translations;
  return positions;
}

std::vector<Rgb> NodeColors(const GraphMethod& graph_method) {
  std::vector<Rgb> colors;
  for (NodeClass node_class : graph_method.node_classes())
    colors.push_back(NodeClassColor(node_class));
  return colors;
}

std::array<int, 3> CountNodeClasses(const GraphMethod& graph_method) {
  std::array<int, 3> counts = {0, 0, 0};
  for (NodeClass c : graph_method.node_classes()) {
    counts[c == NodeClass::kTotallyFree ? 0 : c == NodeClass::kHalfFree ? 1 : 2]++;
  }
  return counts;
}

}  // namespace editor
}  // namespace msdeform
