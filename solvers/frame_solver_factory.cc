#include "msdeform/solvers/frame_solver_factory.h"

#include "msdeform/solvers/term_family.h"

namespace msdeform {

std::unique_ptr<FrameSolver> MakeFrameSolver(const DeformationEnergy& energy,
                                             const FrameSolverOptions& options) {
  if (options.backend == Solver::kCeres) {
    return std::make_unique<CeresSolver>(options.ceres, options.stopping, options.num_threads);
  }
  for (const std::shared_ptr<const TermFamily>& family : energy.families) {
    if (std::unique_ptr<FrameSolver> solver = family->MakeSolver(options)) return solver;
  }
  GaussNewtonThreads threads;
  threads.num_threads = options.num_threads;
  return std::make_unique<GaussNewtonSolver>(options.gauss_newton, options.stopping, threads);
}

}  // namespace msdeform
