#include "msdeform/energies/energy_term.h"

#include <memory>
#include <set>

namespace msdeform {

bool CheckEnergyTerm(const EnergyTerm& term, int num_nodes, std::string* error) {
  const std::string name = "energy term '" + term.name + "'";
  if (!term.new_autodiff) {
    *error = name + " has no cost function (new_autodiff is empty)";
    return false;
  }
  std::set<std::pair<int, int>> seen;
  for (const TermBlock& block : term.blocks) {
    if (block.node < 0 || block.node >= num_nodes) {
      *error = name + " names node " + std::to_string(block.node) + " of a graph of " +
               std::to_string(num_nodes) + " nodes";
      return false;
    }
    if (!seen.insert({block.node, static_cast<int>(block.kind)}).second) {
      *error = name + " names a block of node " + std::to_string(block.node) + " twice";
      return false;
    }
  }
  for (bool autodiff : {true, false}) {
    if (!autodiff && !term.new_analytic) continue;
    std::unique_ptr<ceres::CostFunction> cost(term.NewCostFunction(autodiff));
    const std::vector<int32_t>& sizes = cost->parameter_block_sizes();
    bool same = sizes.size() == term.blocks.size();
    for (size_t i = 0; same && i < sizes.size(); ++i) same = sizes[i] == term.blocks[i].size();
    if (!same) {
      *error = name + ": its " + (autodiff ? "autodiff" : "analytic") +
               " cost function's parameter blocks differ from its blocks (9 per rotation, 3 "
               "per translation, in order)";
      return false;
    }
  }
  return true;
}

std::vector<const double*> TermParameters(const EnergyTerm& term,
                                          const NodeTransforms& transforms) {
  std::vector<const double*> parameters;
  for (const TermBlock& block : term.blocks) {
    parameters.push_back(block.kind == TermBlock::Kind::kRotation
                             ? transforms.rotations.col(block.node).data()
                             : transforms.translations.col(block.node).data());
  }
  return parameters;
}

double EnergyTermCost(const EnergyTerm& term, const NodeTransforms& transforms) {
  std::unique_ptr<ceres::CostFunction> cost(term.NewCostFunction(false));
  std::vector<double> residuals(cost->num_residuals());
  cost->Evaluate(TermParameters(term, transforms).data(), residuals.data(), nullptr);
  double sum = 0.0;
  for (double r : residuals) sum += r * r;
  return 0.5 * sum;
}

}  // namespace msdeform
