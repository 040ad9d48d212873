#include "experiments/solver_lab.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

#include "msdeform/core/build_info.h"
#include "msdeform/core/scenario.h"
#include "msdeform/core/timing.h"
#include "msdeform/core/metrics.h"
#include "experiments/tables.h"
#include "msdeform/methods/graph_method.h"
#include "msdeform/solvers/deformation_energy.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using GN = GaussNewtonOptions;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kReferenceMaxIterations = 500;
constexpr double kReferenceTolerance = 1e-14;
// The claw drag of data/scenarios/armadillo_claw.json on the subdivided
// armadillos (they share the 26K mesh's vertex ids, so the entry applies).
const std::pair<const char*, const char*> kClawScenarios[] = {{"claw_104k", "armadillo_104k"},
                                                              {"claw_416k", "armadillo_416k"}};

bool Contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string Int(long long value) { return std::to_string(value); }

// The median, NaN for none (core/timing.h's Median gives 0).
double MedianOrNaN(const std::vector<double>& values) {
  return values.empty() ? kNaN : Median(values);
}

double MaxOrNaN(const std::vector<double>& values) {
  return values.empty() ? kNaN : *std::max_element(values.begin(), values.end());
}

// (E - E*) / E*; the absolute difference when the minimum is 0 (a handle the
// nodes reach exactly).
double RelativeGap(double energy, double minimum) {
  return (energy - minimum) / (minimum > 0.0 ? minimum : 1.0);
}

// (When ArapOptions gains a solver field, it is a solver field too.)
void ResetSolverFields(DeformerOptions* options) {
  const DeformerOptions defaults;
  options->backend = defaults.backend;
  options->stopping = defaults.stopping;
  options->initial_guess = defaults.initial_guess;
  options->gauss_newton = defaults.gauss_newton;
  options->ceres = defaults.ceres;
  options->arap.solver = defaults.arap.solver;
}

// ---------------------------------------------------------------- scenarios

// A scenario of the lab, loaded only when its turn comes (the 416K mesh is
// large).
struct LabScenario {
  std::string name;
  std::function<bool(int frames, ExperimentScenario*, std::string*)> load;
};

bool LoadClawScenario(const std::string& data_dir, const std::string& name,
                      const std::string& mesh_name, int frames, ExperimentScenario* scenario,
                      std::string* error) {
  if (!LoadExperimentScenario(data_dir + "/scenarios/armadillo_claw.json", frames, scenario, error,
                              data_dir + "/meshes/" + mesh_name + ".off")) {
    *error += " (build/apps/msdeform_make_large makes the large meshes; or leave them out)";
    return false;
  }
  scenario->name = name;
  return true;
}

// Every *.json of scenario_dir in name order, then the claw drags; filtered
// by `only` (file stems and claw names).
bool ListScenarios(const SolverLabOptions& options, const std::vector<std::string>& only,
                   std::vector<LabScenario>* scenarios, std::string* error) {
  std::vector<std::string> files;
  if (!ListScenarioFiles(options.scenario_dir, &files, error)) return false;
  scenarios->clear();
  for (const std::string& file : files) {
    const std::string stem = fs::path(file).stem().string();
    if (!only.empty() && !Contains(only, stem)) continue;
    scenarios->push_back(
        {stem, [file](int frames, ExperimentScenario* scenario, std::string* error) {
           return LoadExperimentScenario(file, frames, scenario, error);
         }});
  }
  const bool large_meshes = options.large_meshes && !options.quick;
  const std::string data_dir = options.data_dir.empty() ? DataDir() : options.data_dir;
  for (const auto& [name, mesh] : kClawScenarios) {
    if (!large_meshes || (!only.empty() && !Contains(only, name))) continue;
    const std::string claw = name, mesh_name = mesh;
    scenarios->push_back(
        {claw,
         [data_dir, claw, mesh_name](int frames, ExperimentScenario* scenario, std::string* error) {
           return LoadClawScenario(data_dir, claw, mesh_name, frames, scenario, error);
         }});
  }
  if (scenarios->empty()) {
    *error = options.scenario_dir + ": no scenario selected";
    return false;
  }
  return true;
}

// ---------------------------------------------------------------- one drag

// A frame that succeeded: its 1-based number, its stats and its energy:
// Eq. 17 at the frame's solution evaluated term by term (EvaluateEnergy), the
// same function for every backend. (A backend's reported cost can differ from
// it by rounding; cost_error shows it. The Gauss-Newton backend evaluates its
// cost from compressed residuals: at most 1.3e-13 of the energy on the
// cactus, cylinder_bend, man_knee_bend and both claws, where the quadratic
// form it used before lost up to 4e-7 (416K claw). Ceres's grouped position
// blocks take their constant from a QR of the group's rows: at most 8.3e-15
// on man_knee_bend and the cactus, where the expanded form they used before
// lost up to 4.4e-7.)
struct LabFrame {
  int frame = 0;
  DragStats stats;
  double energy = 0.0;
};

