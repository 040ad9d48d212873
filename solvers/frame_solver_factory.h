// The one place that chooses a layout's frame solver, from what the energy's
// terms need rather than from the energy's name: a term family that needs
// its own solver (solvers/term_family.h) gets it under --backend=gauss_newton,
// anything else runs on the shared Gauss-Newton solver
// (solvers/gauss_newton_solver.h) or on Ceres (solvers/ceres_solver.h).
//
//   std::unique_ptr<FrameSolver> solver = MakeFrameSolver(energy, options);
//   solver->Setup(energy, transforms, &error);

#ifndef MSDEFORM_SOLVERS_FRAME_SOLVER_FACTORY_H_
#define MSDEFORM_SOLVERS_FRAME_SOLVER_FACTORY_H_

#include <memory>

#include "msdeform/solvers/ceres_solver.h"
#include "msdeform/solvers/deformation_energy.h"
#include "msdeform/solvers/frame_solver.h"
#include "msdeform/solvers/gauss_newton_solver.h"

namespace msdeform {

// The backend that minimises a layout's energy each frame: the Gauss-Newton
// solver (or the solver a term family asks for), or Ceres, the reference.
enum class Solver { kCeres, kGaussNewton };

// What every frame solver may be built with (DeformerOptions holds the same
// fields; scales/session.cc copies them).
struct FrameSolverOptions {
  Solver backend = Solver::kGaussNewton;
  StoppingRule stopping;
  GaussNewtonOptions gauss_newton;
  CeresOptions ceres;
  int num_threads = 1;  // Gauss-Newton's assembly, Ceres's evaluation
};

// Never null. The first family of `energy` (in order) that asks for its own
// solver gets it when the backend is Gauss-Newton.
std::unique_ptr<FrameSolver> MakeFrameSolver(const DeformationEnergy& energy,
                                             const FrameSolverOptions& options);

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_FRAME_SOLVER_FACTORY_H_
