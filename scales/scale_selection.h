// Scale selection and node classes (paper §4.2, Eq. 6-7; docs/method.md §4) and
// the coherence weights alpha_jk (Eq. 15; docs/method.md §5).
//
// From the normalised deforming extent e' of each DG1 node (= surface
// particle), the threshold is
//   T = max(0.1, max{ e'_i : e'_i < 0.5, i a fixed-handle node })   (Eq. 7)
// (0.5 in place of the inner max when no fixed-handle node qualifies).
// Group 1 is the DG1 nodes with e' > T (P1 of them), and the scale is
//   s = min{ i : P1 < i P }, clamped to [1, N]                      (Eq. 6).
// The classes at a scale are decided in node_classes.{h,cc}
// (ClassifyNodesAtScale), by these rules:
// at scale s a node's e' is the max (or, as an ablation, the mean) over its
// DG1 members, and each node is
//   Half Free    if a member's cell holds a fixed-handle vertex (9 variables)
//                and, by default, a Totally Free node is its neighbour (the
//                joint; the paper's rule, every fixed-handle node Half Free, is
//                HalfFreeRule::kEveryFixedHandleNode),
//   Totally Free if it holds a moveable-handle vertex or has e' > T (12),
//   Fixed        otherwise (0), and always when all its members are still
//                (HandleNodes::still: in components with no moveable handle).
// By default (pin_fixed_region) every node that skins a fixed-handle vertex
// with non-zero weight is then Fixed, whatever the rules above said: a fixed
// vertex is a blend of identities and stays exactly at rest, and the vertices
// beyond it blend from rest into the free nodes' motion over the skinning
// support (docs/decisions/lattice.md, "Exact fixed regions"). BorderRule then decides
// what the other Fixed nodes next to a Totally Free one become (by default
// Totally Free: one more ring; the paper keeps them Fixed).
// A node holding both fixed and moveable vertices cannot serve both, and
// neither can a pinned node that holds or skins moveable vertices (the handle
// would lag behind its target), so the selection moves to finer scales until
// no node does. On DG1 such a node is left unpinned (the fixed vertices it
// skins are then held by Position terms only; GraphMethod::fixed_region_exact).

#ifndef MSDEFORM_SCALES_SCALE_SELECTION_H_
#define MSDEFORM_SCALES_SCALE_SELECTION_H_

#include <functional>
#include <string>
#include <vector>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/option_table.h"
#include "msdeform/solvers/node_class.h"

namespace msdeform {

// "fixed", "half_free", "totally_free".
const char* NodeClassName(NodeClass node_class);

// How a coarse node's e' is made from its DG1 members' e'.
enum class MemberExtent { kMax, kMean };
// "max", "mean".
const EnumNames<MemberExtent>& MemberExtentNames();

// Which nodes holding fixed-handle vertices are Half Free (the rest are Fixed).
enum class HalfFreeRule {
  // Those with a Totally Free neighbour at the selected scale: the others
  // cannot move, so they need no variables however large the fixed region.
  kNextToTotallyFree,
  // Every one (the paper's rule; an ablation).
  kEveryFixedHandleNode,
  // None: fixed-handle nodes are Fixed (paper Fig. 5, "Deformed 3"; the
  // DeformerOptions::fix_fixed_handle_nodes ablation).
  kNone,
};

// What a Fixed node (no handle vertex, e' <= T) with a Totally Free neighbour
// becomes; Fixed pins its Totally Free neighbours to rest through E(j, k).
enum class BorderRule {
  kFixed,      // stays Fixed (the paper)
  kHalfFree,   // a joint: rotation only (9 variables)
  kTotallyFree,  // one more ring of Totally Free nodes (12 variables)
};

// "next_to_totally_free", "every_fixed_handle_node", "none".
const EnumNames<HalfFreeRule>& HalfFreeRuleNames();
const char* HalfFreeRuleName(HalfFreeRule rule);
bool ParseHalfFreeRule(const std::string& name, HalfFreeRule* rule);
// "fixed", "half_free", "totally_free".
const EnumNames<BorderRule>& BorderRuleNames();
const char* BorderRuleName(BorderRule rule);
bool ParseBorderRule(const std::string& name, BorderRule* rule);

struct ScaleSelectionOptions {
  // Lower bound of the threshold T (Eq. 7: 0.1).
  double threshold_floor = 0.1;
  // Fixed-handle nodes with e' below this count towards T (Eq. 7: 0.5).
  double fixed_extent_cutoff = 0.5;
  // Coarse node e' from members (docs/method.md §4: max; mean is an ablation).
  MemberExtent member_extent = MemberExtent::kMax;
  // A DG1 edit is "local detail" (alpha all 1) when a fixed-handle node lies
  // within this geodesic distance, along DG1 edges, of the moveable handle;
  // as a fraction of the bounding-box diagonal (docs/method.md: 0.1).
  double local_detail_distance = 0.1;
  // Totally Free nodes map e linearly from [e_l, e_f] to omega in [1, omega_max].
  double omega_max = 4.0;
  // Ablation: alpha_jk = 1 for every edge.
  bool alpha_all_one = false;
  // Half Free nodes (docs/decisions/node-classes.md).
  HalfFreeRule half_free = HalfFreeRule::kNextToTotallyFree;
  // Fixed nodes bordering the Totally Free region (docs/decisions/node-classes.md, "Node
  // classes on large fixed regions": one more Totally Free ring distorted
  // least over the experiment edits; the paper keeps them Fixed).
  BorderRule border = BorderRule::kTotallyFree;
  // Nodes that skin a fixed-handle vertex are Fixed, so the fixed region
  // stays exactly at rest (docs/decisions/lattice.md, "Exact fixed regions"); false:
  // the paper's classes, where only Position terms hold the fixed vertices.
  bool pin_fixed_region = true;

