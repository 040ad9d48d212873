// A term of the deformation energy beyond Eq. 17's own, described once so
// that both backends run it (solvers/deformation_energy.h, `terms`): the Ceres
// backend adds its cost function as a residual block, the Gauss-Newton
// backend assembles it once per handle layout when it is linear and
// evaluates its residual and Jacobian every iteration when it is not.
//
// A term is a templated residual functor over a few nodes' parameter blocks,
// in the shape of the other functors in energies/ (a struct with const data
// and `template <typename T> bool operator()(const T* block..., T* r) const`):
//
//   struct VolumeCost { ... };  // examples/energy_terms/volume_term.h
//   energy.terms.push_back(MakeEnergyTerm<VolumeCost, 1, 9>(
//       "volume", {TermBlock::Rotation(j)}, /*linear=*/false, VolumeCost(sqrt_weight)));
//
// Blocks: TermBlock::Rotation(j) is R_j (9 doubles, column-major),
// TermBlock::Translation(j) is t_j (3). A block of a node whose class keeps
// it constant (a Fixed node's R and t, a Half Free node's t) is held at the
// layout's value, as the built-in terms' blocks are. Costs are 1/2 |r|^2.

#ifndef MSDEFORM_ENERGIES_ENERGY_TERM_H_
#define MSDEFORM_ENERGIES_ENERGY_TERM_H_

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <ceres/autodiff_cost_function.h>
#include <ceres/cost_function.h>

#include "msdeform/core/deformation_graph.h"

namespace msdeform {

// One parameter block of a term: R_node (9 doubles) or t_node (3 doubles).
struct TermBlock {
  enum class Kind { kRotation, kTranslation };
  int node = 0;
  Kind kind = Kind::kRotation;

  static TermBlock Rotation(int node) { return {node, Kind::kRotation}; }
  static TermBlock Translation(int node) { return {node, Kind::kTranslation}; }
  int size() const { return kind == Kind::kRotation ? 9 : 3; }
};

struct EnergyTerm {
  std::string name;               // for messages: "volume"
  std::vector<TermBlock> blocks;  // the cost function's parameter blocks, in order
  // The residual is affine in the blocks (its Jacobian is constant): the
  // Gauss-Newton backend then assembles it once per layout, into H = A^T A.
  bool linear = false;
  // New cost functions over `blocks` (the caller owns them): the autodiff of
  // the term's functor (required), and a hand-written Jacobian (optional;
  // the autodiff one serves both when it is empty).
  std::function<ceres::CostFunction*()> new_autodiff;
  std::function<ceres::CostFunction*()> new_analytic;

  ceres::CostFunction* NewCostFunction(bool autodiff) const {
    return autodiff || !new_analytic ? new_autodiff() : new_analytic();
  }
};

// A term from a templated functor with kNumResiduals residuals over blocks
// of sizes kBlockSizes... (9 for a rotation, 3 for a translation, in the
// order of `blocks`).
template <typename Functor, int kNumResiduals, int... kBlockSizes>
EnergyTerm MakeEnergyTerm(std::string name, std::vector<TermBlock> blocks, bool linear,
                          const Functor& functor) {
  EnergyTerm term;
  term.name = std::move(name);
  term.blocks = std::move(blocks);
  term.linear = linear;
  term.new_autodiff = [functor]() -> ceres::CostFunction* {
    return new ceres::AutoDiffCostFunction<Functor, kNumResiduals, kBlockSizes...>(
        new Functor(functor));
  };
  return term;
}

// Refuses a term whose blocks name a node outside [0, num_nodes), repeat a
// block (Ceres forbids it), or disagree with its cost function's block
// sizes; the message names the term.
bool CheckEnergyTerm(const EnergyTerm& term, int num_nodes, std::string* error);

// 1/2 |r|^2 of `term` at `transforms`.
double EnergyTermCost(const EnergyTerm& term, const NodeTransforms& transforms);

// Pointers to the term's blocks in `transforms`, in the term's order.
std::vector<const double*> TermParameters(const EnergyTerm& term,
                                          const NodeTransforms& transforms);

}  // namespace msdeform

#endif  // MSDEFORM_ENERGIES_ENERGY_TERM_H_
