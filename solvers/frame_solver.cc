#include "msdeform/solvers/frame_solver.h"

#include <cmath>
#include <utility>

namespace msdeform {

bool StoppingRule::Check(std::string* error) const {
  if (max_iterations < 1) {
    *error = "max_iterations must be >= 1 (a frame with no iteration leaves the handle behind)";
    return false;
  }
  const std::pair<const char*, double> tolerances[] = {
      {"function_tolerance", function_tolerance},
      {"gradient_tolerance", gradient_tolerance},
      {"parameter_tolerance", parameter_tolerance}};
  for (const auto& [name, value] : tolerances) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
      *error = std::string(name) + " must be a finite number >= 0";
      return false;
    }
  }
  return true;
}

}  // namespace msdeform