// One drag: the frames that succeeded, the frames that failed, and the result.
struct LabDrag {
  std::vector<LabFrame> frames;
  std::vector<int> failed_frames;
  int variables = 0;
  double handle_rms_rel = kNaN;  // after the last frame, over the diagonal
  bool result_finite = true;     // the final vertices
};

// Runs `options` along the scenario's path, going on after a failed frame.
// False only when the deformer does not set up.
bool RunLabDrag(const ExperimentScenario& scenario, const DeformerOptions& options, LabDrag* drag,
                std::string* error) {
  *drag = LabDrag();
  GraphMethod deformer(options.method);
  if (!deformer.Precompute(scenario.mesh, options, error) ||
      !deformer.SetHandles(scenario.layout, error)) {
    return false;
  }
  drag->variables = deformer.variables();
  DragAlongOptions along;
  along.continue_after_failure = true;
  along.on_frame = [&](int frame, const DragStats& stats) {
    drag->frames.push_back(
        {frame, stats,
         EvaluateEnergy(deformer.energy(), deformer.transforms(), scenario.path[frame - 1])});
  };
  DragLog log;
  std::string failure;  // only a failed last frame; every failure is in the log
  DragAlong(&deformer, scenario.path, along, &log, &failure);
  drag->failed_frames = log.failed_frames;
  const Eigen::Matrix3Xd& deformed = deformer.deformed_vertices();
  drag->result_finite = deformed.allFinite();
  drag->handle_rms_rel =
      HandleRmsError(scenario.mesh, deformed, scenario.layout, scenario.path.back()) /
      BoundingBoxDiagonal(scenario.mesh);
  return true;
}

// E*_f (index f - 1) from the reference run; the frames where the reference
// hit its iteration cap go to *unconverged.
bool ReferenceEnergies(const ExperimentScenario& scenario, const DeformerOptions& base,
                       std::vector<double>* minimum, int* unconverged, std::string* error) {
  LabDrag drag;
  if (!RunLabDrag(scenario, ReferenceOptions(base), &drag, error)) return false;
  if (!drag.failed_frames.empty()) {
    *error = "the reference run failed at frame " + std::to_string(drag.failed_frames[0]);
    return false;
  }
  minimum->assign(scenario.path.size(), kNaN);
  *unconverged = 0;
  for (const LabFrame& f : drag.frames) {
    (*minimum)[f.frame - 1] = f.energy;
    *unconverged += !f.stats.converged;
  }
  return true;
}

// ---------------------------------------------------------------- rows

// One row of solvers.csv, as numbers (NaN: no frame to measure).
struct LabRow {
  std::string scenario;
  int vertices = 0;
  int variables = 0;
  std::string variant;
  std::string energy;
  std::string description;
  int budget = 0;
  bool exact_steps = false;
  double frame_ms = kNaN;
  double solve_ms = kNaN;
  double skin_ms = kNaN;
  double ms_per_iteration = kNaN;
  double iterations = kNaN;
  int iterations_total = 0;
  double factorizations = kNaN;
  double energy_gap = kNaN;
  double energy_gap_max = kNaN;
  double energy_gap_last = kNaN;
  double energy_gap_min = kNaN;  // below -1e-9: a lower minimum than the reference's
  double cost_error = kNaN;      // max |reported cost - energy| / energy over the frames
  double handle_rms_rel = kNaN;
  int failed_frames = 0;
  int nonfinite_frames = 0;

  bool Clean() const { return failed_frames == 0 && nonfinite_frames == 0; }
};

// The row of one drag against the reference's minima. A frame whose cost or
// gap is not finite counts in nonfinite_frames and not in the medians; a
// non-finite final mesh counts once more.
LabRow SummariseDrag(const ExperimentScenario& scenario, const SolverVariant& variant,
                     const DeformerOptions& options, int budget, const LabDrag& drag,
                     const std::vector<double>& minimum) {
  LabRow row;
  row.scenario = scenario.name;
  row.vertices = scenario.mesh.num_vertices();
  row.variables = drag.variables;
  row.variant = variant.name;
  row.energy = EnergyName(options.energy);
  row.description = DescribeSolver(options);
  row.budget = budget;
  row.exact_steps = HasExactSteps(options);
  std::vector<double> frame_ms, solve_ms, skin_ms, iterations, factorizations, gaps, cost_errors;
  double solve_total_ms = 0.0;
  for (const LabFrame& f : drag.frames) {
    const DragStats& stats = f.stats;
    frame_ms.push_back(stats.frame_ms);
    solve_ms.push_back(stats.solve_ms);
    skin_ms.push_back(stats.skin_ms);
    iterations.push_back(stats.iterations);
    factorizations.push_back(stats.factorizations);
    row.iterations_total += stats.iterations;
    solve_total_ms += stats.solve_ms;
    const double gap = RelativeGap(f.energy, minimum[f.frame - 1]);
    const double cost_error = std::abs(stats.final_cost - f.energy) / std::abs(f.energy);
    if (!std::isfinite(gap) || !std::isfinite(stats.final_cost)) {
      ++row.nonfinite_frames;
      continue;
    }
    gaps.push_back(gap);
    if (f.frame == static_cast<int>(scenario.path.size())) row.energy_gap_last = gap;
    if (std::isfinite(cost_error)) cost_errors.push_back(cost_error);
  }
  row.frame_ms = MedianOrNaN(frame_ms);
  row.solve_ms = MedianOrNaN(solve_ms);
  row.skin_ms = MedianOrNaN(skin_ms);
  row.iterations = MedianOrNaN(iterations);
  row.factorizations = MedianOrNaN(factorizations);
  row.ms_per_iteration = row.iterations_total > 0 ? solve_total_ms / row.iterations_total : kNaN;
  row.energy_gap = MedianOrNaN(gaps);
  row.energy_gap_max = MaxOrNaN(gaps);
  row.energy_gap_min = gaps.empty() ? kNaN : *std::min_element(gaps.begin(), gaps.end());
  row.cost_error = MaxOrNaN(cost_errors);
  row.handle_rms_rel = drag.handle_rms_rel;
  row.failed_frames = static_cast<int>(drag.failed_frames.size());
  row.nonfinite_frames += !drag.result_finite;
  return row;
}

