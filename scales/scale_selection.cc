#include "msdeform/scales/scale_selection.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <sstream>
#include <utility>

#include <glog/logging.h>

#include "msdeform/scales/node_classes.h"

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
  // The ranges are ScaleSelectionOptionTable()'s rows (scale_selection.h).
  return ScaleSelectionOptionTable().CheckRanges(*this, error);
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

  // Classes (node_classes.h), moving finer while DG_scale cannot serve the
  // layout.
  ScaleClasses classes;
  for (; scale >= 1; --scale) {
    if (ClassifyNodesAtScale(graph_at(scale), scale, dg1_extent, handles, result.threshold,
                             options, &classes)) {
      break;
    }
  }
  if (scale < 1) {
    *error =
        "a lattice cell holds both fixed and moveable handle vertices; separate the handles "
        "or use a smaller cell width";
    return false;
  }
  result.scale = scale;
  result.node_extent = std::move(classes.node_extent);
  result.node_class = std::move(classes.node_class);
  result.num_pinned = classes.num_pinned;

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

const OptionTable<ScaleSelectionOptions>& ScaleSelectionOptionTable() {
  static const OptionTable<ScaleSelectionOptions>& table =
      MakeOptionTable<ScaleSelectionOptions>([](auto& t) { DeclareScaleSelectionOptionRows(t); });
  return table;
}

}  // namespace msdeform
