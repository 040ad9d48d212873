#include "msdeform/scales/handle_setup.h"

#include <chrono>
#include <cmath>
#include <utility>

#include <glog/logging.h>

#include "msdeform/core/parallel.h"
#include "msdeform/core/timing.h"
#include "msdeform/scales/node_classes.h"
#include "msdeform/scales/subspace_arap_build.h"
#include "msdeform/solvers/subspace_arap_terms.h"

namespace msdeform {
namespace {

std::vector<int> Indices(const std::vector<char>& flags) {
  std::vector<int> indices;
  for (int i = 0; i < static_cast<int>(flags.size()); ++i)
    if (flags[i]) indices.push_back(i);
  return indices;
}

}  // namespace

HandleSetup::HandleSetup(std::shared_ptr<const Precompute> precompute)
    : precompute_(std::move(precompute)) {}

std::shared_ptr<const HandleSetup> HandleSetup::Create(
    std::shared_ptr<const Precompute> precompute, const HandleLayout& handles,
    std::string* error) {
  CHECK(precompute != nullptr);
  if (!ValidateHandles(handles, precompute->mesh().num_vertices(), error)) return nullptr;
  std::shared_ptr<HandleSetup> setup(new HandleSetup(std::move(precompute)));
  if (!setup->Build(handles, error)) return nullptr;
  return setup;
}

bool HandleSetup::Build(const HandleLayout& handles, std::string* error) {
  const Precompute& pre = *precompute_;
  const DeformerOptions& options = pre.options();
  handles_ = handles;
  still_vertices_ = StillVertices(pre.components(), handles_);
  const HandleNodes nodes = HandleNodesOf(pre.lattice(), handles_, still_vertices_);
  if (options.method == Method::kMultiScale) {
    const auto start = std::chrono::steady_clock::now();
    if (!pre.EstimateRigidity(Indices(nodes.holds_fixed), Indices(nodes.holds_moveable),
                              &rigidity_, error)) {
      return false;
    }
    rigidity_ms_ = MillisecondsSince(start);
    stages_.Add("rigidity", rigidity_ms_);
    const auto selection_start = std::chrono::steady_clock::now();
    const int num_dg1 = pre.lattice().num_surface_particles();
    const std::vector<double> dg1_extent(rigidity_.relative_extent.data(),
                                         rigidity_.relative_extent.data() + num_dg1);
    ScaleSelectionOptions selection_options = options.selection;
    if (options.fix_fixed_handle_nodes) selection_options.half_free = HalfFreeRule::kNone;
    // The scales tried stay connected until the selection is done, whatever
    // other set-ups do with the cache meanwhile.
    std::vector<Precompute::GraphPin> tried;
    // Connecting a scale (its nearest nodes and weights) is the skinning data
    // stage, the rest of SelectScale the scale selection.
    StageTimes connect_times;
    auto graph_at = [&pre, &tried, &connect_times](int scale) -> const DeformationGraph& {
      ScopedStage stage(&connect_times, "skinning_data");
      tried.push_back(pre.ConnectAndPin(scale - 1));
      return pre.graphs()[scale - 1];
    };
    if (!SelectScale(graph_at, static_cast<int>(pre.graphs().size()), dg1_extent, nodes,
                     options.graph.nodes_per_scale, pre.diagonal(), selection_options,
                     &selection_, error)) {
      return false;
    }
    active_graph_ = selection_.scale - 1;
    {
      ScopedStage stage(&connect_times, "skinning_data");
      pin_ = pre.ConnectAndPin(active_graph_);
    }
    stages_.Add("scale_selection",
                MillisecondsSince(selection_start) - connect_times.Get("skinning_data"));
    stages_.Append(connect_times);
    // Every class, the still components' Fixed nodes included, was decided
    // by SelectScale before the alpha weights (docs/method.md §4).
    node_classes_ = selection_.node_class;
    // A moveable vertex no free node skins is an error before any energy is built.
    {
      ScopedStage stage(&stages_, "skinned_vertices");
      if (!FindSkinnedVertices(error)) return false;
    }
    {
      ScopedStage stage(&stages_, "energy");
      BuildEnergy();
    }
    setup_ms_ = MillisecondsSince(selection_start);
  } else {
    const auto start = std::chrono::steady_clock::now();
    active_graph_ = pre.static_graph();
    pin_ = pre.ConnectAndPin(active_graph_);
    node_classes_ = StaticGraphNodeClasses(graph(), nodes.still);
    {
      ScopedStage stage(&stages_, "skinned_vertices");
      if (!FindSkinnedVertices(error)) return false;
    }
    {
      ScopedStage stage(&stages_, "energy");
      BuildEnergy();
    }
    setup_ms_ = MillisecondsSince(start);
  }
  return true;
}

std::vector<int> HandleSetup::FixedVerticesWithAFreeNode() const {
  const std::vector<int>& fixed = handles_.fixed;
  const std::vector<int> positions =
      SelectIndices(static_cast<int>(fixed.size()), precompute_->options().num_threads,
                    [&](int i) {
                      const int v = fixed[i];
                      return (still_vertices_.empty() || !still_vertices_[v]) &&
                             SkinnedByAFreeNode(graph().weights, node_classes_, v);
                    });
  std::vector<int> vertices(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) vertices[i] = fixed[positions[i]];
  return vertices;
}

int HandleSetup::num_variables() const {
  int variables = 0;
  for (NodeClass node_class : node_classes_) {
    variables += node_class == NodeClass::kTotallyFree ? 12
                 : node_class == NodeClass::kHalfFree  ? 9
                                                       : 0;
  }
  return variables;
}

bool HandleSetup::FindSkinnedVertices(std::string* error) {
  // Only vertices with a non-Fixed node of non-zero weight can move; the rest
  // stay at rest bit for bit (a Fixed node is the identity). So do the
  // vertices of still components, also where a coarse node spans two
  // components (merged when no edge was left) and moves with the other one.
  const SkinningWeights& weights = graph().weights;
  const int num_threads = precompute_->options().num_threads;
  skinned_vertices_ = SelectIndices(weights.num_vertices(), num_threads, [&](int v) {
    return (still_vertices_.empty() || !still_vertices_[v]) &&
           SkinnedByAFreeNode(weights, node_classes_, v);
  });
  skin_all_ = static_cast<int>(skinned_vertices_.size()) == weights.num_vertices();
  if (skin_all_) std::vector<int>().swap(skinned_vertices_);

  // Fixed vertices skinned only by Fixed nodes stay at rest exactly.
  fixed_region_exact_ = FixedVerticesWithAFreeNode().empty();

  // A moveable-handle vertex that no non-Fixed node skins cannot follow the
  // handle: every frame would leave it at rest.
  if (const int v = FirstVertexSkinnedOnlyByFixedNodes(weights, node_classes_, handles_.moveable);
      v >= 0) {
    *error = "moveable handle vertex " + std::to_string(v) + " is skinned only by Fixed nodes at " +
             (precompute_->options().method == Method::kMultiScale
                  ? "scale " + std::to_string(active_graph_ + 1)
                  : std::string("the static graph")) +
             " and cannot move; use a finer lattice (a smaller --cell_width) or another --border";
    return false;
  }
  return true;
}

void HandleSetup::BuildEnergy() {
  const DeformerOptions& options = precompute_->options();
  const Mesh& mesh = precompute_->mesh();
  const DeformationGraph& graph = this->graph();
  const int n = graph.num_nodes();
  energy_ = DeformationEnergy();
  energy_.node_class = node_classes_;
  energy_.num_handle_groups = handles_.num_groups();
  num_coherence_terms_ = 0;
  num_position_terms_ = 0;

  if (options.energy == Energy::kArap) {
    // The mesh's ARAP energy over the free nodes, in place of Eq. 17.
    // The energy keeps the precompute (mesh, cotangent weights) and a pin on
    // the graph (its weights) for as long as any copy of it lives.
    struct Owner {
      std::shared_ptr<const Precompute> precompute;
      Precompute::GraphPin pin;
    };
    auto owner = std::make_shared<Owner>();
    owner->precompute = precompute_;
    owner->pin = precompute_->ConnectAndPin(active_graph_);
    SubspaceArapInput input;
    input.owner = std::move(owner);
    input.mesh = &mesh;
    input.cotangent = &precompute_->cotangent();
    input.graph = &graph;
    input.node_class = &node_classes_;
    input.handles = &handles_;
    input.still_vertices = &still_vertices_;
    input.length_unit = options.length_unit > 0.0 ? options.length_unit : precompute_->diagonal();
    input.num_threads = options.num_threads;
    energy_.families.push_back(
        std::make_shared<SubspaceArapTerms>(BuildSubspaceArap(input, options.arap)));
    if (options.add_energy_terms) options.add_energy_terms(graph, &energy_);
    return;
  }

  // E_rot over Totally and Half Free nodes.
  energy_.sqrt_rot = std::sqrt(options.w_rot);
  for (int j = 0; j < n; ++j)
    if (node_classes_[j] != NodeClass::kFixed) energy_.rot_nodes.push_back(j);

  // Residuals with a length unit are divided by the length unit.
  const double length_scale =
      1.0 / (options.length_unit > 0.0 ? options.length_unit : precompute_->diagonal());
  // E_coh over the directed edges of E (docs/method.md §5).
  const bool multiscale = options.method == Method::kMultiScale;
  auto in_edge_set = [&](int j, int k) {
    const NodeClass cj = node_classes_[j], ck = node_classes_[k];
    if (cj == NodeClass::kTotallyFree || ck == NodeClass::kTotallyFree) return true;
    return options.keep_left_out_terms && cj == NodeClass::kHalfFree;
  };
  for (const auto& [a, b] : graph.edges) {
    for (const auto& [j, k] : {std::make_pair(a, b), std::make_pair(b, a)}) {
      if (!in_edge_set(j, k)) continue;
      const double alpha = multiscale ? selection_.Alpha(j, k) : 1.0;
      energy_.coherence.push_back({j, k, graph.positions.col(k) - graph.positions.col(j),
                                   std::sqrt(options.w_coh * alpha) * length_scale});
      ++num_coherence_terms_;
    }
  }

  // E_con: each moveable handle vertex follows its group's target; the fixed
  // handles are held at rest (handle_group -1; static baselines: all;
  // multi-scale: see below).
  const double sqrt_con = std::sqrt(options.w_con) * length_scale;
  auto add_position = [&](int v, int handle_group) {
    DeformationEnergy::Position term;
    for (int slot = 0; slot < graph.weights.k(); ++slot) {
      const double weight = graph.weights.weight(slot, v);
      if (weight == 0.0) continue;
      const int j = graph.weights.node(slot, v);
      term.nodes.push_back(j);
      term.terms.push_back({weight, mesh.vertices.col(v) - graph.positions.col(j),
                            graph.positions.col(j)});
    }
    term.rest = mesh.vertices.col(v);
    term.handle_group = handle_group;
    term.sqrt_weight = sqrt_con;
    energy_.positions.push_back(std::move(term));
  };
  for (int i = 0; i < static_cast<int>(handles_.moveable.size()); ++i) {
    add_position(handles_.moveable[i], handles_.group_of(i));
  }
  num_position_terms_ = static_cast<int>(handles_.moveable.size());
  // A still component's fixed vertices stay at rest without a term (they are
  // not skinned); a term would only pull on a node shared with a moving
  // component. The multi-scale method needs a term only where a fixed vertex
  // has a non-Fixed node (a Half Free rotation or a Totally Free neighbour
  // would carry it along); elsewhere it stays at rest exactly.
  if (multiscale && options.hold_fixed_vertices) {
    for (int v : FixedVerticesWithAFreeNode()) add_position(v, -1);
  } else if (!multiscale) {
    for (int v : handles_.fixed) {
      if (!still_vertices_.empty() && still_vertices_[v]) continue;
      add_position(v, -1);
    }
  }

  // Rotations the terms above leave free to spin (a Half Free node with one
  // edge direction, or none) get a gauge term that picks one member of the
  // family of equal-energy minima (docs/decisions/gauge-freedom.md).
  energy_.gauge = GaugeTerms(energy_);
  // Terms beyond Eq. 17 (energies/energy_term.h; docs/extending.md).
  if (options.add_energy_terms) options.add_energy_terms(graph, &energy_);
}

}  // namespace msdeform
