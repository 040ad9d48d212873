#include "msdeform/methods/method.h"

#include <string>
#include <utility>
#include <vector>

namespace msdeform {

EditingMethod::~EditingMethod() = default;

bool EditingMethod::Precompute(const Mesh& mesh, const MethodOptions& options,
                               std::string* error) {
  stage_ = Stage::kEmpty;
  if (!DoPrecompute(mesh, options, error)) return false;
  stage_ = Stage::kPrecomputed;
  return true;
}

bool EditingMethod::SetHandles(const HandleLayout& layout, std::string* error) {
  if (stage_ == Stage::kEmpty) {
    *error = name_ + ": SetHandles before a successful Precompute";
    return false;
  }
  stage_ = Stage::kPrecomputed;
  if (!DoSetHandles(layout, error)) return false;
  num_handle_groups_ = layout.num_groups();
  num_moveable_ = static_cast<int>(layout.moveable.size());
  stage_ = Stage::kHandlesSet;
  return true;
}

bool EditingMethod::Drag(const HandleTransforms& deformed_from_rest, MethodStats* stats,
                         std::string* error) {
  if (stage_ != Stage::kHandlesSet) {
    *error = name_ + ": Drag before a successful SetHandles";
    return false;
  }
  if (!deformed_from_rest.CheckFinite(error) ||
      !deformed_from_rest.Fits(num_handle_groups_, error)) {
    return false;
  }
  MethodStats local;
  return DoDrag(deformed_from_rest, stats != nullptr ? stats : &local, error);
}

bool EditingMethod::DragTo(const Eigen::Matrix3Xd& targets, MethodStats* stats,
                           std::string* error) {
  if (stage_ != Stage::kHandlesSet) {
    *error = name_ + ": DragTo before a successful SetHandles";
    return false;
  }
  if (!takes_vertex_targets()) {
    *error = name_ + " moves the handle by a transform a handle group, not by vertex targets";
    return false;
  }
  if (targets.cols() != num_moveable_) {
    *error = std::to_string(targets.cols()) + " targets for " + std::to_string(num_moveable_) +
             " moveable vertices";
    return false;
  }
  if (!targets.allFinite()) {
    *error = "the targets are not finite";
    return false;
  }
  MethodStats local;
  return DoDragTo(targets, stats != nullptr ? stats : &local, error);
}

bool EditingMethod::DoDragTo(const Eigen::Matrix3Xd&, MethodStats*, std::string* error) {
  *error = name_ + ": DoDragTo is not implemented";
  return false;
}

bool DragAlong(EditingMethod* method, const std::vector<HandleTransforms>& path,
               const DragAlongOptions& options, DragLog* log, std::string* error) {
  *log = DragLog();
  const int num_frames = static_cast<int>(path.size());
  for (int f = 0; f < num_frames; ++f) {
    MethodStats stats;
    std::string frame_error;
    if (!method->Drag(path[f], &stats, &frame_error)) {
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

bool DragAlong(EditingMethod* method, const std::vector<Eigen::Affine3d>& path,
               const DragAlongOptions& options, DragLog* log, std::string* error) {
  return DragAlong(method, std::vector<HandleTransforms>(path.begin(), path.end()), options, log,
                   error);
}

}  // namespace msdeform
