#include "msdeform/scales/node_classes.h"

#include <algorithm>

namespace msdeform {

std::vector<char> StillVertices(const Components& components, const HandleLayout& layout) {
  if (components.count <= 1) return {};
  std::vector<char> moves(components.count, 0);
  for (int v : layout.moveable) moves[components.component_of_vertex[v]] = 1;
  std::vector<char> still(components.component_of_vertex.size());
  for (size_t v = 0; v < still.size(); ++v) still[v] = !moves[components.component_of_vertex[v]];
  return still;
}

namespace {

// Per surface particle (DG1 node): whether it holds one of `vertices`.
std::vector<char> CellsHolding(const Lattice& lattice, const std::vector<int>& vertices) {
  std::vector<char> holds(lattice.num_surface_particles(), 0);
  for (int v : vertices) holds[lattice.particle_of_vertex(v)] = 1;
  return holds;
}

// Per surface particle: whether it holds only still vertices; empty when
// `still_vertices` is (one component).
std::vector<char> StillCells(const Lattice& lattice, const std::vector<char>& still_vertices) {
  if (still_vertices.empty()) return {};
  const CompressedLists& vertices = lattice.vertices_of_particle();
  std::vector<char> still(lattice.num_surface_particles(), 1);
  for (int cell = 0; cell < lattice.num_surface_particles(); ++cell) {
    for (const int* v = vertices.begin(cell); v != vertices.end(cell); ++v) {
      if (!still_vertices[*v]) {
        still[cell] = 0;
        break;
      }
    }
  }
  return still;
}

}  // namespace

HandleNodes HandleNodesOf(const Lattice& lattice, const HandleLayout& layout,
                          const std::vector<char>& still_vertices) {
  HandleNodes handles;
  handles.holds_fixed = CellsHolding(lattice, layout.fixed);
  handles.holds_moveable = CellsHolding(lattice, layout.moveable);
  handles.still = StillCells(lattice, still_vertices);
  for (int v : layout.fixed) {
    if (still_vertices.empty() || !still_vertices[v]) handles.fixed_vertices.push_back(v);
  }
  handles.moveable_vertices = layout.moveable;
  return handles;
}

std::vector<char> StillNodes(const DeformationGraph& graph, const std::vector<char>& still_dg1) {
  std::vector<char> still(graph.num_nodes(), 0);
  if (still_dg1.empty()) return still;
  for (int j = 0; j < graph.num_nodes(); ++j) {
    still[j] = graph.members.begin(j) != graph.members.end(j);
    for (const int* m = graph.members.begin(j); m != graph.members.end(j) && still[j]; ++m) {
      still[j] = still_dg1[*m] != 0;
    }
  }
  return still;
}

bool SkinnedByAFreeNode(const SkinningWeights& weights, const std::vector<NodeClass>& node_class,
                        int v) {
  for (int slot = 0; slot < weights.k(); ++slot) {
    if (weights.weight(slot, v) != 0.0 && node_class[weights.node(slot, v)] != NodeClass::kFixed) {
      return true;
    }
  }
  return false;
}

int FirstVertexSkinnedOnlyByFixedNodes(const SkinningWeights& weights,
                                       const std::vector<NodeClass>& node_class,
                                       const std::vector<int>& vertices) {
  for (int v : vertices) {
    if (!SkinnedByAFreeNode(weights, node_class, v)) return v;
  }
  return -1;
}

bool ClassifyNodesAtScale(const DeformationGraph& graph, int scale,
                          const std::vector<double>& dg1_extent, const HandleNodes& handles,
                          double threshold, const ScaleSelectionOptions& options,
                          ScaleClasses* classes) {
  const int n = graph.num_nodes();
  ScaleClasses& result = *classes;
  result = ScaleClasses();
  bool conflict = false;
  const std::vector<char> still = StillNodes(graph, handles.still);
  std::vector<char> holds_fixed(n, 0);
  result.node_extent.assign(n, 0.0);
  result.node_class.assign(n, NodeClass::kFixed);
  for (int j = 0; j < n && !conflict; ++j) {
    bool moveable = false;
    double extent = 0.0;
    for (const int* m = graph.members.begin(j); m != graph.members.end(j); ++m) {
      holds_fixed[j] |= handles.holds_fixed[*m] != 0;
      moveable |= handles.holds_moveable[*m] != 0;
      extent = options.member_extent == MemberExtent::kMax ? std::max(extent, dg1_extent[*m])
                                                           : extent + dg1_extent[*m];
    }
    if (options.member_extent == MemberExtent::kMean) extent /= graph.members.size(j);
    result.node_extent[j] = extent;
    conflict = holds_fixed[j] && moveable;
    if (still[j]) continue;  // Fixed, before anything reads the classes
    if (!holds_fixed[j] && (moveable || extent > threshold)) {
      result.node_class[j] = NodeClass::kTotallyFree;
    }
  }
  if (conflict) return false;
  // Nodes that skin a fixed vertex are Fixed. The handle must keep its
  // nodes free: a pinned node that holds or skins a moveable vertex sends
  // the selection to a finer scale (on DG1 it stays unpinned).
  std::vector<char> pinned(n, 0);
  if (options.pin_fixed_region) {
    const SkinningWeights& weights = graph.weights;
    for (int v : handles.fixed_vertices) {
      for (int slot = 0; slot < weights.k(); ++slot) {
        if (weights.weight(slot, v) != 0.0) pinned[weights.node(slot, v)] = 1;
      }
    }
    std::vector<char> serves_handle(n, 0);
    for (int v : handles.moveable_vertices) {
      for (int slot = 0; slot < weights.k(); ++slot) {
        if (weights.weight(slot, v) != 0.0) serves_handle[weights.node(slot, v)] = 1;
      }
    }
    for (int j = 0; j < n; ++j) {
      for (const int* m = graph.members.begin(j); m != graph.members.end(j); ++m) {
        serves_handle[j] |= handles.holds_moveable[*m] != 0;
      }
      if (pinned[j] && serves_handle[j]) {
        if (scale > 1) conflict = true;
        pinned[j] = 0;
      }
    }
    if (conflict) return false;
    for (int j = 0; j < n; ++j) {
      if (pinned[j]) result.node_class[j] = NodeClass::kFixed;
    }
  }
  // Nodes next to the Totally Free region (decided before any changes).
  std::vector<char> borders_free(n, 0);
  for (int j = 0; j < n; ++j) {
    for (const int* k = graph.neighbors.begin(j); k != graph.neighbors.end(j); ++k) {
      borders_free[j] |= result.node_class[*k] == NodeClass::kTotallyFree;
    }
  }
  for (int j = 0; j < n; ++j) {
    if (result.node_class[j] == NodeClass::kTotallyFree || still[j] || pinned[j]) continue;
    if (holds_fixed[j]) {
      if (options.half_free == HalfFreeRule::kEveryFixedHandleNode ||
          (options.half_free == HalfFreeRule::kNextToTotallyFree && borders_free[j])) {
        result.node_class[j] = NodeClass::kHalfFree;
      }
    } else if (borders_free[j] && options.border != BorderRule::kFixed) {
      result.node_class[j] = options.border == BorderRule::kHalfFree ? NodeClass::kHalfFree
                                                                     : NodeClass::kTotallyFree;
    }
  }
  result.num_pinned = static_cast<int>(std::count(pinned.begin(), pinned.end(), 1));
  return true;
}

std::vector<NodeClass> StaticGraphNodeClasses(const DeformationGraph& graph,
                                              const std::vector<char>& still_dg1) {
  const std::vector<char> still = StillNodes(graph, still_dg1);
  std::vector<NodeClass> classes(graph.num_nodes(), NodeClass::kTotallyFree);
  for (size_t j = 0; j < still.size(); ++j) {
    if (still[j]) classes[j] = NodeClass::kFixed;
  }
  return classes;
}

}  // namespace msdeform
