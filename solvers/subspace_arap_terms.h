// The subspace ARAP energy (--energy=arap; solvers/subspace_arap.h) as a term
// family of DeformationEnergy (solvers/term_family.h): its rotation clusters
// are auxiliary variables, so it brings its own solvers (local/global or
// Gauss-Newton on nodes and rotations, solvers/arap_solver.h) and its own
// Ceres blocks (solvers/ceres_solver_arap.h), and it holds the handle and
// fixed vertices exactly (ArapConstraints::kExact).

#ifndef MSDEFORM_SOLVERS_SUBSPACE_ARAP_TERMS_H_
#define MSDEFORM_SOLVERS_SUBSPACE_ARAP_TERMS_H_

#include <memory>
#include <string>
#include <vector>

#include "msdeform/solvers/deformation_energy.h"
#include "msdeform/solvers/subspace_arap.h"
#include "msdeform/solvers/term_family.h"

namespace msdeform {

class SubspaceArapTerms : public TermFamily {
 public:
  explicit SubspaceArapTerms(std::shared_ptr<const SubspaceArap> arap);

  std::string name() const override;
  double Cost(const NodeTransforms& transforms, const HandleTransforms& handles) const override;
  // arap.solver's solver (ArapOptions::solver).
  std::unique_ptr<FrameSolver> MakeSolver(const FrameSolverOptions& options) const override;
  // Refused unless the energy holds this family alone.
  std::unique_ptr<CeresFamilyBlocks> AddToCeresProblem(
      const DeformationEnergy& energy, NodeTransforms* parameters,
      const std::function<void(int)>& ensure_blocks, ceres::Problem* problem,
      std::string* error) const override;
  const std::vector<int>& exact_moveable() const override { return arap_->exact_moveable(); }
  const std::vector<int>& exact_fixed() const override { return arap_->exact_fixed(); }

  const std::shared_ptr<const SubspaceArap>& arap() const { return arap_; }

 private:
  std::shared_ptr<const SubspaceArap> arap_;
};

// The subspace ARAP energy `energy` holds, or null.
std::shared_ptr<const SubspaceArap> FindSubspaceArap(const DeformationEnergy& energy);

// Whether `energy` is a subspace ARAP energy with no other term, which is
// what the ARAP solvers run; false with a one-line message naming `solver`
// ("the local/global solver") otherwise.
bool IsArapEnergyAlone(const DeformationEnergy& energy, const std::string& solver,
                       std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_SOLVERS_SUBSPACE_ARAP_TERMS_H_