// Trace rows (scenario, variant, frame, iteration, ms, cost, energy_gap) of
// frame 1 and the last frame. The cost is that of the iterate the solver
// holds after each iteration: the running minimum of the trace. (The
// Gauss-Newton trace is that already, a rejected step repeating the cost;
// Ceres's IterationSummary::cost of a rejected step is the rejected
// candidate's, while Ceres keeps the iterate.) The gap shifts the solver's
// costs by the frame's rounding offset (energy - reported final cost), so a
// trace ends at the frame's energy_gap.
void AddTraces(const std::string& scenario, const std::string& variant, const LabDrag& drag,
               const std::vector<double>& minimum, Table* traces) {
  const int last = static_cast<int>(minimum.size());
  for (const LabFrame& f : drag.frames) {
    if (f.frame != 1 && f.frame != last) continue;
    const double offset = f.energy - f.stats.final_cost;
    double cost = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < f.stats.trace.size(); ++i) {
      const TracePoint& point = f.stats.trace[i];
      cost = std::min(cost, point.cost);
      traces->AddRow({scenario, variant, Int(f.frame), Int(static_cast<long long>(i)),
                      FormatNumber(point.ms, 6), FormatNumber(cost, 15),
                      FormatNumber(RelativeGap(cost + offset, minimum[f.frame - 1]), 6)});
    }
  }
}

// ---------------------------------------------------------------- tables

Table RunsTable(const std::vector<LabRow>& rows) {
  Table table{"All runs: scenario x variant x budget",
              {"scenario", "vertices", "variables", "variant", "energy", "description", "budget",
               "frame_ms", "solve_ms", "skin_ms", "ms_per_iteration", "iterations",
               "iterations_total", "factorizations", "energy_gap", "energy_gap_max",
               "energy_gap_last", "energy_gap_min", "cost_error", "handle_rms_rel",
               "failed_frames", "nonfinite_frames"},
              {},
              {}};
  for (const LabRow& r : rows) {
    table.AddRow({r.scenario, Int(r.vertices), Int(r.variables), r.variant, r.energy,
                  r.description,
                  BudgetName(r.budget), FormatNumber(r.frame_ms), FormatNumber(r.solve_ms),
                  FormatNumber(r.skin_ms), FormatNumber(r.ms_per_iteration),
                  FormatNumber(r.iterations), Int(r.iterations_total),
                  FormatNumber(r.factorizations), FormatNumber(r.energy_gap),
                  FormatNumber(r.energy_gap_max), FormatNumber(r.energy_gap_last),
                  FormatNumber(r.energy_gap_min), FormatNumber(r.cost_error),
                  FormatNumber(r.handle_rms_rel), Int(r.failed_frames),
                  Int(r.nonfinite_frames)});
  }
  table.notes = {
      "budget: the per-frame iteration cap (StoppingRule::max_iterations; \"converged\": " +
          Int(kConvergedMaxIterations) +
          " with the default tolerances). Times in ms, medians over the frames that succeeded; "
          "ms_per_iteration = total solve ms / total iterations; iterations and factorizations "
          "are medians per frame.",
      "energy: what the variant minimises (ed: Eq. 17; arap: the subspace ARAP energy, "
      "solvers/subspace_arap.h), each against the reference of its own energy. "
      "energy_gap = (E_f - E*_f) / E*_f per frame f (median, max, last frame, min), E_f the "
      "energy at the frame's solution evaluated by EvaluateEnergy and E*_f the same for "
      "the reference (energy_gap_min below 0 would be a lower minimum than the reference's); "
      "cost_error: the largest |reported cost - E_f| / E_f over the frames, the backend's "
      "rounding in its own cost (DragStats::final_cost); handle_rms_rel: the handle's "
      "RMS error after the last frame over the bounding-box diagonal; failed_frames: frames "
      "whose solve failed (the drag goes on from the last good frame); nonfinite_frames: "
      "frames with a non-finite cost or gap, plus one for a non-finite final mesh."};
  return table;
}

