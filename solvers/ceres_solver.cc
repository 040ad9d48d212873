#include "msdeform/solvers/ceres_solver.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <utility>

#include <ceres/problem.h>
#include <ceres/solver.h>
#include <ceres/version.h>
#include <glog/logging.h>

#include "msdeform/energies/coherence_cost.h"
#include "msdeform/energies/energy_term.h"
#include "msdeform/energies/gauge_cost.h"
#include "msdeform/energies/position_cost.h"
#include "msdeform/energies/position_group_cost.h"
#include "msdeform/energies/rot_cost.h"
#include "msdeform/solvers/term_family.h"

namespace msdeform {
namespace {

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string Upper(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return text;
}

}  // namespace

std::string TrustRegionName(ceres::TrustRegionStrategyType type) {
  return Lower(ceres::TrustRegionStrategyTypeToString(type));
}

bool ParseTrustRegion(const std::string& name, ceres::TrustRegionStrategyType* type) {
  return ceres::StringToTrustRegionStrategyType(Upper(name), type);
}

std::string CeresLinearSolverName(ceres::LinearSolverType type) {
  return Lower(ceres::LinearSolverTypeToString(type));
}

bool ParseCeresLinearSolver(const std::string& name, ceres::LinearSolverType* type) {
  ceres::LinearSolverType parsed;
  if (!ceres::StringToLinearSolverType(Upper(name), &parsed)) return false;
  if (parsed != ceres::SPARSE_NORMAL_CHOLESKY && parsed != ceres::CGNR) return false;
  *type = parsed;
  return true;
}

std::string SparseLibraryName(ceres::SparseLinearAlgebraLibraryType type) {
  return Lower(ceres::SparseLinearAlgebraLibraryTypeToString(type));
}

bool ParseSparseLibrary(const std::string& name, ceres::SparseLinearAlgebraLibraryType* type) {
  ceres::SparseLinearAlgebraLibraryType parsed;
  if (!ceres::StringToSparseLinearAlgebraLibraryType(Upper(name), &parsed)) return false;
  const auto available = CeresSparseLibraries();
  if (std::find(available.begin(), available.end(), parsed) == available.end()) return false;
  *type = parsed;
  return true;
}

const EnumNames<CeresOptions::Jacobians>& JacobiansNames() {
  static const EnumNames<CeresOptions::Jacobians> names{
      {CeresOptions::Jacobians::kAnalytic, "analytic"},
      {CeresOptions::Jacobians::kAutodiff, "autodiff"}};
  return names;
}

const char* JacobiansName(CeresOptions::Jacobians jacobians) {
  return JacobiansNames().Name(jacobians);
}

bool ParseJacobians(const std::string& name, CeresOptions::Jacobians* jacobians) {
  return JacobiansNames().Parse(name, jacobians);
}

std::string CeresVersion() { return CERES_VERSION_STRING; }

std::vector<ceres::SparseLinearAlgebraLibraryType> CeresSparseLibraries() {
  std::vector<ceres::SparseLinearAlgebraLibraryType> libraries;
  for (auto type : {ceres::EIGEN_SPARSE, ceres::SUITE_SPARSE, ceres::CX_SPARSE}) {
    if (ceres::IsSparseLinearAlgebraLibraryTypeAvailable(type)) libraries.push_back(type);
  }
  return libraries;
}

namespace {

// The Ceres options of a solve. Check() asks Ceres's own validation of them, so
// that every pair Ceres refuses (DOGLEG needs an exact factorisation: not
// CGNR) is refused by Check with one line, before a Deformer is set up.
ceres::Solver::Options CeresSolverOptions(const CeresOptions& options,
                                          const StoppingRule& stopping, int num_threads) {
  ceres::Solver::Options solver;
  solver.minimizer_type = ceres::TRUST_REGION;
  solver.trust_region_strategy_type = options.trust_region;
  solver.dogleg_type = ceres::TRADITIONAL_DOGLEG;
  solver.linear_solver_type = options.linear_solver;
  solver.preconditioner_type = ceres::JACOBI;
  solver.sparse_linear_algebra_library_type = options.sparse_library;
  solver.max_num_iterations = stopping.max_iterations;
  solver.function_tolerance = stopping.function_tolerance;
  solver.gradient_tolerance = stopping.gradient_tolerance;
  solver.parameter_tolerance = stopping.parameter_tolerance;
  solver.num_threads = num_threads;
  solver.logging_type = ceres::SILENT;
  solver.minimizer_progress_to_stdout = false;
  return solver;
}

}  // namespace

bool CeresOptions::Check(std::string* error) const {
  if (trust_region != ceres::LEVENBERG_MARQUARDT && trust_region != ceres::DOGLEG) {
    *error = "Ceres trust_region must be levenberg_marquardt or dogleg";
    return false;
  }
  if (linear_solver != ceres::SPARSE_NORMAL_CHOLESKY && linear_solver != ceres::CGNR) {
    *error = "Ceres linear_solver must be sparse_normal_cholesky or cgnr";
    return false;
  }
  if (!ceres::IsSparseLinearAlgebraLibraryTypeAvailable(sparse_library)) {
    *error = "Ceres sparse library " + SparseLibraryName(sparse_library) +
             " is not in this build of Ceres";
    return false;
  }
  std::string invalid;
  if (!CeresSolverOptions(*this, StoppingRule(), 1).IsValid(&invalid)) {
    *error = "Ceres trust_region " + TrustRegionName(trust_region) + " with linear_solver " +
             CeresLinearSolverName(linear_solver) + " is refused by Ceres: " + invalid;
    return false;
  }
  return true;
}

struct CeresSolver::Impl {
  ceres::Solver::Options solver;
  NodeTransforms parameters;  // the storage of every parameter block
  std::unique_ptr<ceres::Problem> problem;
  struct PositionTerm {
    PositionCostAnalytic* cost;  // owned by problem (analytic), or
    PositionCost* functor;       // owned by its autodiff cost function
    Eigen::Vector3d rest;
    int handle_group;
  };
  std::vector<PositionTerm> position_costs;  // ungrouped
  // Grouped (the cost owned by problem) and the handle group each follows.
  std::vector<std::pair<PositionGroupCost*, int>> position_groups;
  // The blocks of the families with their own structure (solvers/term_family.h).
  std::vector<std::unique_ptr<CeresFamilyBlocks>> families;
};

CeresSolver::CeresSolver(const CeresOptions& options, const StoppingRule& stopping,
                         int num_threads)
    : options_(options), stopping_(stopping), num_threads_(std::max(1, num_threads)) {}
CeresSolver::~CeresSolver() = default;

bool CeresSolver::Setup(const DeformationEnergy& energy, const NodeTransforms& transforms,
                        std::string* error) {
  if (!options_.Check(error) || !stopping_.Check(error)) return false;
  CHECK_EQ(static_cast<int>(energy.node_class.size()), transforms.num_nodes());
  impl_ = std::make_unique<Impl>();
  Impl& impl = *impl_;
  ceres::Solver::Options& solver = impl.solver;
  solver = CeresSolverOptions(options_, stopping_, num_threads_);
  std::string invalid;
  if (!solver.IsValid(&invalid)) {
    *error = "invalid Ceres solver options: " + invalid;
    return false;
  }
  num_variables_ = energy.num_variables();

  impl.parameters = transforms;
  const int n = transforms.num_nodes();
  const std::vector<NodeClass>& node_class = energy.node_class;
  impl.problem = std::make_unique<ceres::Problem>(ceres::Problem::Options());
  ceres::Problem& problem = *impl.problem;
  auto rotation = [&](int j) { return impl.parameters.rotations.col(j).data(); };
  auto translation = [&](int j) { return impl.parameters.translations.col(j).data(); };

  // Parameter blocks: the class of a node decides which of its blocks vary.
  std::vector<char> added(n, 0);
  auto ensure_blocks = [&](int j) {
    if (added[j]) return;
    added[j] = 1;
    problem.AddParameterBlock(rotation(j), 9);
    problem.AddParameterBlock(translation(j), 3);
    if (node_class[j] != NodeClass::kTotallyFree) problem.SetParameterBlockConstant(translation(j));
    if (node_class[j] == NodeClass::kFixed) problem.SetParameterBlockConstant(rotation(j));
  };

  for (const std::shared_ptr<const TermFamily>& family : energy.families) {
    impl.families.push_back(
        family->AddToCeresProblem(energy, &impl.parameters, ensure_blocks, &problem, error));
    if (impl.families.back() == nullptr) return false;
  }
  const bool autodiff = options_.jacobians == CeresOptions::Jacobians::kAutodiff;
  for (int j : energy.rot_nodes) {
    ensure_blocks(j);
    problem.AddResidualBlock(
        autodiff ? RotCost::Create(energy.sqrt_rot) : new RotCostAnalytic(energy.sqrt_rot),
        nullptr, rotation(j));
  }
  for (const DeformationEnergy::Gauge& term : energy.gauge) {
    ensure_blocks(term.node);
    problem.AddResidualBlock(autodiff ? GaugeCost::Create(term.axis, term.sqrt_weight)
                                      : new GaugeCostAnalytic(term.axis, term.sqrt_weight),
                             nullptr, rotation(term.node));
  }
  for (const DeformationEnergy::Coherence& term : energy.coherence) {
    ensure_blocks(term.j);
    ensure_blocks(term.k);
    // g_j = 0 and g_k = edge: the functor only uses their difference.
    const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    problem.AddResidualBlock(
        autodiff ? CoherenceCost::Create(origin, term.edge, term.sqrt_weight)
                 : new CoherenceCostAnalytic(origin, term.edge, term.sqrt_weight),
        nullptr, rotation(term.j), translation(term.j), translation(term.k));
  }
  for (const EnergyTerm& term : energy.terms) {
    if (!CheckEnergyTerm(term, n, error)) return false;
    std::vector<double*> blocks;
    for (const TermBlock& block : term.blocks) {
      ensure_blocks(block.node);
      blocks.push_back(block.kind == TermBlock::Kind::kRotation ? rotation(block.node)
                                                                : translation(block.node));
    }
    problem.AddResidualBlock(term.NewCostFunction(autodiff), nullptr, blocks);
  }

  if (!options_.group_position_terms || autodiff) {
    for (const DeformationEnergy::Position& term : energy.positions) {
      std::vector<double*> blocks;
      for (int j : term.nodes) {
        ensure_blocks(j);
        blocks.push_back(rotation(j));
        blocks.push_back(translation(j));
      }
      PositionCost* functor = nullptr;
      PositionCostAnalytic* analytic = nullptr;
      ceres::CostFunction* cost;
      if (autodiff) {
        cost = PositionCost::Create(term.terms, term.rest, term.sqrt_weight, &functor);
      } else {
        cost = analytic = new PositionCostAnalytic(term.terms, term.rest, term.sqrt_weight);
      }
      problem.AddResidualBlock(cost, nullptr, blocks);
      if (term.follows_handle()) {
        impl.position_costs.push_back({analytic, functor, term.rest, term.handle_group});
      }
    }
    return true;
  }
  // Handle vertices with the same nodes (and the same handle group, or held
  // at rest) become
  // one PositionGroupCost; a vertex's terms are put in node-id order.
  std::map<std::vector<int>, int> group_of_key;
  struct Group {
    std::vector<int> nodes;
    int handle_group;
    double sqrt_weight;
    std::vector<std::vector<SkinningTerm>> terms;
    std::vector<Eigen::Vector3d> rest;
  };
  std::vector<Group> groups;
  for (const DeformationEnergy::Position& term : energy.positions) {
    std::vector<int> order(term.nodes.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return term.nodes[a] < term.nodes[b]; });
    std::vector<int> key = {term.handle_group};
    std::vector<SkinningTerm> terms;
    for (int i : order) {
      key.push_back(term.nodes[i]);
      terms.push_back(term.terms[i]);
    }
    auto [it, inserted] = group_of_key.emplace(key, static_cast<int>(groups.size()));
    if (inserted) {
      groups.push_back({std::vector<int>(key.begin() + 1, key.end()), term.handle_group,
                        term.sqrt_weight, {}, {}});
    }
    CHECK_EQ(groups[it->second].sqrt_weight, term.sqrt_weight);
    groups[it->second].terms.push_back(std::move(terms));
    groups[it->second].rest.push_back(term.rest);
  }
  for (const Group& group : groups) {
    std::vector<double*> blocks;
    for (int j : group.nodes) {
      ensure_blocks(j);
      blocks.push_back(rotation(j));
      blocks.push_back(translation(j));
    }
    auto* cost =
        new PositionGroupCost(group.terms, group.rest, group.handle_group >= 0, group.sqrt_weight);
    problem.AddResidualBlock(cost, nullptr, blocks);
    impl.position_groups.push_back({cost, std::max(0, group.handle_group)});
  }
  return true;
}

