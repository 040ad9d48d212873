// msdeform_experiments: regenerates every table under experiments/results/
// from the scenarios under experiments/scenarios/ (README.md), and with
// --solver_lab the solver lab's instead (experiments/solver_lab.h).
//
//   build/experiments/msdeform_experiments                 # the full run
//   build/experiments/msdeform_experiments --quick --out_dir=/tmp/quick
//   build/experiments/msdeform_experiments --energies=ed   # the graph methods with Eq. 17 only
//   build/experiments/msdeform_experiments --solver_lab    # solvers.{csv,md}, solver_traces.csv
//   build/experiments/msdeform_experiments --solver_lab --quick --out_dir=/tmp/lab

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <gflags/gflags.h>
#include <glog/logging.h>

#include "apps/flags/deformer_flags.h"
#include "apps/flags/method_flags.h"
#include "apps/flags/program.h"
#include "experiments/runner.h"
#include "experiments/solver_lab.h"
#include "msdeform/core/build_info.h"
#include "msdeform/core/scenario.h"
#include "msdeform/methods/registry.h"

DEFINE_string(scenarios, "",
              "[input] Folder of the scenario entries (*.json). Default: experiments/scenarios "
              "of the source tree (core/build_info.h, SourceTreePath).");
DEFINE_string(data_dir, "",
              "[input] Solver lab: folder of scenarios/armadillo_claw.json and "
              "meshes/armadillo_{104k,416k}.off, the claw_104k and claw_416k drags (default: "
              "$MSDEFORM_DATA_DIR, else the source tree's data/; core/build_info.h).");
DEFINE_string(out_dir, "experiments_out",
              "[output] Where the tables go (created if missing). The committed tables are "
              "regenerated with --out_dir=experiments/results from the repository root.");
DEFINE_bool(quick, false, "[input] The CI subset: cactus and hand_finger, 5 frames, ablations "
                          "on the cactus (--solver_lab: the cactus, 5 frames, budgets 1, 3 and "
                          "converged, every variant).");
DEFINE_int32(frames, 0, "[input] Drag frames per scenario (0: the scenario's; 5 with --quick).");
DEFINE_string(only, "", "[input] Comma-separated scenario names to run (default: all; the "
                        "solver lab also knows claw_104k and claw_416k).");
DEFINE_bool(large_meshes, true,
            "[input] Solver lab: also the claw drag on the 104K and 416K armadillo.");
DEFINE_bool(solver_lab, false,
            "[solver] Run the solver lab instead of the tables: every solver variant x scenario "
            "x iteration budget against a tightly converged reference (solvers.csv, solvers.md, "
            "solver_traces.csv; experiments/solver_lab.h). The solver flags are the lab's.");
DEFINE_string(variants, "",
              "[solver] Solver lab: comma-separated variant names (default: all, e.g. gn_lagged, "
              "gn_exact, ceres_lm_eigen_sparse, arap_local_global).");
namespace {

// The help texts that list methods, from the registry's descriptors.
const char* MethodsHelp() {
  static const std::string help =
      "[method] Comma-separated methods of table 2, any registered one: " +
      msdeform::MethodNameList() + " (default: all; methods/registry.h).";
  return help.c_str();
}

const char* EnergiesHelp() {
  static const std::string help = [] {
    std::vector<std::string> graph;
    for (const msdeform::MethodDescriptor& method : msdeform::RegisteredMethods()) {
      if (method.graph) graph.push_back(method.name);
    }
    std::string names;  // "a, b and c"
    for (size_t i = 0; i < graph.size(); ++i) {
      names += (i == 0 ? "" : i + 1 == graph.size() ? " and " : ", ") + graph[i];
    }
    return "[method] Comma-separated energies that " + names +
           " run with in table 2, one row each: ed (Eq. 17), arap (the subspace ARAP energy, "
           "solvers/subspace_arap.h). The other methods run once; the ablations add their "
           "energy_arap and arap_* rows either way.";
  }();
  return help.c_str();
}

}  // namespace

DEFINE_string(methods, "", MethodsHelp());
DEFINE_string(energies, "ed,arap", EnergiesHelp());
DEFINE_string(reference_method, "full_arap",
              "[method] The method whose final mesh is the reference of arap_energy_ratio, "
              "ref_distance_rel and ref_distance_max_rel, run once per scenario (default: the "
              "converged ARAP energy; empty: none).");
DEFINE_bool(time_other_backend, true,
            "[solver] Also time multiscale and static with the other backend (Ceres when "
            "--solver=gauss_newton, the default).");