// The fastest clean row of `scenario` and `energy` that passes `accept`, or
// null.
const LabRow* Fastest(const std::vector<LabRow>& rows, const std::string& scenario,
                      const std::string& energy, const std::function<bool(const LabRow&)>& accept) {
  const LabRow* best = nullptr;
  for (const LabRow& r : rows) {
    if (r.scenario != scenario || r.energy != energy || !r.Clean() || !accept(r) ||
        !std::isfinite(r.frame_ms)) {
      continue;
    }
    if (best == nullptr || r.frame_ms < best->frame_ms) best = &r;
  }
  return best;
}

// The energies of `variants`, in order of first appearance.
std::vector<std::string> VariantEnergies(const std::vector<SolverVariant>& variants) {
  std::vector<std::string> energies;
  for (const SolverVariant& variant : variants) {
    if (!Contains(energies, EnergyName(variant.energy))) energies.push_back(EnergyName(variant.energy));
  }
  return energies;
}

Table WinnersTable(const std::vector<LabRow>& rows, const std::vector<std::string>& scenarios,
                   const std::vector<std::string>& energies) {
  Table table{"Winner at equal quality, per scenario and energy",
              {"scenario", "energy", "variables", "winner", "budget", "frame_ms", "iterations",
               "ms_per_iteration", "energy_gap_max", "exact_converged", "exact_converged_frame_ms",
               "exact_converged_iterations", "exact_converged_energy_gap_max", "speedup"},
              {},
              {}};
  for (const std::string& scenario : scenarios) {
    for (const std::string& energy : energies) {
      const LabRow* winner = Fastest(rows, scenario, energy, [](const LabRow& r) {
        return r.energy_gap_max <= kEqualQualityGap;
      });
      const LabRow* converged = Fastest(rows, scenario, energy, [](const LabRow& r) {
        return r.budget == kConvergedBudget && r.exact_steps && r.energy_gap_max <= kMinimumGap;
      });
      std::vector<std::string> cells = {scenario, energy};
      cells.push_back(winner      ? Int(winner->variables)
                      : converged ? Int(converged->variables)
                                  : "");
      if (winner != nullptr) {
        cells.insert(cells.end(),
                     {winner->variant, BudgetName(winner->budget), FormatNumber(winner->frame_ms),
                      FormatNumber(winner->iterations), FormatNumber(winner->ms_per_iteration),
                      FormatNumber(winner->energy_gap_max)});
      } else {
        cells.insert(cells.end(), {"(none)", "", "", "", "", ""});
      }
      if (converged != nullptr) {
        cells.insert(cells.end(), {converged->variant, FormatNumber(converged->frame_ms),
                                   FormatNumber(converged->iterations),
                                   FormatNumber(converged->energy_gap_max)});
      } else {
        cells.insert(cells.end(), {"(none)", "", "", ""});
      }
      cells.push_back(winner && converged
                          ? FormatNumber(converged->frame_ms / winner->frame_ms, 3)
                          : "");
      table.AddRow(cells);
    }
  }
  table.notes = {
      "winner: the fastest variant and budget of the energy by median frame_ms among the runs "
      "with "
      "energy_gap_max <= " +
      FormatNumber(kEqualQualityGap) +
      " and no failed or non-finite frame. exact_converged: for comparison, the fastest run "
      "at budget converged with exact steps (sparse Cholesky) that reaches the minimum "
      "(energy_gap_max <= " +
      FormatNumber(kMinimumGap) + "); speedup = exact_converged_frame_ms / winner frame_ms."};
  return table;
}

Table VariantsTable(const std::vector<LabRow>& rows, const std::vector<SolverVariant>& variants) {
  Table table{"Iterations against the cost of an iteration, per variant (budget converged)",
              {"variant", "energy", "description", "scenarios", "ms_per_iteration", "iterations", "frame_ms",
               "energy_gap_max", "failed_frames"},
              {},
              {}};
  for (const SolverVariant& variant : variants) {
    std::vector<double> per_iteration, iterations, frame_ms, gap_max;
    std::string description;
    int failed = 0;
    for (const LabRow& r : rows) {
      if (r.variant != variant.name || r.budget != kConvergedBudget) continue;
      description = r.description;
      if (std::isfinite(r.ms_per_iteration)) per_iteration.push_back(r.ms_per_iteration);
      if (std::isfinite(r.iterations)) iterations.push_back(r.iterations);
      if (std::isfinite(r.frame_ms)) frame_ms.push_back(r.frame_ms);
      if (std::isfinite(r.energy_gap_max)) gap_max.push_back(r.energy_gap_max);
      failed += r.failed_frames + r.nonfinite_frames;
    }
    if (description.empty()) continue;
    table.AddRow({variant.name, EnergyName(variant.energy), description,
                  Int(static_cast<long long>(frame_ms.size())),
                  FormatNumber(MedianOrNaN(per_iteration)), FormatNumber(MedianOrNaN(iterations)),
                  FormatNumber(MedianOrNaN(frame_ms)), FormatNumber(MaxOrNaN(gap_max)),
                  Int(failed)});
  }
  table.notes = {
      "Medians over the scenarios of each run's ms_per_iteration, median iterations "
      "per frame and median frame_ms at budget converged; energy_gap_max and "
      "failed_frames (failed + non-finite) over all scenarios."};
  return table;
}

