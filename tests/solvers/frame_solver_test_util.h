// Shared by the tests that run a frame solver to the minimum itself
// (frame_solver_test.cc, gauss_newton_solver_test.cc,
// tests/examples/energy_terms/volume_term_test.cc).

#ifndef MSDEFORM_TESTS_SCALES_FRAME_SOLVER_TEST_UTIL_H_
#define MSDEFORM_TESTS_SCALES_FRAME_SOLVER_TEST_UTIL_H_

#include "msdeform/solvers/frame_solver.h"

namespace msdeform {

// Stopping rules near double precision, so that a solve stops at the minimum
// and not at a tolerance: function and parameter tolerance `tolerance`,
// gradient tolerance `gradient_tolerance`. `max_iterations` is the caller's
// cap for its problem, chosen not to bind.
constexpr StoppingRule TightStopping(int max_iterations, double tolerance = 1e-15,
                                     double gradient_tolerance = 1e-13) {
  StoppingRule stopping;
  stopping.max_iterations = max_iterations;
  stopping.function_tolerance = tolerance;
  stopping.gradient_tolerance = gradient_tolerance;
  stopping.parameter_tolerance = tolerance;
  return stopping;
}

}  // namespace msdeform

#endif  // MSDEFORM_TESTS_SCALES_FRAME_SOLVER_TEST_UTIL_H_
