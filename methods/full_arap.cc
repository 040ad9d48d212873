#include "msdeform/methods/full_arap.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <utility>

#include "msdeform/core/timing.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/methods/registry.h"

namespace msdeform {

const OptionTable<LocalGlobalArapOptions>& FullArapOptionTable() {
  static const OptionTable<LocalGlobalArapOptions> table = [] {
    using O = LocalGlobalArapOptions;
    OptionTable<O> t;
    t.Double("relative_tolerance", &O::relative_tolerance,
             "full_arap: a frame stops when an iteration lowers the ARAP energy by at most this "
             "fraction of it.")
        .Range(0, 1, "a number in [0, 1]")
        .Alias("full_arap_tolerance")
        .Flag("method");
    t.Int("max_iterations", &O::max_iterations,
          "full_arap: local/global iterations per frame at most.")
        .Range(1, 10000000, "an integer in 1..10000000")
        .Alias("full_arap_max_iterations")
        .Flag("method");
    t.Int("anderson_window", &O::anderson_window,
          "full_arap: Anderson acceleration's window (past iterates combined); 0 runs plain "
          "local/global.")
        .Range(0, 50, "an integer in 0..50")
        .Alias("full_arap_anderson_window")
        .Flag("method");
    t.Enum("factorization", &O::factorization, LocalGlobalArapFactorizationNames(),
           "full_arap: the Laplacian's sparse Cholesky: simplicial (Eigen's SimplicialLLT, AMD "
           "ordering), cholmod (CHOLMOD's supernodal LLT, METIS where AMD fills too much) or "
           "auto (cholmod from 500,000 free vertices).")
        .Alias("full_arap_factorization")
        .Flag("method");
    return t;
  }();
  return table;
}

bool FullArapMethod::DoPrecompute(const Mesh& mesh, const MethodOptions& options,
                                  std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  const LocalGlobalArapOptions& own = options.own.Get<LocalGlobalArapOptions>("full_arap");
  if (!FullArapOptionTable().CheckRanges(own, error) || !own.Check(error)) {
    *error = "full_arap." + *error;
    return false;
  }
  if (!ValidateMesh(mesh, error)) return false;
  mesh_ = mesh;
  options_ = own;
  options_.num_threads = options.deformer.num_threads;
  deformed_ = mesh_.vertices;
  precompute_ms_ = MillisecondsSince(start);
  return true;
}

bool FullArapMethod::DoSetHandles(const HandleLayout& layout, std::string* error) {
  if (!ValidateHandles(layout, mesh_.num_vertices(), error)) return false;
  ConstrainedVertices(layout, &constrained_, &handle_group_);
  deformed_ = mesh_.vertices;
  summary_ = LocalGlobalArapSummary();
  return arap_.Setup(mesh_, constrained_, options_, error);
}

bool FullArapMethod::DoDrag(const HandleTransforms& deformed_from_rest, MethodStats* stats,
                            std::string*) {
  Solve(ConstrainedTargets(mesh_.vertices, constrained_, handle_group_, deformed_from_rest),
        stats);
  return true;
}

bool FullArapMethod::DoDragTo(const Eigen::Matrix3Xd& targets, MethodStats* stats,
                              std::string*) {
  Solve(ConstrainedTargets(mesh_.vertices, constrained_, handle_group_, targets), stats);
  return true;
}

void FullArapMethod::Solve(const Eigen::Matrix3Xd& targets, MethodStats* stats) {
  const auto frame_start = std::chrono::steady_clock::now();
  summary_ = arap_.Solve(targets, &deformed_);
  *stats = MethodStats();
  stats->solve_ms = MillisecondsSince(frame_start);
  stats->iterations = summary_.iterations;
  stats->factorizations = 0;
  stats->initial_cost = summary_.initial_energy;
  stats->final_cost = summary_.final_energy;
  stats->converged = summary_.converged;
  stats->frame_ms = MillisecondsSince(frame_start);
}

MSDEFORM_REGISTER_METHODS(full_arap, registry) {
  MethodDescriptor full_arap;
  full_arap.name = "full_arap";
  full_arap.energy = "arap";
  full_arap.options = "full_arap";
  full_arap.deformer_rows = {"num_threads"};
  full_arap.add_option_rows = [](OptionTable<MethodOptions>* t) {
    EmbedOwnOptions("full_arap", FullArapOptionTable(), t);
  };
  full_arap.create = [] { return std::make_unique<FullArapMethod>(); };
  registry->push_back(std::move(full_arap));
}

}  // namespace msdeform