Table TracesTable() {
  return Table{"Convergence traces",
               {"scenario", "variant", "frame", "iteration", "ms", "cost", "energy_gap"},
               {},
               {}};
}

// ---------------------------------------------------------------- the lab

// The settings the lab ran with, resolved from the options.
struct LabPlan {
  std::vector<LabScenario> scenarios;
  std::vector<SolverVariant> variants;
  std::vector<int> budgets;
  int frames = 0;
  DeformerOptions base;
};

bool MakePlan(const SolverLabOptions& options, LabPlan* plan, std::string* error) {
  std::vector<std::string> only = options.only;
  plan->frames = options.frames;
  plan->budgets = options.budgets;
  if (options.quick) {
    if (only.empty()) only = {"cactus"};
    if (plan->frames == 0) plan->frames = 5;
    plan->budgets = {1, 3, kConvergedBudget};
  }
  if (!ListScenarios(options, only, &plan->scenarios, error)) return false;
  for (const SolverVariant& variant : SolverVariants()) {
    if (options.variants.empty() || Contains(options.variants, variant.name)) {
      plan->variants.push_back(variant);
    }
  }
  plan->base = options.deformer;
  ResetSolverFields(&plan->base);
  plan->base.num_threads = options.threads;
  plan->base.graph.num_threads = options.threads;
  return true;
}

// "same options: a = b, ..." for the variants that repeat an earlier one
// under the current defaults; "" when none does.
std::string RepeatedVariants(const LabPlan& plan) {
  std::vector<std::string> descriptions;
  std::string text;
  for (size_t i = 0; i < plan.variants.size(); ++i) {
    descriptions.push_back(
        DescribeSolver(VariantOptions(plan.base, plan.variants[i], kConvergedBudget)));
    for (size_t j = 0; j < i; ++j) {
      if (descriptions[j] != descriptions[i]) continue;
      text += (text.empty() ? "" : ", ") + plan.variants[i].name + " = " + plan.variants[j].name;
      break;
    }
  }
  return text.empty() ? text
                      : "same options under the current defaults (rows differ by timing noise "
                        "only): " +
                            text;
}

std::vector<std::string> Header(const SolverLabOptions& options, const LabPlan& plan,
                                const std::vector<std::string>& reference_notes) {
  std::vector<std::string> header = ProvenanceLines();
  std::ostringstream settings;
  settings << "settings: " << (options.quick ? "quick subset" : "full lab") << ", "
           << (plan.frames > 0 ? std::to_string(plan.frames) + " frames per drag"
                               : std::string("each scenario's frames"))
           << ", " << options.threads << " thread(s), method " << MethodName(plan.base.method)
           << ", seed " << plan.base.graph.seed << ", budgets";
  for (int budget : plan.budgets) settings << " " << BudgetName(budget);
  const StoppingRule tolerances;
  settings << " (converged: at most " << kConvergedMaxIterations << " iterations, function "
           << tolerances.function_tolerance << ", gradient " << tolerances.gradient_tolerance
           << ", parameter " << tolerances.parameter_tolerance << " tolerance)";
  header.push_back(settings.str());
  // Every setting that changes a number, as the runner's tables list them;
  // the solver fields are each variant's and the stopping rule the budget's.
  std::string described = "base options (solver fields: the variant's):";
  for (const auto& [name, value] : DescribeOptions(plan.base)) {
    described += " " + name + "=" + value;
  }
  header.push_back(described);
  const std::string repeats = RepeatedVariants(plan);
  if (!repeats.empty()) header.push_back(repeats);
  std::ostringstream reference;
  const std::vector<std::string> energies = VariantEnergies(plan.variants);
  for (size_t i = 0; i < energies.size(); ++i) {
    DeformerOptions base = plan.base;
    EnergyNames().Parse(energies[i], &base.energy);
    reference << (i == 0 ? "reference E*_f" : "; ")
              << (energies.size() > 1 ? " (" + energies[i] + ")" : std::string()) << ": "
              << DescribeSolver(ReferenceOptions(base));
  }
  reference << ", at most " << kReferenceMaxIterations << " iterations, tolerances "
            << kReferenceTolerance;
  for (const std::string& note : reference_notes) reference << "; " << note;
  header.push_back(reference.str());
  return header;
}