  // The ranges of ScaleSelectionOptionTable()'s rows.
  bool Check(std::string* error) const;
};

// ScaleSelectionOptions' rows (core/option_table.h), declared in its header beside the fields: a
// new field is the field above and its row here. ScaleSelectionOptionTable() (scale_selection.cc)
// builds the table from them once; a template, so that only that file compiles the rows.
template <typename Table>
void DeclareScaleSelectionOptionRows(Table& t) {
  using S = ScaleSelectionOptions;
  t.Double("threshold_floor", &S::threshold_floor,
           "Lower bound of the rigidity threshold T (Eq. 7: 0.1).")
      .Range(0, 1, "a number in [0, 1)", /*high_open=*/true);
  t.Double("fixed_extent_cutoff", &S::fixed_extent_cutoff,
           "Fixed-handle nodes with e' below this count towards T (Eq. 7: 0.5).")
      .Range(0, 1, "a number in (0, 1]")
      .lo_open = true;
  t.Enum("member_extent", &S::member_extent, MemberExtentNames(),
         "A coarse node's e' from its DG1 members: max or mean (an ablation).");
  t.Double("local_detail_distance", &S::local_detail_distance,
           "Local-detail edit within this geodesic distance, over the diagonal.")
      .AtLeast(0, "a finite number >= 0");
  t.Double("omega_max", &S::omega_max,
           "Totally Free nodes map e to omega in [1, omega_max].")
      .AtLeast(1, "a finite number >= 1");
  t.Bool("alpha_all_one", &S::alpha_all_one, "Every coherence weight alpha = 1.");
  t.Enum("half_free", &S::half_free, HalfFreeRuleNames(),
         "Which fixed-handle nodes are Half Free: next_to_totally_free, "
         "every_fixed_handle_node (the paper) or none.");
  t.Enum("border", &S::border, BorderRuleNames(),
         "What a Fixed node next to a Totally Free one becomes: fixed (the paper), "
         "half_free or totally_free.");
  t.Bool("pin_fixed_region", &S::pin_fixed_region,
         "Multi-scale: nodes that skin a fixed-handle vertex are Fixed, so the fixed "
         "region stays exactly at rest (the paper: false).");
}
const OptionTable<ScaleSelectionOptions>& ScaleSelectionOptionTable();

// Which DG1 nodes (surface cells) hold handle vertices.
struct HandleNodes {
  std::vector<char> holds_fixed;     // per DG1 node
  std::vector<char> holds_moveable;  // per DG1 node
  // Per DG1 node: it holds only vertices of mesh components without a
  // moveable-handle vertex, which nothing moves. Empty: none (one component).
  std::vector<char> still;
  // The fixed- and moveable-handle vertices (mesh ids) for pin_fixed_region;
  // still components' vertices may be left out (nothing moves them).
  std::vector<int> fixed_vertices;
  std::vector<int> moveable_vertices;
};

struct ScaleSelection {
  double threshold = 0.0;        // T (Eq. 7)
  int group1_size = 0;           // P1
  int eq6_scale = 1;             // s from Eq. 6, 1-based
  int scale = 1;                 // selected scale after conflicts, 1-based
  bool local_detail_edit = false;
  // Nodes that pin_fixed_region keeps Fixed: those skinning a fixed vertex
  // (some would have been Fixed anyway).
  int num_pinned = 0;
  std::vector<double> node_extent;       // e' per node of the selected scale
  std::vector<NodeClass> node_class;     // per node of the selected scale
  std::vector<double> omega;             // per node; 1 unless Totally Free
  int num_totally_free = 0;              // m
  int num_half_free = 0;                 // q
  int num_fixed = 0;

  int num_variables() const { return 12 * num_totally_free + 9 * num_half_free; }
  // alpha_jk of Eq. 15: min(omega_j, omega_k) when both are Totally Free, else 1.
  double Alpha(int j, int k) const;
};

// `graphs[i]` is DG_{i+1}, built with P = `nodes_per_scale` nodes per scale
// step (GraphOptions::nodes_per_scale, the one place P is stated; Eq. 6 uses
// the same P); `dg1_extent` is e' per DG1 node; `diagonal` the mesh's
// bounding-box diagonal. Returns false (with a message) when even DG1
// has a node holding both fixed and moveable vertices.
bool SelectScale(const std::vector<DeformationGraph>& graphs,
                 const std::vector<double>& dg1_extent, const HandleNodes& handles,
                 int nodes_per_scale, double diagonal, const ScaleSelectionOptions& options,
                 ScaleSelection* selection, std::string* error);

// The same with the graphs handed over one at a time: `graph_at(s)` is DG_s,
// connected (edges and neighbours; core/deformation_graph.h), for s in
// 1..num_scales. It is asked for DG1 and for the scales it tries, from Eq. 6's
// down while a node holds both kinds of handle: so a caller can connect the
// coarse scales only when they are used.
bool SelectScale(const std::function<const DeformationGraph&(int scale)>& graph_at,
                 int num_scales, const std::vector<double>& dg1_extent,
                 const HandleNodes& handles, int nodes_per_scale, double diagonal,
                 const ScaleSelectionOptions& options, ScaleSelection* selection,
                 std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_SCALE_SELECTION_H_
