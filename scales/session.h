// Stage 3 of 3 of an edit (scales/precompute.h; docs/extending.md, "The stages of an edit"): the
// frames of one set-up. The backend's solver (a Ceres problem, or the
// Gauss-Newton system with its symbolic factorisation) set up once, the node
// transforms warm-started from frame to frame, and the skinned mesh.

#ifndef MSDEFORM_SCALES_SESSION_H_
#define MSDEFORM_SCALES_SESSION_H_

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include "msdeform/core/deformation_graph.h"
#include "msdeform/scales/handle_setup.h"
#include "msdeform/solvers/frame_solver.h"

namespace msdeform {

// Per-frame numbers.
struct DragStats {
  double frame_ms = 0.0;  // the whole Drag
  double solve_ms = 0.0;
  double skin_ms = 0.0;  // positions; normals are skinned when asked for
  int iterations = 0;
  int factorizations = 0;
  double initial_cost = 0.0;  // at the initial guess
  double final_cost = 0.0;
  bool converged = false;
  // The solve's convergence trace (solvers/frame_solver.h).
  std::vector<TracePoint> trace;
};

class Session {
 public:
  // A session of `setup` (not null), at the rest pose. nullptr with a
  // message when the backend cannot be set up.
  static std::unique_ptr<Session> Create(std::shared_ptr<const HandleSetup> setup,
                                         std::string* error);

  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // Moves each handle group g to deformed_from_rest[g] * (its rest
  // positions), solves warm-started from the previous frame and skins the mesh (only
  // HandleSetup::skinned_vertices; the others stay at rest). A failed solve keeps
  // the last good transforms and returns false with a message.
  bool Drag(const HandleTransforms& deformed_from_rest, DragStats* stats, std::string* error);

  const HandleSetup& setup() const { return *setup_; }
  const NodeTransforms& transforms() const { return transforms_; }
  const Eigen::Matrix3Xd& deformed_vertices() const { return deformed_vertices_; }
  // The deformed unit normals (Eq. 10) of the last Drag, skinned on the first
  // call after it. Safe from several threads at once (const readers); not
  // during a Drag.
  const Eigen::Matrix3Xd& deformed_normals() const;
  // Milliseconds Create spent setting up the solver (the identity transforms
  // and the backend's FrameSolver::Setup).
  double setup_ms() const { return setup_ms_; }

 private:
  explicit Session(std::shared_ptr<const HandleSetup> setup);

  std::shared_ptr<const HandleSetup> setup_;
  std::unique_ptr<FrameSolver> solver_;
  NodeTransforms transforms_;
  NodeTransforms previous_transforms_;  // the frame before, for kExtrapolated
  HandleTransforms handle_;  // the last Drag's
  int frames_ = 0;
  Eigen::Matrix3Xd deformed_vertices_;
  mutable Eigen::Matrix3Xd deformed_normals_;  // empty until first skinned
  mutable bool normals_stale_ = false;  // a Drag moved the positions since
  mutable std::mutex normals_mutex_;
  double setup_ms_ = 0.0;
};

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_SESSION_H_
