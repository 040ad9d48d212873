#include "msdeform/methods/polish.h"

#include <chrono>
#include <cmath>
#include <utility>

#include <glog/logging.h>

#include "msdeform/core/timing.h"

namespace msdeform {
namespace {

LocalGlobalArapOptions SolverOptions(const PolishOptions& options) {
  LocalGlobalArapOptions solver;
  solver.relative_tolerance = options.relative_tolerance;
  // The iteration budget is the stop callback's (Polisher::Polish), so a new
  // budget needs no new factorisation.
  solver.max_iterations = 1000000000;
  solver.anderson_window = options.anderson_window;
  solver.num_threads = options.num_threads;
  return solver;
}

}  // namespace

bool PolishOptions::Check(std::string* error) const {
  if (max_iterations < 0) {
    *error = "max_iterations must be >= 0";
    return false;
  }
  if (!(time_budget_ms >= 0.0) || !std::isfinite(time_budget_ms)) {
    *error = "time_budget_ms must be finite and >= 0 (0: no limit)";
    return false;
  }
  if (!(relative_tolerance >= 0.0) || !(relative_tolerance <= 1.0)) {
    *error = "relative_tolerance must be in [0, 1]";
    return false;
  }
  if (anderson_window < 0 || anderson_window > 50) {
    *error = "anderson_window must be in 0..50";
    return false;
  }
  if (num_threads < 1) {
    *error = "num_threads must be >= 1";
    return false;
  }
  return true;
}

bool Polisher::Setup(const Mesh& rest, const HandleLayout& layout, const PolishOptions& options,
                     std::string* error) {
  ready_ = false;
  if (!options.Check(error)) return false;
  if (!ValidateHandles(layout, rest.num_vertices(), error)) return false;
  ConstrainedVertices(layout, &constrained_, &handle_group_);
  rest_ = rest;
  options_ = options;
  if (!arap_.Setup(rest_, constrained_, SolverOptions(options_), error)) return false;
  ready_ = true;
  return true;
}

bool Polisher::SetOptions(const PolishOptions& options, std::string* error) {
  if (!ready_) {
    *error = "polish: no handle layout set up";
    return false;
  }
  if (!options.Check(error)) return false;
  const bool refactor = options.relative_tolerance != options_.relative_tolerance ||
                        options.anderson_window != options_.anderson_window ||
                        options.num_threads != options_.num_threads;
  if (refactor) {
    ready_ = false;
    if (!arap_.Setup(rest_, constrained_, SolverOptions(options), error)) return false;
    ready_ = true;
  }
  options_ = options;
  return true;
}

Eigen::Matrix3Xd Polisher::Targets(const HandleTransforms& deformed_from_rest) const {
  return ConstrainedTargets(rest_.vertices, constrained_, handle_group_, deformed_from_rest);
}

PolishReport Polisher::Polish(const HandleTransforms& deformed_from_rest,
                              Eigen::Matrix3Xd* vertices, const std::atomic<bool>* cancel) {
  CHECK(ready_) << "Polish before a successful Setup";
  return PolishConstrained(Targets(deformed_from_rest), vertices, cancel);
}

PolishReport Polisher::PolishTo(const Eigen::Matrix3Xd& moveable_targets,
                                Eigen::Matrix3Xd* vertices, const std::atomic<bool>* cancel) {
  CHECK(ready_) << "Polish before a successful Setup";
  CHECK_EQ(moveable_targets.cols(),
           std::count_if(handle_group_.begin(), handle_group_.end(), [](int g) { return g >= 0; }));
  return PolishConstrained(
      ConstrainedTargets(rest_.vertices, constrained_, handle_group_, moveable_targets), vertices,
      cancel);
}

PolishReport Polisher::PolishConstrained(const Eigen::Matrix3Xd& targets,
                                         Eigen::Matrix3Xd* vertices,
                                         const std::atomic<bool>* cancel) {
  CHECK_EQ(vertices->cols(), rest_.vertices.cols());
  const auto start = std::chrono::steady_clock::now();
  PolishReport report;
  // The energy of the frame as the method left it: Solve's initial energy
  // when the constrained vertices are already at their targets (the methods
  // that hold them exactly), else one more local step.
  bool at_targets = true;
  for (size_t j = 0; j < constrained_.size() && at_targets; ++j) {
    at_targets = vertices->col(constrained_[j]) == targets.col(j);
  }
  if (!at_targets) report.energy_before = arap_.Energy(*vertices);

  Eigen::Matrix3Xd polished = *vertices;
  const int max_iterations = options_.max_iterations;
  const double budget_ms = options_.time_budget_ms;
  const auto stop = [&](int iterations, double ms) {
    if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) return true;
    if (iterations >= max_iterations) return true;
    // Start no iteration the mean one so far says would end past the budget.
    if (budget_ms > 0.0) {
      const double per_iteration = iterations > 0 ? ms / iterations : 0.0;
      if (ms + per_iteration > budget_ms) return true;
    }
    return false;
  };
  const LocalGlobalArapSummary summary = arap_.Solve(targets, &polished, stop);
  if (at_targets) report.energy_before = summary.initial_energy;
  report.energy_start = summary.initial_energy;
  report.iterations = summary.iterations;
  report.converged = summary.converged;
  report.cancelled = cancel != nullptr && cancel->load(std::memory_order_relaxed);
  if (report.cancelled) {
    report.energy_start = report.energy_after = report.energy_before;
  } else {
    report.energy_after = summary.final_energy;
    *vertices = std::move(polished);
  }
  report.ms = MillisecondsSince(start);
  return report;
}

bool PolishOnce(const Mesh& rest, const HandleLayout& layout,
                const HandleTransforms& deformed_from_rest, const PolishOptions& options,
                Eigen::Matrix3Xd* vertices, PolishReport* report, std::string* error) {
  Polisher polisher;
  if (!polisher.Setup(rest, layout, options, error)) return false;
  *report = polisher.Polish(deformed_from_rest, vertices);
  report->setup_ms = polisher.setup_ms();
  return true;
}

}  // namespace msdeform