// Moves the handle targets to `handles`; returns what the grouped position
// blocks leave out of Ceres's cost.
double CeresSolver::SetHandles(const HandleTransforms& handles) {
  Impl& impl = *impl_;
  for (Impl::PositionTerm& term : impl.position_costs) {
    const Eigen::Vector3d target = handles[term.handle_group] * term.rest;
    if (term.cost != nullptr) term.cost->set_target(target);
    if (term.functor != nullptr) term.functor->target = target;
  }
  double constant_cost = 0.0;
  for (const auto& [group, handle_group] : impl.position_groups) {
    group->SetHandle(handles[handle_group]);
    constant_cost += group->ConstantCost();
  }
  return constant_cost;
}

double CeresSolver::Cost(const HandleTransforms& handles, const NodeTransforms& transforms) {
  CHECK(impl_ != nullptr) << "Setup first";
  Impl& impl = *impl_;
  CHECK_EQ(transforms.num_nodes(), impl.parameters.num_nodes());
  impl.parameters.rotations = transforms.rotations;
  impl.parameters.translations = transforms.translations;
  const double constant_cost = SetHandles(handles);
  for (auto& family : impl.families) family->SetFrame(handles, impl.parameters);
  double cost = 0.0;
  impl.problem->Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, nullptr);
  return cost + constant_cost;
}

