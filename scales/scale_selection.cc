#include "msdeform/scales/scale_selection.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <sstream>

#include <glog/logging.h>

namespace msdeform {

const char* NodeClassName(NodeClass node_class) {
  switch (node_class) {
    case NodeClass::kFixed:
      return "fixed";
    case NodeClass::kHalfFree:
      return "half_free";
    case NodeClass::kTotallyFree:
      return "totally_free";
  }
  return "unknown";
}

const EnumNames<HalfFreeRule>& HalfFreeRuleNames() {
  static const EnumNames<HalfFreeRule> names = {
      {HalfFreeRule::kNextToTotallyFree, "next_to_totally_free"},
      {HalfFreeRule::kEveryFixedHandleNode, "every_fixed_handle_node"},
      {HalfFreeRule::kNone, "none"}};
  return names;
}

const char* HalfFreeRuleName(HalfFreeRule rule) { return HalfFreeRuleNames().Name(rule); }

bool ParseHalfFreeRule(const std::string& name, HalfFreeRule* rule) {
  return HalfFreeRuleNames().Parse(name, rule);
}

// A border rule is named by the class the node becomes.
const EnumNames<BorderRule>& BorderRuleNames() {
  static const EnumNames<BorderRule> names = {
      {BorderRule::kFixed, NodeClassName(NodeClass::kFixed)},
      {BorderRule::kHalfFree, NodeClassName(NodeClass::kHalfFree)},
      {BorderRule::kTotallyFree, NodeClassName(NodeClass::kTotallyFree)}};
  return names;
}

const char* BorderRuleName(BorderRule rule) { return BorderRuleNames().Name(rule); }

bool ParseBorderRule(const std::string& name, BorderRule* rule) {
  return BorderRuleNames().Parse(name, rule);
}

const EnumNames<MemberExtent>& MemberExtentNames() {
  static const EnumNames<MemberExtent> names = {{MemberExtent::kMax, "max"},
                                                {MemberExtent::kMean, "mean"}};
  return names;
}

bool ScaleSelectionOptions::Check(std::string* error) const {
  if (!(threshold_floor >= 0.0 && threshold_floor < 1.0)) {
    *error = "threshold_floor must be in [0, 1)";
    return false;
  }
  if (!(fixed_extent_cutoff > 0.0 && fixed_extent_cutoff <= 1.0)) {
    *error = "fixed_extent_cutoff must be in (0, 1]";
    return false;
  }
  if (!(local_detail_distance >= 0.0) || !std::isfinite(local_detail_distance)) {
    *error = "local_detail_distance must be a finite number >= 0";
    return false;
  }
  if (!(omega_max >= 1.0) || !std::isfinite(omega_max)) {
    *error = "omega_max must be a finite number >= 1";
    return false;
  }
  return true;
}

double ScaleSelection::Alpha(int j, int k) const {
  if (node_class[j] == NodeClass::kTotallyFree && node_class[k] == NodeClass::kTotallyFree) {
    return std::min(omega[j], omega[k]);
  }
  return 1.0;
}

namespace {

// Shortest distance along DG1 edges from any moveable-handle node to any
// fixed-handle node (infinity when none is reachable).
double GeodesicHandleDistance(const DeformationGraph& dg1, const HandleNodes& handles) {
  const int n = dg1.num_nodes();
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (int i = 0; i < n; ++i) {
    if (handles.holds_moveable[i]) {
      distance[i] = 0.0;
      queue.emplace(0.0, i);
    }
  }
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > distance[i]) continue;
    if (handles.holds_fixed[i]) return d;  // Popped in increasing distance.
    for (const int* j = dg1.neighbors.begin(i); j != dg1.neighbors.end(i); ++j) {
      const double through = d + (dg1.positions.col(i) - dg1.positions.col(*j)).norm();
      if (through < distance[*j]) {
        distance[*j] = through;
        queue.emplace(through, *j);
      }
    }
  }
  return std::numeric_limits<double>::infinity();
}

}  // namespace

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

bool SelectScale(const std::vector<DeformationGraph>& graphs,
                 const std::vector<double>& dg1_extent, const HandleNodes& handles,
                 int nodes_per_scale, double diagonal, const ScaleSelectionOptions& options,
                 ScaleSelection* selection, std::string* error) {
  return SelectScale([&graphs](int scale) -> const DeformationGraph& { return graphs[scale - 1]; },
                     static_cast<int>(graphs.size()), dg1_extent, handles, nodes_per_scale,
                     diagonal, options, selection, error);
}

