#include "msdeform/scales/deformer_options.h"

#include <cstdio>
#include <string>
#include <utility>

#include "msdeform/core/nearest_nodes.h"


namespace msdeform {

const EnumNames<Method>& GraphMethodNames() {
  static const EnumNames<Method> names = {{Method::kMultiScale, "multiscale"},
                                          {Method::kStatic, "static"},
                                          {Method::kStaticDense, "static_dense"}};
  return names;
}

const char* MethodName(Method method) { return GraphMethodNames().Name(method); }

bool ParseMethod(const std::string& name, Method* method) {
  return GraphMethodNames().Parse(name, method);
}

const EnumNames<Solver>& SolverNames() {
  static const EnumNames<Solver> names = {{Solver::kGaussNewton, "gauss_newton"},
                                          {Solver::kCeres, "ceres"}};
  return names;
}

const char* SolverName(Solver solver) { return SolverNames().Name(solver); }

bool ParseSolver(const std::string& name, Solver* solver) {
  return SolverNames().Parse(name, solver);
}

const EnumNames<Energy>& EnergyNames() {
  static const EnumNames<Energy> names = {{Energy::kEd, "ed"}, {Energy::kArap, "arap"}};
  return names;
}

const char* EnergyName(Energy energy) { return EnergyNames().Name(energy); }

const EnumNames<InitialGuess>& InitialGuessNames() {
  static const EnumNames<InitialGuess> names = {{InitialGuess::kPrevious, "previous"},
                                                {InitialGuess::kExtrapolated, "extrapolated"},
                                                {InitialGuess::kRest, "rest"}};
  return names;
}

const char* InitialGuessName(InitialGuess guess) { return InitialGuessNames().Name(guess); }

bool ParseInitialGuess(const std::string& name, InitialGuess* guess) {
  return InitialGuessNames().Parse(name, guess);
}

bool ParseMethodVariant(const std::string& rigidity, const std::string& half_free,
                        const std::string& border, DeformerOptions* options,
                        std::string* error) {
  if (!ParseRigidityModel(rigidity, &options->rigidity.model)) {
    *error = "--rigidity=" + rigidity + ": expected harmonic or paper";
    return false;
  }
  if (!ParseHalfFreeRule(half_free, &options->selection.half_free)) {
    *error = "--half_free=" + half_free +
             ": expected next_to_totally_free, every_fixed_handle_node or none";
    return false;
  }
  if (!ParseBorderRule(border, &options->selection.border)) {
    *error = "--border=" + border + ": expected fixed, half_free or totally_free";
    return false;
  }
  return true;
}

std::vector<std::pair<std::string, std::string>> DescribeOptions(const DeformerOptions& options) {
  return DeformerOptionTable().Describe(options);
}

DeformerOptions PaperProcedure(DeformerOptions options) {
  options.rigidity.model = RigidityModel::kShapeMatching;
  options.selection.half_free = HalfFreeRule::kEveryFixedHandleNode;
  options.selection.border = BorderRule::kFixed;
  options.selection.pin_fixed_region = false;
  options.lattice.split_cells = false;
  options.hold_fixed_vertices = false;
  return options;
}

DeformerOptions WithEnergy(DeformerOptions options, Energy energy) {
  options.energy = energy;
  if (energy != Energy::kArap) options.arap = ArapOptions();
  return options;
}

bool CheckUnderEnergies(const DeformerOptions& options, const std::vector<Energy>& energies,
                        std::string* error) {
  for (const Energy energy : energies) {
    if (!WithEnergy(options, energy).Check(error)) return false;
  }
  return true;
}

bool DeformerOptions::Check(std::string* error) const {
  // Every row's range, checked from DeformerOptionTable(): a C++ or Python
  // caller gets the command line's one line ("rigidity.damping=1: expected a
  // number in [0, 1)"), and a range is written only in its row.
  if (!DeformerOptionTable().CheckRanges(*this, error)) return false;
  // Anderson acceleration is a part of the local/global iteration only: a
  // window given to another solve would be silently unused.
  if (arap.anderson_window > 0 &&
      (energy != Energy::kArap || backend != Solver::kGaussNewton ||
       arap.solver != ArapSolver::kLocalGlobal)) {
    *error = "arap.anderson_window=" + std::to_string(arap.anderson_window) +
             ": read only by energy=arap with backend=gauss_newton and "
             "arap.solver=local_global (0 turns it off)";
    return false;
  }
  // The subspace ARAP energy's options are read by it alone: under another
  // energy a changed one would be silently unused.
  if (energy != Energy::kArap) {
    static const DeformerOptions defaults;
    for (const auto& row : DeformerOptionTable().rows()) {
      if (row.name.rfind("arap.", 0) != 0 || row.get(*this) == row.get(defaults)) continue;
      *error = row.name + "=" + row.get(*this) + ": read only by energy=arap (energy=" +
               EnergyName(energy) + ")";
      return false;
    }
  }
  // What a row cannot say: relations between fields and the embedded
  // structs' own checks (core's lattice and graph, the solvers').
  return lattice.Check(error) && graph.Check(error) && rigidity.Check(error) &&
         selection.Check(error) && arap.Check(error) && stopping.Check(error) &&
         gauss_newton.Check(error) && ceres.Check(error);
}

const OptionTable<DeformerOptions>& DeformerOptionTable() {
  static const OptionTable<DeformerOptions>& table =
      MakeOptionTable<DeformerOptions>([](auto& t) { DeclareDeformerOptionRows(t); });
  return table;
}

}  // namespace msdeform
