#include "msdeform/methods/method.h"

#include <utility>

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
  stage_ = Stage::kHandlesSet;
  return true;
}

bool EditingMethod::Drag(const Eigen::Affine3d& deformed_from_rest, MethodStats* stats,
                         std::string* error) {
  if (stage_ != Stage::kHandlesSet) {
    *error = name_ + ": Drag before a successful SetHandles";
    return false;
  }
  MethodStats local;
  return DoDrag(deformed_from_rest, stats != nullptr ? stats : &local, error);
}

}  // namespace msdeform
