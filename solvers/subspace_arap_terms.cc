#include "msdeform/solvers/subspace_arap_terms.h"

#include <utility>

#include "msdeform/solvers/arap_solver.h"
#include "msdeform/solvers/ceres_solver_arap.h"
#include "msdeform/solvers/frame_solver_factory.h"

namespace msdeform {
namespace {

class CeresArapBlocks : public CeresFamilyBlocks {
 public:
  CeresArapBlocks(std::shared_ptr<const SubspaceArap> arap, NodeTransforms* parameters,
                  const std::function<void(int)>& ensure_blocks, ceres::Problem* problem)
      : problem_(std::move(arap), parameters, ensure_blocks, problem) {}
  void SetFrame(const HandleTransforms& handles, const NodeTransforms& parameters) override {
    problem_.SetFrame(handles, parameters);
  }

 private:
  CeresArapProblem problem_;
};

}  // namespace

SubspaceArapTerms::SubspaceArapTerms(std::shared_ptr<const SubspaceArap> arap)
    : arap_(std::move(arap)) {}

std::string SubspaceArapTerms::name() const { return "the subspace ARAP energy (--energy=arap)"; }

double SubspaceArapTerms::Cost(const NodeTransforms& transforms,
                               const HandleTransforms& handles) const {
  SubspaceArap::Slots u;
  arap_->Gather(transforms, handles, &u);
  return arap_->Cost(u);
}

std::unique_ptr<FrameSolver> SubspaceArapTerms::MakeSolver(
    const FrameSolverOptions& options) const {
  return MakeArapSolver(arap_->options().solver, options.stopping, options.gauss_newton,
                        arap_->options().anderson_window);
}

std::unique_ptr<CeresFamilyBlocks> SubspaceArapTerms::AddToCeresProblem(
    const DeformationEnergy& energy, NodeTransforms* parameters,
    const std::function<void(int)>& ensure_blocks, ceres::Problem* problem,
    std::string* error) const {
  if (!IsArapEnergyAlone(energy, "the Ceres backend", error)) return nullptr;
  // Analytic Jacobians whatever ceres.jacobians says: the cluster blocks are
  // linear in the nodes' blocks (energies/arap_cluster_cost.h).
  return std::make_unique<CeresArapBlocks>(arap_, parameters, ensure_blocks, problem);
}

std::shared_ptr<const SubspaceArap> FindSubspaceArap(const DeformationEnergy& energy) {
  for (const std::shared_ptr<const TermFamily>& family : energy.families) {
    if (auto* terms = dynamic_cast<const SubspaceArapTerms*>(family.get())) return terms->arap();
  }
  return nullptr;
}

bool IsArapEnergyAlone(const DeformationEnergy& energy, const std::string& solver,
                       std::string* error) {
  if (!FindSubspaceArap(energy)) {
    *error = solver + " needs the subspace ARAP energy (--energy=arap)";
    return false;
  }
  if (!energy.rot_nodes.empty() || !energy.coherence.empty() || !energy.positions.empty() ||
      !energy.terms.empty() || energy.families.size() != 1) {
    *error = solver + " minimises the subspace ARAP energy alone; the layout also has Eq. 17 "
             "or extra terms";
    return false;
  }
  return true;
}

}  // namespace msdeform