bool WriteLabFiles(const SolverLabOptions& options, const LabPlan& plan,
                   const std::vector<LabRow>& rows, const std::vector<std::string>& scenarios,
                   const Table& traces, const std::vector<std::string>& header,
                   std::string* error) {
  const Table runs = RunsTable(rows);
  const Table winners = WinnersTable(rows, scenarios, VariantEnergies(plan.variants));
  const Table variants = VariantsTable(rows, plan.variants);
  return WriteCsv(options.out_dir, "solvers", runs, header, error) &&
         WriteMarkdown(
             options.out_dir, "solvers",
             "Solver lab: variants x budgets against the converged minimum", header,
             {MarkdownTable(winners, 2), MarkdownTable(variants, 2), MarkdownTable(runs, 2)},
             error) &&
         WriteCsv(options.out_dir, "solver_traces", traces, header, error);
}

std::string ProgressLine(const std::vector<LabRow>& rows, double seconds, double total_seconds) {
  std::ostringstream line;
  line << "  " << rows.front().variant << ":";
  for (const LabRow& r : rows) {
    line << " " << BudgetName(r.budget) << " " << FormatNumber(r.frame_ms, 3) << " ms gap "
         << FormatNumber(r.energy_gap_max, 2);
    if (r.energy_gap_min < -1e-9) line << " (min gap " << FormatNumber(r.energy_gap_min, 2) << ")";
    if (!r.Clean())
      line << " (" << r.failed_frames << " failed, " << r.nonfinite_frames << " non-finite)";
    line << ";";
  }
  line << " " << FormatFixed(seconds, 1) << " s (" << FormatFixed(total_seconds, 0) << " s in all)";
  return line.str();
}

}  // namespace

std::vector<SolverVariant> SolverVariants() {
  std::vector<SolverVariant> variants = {
      {"gn_lagged", [](DeformerOptions*) {}},
      {"gn_exact",
       [](DeformerOptions* o) {
         o->gauss_newton.factorization = GN::Factorization::kEveryIteration;
       }},
      {"gn_per_frame",
       [](DeformerOptions* o) { o->gauss_newton.factorization = GN::Factorization::kPerFrame; }},
      {"gn_lm",
       [](DeformerOptions* o) { o->gauss_newton.damping = GN::Damping::kLevenbergMarquardt; }},
      {"gn_pcg_jacobi",
       [](DeformerOptions* o) { o->gauss_newton.linear_solver = GN::LinearSolver::kPcgJacobi; }},
      {"gn_pcg_ichol",
       [](DeformerOptions* o) {
         o->gauss_newton.linear_solver = GN::LinearSolver::kPcgIncompleteCholesky;
       }},
      // Eigen's scalar SimplicialLLT: the default Cholesky before the
      // supernodal one (2026-11-26); the same steps, slower.
      {"gn_eigen_llt",
       [](DeformerOptions* o) { o->gauss_newton.cholesky = GN::Cholesky::kEigenLLT; }},
      {"gn_ldlt", [](DeformerOptions* o) { o->gauss_newton.cholesky = GN::Cholesky::kEigenLDLT; }},
      {"gn_cholmod", [](DeformerOptions* o) { o->gauss_newton.cholesky = GN::Cholesky::kCholmod; }},
      {"gn_cold", [](DeformerOptions* o) { o->initial_guess = InitialGuess::kRest; }},
      {"gn_extrapolated",
       [](DeformerOptions* o) { o->initial_guess = InitialGuess::kExtrapolated; }},
      // The factorisation rule before 2026-11-23 (refactorise unless a step
      // shrinks the gradient 4x): the default of then.
      {"gn_refactor_025", [](DeformerOptions* o) { o->gauss_newton.refactor_ratio = 0.25; }},
  };
  // Ceres with each sparse library it has, then CGNR.
  for (auto trust_region : {ceres::LEVENBERG_MARQUARDT, ceres::DOGLEG}) {
    for (auto library : CeresSparseLibraries()) {
      variants.push_back(
          {std::string(trust_region == ceres::DOGLEG ? "ceres_dogleg_" : "ceres_lm_") +
               SparseLibraryName(library),
           [trust_region, library](DeformerOptions* o) {
             o->backend = Solver::kCeres;
             o->ceres.trust_region = trust_region;
             o->ceres.sparse_library = library;
           }});
    }
  }
  variants.push_back({"ceres_cgnr", [](DeformerOptions* o) {
                        o->backend = Solver::kCeres;
                        o->ceres.linear_solver = ceres::CGNR;
                      }});
  // The Jacobians (CeresOptions::jacobians): the autodiff functors take one
  // position block per vertex, so the analytic per-vertex row is their
  // like-for-like timing.
  variants.push_back({"ceres_lm_per_vertex", [](DeformerOptions* o) {
                        o->backend = Solver::kCeres;
                        o->ceres.group_position_terms = false;
                      }});
  variants.push_back({"ceres_lm_autodiff", [](DeformerOptions* o) {
                        o->backend = Solver::kCeres;
                        o->ceres.jacobians = CeresOptions::Jacobians::kAutodiff;
                      }});
  // The subspace ARAP energy's solvers, one line each.
  variants.push_back({"arap_local_global", [](DeformerOptions*) {}, Energy::kArap});
  variants.push_back({"arap_gauss_newton",
                      [](DeformerOptions* o) { o->arap.solver = ArapSolver::kGaussNewton; },
                      Energy::kArap});
  return variants;
}

