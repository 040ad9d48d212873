#include "msdeform/methods/full_arap.h"

#include <algorithm>
#include <chrono>

#include "msdeform/core/timing.h"
#include "msdeform/methods/method_options.h"

namespace msdeform {

bool FullArapMethod::DoPrecompute(const Mesh& mesh, const MethodOptions& options,
                                  std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  if (!options.full_arap.Check(error) || !ValidateMesh(mesh, error)) return false;
  mesh_ = mesh;
  options_ = options.full_arap;
  options_.num_threads = options.deformer.num_threads;
  deformed_ = mesh_.vertices;
  precompute_ms_ = MillisecondsSince(start);
  return true;
}

bool FullArapMethod::DoSetHandles(const HandleLayout& layout, std::string* error) {
  if (!ValidateHandles(layout, mesh_.num_vertices(), error)) return false;
  constrained_.clear();
  follows_handle_.clear();
  // Merge the two sorted, disjoint lists.
  size_t f = 0, m = 0;
  while (f < layout.fixed.size() || m < layout.moveable.size()) {
    const bool take_moveable =
        f == layout.fixed.size() ||
        (m < layout.moveable.size() && layout.moveable[m] < layout.fixed[f]);
    constrained_.push_back(take_moveable ? layout.moveable[m++] : layout.fixed[f++]);
    follows_handle_.push_back(take_moveable ? 1 : 0);
  }
  deformed_ = mesh_.vertices;
  summary_ = LocalGlobalArapSummary();
  return arap_.Setup(mesh_, constrained_, options_, error);
}

bool FullArapMethod::DoDrag(const Eigen::Affine3d& deformed_from_rest, MethodStats* stats,
                            std::string* error) {
  const auto frame_start = std::chrono::steady_clock::now();
  Eigen::Matrix3Xd targets(3, constrained_.size());
  for (size_t j = 0; j < constrained_.size(); ++j) {
    const Eigen::Vector3d rest = mesh_.vertices.col(constrained_[j]);
    targets.col(j) = follows_handle_[j] ? Eigen::Vector3d(deformed_from_rest * rest) : rest;
  }
  summary_ = arap_.Solve(targets, &deformed_);
  *stats = MethodStats();
  stats->solve_ms = MillisecondsSince(frame_start);
  stats->iterations = summary_.iterations;
  stats->factorizations = 0;
  stats->initial_cost = summary_.initial_energy;
  stats->final_cost = summary_.final_energy;
  stats->converged = summary_.converged;
  stats->frame_ms = MillisecondsSince(frame_start);
  return true;
}

}  // namespace msdeform
