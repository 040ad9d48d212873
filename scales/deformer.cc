#include "msdeform/scales/deformer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <mutex>
#include <utility>

#include <glog/logging.h>

#include "msdeform/core/skinning.h"
#include "msdeform/core/timing.h"

namespace msdeform {
namespace {

// Unique surface particles (= DG1 nodes) holding the given vertices.
std::vector<char> CellsHolding(const Lattice& lattice, const std::vector<int>& vertices) {
  std::vector<char> holds(lattice.num_surface_particles(), 0);
  for (int v : vertices) holds[lattice.particle_of_vertex(v)] = 1;
  return holds;
}

std::vector<int> Indices(const std::vector<char>& flags) {
  std::vector<int> indices;
  for (int i = 0; i < static_cast<int>(flags.size()); ++i)
    if (flags[i]) indices.push_back(i);
  return indices;
}

// Per vertex: whether its mesh component holds no moveable-handle vertex.
// Nothing moves such a component, so it keeps its rest pose. An isolated
// vertex (in no face) is a component of its own.
std::vector<char> StillVertices(const Components& components, const HandleLayout& layout) {
  if (components.count <= 1) return {};
  std::vector<char> moves(components.count, 0);
  for (int v : layout.moveable) moves[components.component_of_vertex[v]] = 1;
  std::vector<char> still(components.component_of_vertex.size());
  for (size_t v = 0; v < still.size(); ++v) still[v] = !moves[components.component_of_vertex[v]];
  return still;
}

// Per surface cell (DG1 node): whether it holds only still vertices
// (StillVertices); empty when the mesh has one component.
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

Deformer::Deformer() = default;
Deformer::~Deformer() = default;

bool Deformer::Init(const Mesh& mesh, const DeformerOptions& options, std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  // Bad options or a bad mesh leave the object as it was; a failure after
  // this point (the lattice, the graphs) leaves it empty: every call but Init
  // is refused until an Init succeeds.
  if (!options.Check(error)) return false;
  if (!ValidateMesh(mesh, error)) return false;
  ResetLayout();
  stage_ = Stage::kEmpty;
  graphs_.clear();
  rigidity_estimator_.reset();
  options_ = options;
  mesh_ = mesh;
  rest_normals_ = VertexNormals(mesh_);
  components_ = ConnectedComponents(mesh_);
  diagonal_ = BoundingBoxDiagonal(mesh_);
  if (!Lattice::Build(mesh_, options_.lattice, &lattice_, error)) return false;
  static_graph_ = -1;
  connected_coarse_.clear();
  switch (options_.method) {
    case Method::kMultiScale:
      // The coarse scales are connected when first used (ConnectedGraph).
      if (!BuildMultiScaleGraphs(mesh_, lattice_, GraphBuildOptions(), &graphs_, error,
                                 Connect::kFinestOnly)) {
        return false;
      }
      break;
    case Method::kStatic: {
      // DG1 and one graph of static_nodes nodes by the same edge collapse.
      if (!BuildCollapsedGraphs(mesh_, lattice_, GraphBuildOptions(),
                                {std::min(options_.static_nodes, lattice_.num_surface_particles())},
                                &graphs_, error)) {
        return false;
      }
      static_graph_ = 1;
      break;
    }
    case Method::kStaticDense:
      if (!BuildCollapsedGraphs(mesh_, lattice_, GraphBuildOptions(), {}, &graphs_, error)) {
        return false;
      }
      static_graph_ = 0;
      break;
  }
  if (options_.method == Method::kMultiScale) {
    rigidity_estimator_ = std::make_unique<RigidityEstimator>();
    if (!rigidity_estimator_->Init(lattice_, options_.rigidity, error)) return false;
  }
  ResetLayout();  // no layout yet, the new mesh at rest
  precompute_ms_ = MillisecondsSince(start);
  stage_ = Stage::kInitialised;
  return true;
}

GraphOptions Deformer::GraphBuildOptions() const {
  // One thread count for the whole Deformer unless the graphs ask for their own.
  GraphOptions graph = options_.graph;
  if (graph.num_threads == 0) graph.num_threads = options_.num_threads;
  return graph;
}

void Deformer::ResetLayout() {
  solver_.reset();
  layout_ = HandleLayout();
  still_vertices_.clear();
  rigidity_ = RigidityEstimate();
  selection_ = ScaleSelection();
  active_graph_ = std::max(static_graph_, 0);
  node_classes_.clear();
  transforms_ = NodeTransforms();
  previous_transforms_ = NodeTransforms();
  energy_ = DeformationEnergy();
  frames_since_layout_ = 0;
  skinned_vertices_.clear();
  skin_all_ = true;
  fixed_region_exact_ = true;
  num_position_terms_ = 0;
  num_coherence_terms_ = 0;
  deformed_vertices_ = mesh_.vertices;
  deformed_normals_ = rest_normals_;
  normals_stale_ = false;
  rigidity_ms_ = 0.0;
  setup_ms_ = 0.0;
  if (stage_ == Stage::kHandlesSet) stage_ = Stage::kInitialised;
}

bool Deformer::SetHandles(const HandleLayout& layout, std::string* error) {
  if (stage_ == Stage::kEmpty) {
    *error = "SetHandles before a successful Init";
    return false;
  }
  // An invalid layout leaves the current one in place; a failure after this
  // point leaves no layout (Drag is refused until a SetHandles succeeds).
  if (!ValidateHandles(layout, mesh_.num_vertices(), error)) return false;
  ResetLayout();
  if (!BuildLayout(layout, error)) {
    ResetLayout();
    return false;
  }
  stage_ = Stage::kHandlesSet;
  return true;
}

bool Deformer::BuildLayout(const HandleLayout& layout, std::string* error) {
  layout_ = layout;
  still_vertices_ = StillVertices(components_, layout_);
  const std::vector<char> still_cells = StillCells(lattice_, still_vertices_);
  if (options_.method == Method::kMultiScale) {
    const auto start = std::chrono::steady_clock::now();
    HandleNodes handles;
    handles.holds_fixed = CellsHolding(lattice_, layout_.fixed);
    handles.holds_moveable = CellsHolding(lattice_, layout_.moveable);
    handles.still = still_cells;
    for (int v : layout_.fixed) {
      if (still_vertices_.empty() || !still_vertices_[v]) handles.fixed_vertices.push_back(v);
    }
    handles.moveable_vertices = layout_.moveable;
    if (!rigidity_estimator_->Estimate(Indices(handles.holds_fixed),
                                       Indices(handles.holds_moveable), &rigidity_, error)) {
      return false;
    }
    rigidity_ms_ = MillisecondsSince(start);
    const auto selection_start = std::chrono::steady_clock::now();
    const std::vector<double> dg1_extent(
        rigidity_.relative_extent.data(),
        rigidity_.relative_extent.data() + lattice_.num_surface_particles());
    ScaleSelectionOptions selection_options = options_.selection;
    if (options_.fix_fixed_handle_nodes) selection_options.half_free = HalfFreeRule::kNone;
    if (!SelectScale(
            [this](int scale) -> const DeformationGraph& { return ConnectedGraph(scale - 1); },
            static_cast<int>(graphs_.size()), dg1_extent, handles,
            options_.graph.nodes_per_scale, diagonal_, selection_options, &selection_, error)) {
      return false;
    }
    active_graph_ = selection_.scale - 1;
    // Every class, the still components' Fixed nodes included, was decided
    // by SelectScale before the alpha weights (docs/method.md §4).
    node_classes_ = selection_.node_class;
    if (!BuildProblem(error)) return false;
    setup_ms_ = MillisecondsSince(selection_start);
  } else {
    const auto setup_start = std::chrono::steady_clock::now();
    active_graph_ = static_graph_;
    const std::vector<char> still_nodes = StillNodes(graphs_[active_graph_], still_cells);
    node_classes_.assign(graphs_[active_graph_].num_nodes(), NodeClass::kTotallyFree);
    for (size_t j = 0; j < still_nodes.size(); ++j) {
      if (still_nodes[j]) node_classes_[j] = NodeClass::kFixed;
    }
    if (!BuildProblem(error)) return false;
    setup_ms_ = MillisecondsSince(setup_start);
  }
  return true;
}

const DeformationGraph& Deformer::ConnectedGraph(int index) {
  CHECK(index >= 0 && index < static_cast<int>(graphs_.size())) << index;
  DeformationGraph& graph = graphs_[index];
  if (index == 0) return graph;  // DG1 is connected in Init
  const auto used = std::find(connected_coarse_.begin(), connected_coarse_.end(), index);
  if (used != connected_coarse_.end()) connected_coarse_.erase(used);
  connected_coarse_.push_back(index);
  if (!graph.is_connected()) ConnectGraph(mesh_, lattice_, GraphBuildOptions(), &graph);
  // Evict the least recently used, never the graph being solved on.
  for (size_t i = 0; static_cast<int>(connected_coarse_.size()) > options_.cached_scales &&
                     i < connected_coarse_.size();) {
    const int evict = connected_coarse_[i];
    if (evict == index || (solver_ != nullptr && evict == active_graph_)) {
      ++i;
      continue;
    }
    graphs_[evict].Disconnect();
    connected_coarse_.erase(connected_coarse_.begin() + i);
  }
  return graph;
}

int Deformer::num_variables() const {
  int variables = 0;
  for (NodeClass node_class : node_classes_) {
    variables += node_class == NodeClass::kTotallyFree ? 12
                 : node_class == NodeClass::kHalfFree  ? 9
                                                       : 0;
  }
  return variables;
}

bool Deformer::BuildProblem(std::string* error) {
  const DeformationGraph& graph = graphs_[active_graph_];
  transforms_ = NodeTransforms::Identity(graph.num_nodes());
  BuildEnergy();

  // Only vertices with a non-Fixed node of non-zero weight can move; the rest
  // stay at rest bit for bit (a Fixed node is the identity). So do the
  // vertices of still components, also where a coarse node spans two
  // components (merged when no edge was left) and moves with the other one.
  skinned_vertices_.clear();
  const SkinningWeights& weights = graph.weights;
  for (int v = 0; v < weights.num_vertices(); ++v) {
    if (!still_vertices_.empty() && still_vertices_[v]) continue;
    if (SkinnedByAFreeNode(weights, node_classes_, v)) skinned_vertices_.push_back(v);
  }
  skin_all_ = static_cast<int>(skinned_vertices_.size()) == weights.num_vertices();
  if (skin_all_) std::vector<int>().swap(skinned_vertices_);

  // Fixed vertices skinned only by Fixed nodes stay at rest exactly.
  fixed_region_exact_ = true;
  for (int v : layout_.fixed) {
    if (!still_vertices_.empty() && still_vertices_[v]) continue;
    if (SkinnedByAFreeNode(weights, node_classes_, v)) fixed_region_exact_ = false;
  }

  // A moveable-handle vertex that no non-Fixed node skins cannot follow the
  // handle: every frame would leave it at rest.
  if (const int v = FirstVertexSkinnedOnlyByFixedNodes(weights, node_classes_, layout_.moveable);
      v >= 0) {
    *error = "moveable handle vertex " + std::to_string(v) + " is skinned only by Fixed nodes at " +
             (options_.method == Method::kMultiScale
                  ? "scale " + std::to_string(active_graph_ + 1)
                  : std::string("the static graph")) +
             " and cannot move; use a finer lattice (a smaller --cell_width) or another --border";
    return false;
  }

  if (options_.backend == Solver::kGaussNewton) {
    solver_ = std::make_unique<GaussNewtonSolver>(options_.gauss_newton, options_.stopping);
  } else {
    solver_ = std::make_unique<CeresSolver>(options_.ceres, options_.stopping,
                                            options_.num_threads);
  }
  if (!solver_->Setup(energy_, transforms_, error)) {
    *error = "setting up the " + std::string(SolverName(options_.backend)) + " solve: " + *error;
    return false;
  }
  previous_transforms_ = transforms_;
  frames_since_layout_ = 0;
  return true;
}

void Deformer::BuildEnergy() {
  const DeformationGraph& graph = graphs_[active_graph_];
  const int n = graph.num_nodes();
  energy_ = DeformationEnergy();
  energy_.node_class = node_classes_;
  num_coherence_terms_ = 0;
  num_position_terms_ = 0;

  // E_rot over Totally and Half Free nodes.
  energy_.sqrt_rot = std::sqrt(options_.w_rot);
  for (int j = 0; j < n; ++j)
    if (node_classes_[j] != NodeClass::kFixed) energy_.rot_nodes.push_back(j);

  // Residuals with a length unit are divided by the length unit.
  const double length_scale =
      1.0 / (options_.length_unit > 0.0 ? options_.length_unit : diagonal_);
  // E_coh over the directed edges of E (docs/method.md §5).
  const bool multiscale = options_.method == Method::kMultiScale;
  auto in_edge_set = [&](int j, int k) {
    const NodeClass cj = node_classes_[j], ck = node_classes_[k];
    if (cj == NodeClass::kTotallyFree || ck == NodeClass::kTotallyFree) return true;
    return options_.keep_left_out_terms && cj == NodeClass::kHalfFree;
  };
  for (const auto& [a, b] : graph.edges) {
    for (const auto& [j, k] : {std::make_pair(a, b), std::make_pair(b, a)}) {
      if (!in_edge_set(j, k)) continue;
      const double alpha = multiscale ? selection_.Alpha(j, k) : 1.0;
      energy_.coherence.push_back({j, k, graph.positions.col(k) - graph.positions.col(j),
                                   std::sqrt(options_.w_coh * alpha) * length_scale});
      ++num_coherence_terms_;
    }
  }

  // E_con: the moveable handle follows its target; the fixed handles are held
  // at rest (static baselines: all; multi-scale: see below).
  const double sqrt_con = std::sqrt(options_.w_con) * length_scale;
  auto add_position = [&](int v, bool follows_handle) {
    DeformationEnergy::Position term;
    for (int slot = 0; slot < graph.weights.k(); ++slot) {
      const double weight = graph.weights.weight(slot, v);
      if (weight == 0.0) continue;
      const int j = graph.weights.node(slot, v);
      term.nodes.push_back(j);
      term.terms.push_back({weight, mesh_.vertices.col(v) - graph.positions.col(j),
                            graph.positions.col(j)});
    }
    term.rest = mesh_.vertices.col(v);
    term.follows_handle = follows_handle;
    term.sqrt_weight = sqrt_con;
    energy_.positions.push_back(std::move(term));
  };
  for (int v : layout_.moveable) add_position(v, true);
  num_position_terms_ = static_cast<int>(layout_.moveable.size());
  // A still component's fixed vertices stay at rest without a term (they are
  // not skinned); a term would only pull on a node shared with a moving
  // component. The multi-scale method needs a term only where a fixed vertex
  // has a non-Fixed node (a Half Free rotation or a Totally Free neighbour
  // would carry it along); elsewhere it stays at rest exactly.
  if (!multiscale || options_.hold_fixed_vertices) {
    for (int v : layout_.fixed) {
      if (!still_vertices_.empty() && still_vertices_[v]) continue;
      if (multiscale && !SkinnedByAFreeNode(graph.weights, node_classes_, v)) continue;
      add_position(v, false);
    }
  }

  // Rotations the terms above leave free to spin (a Half Free node with one
  // edge direction, or none) get a gauge term that picks one member of the
  // family of equal-energy minima (docs/decisions.md, "Gauge freedom").
  energy_.gauge = GaugeTerms(energy_);
}

bool Deformer::Drag(const Eigen::Affine3d& deformed_from_rest, DragStats* stats,
                    std::string* error) {
  if (stage_ != Stage::kHandlesSet) {
    *error = stage_ == Stage::kEmpty ? "Drag before a successful Init"
                                     : "Drag before a successful SetHandles";
    return false;
  }
  const auto frame_start = std::chrono::steady_clock::now();
  if (!deformed_from_rest.matrix().allFinite()) {
    *error = "the handle transform is not finite";
    return false;
  }
  DragStats local_stats;
  DragStats& frame = stats != nullptr ? *stats : local_stats;
  frame = DragStats();

  const NodeTransforms last_good = transforms_;
  // The initial guess; only the free blocks matter (the solver keeps the
  // others), and the Fixed nodes are the identity in every guess.
  switch (options_.initial_guess) {
    case InitialGuess::kRest:
      transforms_ = NodeTransforms::Identity(transforms_.num_nodes());
      break;
    case InitialGuess::kPrevious:
      break;
    case InitialGuess::kExtrapolated:
      // Safeguarded: the extrapolation only where it starts lower than the
      // previous solution (a path that turns, or a frame that did not
      // converge, can make it worse).
      if (frames_since_layout_ >= 2) {
        NodeTransforms extrapolated = last_good;
        extrapolated.rotations = 2.0 * last_good.rotations - previous_transforms_.rotations;
        extrapolated.translations =
            2.0 * last_good.translations - previous_transforms_.translations;
        if (solver_->Cost(deformed_from_rest, extrapolated) <
            solver_->Cost(deformed_from_rest, last_good)) {
          transforms_ = std::move(extrapolated);
        }
      }
      break;
  }
  const auto solve_start = std::chrono::steady_clock::now();
  SolveSummary summary = solver_->Solve(deformed_from_rest, &transforms_);
  frame.solve_ms = MillisecondsSince(solve_start);
  frame.iterations = summary.iterations;
  frame.factorizations = summary.factorizations;
  frame.initial_cost = summary.initial_cost;
  frame.final_cost = summary.final_cost;
  frame.converged = summary.converged;
  frame.trace = std::move(summary.trace);
  if (summary.failed || !std::isfinite(summary.final_cost) || !transforms_.rotations.allFinite() ||
      !transforms_.translations.allFinite()) {
    transforms_ = last_good;
    *error = "the solve failed (" + summary.message + "); kept the last good frame";
    return false;
  }
  previous_transforms_ = last_good;
  ++frames_since_layout_;

  const auto skin_start = std::chrono::steady_clock::now();
  SkinningOptions skinning;
  skinning.num_threads = options_.num_threads;
  SkinPositionsAndNormals(mesh_.vertices, rest_normals_, graphs_[active_graph_], transforms_,
                          skin_all_ ? nullptr : &skinned_vertices_, &deformed_vertices_,
                          /*deformed_normals=*/nullptr, skinning);
  normals_stale_ = true;
  frame.skin_ms = MillisecondsSince(skin_start);
  frame.frame_ms = MillisecondsSince(frame_start);
  return true;
}

const Eigen::Matrix3Xd& Deformer::deformed_normals() const {
  // Skinned on first use; the lock makes concurrent const readers safe.
  std::lock_guard<std::mutex> lock(*normals_mutex_);
  if (normals_stale_) {
    SkinningOptions skinning;
    skinning.num_threads = options_.num_threads;
    SkinPositionsAndNormals(mesh_.vertices, rest_normals_, graphs_[active_graph_], transforms_,
                            skin_all_ ? nullptr : &skinned_vertices_, /*deformed=*/nullptr,
                            &deformed_normals_, skinning);
    normals_stale_ = false;
  }
  return deformed_normals_;
}

bool DragAlong(Deformer* deformer, const std::vector<Eigen::Affine3d>& path,
               const DragAlongOptions& options, DragLog* log, std::string* error) {
  *log = DragLog();
  const int num_frames = static_cast<int>(path.size());
  for (int f = 0; f < num_frames; ++f) {
    DragStats stats;
    std::string frame_error;
    if (!deformer->Drag(path[f], &stats, &frame_error)) {
      log->failed_frames.push_back(f + 1);
      if (options.continue_after_failure && f + 1 < num_frames) continue;
      *error = "frame " + std::to_string(f + 1) + " of " + std::to_string(num_frames) +
               (options.continue_after_failure ? " (the result)" : "") + ": " + frame_error;
      return false;
    }
    if (options.on_frame) options.on_frame(f + 1, stats);
    log->frames.push_back(std::move(stats));
  }
  return true;
}

}  // namespace msdeform