namespace msdeform {
namespace {

void PrintLine(const std::string& line) {
  std::printf("%s\n", line.c_str());
  std::fflush(stdout);
}

// The runner sets the energy per row (--energies) and the lab per variant:
// --energy given with either is an error.
bool CheckNoEnergyFlag(const std::string& instead, std::string* error) {
  gflags::CommandLineFlagInfo info;
  if (gflags::GetCommandLineFlagInfo("energy", &info) && !info.is_default) {
    *error = "--energy: " + instead;
    return false;
  }
  return true;
}

bool ParseEnergies(const std::string& list, std::vector<Energy>* energies, std::string* error) {
  energies->clear();
  for (const std::string& name : SplitList(list)) {
    Energy energy;
    if (!EnergyNames().Parse(name, &energy)) {
      *error = "--energies: unknown energy '" + name + "' (expected " +
               EnergyNames().Expected() + ")";
      return false;
    }
    if (std::find(energies->begin(), energies->end(), energy) != energies->end()) {
      *error = "--energies: '" + name + "' is given twice";
      return false;
    }
    energies->push_back(energy);
  }
  if (energies->empty()) {
    *error = "--energies: give at least one of " + EnergyNames().Expected();
    return false;
  }
  return true;
}

bool FillOptions(RunnerOptions* options, std::string* error) {
  if (!CheckNoEnergyFlag("the tables run each energy of --energies side by side (drop the "
                         "flag; --energies=arap runs one)",
                         error) ||
      !ParseEnergies(FLAGS_energies, &options->energies, error)) {
    return false;
  }
  options->scenario_dir =
      FLAGS_scenarios.empty() ? SourceTreePath("experiments/scenarios") : FLAGS_scenarios;
  options->out_dir = FLAGS_out_dir;
  options->quick = FLAGS_quick;
  options->frames = FLAGS_frames;
  options->only = SplitList(FLAGS_only);
  options->methods = SplitList(FLAGS_methods);
  options->time_other_backend = FLAGS_time_other_backend;
  // The Deformer's flags (--method names a graph method), then the methods'
  // own (--cgal_iterations, --fastlsm_steps, ...).
  if (!DeformerOptionsFromFlags(&options->method_options.deformer, error, {},
                                EnergyNames().values()) ||
      !MethodOwnOptionsFromFlags(&options->method_options, error)) {
    return false;
  }
  options->threads = options->method_options.deformer.num_threads;
  options->reference_method = FLAGS_reference_method;
  options->progress = PrintLine;
  return options->Check(error);
}

// The lab sets the solver per variant and budget: a solver flag of
// apps/flags/deformer_flags.cc ("[solver] ...") given with --solver_lab is an error.
bool CheckNoSolverFlags(std::string* error) {
  std::vector<gflags::CommandLineFlagInfo> flags;
  gflags::GetAllFlags(&flags);
  for (const gflags::CommandLineFlagInfo& flag : flags) {
    const bool shared = flag.filename.find("deformer_flags.cc") != std::string::npos;
    if (shared && flag.description.rfind("[solver] ", 0) == 0 && !flag.is_default) {
      *error = "--" + flag.name + ": the solver lab sets the solver per variant and budget "
               "(drop the flag; --variants picks variants)";
      return false;
    }
  }
  return true;
}

bool FillLabOptions(SolverLabOptions* options, std::string* error) {
  if (!CheckNoSolverFlags(error) ||
      !CheckNoEnergyFlag("the solver lab sets the energy per variant (drop the flag; "
                         "--variants picks variants, e.g. arap_local_global)",
                         error)) {
    return false;
  }
  options->scenario_dir =
      FLAGS_scenarios.empty() ? SourceTreePath("experiments/scenarios") : FLAGS_scenarios;
  options->out_dir = FLAGS_out_dir;
  options->data_dir = FLAGS_data_dir;
  options->quick = FLAGS_quick;
  options->frames = FLAGS_frames;
  options->large_meshes = FLAGS_large_meshes;
  options->only = SplitList(FLAGS_only);
  options->variants = SplitList(FLAGS_variants);
  if (!DeformerOptionsFromFlags(&options->deformer, error, {}, EnergyNames().values())) {
    return false;
  }
  options->threads = options->deformer.num_threads;
  options->progress = PrintLine;
  return options->Check(error);
}

}  // namespace
}  // namespace msdeform

// The program after the shared prologue (apps/flags/program.h).
static int Body(const std::vector<std::string>&) {
  if (FLAGS_frames < 0 || FLAGS_frames > msdeform::kMaxScenarioFrames) {
    std::cerr << "msdeform_experiments: --frames=" << FLAGS_frames << ": expected 0.."
              << msdeform::kMaxScenarioFrames << "\n";
    return 1;
  }
  std::string error;
  bool ok = false;
  if (FLAGS_solver_lab) {
    msdeform::SolverLabOptions options;
    ok = msdeform::FillLabOptions(&options, &error) && msdeform::RunSolverLab(options, &error);
  } else {
    msdeform::RunnerOptions options;
    ok = msdeform::FillOptions(&options, &error) && msdeform::RunExperiments(options, &error);
  }
  if (!ok) {
    std::cerr << "msdeform_experiments: " << error << "\n";
    return 1;
  }
  return 0;
}

int main(int argc, char** argv) {
  // The runner measures one core per run unless told otherwise: the default
  // of every spelling of the option (the first given wins, none given the
  // first registered).
  for (const char* spelling : {"num_threads", "threads"}) {
    gflags::SetCommandLineOptionWithMode(
        spelling, std::to_string(msdeform::RunnerOptions().threads).c_str(),
        gflags::SET_FLAGS_DEFAULT);
  }
  msdeform::ProgramInfo info;
  info.name = "msdeform_experiments";
  info.usage =
      "msdeform_experiments [--quick] [--out_dir=DIR] [--scenarios=DIR] [--only=a,b] "
      "[--energies=ed,arap] [--frames=N] [--threads=N] [any msdeform method, solver or ablation flag]\n"
      "the solver lab: msdeform_experiments --solver_lab [--quick] [--out_dir=DIR] [--only=a,b] "
      "[--variants=a,b] [--large_meshes=false] [--frames=N] [--threads=N]";
  return msdeform::RunProgram(info, Body, argc, argv);
}