bool SelectScale(const std::function<const DeformationGraph&(int scale)>& graph_at,
                 int num_scales, const std::vector<double>& dg1_extent,
                 const HandleNodes& handles, int nodes_per_scale, double diagonal,
                 const ScaleSelectionOptions& options, ScaleSelection* selection,
                 std::string* error) {
  CHECK_GE(num_scales, 1);
  if (!options.Check(error)) return false;
  if (nodes_per_scale < 1) {
    *error = "nodes_per_scale (P) must be >= 1";
    return false;
  }
  const DeformationGraph& dg1 = graph_at(1);
  const int d1 = dg1.num_nodes();
  CHECK_EQ(static_cast<int>(dg1_extent.size()), d1);
  CHECK_EQ(static_cast<int>(handles.holds_fixed.size()), d1);
  CHECK_EQ(static_cast<int>(handles.holds_moveable.size()), d1);
  CHECK(handles.still.empty() || static_cast<int>(handles.still.size()) == d1);
  ScaleSelection& result = *selection;
  result = ScaleSelection();

  // Eq. 7.
  double fixed_extent = -1.0;
  for (int i = 0; i < d1; ++i) {
    if (handles.holds_fixed[i] && dg1_extent[i] < options.fixed_extent_cutoff) {
      fixed_extent = std::max(fixed_extent, dg1_extent[i]);
    }
  }
  if (fixed_extent < 0.0) fixed_extent = options.fixed_extent_cutoff;
  result.threshold = std::max(options.threshold_floor, fixed_extent);

  // Eq. 6.
  for (int i = 0; i < d1; ++i) result.group1_size += dg1_extent[i] > result.threshold;
  int scale = 1;
  while (scale < num_scales && !(result.group1_size < scale * nodes_per_scale)) ++scale;
  result.eq6_scale = scale;

  // Classes, moving finer while a node would hold both kinds of handle.
  std::vector<char> pinned;
  for (; scale >= 1; --scale) {
    const DeformationGraph& graph = graph_at(scale);
    const int n = graph.num_nodes();
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
      if (!holds_fixed[j] && (moveable || extent > result.threshold)) {
        result.node_class[j] = NodeClass::kTotallyFree;
      }
    }
    if (conflict) continue;
    // Nodes that skin a fixed vertex are Fixed. The handle must keep its
    // nodes free: a pinned node that holds or skins a moveable vertex sends
    // the selection to a finer scale (on DG1 it stays unpinned).
    pinned.assign(n, 0);
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
      if (conflict) continue;
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
    break;
  }
  if (scale < 1) {
    *error =
        "a lattice cell holds both fixed and moveable handle vertices; separate the handles "
        "or use a smaller cell width";
    return false;
  }
  result.scale = scale;
  result.num_pinned = static_cast<int>(std::count(pinned.begin(), pinned.end(), 1));

  // Counts and alpha weights (omega per Totally Free node).
  const int n = graph_at(scale).num_nodes();
  result.omega.assign(n, 1.0);
  double e_l = std::numeric_limits<double>::infinity(), e_f = -e_l;
  for (int j = 0; j < n; ++j) {
    switch (result.node_class[j]) {
      case NodeClass::kTotallyFree:
        ++result.num_totally_free;
        e_l = std::min(e_l, result.node_extent[j]);
        e_f = std::max(e_f, result.node_extent[j]);
        break;
      case NodeClass::kHalfFree:
        ++result.num_half_free;
        break;
      case NodeClass::kFixed:
        ++result.num_fixed;
        break;
    }
  }
  result.local_detail_edit =
      scale == 1 && GeodesicHandleDistance(dg1, handles) < options.local_detail_distance * diagonal;
  if (!options.alpha_all_one && !result.local_detail_edit && e_f > e_l) {
    for (int j = 0; j < n; ++j) {
      if (result.node_class[j] != NodeClass::kTotallyFree) continue;
      result.omega[j] = 1.0 + (options.omega_max - 1.0) * (result.node_extent[j] - e_l) / (e_f - e_l);
    }
  }
  return true;
}

}  // namespace msdeform