DeformerOptions VariantOptions(const DeformerOptions& base, const SolverVariant& variant,
                               int budget) {
  DeformerOptions options = WithEnergy(base, variant.energy);
  ResetSolverFields(&options);
  variant.apply(&options);
  options.stopping = StoppingRule();
  options.stopping.max_iterations = budget == kConvergedBudget ? kConvergedMaxIterations : budget;
  return options;
}

DeformerOptions ReferenceOptions(const DeformerOptions& base) {
  DeformerOptions options = base;
  ResetSolverFields(&options);
  options.backend = Solver::kGaussNewton;
  options.initial_guess = InitialGuess::kPrevious;
  options.gauss_newton.factorization = GN::Factorization::kEveryIteration;
  // The subspace ARAP energy's reference: Gauss-Newton on its nodes and
  // rotations (local/global converges linearly and stops at the cap).
  if (options.energy == Energy::kArap) options.arap.solver = ArapSolver::kGaussNewton;
  options.stopping.max_iterations = kReferenceMaxIterations;
  options.stopping.function_tolerance = kReferenceTolerance;
  options.stopping.gradient_tolerance = kReferenceTolerance;
  options.stopping.parameter_tolerance = kReferenceTolerance;
  return options;
}

std::string DescribeSolver(const DeformerOptions& options) {
  std::ostringstream text;
  if (options.energy == Energy::kArap && options.backend == Solver::kGaussNewton) {
    // Session's choice for this energy (scales/session.cc).
    if (options.arap.solver == ArapSolver::kGaussNewton) {
      text << "ARAP Gauss-Newton on nodes and cluster rotations (ArapGaussNewtonSolver); "
              "factorised every iteration";
    } else {
      text << "ARAP local/global (ArapLocalGlobalSolver); one factorisation per layout";
    }
  } else if (options.backend == Solver::kGaussNewton) {
    const GaussNewtonOptions& gn = options.gauss_newton;
    text << "Gauss-Newton; ";
    if (gn.linear_solver == GN::LinearSolver::kCholesky) {
      text << "Cholesky (" << CholeskyName(gn.cholesky);
      if (gn.cholesky == GN::Cholesky::kCholmod && !GaussNewtonHasCholmod()) {
        text << ": not built in; eigen_llt";
      }
      text << ")";
    } else {
      text << LinearSolverName(gn.linear_solver);
    }
    text << "; factorisation " << FactorizationName(gn.factorization);
    if (gn.factorization != GN::Factorization::kEveryIteration) {
      text << " (refactor ratio " << gn.refactor_ratio << ")";
    }
    text << "; damping " << DampingName(gn.damping);
  } else {
    const CeresOptions& ceres = options.ceres;
    text << "Ceres; " << TrustRegionName(ceres.trust_region) << "; "
         << CeresLinearSolverName(ceres.linear_solver);
    if (ceres.linear_solver == ceres::SPARSE_NORMAL_CHOLESKY) {
      text << " (" << SparseLibraryName(ceres.sparse_library) << ")";
    } else {
      text << " (jacobi)";
    }
    if (ceres.jacobians != CeresOptions::Jacobians::kAnalytic) {
      text << "; " << JacobiansName(ceres.jacobians) << " Jacobians";
    } else if (!ceres.group_position_terms) {
      text << "; per-vertex position blocks";
    }
  }
  text << "; initial guess " << InitialGuessName(options.initial_guess);
  return text.str();
}

bool HasExactSteps(const DeformerOptions& options) {
  if (options.energy == Energy::kArap && options.backend == Solver::kGaussNewton) return false;
  return options.backend == Solver::kGaussNewton
             ? options.gauss_newton.linear_solver == GN::LinearSolver::kCholesky
             : options.ceres.linear_solver == ceres::SPARSE_NORMAL_CHOLESKY;
}

std::string BudgetName(int budget) {
  return budget == kConvergedBudget ? "converged" : std::to_string(budget);
}

