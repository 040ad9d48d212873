#include "msdeform/scales/deformer_options.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "msdeform/core/nearest_nodes.h"

namespace msdeform {

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

const char* SolverName(Solver solver) {
  switch (solver) {
    case Solver::kCeres:
      return "ceres";
    case Solver::kGaussNewton:
      return "gauss_newton";
  }
  return "unknown";
}

bool ParseSolver(const std::string& name, Solver* solver) {
  for (Solver s : {Solver::kCeres, Solver::kGaussNewton}) {
    if (name == SolverName(s)) {
      *solver = s;
      return true;
    }
  }
  return false;
}

const char* InitialGuessName(InitialGuess guess) {
  switch (guess) {
    case InitialGuess::kRest:
      return "rest";
    case InitialGuess::kPrevious:
      return "previous";
    case InitialGuess::kExtrapolated:
      return "extrapolated";
  }
  return "unknown";
}

bool ParseInitialGuess(const std::string& name, InitialGuess* guess) {
  for (InitialGuess g : {InitialGuess::kRest, InitialGuess::kPrevious, InitialGuess::kExtrapolated}) {
    if (name == InitialGuessName(g)) {
      *guess = g;
      return true;
    }
  }
  return false;
}

bool ParseMethodVariant(const std::string& rigidity, const std::string& half_free,
                        const std::string& border, DeformerOptions* options,
                        std::string* error) {
  if (!ParseRigidityModel(rigidity, &options->rigidity.model)) {
    *error = "--rigidity=" + rigidity + ": expected harmonic or paper";
    return false;
  }
  if (!ParseHalfFreeRule(half_free, &options->selection.half_free)) {
    *error = "--half_free=" + half_free +
             ": expected next_to_totally_free, every_fixed_handle_node or none";
    return false;
  }
  if (!ParseBorderRule(border, &options->selection.border)) {
    *error = "--border=" + border + ": expected fixed, half_free or totally_free";
    return false;
  }
  return true;
}

std::vector<std::pair<std::string, std::string>> DescribeOptions(const DeformerOptions& options) {
  std::vector<std::pair<std::string, std::string>> fields;
  auto number = [](double value) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.17g", value);
    return std::string(text);
  };
  auto add = [&](const char* name, const std::string& value) { fields.emplace_back(name, value); };
  auto flag = [](bool value) { return std::string(value ? "true" : "false"); };
  const LatticeOptions& lattice = options.lattice;
  const GraphOptions& graph = options.graph;
  const RigidityOptions& rigidity = options.rigidity;
  const ScaleSelectionOptions& selection = options.selection;
  add("method", MethodName(options.method));
  add("lattice.cell_width", number(lattice.cell_width));
  add("lattice.cells_per_diagonal", number(lattice.cells_per_diagonal));
  add("lattice.max_grid_cells", std::to_string(lattice.max_grid_cells));
  add("lattice.split_cells", flag(lattice.split_cells));
  add("lattice.piece_margin", number(lattice.piece_margin));
  add("graph.k", std::to_string(graph.k));
  add("graph.nodes_per_scale", std::to_string(graph.nodes_per_scale));
  add("graph.seed", std::to_string(graph.seed));
  add("graph.extra_rings", std::to_string(graph.extra_rings));
  add("graph.num_threads", std::to_string(graph.num_threads));
  add("rigidity.model", RigidityModelName(rigidity.model));
  add("rigidity.num_steps", std::to_string(rigidity.num_steps));
  add("rigidity.time_step", number(rigidity.time_step));
  add("rigidity.external_stiffness", number(rigidity.external_stiffness));
  add("rigidity.initial_speed", number(rigidity.initial_speed));
  add("rigidity.damping", number(rigidity.damping));
  add("rigidity.region_half_width", std::to_string(rigidity.region_half_width));
  add("rigidity.seed", std::to_string(rigidity.seed));
  add("rigidity.region_summation",
      rigidity.region_summation == RegionSummation::kBox ? "box" : "per_region");
  add("rigidity.max_rotation_iterations", std::to_string(rigidity.max_rotation_iterations));
  add("rigidity.rotation_tolerance", number(rigidity.rotation_tolerance));
  add("selection.threshold_floor", number(selection.threshold_floor));
  add("selection.fixed_extent_cutoff", number(selection.fixed_extent_cutoff));
  add("selection.member_extent", selection.member_extent == MemberExtent::kMax ? "max" : "mean");
  add("selection.local_detail_distance", number(selection.local_detail_distance));
  add("selection.omega_max", number(selection.omega_max));
  add("selection.alpha_all_one", flag(selection.alpha_all_one));
  add("selection.half_free", HalfFreeRuleName(selection.half_free));
  add("selection.border", BorderRuleName(selection.border));
  add("selection.pin_fixed_region", flag(selection.pin_fixed_region));
  add("static_nodes", std::to_string(options.static_nodes));
  add("w_rot", number(options.w_rot));
  add("w_coh", number(options.w_coh));
  add("w_con", number(options.w_con));
  add("length_unit", number(options.length_unit));
  add("hold_fixed_vertices", flag(options.hold_fixed_vertices));
  add("keep_left_out_terms", flag(options.keep_left_out_terms));
  add("fix_fixed_handle_nodes", flag(options.fix_fixed_handle_nodes));
  add("num_threads", std::to_string(options.num_threads));
  add("cached_scales", std::to_string(options.cached_scales));
  add("backend", SolverName(options.backend));
  add("stopping.max_iterations", std::to_string(options.stopping.max_iterations));
  add("stopping.function_tolerance", number(options.stopping.function_tolerance));
  add("stopping.gradient_tolerance", number(options.stopping.gradient_tolerance));
  add("stopping.parameter_tolerance", number(options.stopping.parameter_tolerance));
  add("initial_guess", InitialGuessName(options.initial_guess));
  const GaussNewtonOptions& gn = options.gauss_newton;
  add("gauss_newton.linear_solver", LinearSolverName(gn.linear_solver));
  add("gauss_newton.cholesky", CholeskyName(gn.cholesky));
  add("gauss_newton.factorization", FactorizationName(gn.factorization));
  add("gauss_newton.refactor_ratio", number(gn.refactor_ratio));
  add("gauss_newton.damping", DampingName(gn.damping));
  add("gauss_newton.min_damping", number(gn.min_damping));
  add("gauss_newton.initial_damping", number(gn.initial_damping));
  add("gauss_newton.forcing_term", number(gn.forcing_term));
  add("gauss_newton.max_cg_iterations", std::to_string(gn.max_cg_iterations));
  add("ceres.trust_region", TrustRegionName(options.ceres.trust_region));
  add("ceres.linear_solver", CeresLinearSolverName(options.ceres.linear_solver));
  add("ceres.sparse_library", SparseLibraryName(options.ceres.sparse_library));
  add("ceres.group_position_terms", flag(options.ceres.group_position_terms));
  return fields;
}

