#include "msdeform/scales/session.h"

#include <chrono>
#include <cmath>
#include <utility>
#include <vector>

#include <glog/logging.h>

#include "msdeform/core/parallel.h"
#include "msdeform/core/skinning.h"
#include "msdeform/core/timing.h"
#include "msdeform/solvers/frame_solver_factory.h"

namespace msdeform {

Session::Session(std::shared_ptr<const HandleSetup> setup) : setup_(std::move(setup)) {}

std::unique_ptr<Session> Session::Create(std::shared_ptr<const HandleSetup> setup,
                                         std::string* error) {
  CHECK(setup != nullptr);
  std::unique_ptr<Session> session(new Session(std::move(setup)));
  const Precompute& pre = session->setup_->precompute();
  const DeformerOptions& options = pre.options();
  const auto start = std::chrono::steady_clock::now();
  session->transforms_ = NodeTransforms::Identity(session->setup_->graph().num_nodes());
  FrameSolverOptions solver_options;
  solver_options.backend = options.backend;
  solver_options.stopping = options.stopping;
  solver_options.gauss_newton = options.gauss_newton;
  solver_options.ceres = options.ceres;
  solver_options.num_threads = options.num_threads;
  session->solver_ = MakeFrameSolver(session->setup_->energy(), solver_options);
  if (!session->solver_->Setup(session->setup_->energy(), session->transforms_, error)) {
    *error = "setting up the " + std::string(SolverName(options.backend)) + " solve: " + *error;
    return nullptr;
  }
  session->previous_transforms_ = session->transforms_;
  session->setup_ms_ = MillisecondsSince(start);
  // At rest; the normals are copied when first skinned (deformed_normals).
  CopyColumns(pre.mesh().vertices, options.num_threads, &session->deformed_vertices_);
  return session;
}

bool Session::Drag(const HandleTransforms& deformed_from_rest, DragStats* stats,
                   std::string* error) {
  const auto frame_start = std::chrono::steady_clock::now();
  if (!deformed_from_rest.CheckFinite(error) ||
      !deformed_from_rest.Fits(setup_->energy().num_handle_groups, error)) {
    return false;
  }
  const Precompute& pre = setup_->precompute();
  DragStats local_stats;
  DragStats& frame = stats != nullptr ? *stats : local_stats;
  frame = DragStats();

  const NodeTransforms last_good = transforms_;
  // The initial guess; only the free blocks matter (the solver keeps the
  // others), and the Fixed nodes are the identity in every guess.
  switch (pre.options().initial_guess) {
    case InitialGuess::kRest:
      transforms_ = NodeTransforms::Identity(transforms_.num_nodes());
      break;
    case InitialGuess::kPrevious:
      break;
    case InitialGuess::kExtrapolated:
      // Safeguarded: the extrapolation only where it starts lower than the
      // previous solution (a path that turns, or a frame that did not
      // converge, can make it worse).
      if (frames_ >= 2) {
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
  handle_ = deformed_from_rest;
  ++frames_;

  const auto skin_start = std::chrono::steady_clock::now();
  SkinningOptions skinning;
  skinning.num_threads = pre.options().num_threads;
  SkinPositionsAndNormals(pre.mesh().vertices, pre.rest_normals(), setup_->graph(), transforms_,
                          setup_->skin_all() ? nullptr : &setup_->skinned_vertices(),
                          &deformed_vertices_, /*deformed_normals=*/nullptr, skinning);
  // The vertices a term family places exactly (the subspace ARAP energy's
  // exact constraints: constants outside the subspace).
  for (const std::shared_ptr<const TermFamily>& family : setup_->energy().families) {
    // One transform for every group needs no group lookup (a binary search
    // a vertex, every frame).
    const bool one = deformed_from_rest.size() == 1;
    for (int v : family->exact_moveable()) {
      const Eigen::Affine3d& transform =
          deformed_from_rest[one ? 0 : setup_->handles().GroupOfVertex(v)];
      deformed_vertices_.col(v) = transform * Eigen::Vector3d(pre.mesh().vertices.col(v));
    }
    for (int v : family->exact_fixed()) deformed_vertices_.col(v) = pre.mesh().vertices.col(v);
  }
  normals_stale_ = true;
  frame.skin_ms = MillisecondsSince(skin_start);
  frame.frame_ms = MillisecondsSince(frame_start);
  return true;
}

const Eigen::Matrix3Xd& Session::deformed_normals() const {
  // Skinned on first use; the lock makes concurrent const readers safe.
  std::lock_guard<std::mutex> lock(normals_mutex_);
  const Precompute& pre = setup_->precompute();
  if (normals_stale_) {
    // The vertices no free node skins keep their rest normals.
    if (deformed_normals_.cols() == 0) deformed_normals_ = pre.rest_normals();
    SkinningOptions skinning;
    skinning.num_threads = pre.options().num_threads;
    SkinPositionsAndNormals(pre.mesh().vertices, pre.rest_normals(), setup_->graph(),
                            transforms_, setup_->skin_all() ? nullptr : &setup_->skinned_vertices(),
                            /*deformed=*/nullptr, &deformed_normals_, skinning);
    // The exact constraints' vertices are not skinned positions: their
    // normals are the handle's transform of the rest normal (its inverse
    // transpose) and the rest normal.
    // One normal transform a group (one for all when the frame gave one).
    std::vector<Eigen::Matrix3d> normal_transforms;
    for (int g = 0; g < handle_.size(); ++g) {
      normal_transforms.push_back(handle_[g].linear().inverse().transpose());
    }
    const bool one = handle_.size() == 1;
    for (const std::shared_ptr<const TermFamily>& family : setup_->energy().families) {
      for (int v : family->exact_moveable()) {
        const Eigen::Matrix3d& normal_transform =
            normal_transforms[one ? 0 : setup_->handles().GroupOfVertex(v)];
        const Eigen::Vector3d n = normal_transform * Eigen::Vector3d(pre.rest_normals().col(v));
        const double length = n.norm();
        deformed_normals_.col(v) =
            length > 0.0 && std::isfinite(length) ? Eigen::Vector3d(n / length)
                                                  : Eigen::Vector3d::Zero();
      }
      for (int v : family->exact_fixed()) deformed_normals_.col(v) = pre.rest_normals().col(v);
    }
    normals_stale_ = false;
  }
  return deformed_normals_.cols() == 0 ? pre.rest_normals() : deformed_normals_;
}

}  // namespace msdeform
