#include "scales/deformer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include <glog/logging.h>

#include "core/skinning.h"
#include "energies/coherence_cost.h"
#include "energies/position_cost.h"
#include "energies/rot_cost.h"

namespace msdeform {
namespace {

double MillisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// Unique surface particles (= DG1 nodes) holding the given vertices.
std::vector<char> CellsHolding(const Lattice& lattice, const std::vector<int>& vertices) {
  std::vector<char> holds(lattice.num_surface_cells(), 0);
  for (int v : vertices) holds[lattice.cell_of_vertex(v)] = 1;
  return holds;
}

std::vector<int> Indices(const std::vector<char>& flags) {
  std::vector<int> indices;
  for (int i = 0; i < static_cast<int>(flags.size()); ++i)
    if (flags[i]) indices.push_back(i);
  return indices;
}

}  // namespace

const char* MethodName(Method method) {
  switch (method) {
    case Method::kMultiScale:
      return "multiscale";
    case Method::kStatic:
      return "static";
    case Method::kStaticDense:
      return "static_dense";
  }
  return "unknown";
}

bool ParseMethod(const std::string& name, Method* method) {
  for (Method m : {Method::kMultiScale, Method::kStatic, Method::kStaticDense}) {
    if (name == MethodName(m)) {
      *method = m;
      return true;
    }
  }
  return false;
}

DeformerOptions::DeformerOptions() {
  solver.minimizer_type = ceres::TRUST_REGION;
  solver.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.max_num_iterations = 20;
  solver.function_tolerance = 1e-8;
  solver.gradient_tolerance = 1e-10;
  solver.parameter_tolerance = 1e-10;
  solver.logging_type = ceres::SILENT;
  solver.minimizer_progress_to_stdout = false;
}

bool DeformerOptions::Check(std::string* error) const {
  if (!lattice.Check(error) || !graph.Check(error) || !rigidity.Check(error) ||
      !selection.Check(error)) {
    return false;
  }
  if (static_nodes < 1) {
    *error = "static_nodes must be >= 1";
    return false;
  }
  for (double weight : {w_rot, w_coh, w_con}) {
    if (!(weight >= 0.0) || !std::isfinite(weight)) {
      *error = "energy weights must be finite and >= 0";
      return false;
    }
  }
  if (num_threads < 1) {
    *error = "num_threads must be >= 1";
    return false;
  }
  std::string solver_error;
  if (!solver.IsValid(&solver_error)) {
    *error = "invalid Ceres solver options: " + solver_error;
    return false;
  }
  return true;
}

Deformer::Deformer() = default;
Deformer::~Deformer() = default;

bool Deformer::Init(const Mesh& mesh, const DeformerOptions& options, std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  if (!options.Check(error)) return false;
  if (!ValidateMesh(mesh, error)) return false;
  options_ = options;
  mesh_ = mesh;
  rest_normals_ = VertexNormals(mesh_);
  diagonal_ = BoundingBoxDiagonal(mesh_);
  if (!Lattice::Build(mesh_, options_.lattice, &lattice_, error)) return false;
  static_graph_ = -1;
  switch (options_.method) {
    case Method::kMultiScale:
      if (!BuildMultiScaleGraphs(mesh_, lattice_, options_.graph, &graphs_, error)) return false;
      break;
    case Method::kStatic: {
      // DG1 and one graph of static_nodes nodes by the same edge collapse.
      if (!BuildCollapsedGraphs(mesh_, lattice_, options_.graph,
                                {std::min(options_.static_nodes, lattice_.num_surface_cells())},
                                &graphs_, error)) {
        return false;
      }
      static_graph_ = 1;
      break;
    }
    case Method::kStaticDense:
      if (!BuildCollapsedGraphs(mesh_, lattice_, options_.graph, {}, &graphs_, error)) return false;
      static_graph_ = 0;
      break;
  }
  if (options_.method == Method::kMultiScale) {
    rigidity_estimator_ = std::make_unique<RigidityEstimator>();
    if (!rigidity_estimator_->Init(lattice_, options_.rigidity, error)) return false;
  }
  deformed_vertices_ = mesh_.vertices;
  deformed_normals_ = rest_normals_;
  precompute_ms_ = MillisecondsSince(start);
  return true;
}

bool Deformer::SetHandles(const HandleLayout& layout, std::string* error) {
  CHECK(!graphs_.empty()) << "Init first";
  if (!ValidateHandles(layout, mesh_.num_vertices(), error)) return false;
  layout_ = layout;
  rigidity_ = RigidityEstimate();
  selection_ = ScaleSelection();
  rigidity_ms_ = 0.0;

  if (options_.method == Method::kMultiScale) {
    const auto start = std::chrono::steady_clock::now();
    HandleNodes handles;
    handles.holds_fixed = CellsHolding(lattice_, layout_.fixed);
    handles.holds_moveable = CellsHolding(lattice_, layout_.moveable);
    if (!rigidity_estimator_->Estimate(Indices(handles.holds_fixed),
                                       Indices(handles.holds_moveable), &rigidity_, error)) {
      return false;
    }
    rigidity_ms_ = MillisecondsSince(start);
    const auto setup_start = std::chrono::steady_clock::now();
    const std::vector<double> dg1_extent(
        rigidity_.relative_extent.data(),
        rigidity_.relative_extent.data() + lattice_.num_surface_cells());
    if (!SelectScale(graphs_, dg1_extent, handles, diagonal_, options_.selection, &selection_,
                     error)) {
      return false;
    }
    active_graph_ = selection_.scale - 1;
    node_classes_ = selection_.node_class;
    if (options_.fix_fixed_handle_nodes) {
      for (NodeClass& node_class : node_classes_)
        if (node_class == NodeClass::kHalfFree) node_class = NodeClass::kFixed;
    }
    BuildProblem();
    setup_ms_ = MillisecondsSince(setup_start);
  } else {
    const auto setup_start = std::chrono::steady_clock::now();
    active_graph_ = static_graph_;
    node_classes_.assign(graphs_[active_graph_].num_nodes(), NodeClass::kTotallyFree);
    BuildProblem();
    setup_ms_ = MillisecondsSince(setup_start);
  }
  deformed_vertices_ = mesh_.vertices;
  deformed_normals_ = rest_normals_;
  return true;
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

void Deformer::BuildProblem() {
  const DeformationGraph& graph = graphs_[active_graph_];
  const int n = graph.num_nodes();
  transforms_ = NodeTransforms::Identity(n);
  position_costs_.clear();
  num_coherence_terms_ = 0;
  ceres::Problem::Options problem_options;
  problem_ = std::make_unique<ceres::Problem>(problem_options);
  ceres::Problem& problem = *problem_;

  // Lengths in lattice cells: residuals with a length unit are divided by w.
  const double length_scale = 1.0 / lattice_.cell_width();
  auto rotation = [&](int j) { return transforms_.rotations.col(j).data(); };
  auto translation = [&](int j) { return transforms_.translations.col(j).data(); };

  // Parameter blocks: the class of a node decides which of its blocks vary.
  std::vector<char> added(n, 0);
  auto ensure_blocks = [&](int j) {
    if (added[j]) return;
    added[j] = 1;
    problem.AddParameterBlock(rotation(j), 9);
    problem.AddParameterBlock(translation(j), 3);
    if (node_classes_[j] != NodeClass::kTotallyFree) problem.SetParameterBlockConstant(translation(j));
    if (node_classes_[j] == NodeClass::kFixed) problem.SetParameterBlockConstant(rotation(j));
  };

  // E_rot over Totally and Half Free nodes.
  const double sqrt_rot = std::sqrt(options_.w_rot);
  for (int j = 0; j < n; ++j) {
    if (node_classes_[j] == NodeClass::kFixed) continue;
    ensure_blocks(j);
    problem.AddResidualBlock(new RotCostAnalytic(sqrt_rot), nullptr, rotation(j));
  }

  // E_coh over the directed edges of E (METHOD.md §5).
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
      ensure_blocks(j);
      ensure_blocks(k);
      problem.AddResidualBlock(
          new CoherenceCostAnalytic(graph.positions.col(j), graph.positions.col(k),
                                    std::sqrt(options_.w_coh * alpha) * length_scale),
          nullptr, rotation(j), translation(j), translation(k));
      ++num_coherence_terms_;
    }
  }