DeformerOptions PaperProcedure(DeformerOptions options) {
  options.rigidity.model = RigidityModel::kShapeMatching;
  options.selection.half_free = HalfFreeRule::kEveryFixedHandleNode;
  options.selection.border = BorderRule::kFixed;
  options.selection.pin_fixed_region = false;
  options.lattice.split_cells = false;
  options.hold_fixed_vertices = false;
  return options;
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
  if (!(length_unit >= 0.0) || !std::isfinite(length_unit)) {
    *error = "length_unit must be a finite number >= 0 (0: the bounding-box diagonal)";
    return false;
  }
  for (const auto& [name, weight] :
       {std::pair<const char*, double>{"w_rot", w_rot}, {"w_coh", w_coh}, {"w_con", w_con}}) {
    if (!(weight >= 0.0) || !std::isfinite(weight)) {
      *error = std::string(name) + " (energy weight of Eq. 17) must be finite and >= 0";
      return false;
    }
  }
  if (!(w_con > 0.0)) {
    *error = "w_con must be > 0 (the handle would not follow its target)";
    return false;
  }
  if (num_threads < 1 || num_threads > kMaxThreads) {
    *error = "num_threads must be in 1.." + std::to_string(kMaxThreads);
    return false;
  }
  if (cached_scales < 1) {
    *error = "cached_scales must be >= 1";
    return false;
  }
  return stopping.Check(error) && gauss_newton.Check(error) && ceres.Check(error);
}
}  // namespace msdeform
