// A family of terms of the deformation energy that brings its own structure
// (DeformationEnergy::families), and what every backend asks of it.
//
// Eq. 17's families (Rot, Coherence, Position, Gauge) and the user terms of
// energies/energy_term.h are plain data in DeformationEnergy: per-block cost
// functors that the Gauss-Newton assembly and Ceres both run. A TermFamily
// is a family whose residuals need more than that, such as the subspace ARAP
// energy's rotation clusters (solvers/subspace_arap_terms.h), whose
// auxiliary rotations no node block holds. It answers for itself:
//   - its value (Cost), for EvaluateEnergy and the tests;
//   - the frame solver it needs, if the shared Gauss-Newton cannot run it
//     (MakeSolver; solvers/frame_solver_factory.h asks each family);
//   - its Ceres residual blocks (AddToCeresProblem), as Eq. 17's terms have;
//   - the vertices it places exactly instead of skinning them.
// No backend or stage names a family: a new one is a class here and the line
// of the layout that adds it.

#ifndef MSDEFORM_SOLVERS_TERM_FAMILY_H_
#define MSDEFORM_SOLVERS_TERM_FAMILY_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/handles.h"

namespace ceres {
class Problem;
}  // namespace ceres

namespace msdeform {

class FrameSolver;
struct FrameSolverOptions;
struct DeformationEnergy;

// A family's Ceres residual blocks, refreshed before each solve or
// evaluation (the handle, auxiliary variables started at their best fit).
class CeresFamilyBlocks {
 public:
  virtual ~CeresFamilyBlocks() = default;
  virtual void SetFrame(const HandleTransforms& handles, const NodeTransforms& parameters) = 0;
};

class TermFamily {
 public:
  virtual ~TermFamily() = default;

  // Names the family in messages: "the subspace ARAP energy (--energy=arap)".
  virtual std::string name() const = 0;

  // 1/2 sum of squared residuals with the nodes at `transforms` and the
  // handle at `handle` (deformed_from_rest), auxiliary variables at their
  // optimum.
  virtual double Cost(const NodeTransforms& transforms, const HandleTransforms& handles) const = 0;

  // The frame solver that --backend=gauss_newton runs `energy` with when it
  // holds this family, or null when the shared Gauss-Newton solver
  // (solvers/gauss_newton_solver.h) can assemble it.
  virtual std::unique_ptr<FrameSolver> MakeSolver(const FrameSolverOptions& options) const = 0;

  // Adds the family's residual blocks to `problem` (the Ceres backend).
  // `parameters` holds every node's R_j and t_j (kept by the caller);
  // `ensure_blocks(j)` adds node j's two blocks with their class's
  // constancy. Null, with a one-line *error, when Ceres cannot run it with
  // the rest of `energy`.
  virtual std::unique_ptr<CeresFamilyBlocks> AddToCeresProblem(
      const DeformationEnergy& energy, NodeTransforms* parameters,
      const std::function<void(int)>& ensure_blocks, ceres::Problem* problem,
      std::string* error) const = 0;

  // Vertices the family places exactly instead of skinning them: the
  // handle's move with the handle's transform, the fixed ones stay at rest.
  virtual const std::vector<int>& exact_moveable() const = 0;
  virtual const std::vector<int>& exact_fixed() const = 0;
};

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_TERM_FAMILY_H_