bool SolverLabOptions::Check(std::string* error) const {
  if (scenario_dir.empty() || out_dir.empty()) {
    *error = "the scenario folder and the output folder must be given";
    return false;
  }
  if (frames < 0 || frames > kMaxScenarioFrames) {
    *error = "frames must be in 0.." + std::to_string(kMaxScenarioFrames) + " (0: the scenario's)";
    return false;
  }
  if (threads < 1) {
    *error = "threads must be >= 1";
    return false;
  }
  if (budgets.empty()) {
    *error = "budgets must not be empty";
    return false;
  }
  for (int budget : budgets) {
    if (budget < 0) {
      *error = "budgets: " + std::to_string(budget) + " is not >= 0 (0: until converged)";
      return false;
    }
  }
  const std::vector<SolverVariant> all = SolverVariants();
  for (const std::string& name : variants) {
    if (std::none_of(all.begin(), all.end(),
                     [&](const SolverVariant& v) { return v.name == name; })) {
      std::string names;
      for (const SolverVariant& v : all) names += (names.empty() ? "" : ", ") + v.name;
      *error = "variants: unknown variant '" + name + "' (expected one of " + names + ")";
      return false;
    }
  }
  // The variants set the energy (WithEnergy): the arap.* options are theirs.
  return CheckUnderEnergies(deformer, EnergyNames().values(), error);
}

bool RunSolverLab(const SolverLabOptions& options, std::string* error) {
  if (!options.Check(error)) return false;
  auto progress = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  const auto start = Clock::now();
  LabPlan plan;
  if (!MakePlan(options, &plan, error)) return false;
  std::error_code ec;
  fs::create_directories(options.out_dir, ec);
  if (ec) {
    *error = options.out_dir + ": " + ec.message();
    return false;
  }

  std::vector<LabRow> rows;
  std::vector<std::string> scenario_names, reference_notes;
  Table traces = TracesTable();
  int index = 0;
  for (const LabScenario& lab_scenario : plan.scenarios) {
    ++index;
    ExperimentScenario scenario;
    if (!lab_scenario.load(plan.frames, &scenario, error)) return false;
    scenario_names.push_back(scenario.name);
    // E*_f per energy, computed before the first variant of that energy.
    std::map<Energy, std::vector<double>> minima;
    auto reference_of = [&](Energy energy, std::string* error) -> const std::vector<double>* {
      const auto found = minima.find(energy);
      if (found != minima.end()) return &found->second;
      const auto reference_start = Clock::now();
      const DeformerOptions base = WithEnergy(plan.base, energy);
      std::vector<double> minimum;
      int unconverged = 0;
      const std::string label = energy == Energy::kEd
                                    ? std::string("reference")
                                    : std::string("reference (") + EnergyName(energy) + ")";
      if (!ReferenceEnergies(scenario, base, &minimum, &unconverged, error)) {
        *error = scenario.name + " / " + label + ": " + *error;
        return nullptr;
      }
      if (unconverged > 0) {
        reference_notes.push_back(scenario.name +
                                  (energy == Energy::kEd ? "" : std::string(" (") +
                                                                    EnergyName(energy) + ")") +
                                  ": " +
                                  std::to_string(unconverged) +
                                  " frame(s) stopped at the iteration cap");
      }
      progress("[" + std::to_string(index) + "/" + std::to_string(plan.scenarios.size()) + "] " +
               scenario.name + " (" + std::to_string(scenario.mesh.num_vertices()) +
               " vertices, " + std::to_string(scenario.path.size()) + " frames): " + label +
               " in " + FormatFixed(MillisecondsSince(reference_start) / 1000.0, 1) +
               " s, E* of the last "
               "frame " +
               FormatNumber(minimum.back(), 8) +
               (unconverged > 0 ? " (" + std::to_string(unconverged) + " frames unconverged)"
                                : ""));
      return &(minima[energy] = std::move(minimum));
    };
    for (const SolverVariant& variant : plan.variants) {
      const std::vector<double>* minimum_of_energy = reference_of(variant.energy, error);
      if (minimum_of_energy == nullptr) return false;
      const std::vector<double>& minimum = *minimum_of_energy;
      const auto variant_start = Clock::now();
      std::vector<LabRow> variant_rows;
      for (int budget : plan.budgets) {
        const DeformerOptions run_options = VariantOptions(plan.base, variant, budget);
        LabDrag drag;
        if (!RunLabDrag(scenario, run_options, &drag, error)) {
          *error = scenario.name + " / " + variant.name + ": " + *error;
          return false;
        }
        variant_rows.push_back(
            SummariseDrag(scenario, variant, run_options, budget, drag, minimum));
        if (budget == kConvergedBudget)
          AddTraces(scenario.name, variant.name, drag, minimum, &traces);
      }
      progress(ProgressLine(variant_rows, MillisecondsSince(variant_start) / 1000.0,
                            MillisecondsSince(start) / 1000.0));
      rows.insert(rows.end(), variant_rows.begin(), variant_rows.end());
    }
  }
  const std::vector<std::string> header = Header(options, plan, reference_notes);
  if (!WriteLabFiles(options, plan, rows, scenario_names, traces, header, error)) return false;
  progress("wrote solvers (.csv, .md) and solver_traces.csv to " + options.out_dir + " in " +
           FormatFixed(MillisecondsSince(start) / 1000.0, 1) + " s");
  return true;
}

}  // namespace msdeform