SolveSummary CeresSolver::Solve(const HandleTransforms& handles, NodeTransforms* transforms) {
  CHECK(impl_ != nullptr) << "Setup first";
  Impl& impl = *impl_;
  CHECK_EQ(transforms->num_nodes(), impl.parameters.num_nodes());
  impl.parameters.rotations = transforms->rotations;
  impl.parameters.translations = transforms->translations;
  const double constant_cost = SetHandles(handles);
  for (auto& family : impl.families) family->SetFrame(handles, impl.parameters);
  ceres::Solver::Summary ceres_summary;
  ceres::Solve(impl.solver, impl.problem.get(), &ceres_summary);
  VLOG(1) << ceres_summary.FullReport();  // msdeform --verbose --v=1

  SolveSummary summary;
  summary.iterations = std::max(0, static_cast<int>(ceres_summary.iterations.size()) - 1);
  summary.factorizations = ceres_summary.num_linear_solves;
  summary.initial_cost = ceres_summary.initial_cost + constant_cost;
  summary.final_cost = ceres_summary.final_cost + constant_cost;
  summary.converged = ceres_summary.termination_type == ceres::CONVERGENCE;
  summary.failed = ceres_summary.termination_type == ceres::FAILURE;
  summary.message = ceres_summary.message;
  // An unsuccessful iteration reports the rejected candidate's cost; the
  // solver stays where it was, so the trace repeats the last accepted cost
  // (as the Gauss-Newton backend's does).
  double current = ceres_summary.initial_cost;
  for (const ceres::IterationSummary& iteration : ceres_summary.iterations) {
    if (iteration.iteration == 0 || iteration.step_is_successful) current = iteration.cost;
    summary.trace.push_back({1e3 * iteration.cumulative_time_in_seconds, current + constant_cost});
  }
  if (!summary.trace.empty()) summary.trace.front().ms = 0.0;
  transforms->rotations = impl.parameters.rotations;
  transforms->translations = impl.parameters.translations;
  return summary;
}

const OptionTable<CeresOptions>& CeresOptionTable() {
  static const OptionTable<CeresOptions>& table =
      MakeOptionTable<CeresOptions>([](auto& t) { DeclareCeresOptionRows(t); });
  return table;
}

}  // namespace msdeform