  // E_con: the moveable handle follows its target; the static baselines also
  // hold the fixed handles at rest.
  const double sqrt_con = std::sqrt(options_.w_con) * length_scale;
  auto add_position = [&](int v) {
    std::vector<SkinningTerm> terms;
    std::vector<double*> blocks;
    for (int slot = 0; slot < graph.weights.k; ++slot) {
      const double weight = graph.weights.weights(slot, v);
      if (weight == 0.0) continue;
      const int j = graph.weights.nodes(slot, v);
      terms.push_back({weight, mesh_.vertices.col(v) - graph.positions.col(j),
                       graph.positions.col(j)});
      ensure_blocks(j);
      blocks.push_back(rotation(j));
      blocks.push_back(translation(j));
    }
    auto* cost = new PositionCostAnalytic(std::move(terms), mesh_.vertices.col(v), sqrt_con);
    problem.AddResidualBlock(cost, nullptr, blocks);
    return cost;
  };
  for (int v : layout_.moveable) position_costs_.push_back({add_position(v), mesh_.vertices.col(v)});
  if (!multiscale) {
    for (int v : layout_.fixed) add_position(v);
  }
}

bool Deformer::Drag(const Eigen::Affine3d& deformed_from_rest, DragStats* stats,
                    std::string* error) {
  CHECK(problem_ != nullptr) << "SetHandles first";
  if (!deformed_from_rest.matrix().allFinite()) {
    *error = "the handle transform is not finite";
    return false;
  }
  DragStats local_stats;
  DragStats& frame = stats != nullptr ? *stats : local_stats;
  for (PositionTerm& term : position_costs_) term.cost->set_target(deformed_from_rest * term.rest);

  const NodeTransforms last_good = transforms_;
  ceres::Solver::Options solver_options = options_.solver;
  solver_options.num_threads = options_.num_threads;
  ceres::Solver::Summary summary;
  const auto solve_start = std::chrono::steady_clock::now();
  ceres::Solve(solver_options, problem_.get(), &summary);
  frame.solve_ms = MillisecondsSince(solve_start);
  frame.iterations = static_cast<int>(summary.iterations.size()) - 1;
  frame.initial_cost = summary.initial_cost;
  frame.final_cost = summary.final_cost;
  frame.converged = summary.termination_type == ceres::CONVERGENCE;
  if (summary.termination_type == ceres::FAILURE ||
      !transforms_.rotations.allFinite() || !transforms_.translations.allFinite()) {
    transforms_ = last_good;
    *error = "the solve failed (" + summary.message + "); kept the last good frame";
    return false;
  }

  const auto skin_start = std::chrono::steady_clock::now();
  const DeformationGraph& graph = graphs_[active_graph_];
  SkinningOptions skinning;
  skinning.num_threads = options_.num_threads;
  SkinPositions(mesh_.vertices, graph, transforms_, &deformed_vertices_, skinning);
  SkinNormals(rest_normals_, graph, transforms_, &deformed_normals_, skinning);
  frame.skin_ms = MillisecondsSince(skin_start);
  return true;
}

}  // namespace msdeform
