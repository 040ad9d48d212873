#include "experiments/arap_lab.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "experiments/experiment_scenario.h"
#include "experiments/solver_lab.h"
#include "experiments/tables.h"
#include "msdeform/core/timing.h"
#include "msdeform/solvers/deformation_energy.h"
#include "msdeform/solvers/local_global_arap.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Subspace variants stop when an iteration lowers the energy by at most this
// fraction, or moves the variables by at most this fraction: far below the
// 1e-6 gap the lab times (a linear rate r stops near a gap of 1e-12 / (1 - r),
// 1e-9 for r = 0.999); tolerance 0 would run every frame to the cap.
constexpr double kSubspaceTolerance = 1e-12;

std::string Int(long long value) { return std::to_string(value); }

double RelativeGap(double energy, double minimum) {
  return (energy - minimum) / (minimum > 0.0 ? minimum : 1.0);
}

// The measured frames that exist in a drag of `num_frames`, sorted, unique.
std::vector<int> MeasuredFrames(const std::vector<int>& wanted, int num_frames) {
  std::vector<int> frames;
  for (int f : wanted)
    if (f >= 1 && f <= num_frames) frames.push_back(f);
  std::sort(frames.begin(), frames.end());
  frames.erase(std::unique(frames.begin(), frames.end()), frames.end());
  return frames;
}

// Fills the gap fields of `frame` from a trace (energies, milliseconds).
void ReadGaps(const std::vector<double>& energy, const std::vector<double>& ms,
              ArapLabFrame* frame) {
  int iteration = -1;
  double at = -1.0;
  if (FirstIterationWithin(energy, ms, frame->minimum, kArapLabLooseGap, &iteration, &at)) {
    frame->loose_iterations = iteration;
    frame->loose_ms = at;
  }
  if (FirstIterationWithin(energy, ms, frame->minimum, kArapLabTightGap, &iteration, &at)) {
    frame->tight_iterations = iteration;
    frame->tight_ms = at;
  }
}

// ---------------------------------------------------------------- tables

double MedianOf(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  // Infinite entries (not reached) sort last; a median that lands on one is
  // "not reached".
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::string Cell(double value) {
  if (std::isinf(value)) return "not reached";
  return FormatNumber(value);
}

// One row: a scenario x energy x variant over its measured frames.
struct VariantRow {
  std::string scenario;
  bool large = false;
  int vertices = 0;
  std::string energy;  // full_arap or subspace
  std::string variant;
  int cap = 0;
  std::vector<ArapLabFrame> frames;
  // The same frames of the energy's baseline (plain / local_global).
  std::vector<ArapLabFrame> baseline;
};

double IterationsOrInf(int iterations) { return iterations < 0 ? kInf : iterations; }

// Per frame: the variant's iterations to the tight gap over the baseline's.
// A baseline that does not reach it within the cap counts as the cap (so the
// ratio is an upper bound); a variant that does not reach it is infinite.
std::vector<double> TightRatios(const VariantRow& row) {
  std::vector<double> ratios;
  for (size_t i = 0; i < row.frames.size(); ++i) {
    const double mine = IterationsOrInf(row.frames[i].tight_iterations);
    const double base = row.baseline[i].tight_iterations < 0
                            ? row.cap
                            : std::max(1, row.baseline[i].tight_iterations);
    ratios.push_back(mine / base);
  }
  return ratios;
}

// The largest (E_final - E_final,baseline) / E*_f over the frames.
double MaxExcessOverBaseline(const VariantRow& row) {
  double excess = -kInf;
  for (size_t i = 0; i < row.frames.size(); ++i) {
    const double minimum = row.frames[i].minimum > 0.0 ? row.frames[i].minimum : 1.0;
    excess = std::max(excess,
                      (row.frames[i].final_energy - row.baseline[i].final_energy) / minimum);
  }
  return excess;
}

Table RowsTable(const std::vector<VariantRow>& rows) {
  Table table{"Per scenario x energy x variant (medians over the measured frames)",
              {"scenario", "large", "vertices", "energy", "variant", "frames", "cap",
               "iterations_1e-3", "ms_1e-3", "reached_1e-3", "iterations_1e-6", "ms_1e-6",
               "reached_1e-6", "ratio_1e-6_vs_baseline", "iterations_run", "ms_per_iteration",
               "final_gap_max", "final_vs_baseline_max"},
              {},
              {}};
  for (const VariantRow& row : rows) {
    std::vector<double> loose_it, loose_ms, tight_it, tight_ms, run, per_iteration;
    int loose_reached = 0, tight_reached = 0;
    double final_gap = -kInf;
    for (const ArapLabFrame& f : row.frames) {
      loose_it.push_back(IterationsOrInf(f.loose_iterations));
      loose_ms.push_back(f.loose_iterations < 0 ? kInf : f.loose_ms);
      tight_it.push_back(IterationsOrInf(f.tight_iterations));
      tight_ms.push_back(f.tight_iterations < 0 ? kInf : f.tight_ms);
      loose_reached += f.loose_iterations >= 0;
      tight_reached += f.tight_iterations >= 0;
      run.push_back(f.iterations);
      if (f.iterations > 0) per_iteration.push_back(f.ms / f.iterations);
      final_gap = std::max(final_gap, RelativeGap(f.final_energy, f.minimum));
    }
    const int n = static_cast<int>(row.frames.size());
    table.AddRow({row.scenario, row.large ? "yes" : "no", Int(row.vertices), row.energy,
                  row.variant, Int(n), Int(row.cap), Cell(MedianOf(loose_it)),
                  Cell(MedianOf(loose_ms)), Int(loose_reached) + "/" + Int(n),
                  Cell(MedianOf(tight_it)), Cell(MedianOf(tight_ms)),
                  Int(tight_reached) + "/" + Int(n), Cell(MedianOf(TightRatios(row))),
                  Cell(MedianOf(run)), Cell(MedianOf(per_iteration)), FormatNumber(final_gap),
                  FormatNumber(MaxExcessOverBaseline(row))});
  }
  return table;
}

// The target's lines: per Anderson window, on the large edits, how often the
// median ratio is at most a third, and the largest final excess over plain
// on any measured frame of any edit.
std::vector<std::string> TargetLines(const std::vector<VariantRow>& rows,
                                     const std::vector<int>& windows) {
  std::vector<std::string> lines;
  lines.push_back(
      "Target (issue 38): Anderson acceleration reaches a relative gap of 1e-6 in at most a third "
      "of the plain iterations on at least 8 of 10 large edits, and never ends above the plain "
      "run's energy.");
  for (int window : windows) {
    const std::string name = "anderson_" + std::to_string(window);
    int large = 0, within = 0, never_above = 0, edits = 0;
    double worst_excess = -kInf;
    std::vector<std::string> missed;
    for (const VariantRow& row : rows) {
      if (row.energy != "full_arap" || row.variant != name) continue;
      ++edits;
      const double excess = MaxExcessOverBaseline(row);
      worst_excess = std::max(worst_excess, excess);
      never_above += excess <= 0.0;
      if (!row.large) continue;
      ++large;
      if (MedianOf(TightRatios(row)) <= 1.0 / 3.0) {
        ++within;
      } else {
        missed.push_back(row.scenario);
      }
    }
    std::ostringstream line;
    line << "- " << name << ": at most a third of plain's iterations to 1e-6 (median over the "
         << "measured frames) on " << within << " of " << large << " large edits ("
         << (within >= 8 ? "met" : "missed");
    if (!missed.empty()) {
      line << "; not on";
      for (size_t i = 0; i < missed.size(); ++i) line << (i ? ", " : " ") << missed[i];
    }
    line << "); final energy at most plain's on " << never_above << " of " << edits
         << " edits (largest excess (E - E_plain) / E* " << FormatNumber(worst_excess) << ")";
    lines.push_back(line.str());
  }
  return lines;
}

std::string Join(const std::vector<int>& values) {
  std::string text;
  for (int v : values) text += (text.empty() ? "" : " ") + std::to_string(v);
  return text;
}

}  // namespace

const std::vector<std::string>& ArapLabLargeEdits() {
  static const std::vector<std::string> edits = {
      "armadillo_arm_raise", "armadillo_hand_drag", "cactus",          "camel_hoof_drag",
      "camel_neck_bend",     "cylinder_bend",       "dino_tail_swing", "man_foot_drag",
      "man_knee_bend",       "man_leg_lift"};
  return edits;
}

bool ArapLabOptions::Check(std::string* error) const {
  if (scenario_dir.empty() || out_dir.empty()) {
    *error = "the scenario folder and the output folder must be given";
    return false;
  }
  if (frames < 0) {
    *error = "frames must be >= 0 (0: the scenario's)";
    return false;
  }
  if (!full_arap && !subspace) {
    *error = "full_arap and subspace are both off: nothing to measure";
    return false;
  }
  if (stem.empty()) {
    *error = "stem must not be empty";
    return false;
  }
  if (measured_frames.empty()) {
    *error = "measured_frames must not be empty";
    return false;
  }
  for (int f : measured_frames) {
    if (f < 1) {
      *error = "measured_frames: " + std::to_string(f) + " is not >= 1";
      return false;
    }
  }
  for (int w : anderson_windows) {
    if (w < 1 || w > 50) {
      *error = "anderson_windows: " + std::to_string(w) + " is not in 1..50";
      return false;
    }
  }
  if (max_iterations < 1 || reference_max_iterations < 1 || subspace_local_global_iterations < 1 ||
      subspace_gauss_newton_iterations < 1 || subspace_reference_iterations < 1) {
    *error = "the iteration caps must be >= 1";
    return false;
  }
  if (reference_window < 0 || reference_window > 50) {
    *error = "reference_window must be in 0..50";
    return false;
  }
  if (!(reference_tolerance >= 0.0 && reference_tolerance <= 1.0)) {
    *error = "reference_tolerance must be in [0, 1]";
    return false;
  }
  if (threads < 1 || jobs < 1) {
    *error = "threads and jobs must be >= 1";
    return false;
  }
  // The lab runs the subspace energy (energy=arap) and full_arap.
  return WithEnergy(deformer, Energy::kArap).Check(error);
}

bool FirstIterationWithin(const std::vector<double>& energy_trace,
                          const std::vector<double>& ms_trace, double minimum, double gap,
                          int* iteration, double* ms) {
  for (size_t i = 0; i < energy_trace.size(); ++i) {
    if (RelativeGap(energy_trace[i], minimum) <= gap) {
      *iteration = static_cast<int>(i);
      *ms = i < ms_trace.size() ? ms_trace[i] : 0.0;
      return true;
    }
  }
  return false;
}

bool MeasureFullArap(const Mesh& mesh, const HandleLayout& layout,
                     const std::vector<HandleTransforms>& path, const ArapLabOptions& options,
                     std::vector<ArapLabFrame>* frames, std::string* error) {
  frames->clear();
  if (!ValidateHandles(layout, mesh.num_vertices(), error)) return false;
  const std::vector<int> measured =
      MeasuredFrames(options.measured_frames, static_cast<int>(path.size()));
  if (measured.empty()) {
    *error = "no measured frame lies in the drag of " + std::to_string(path.size()) + " frames";
    return false;
  }
  std::vector<int> constrained;
  std::vector<int> handle_group;
  ConstrainedVertices(layout, &constrained, &handle_group);

  // The reference: E*_f, and the converged frame f - 1 of each measured f.
  LocalGlobalArapOptions reference_options;
  reference_options.relative_tolerance = options.reference_tolerance;
  reference_options.max_iterations = options.reference_max_iterations;
  reference_options.anderson_window = options.reference_window;
  reference_options.num_threads = options.threads;
  LocalGlobalArap reference;
  if (!reference.Setup(mesh, constrained, reference_options, error)) return false;
  std::map<int, double> minimum;
  std::map<int, Eigen::Matrix3Xd> start;
  Eigen::Matrix3Xd deformed = mesh.vertices;
  for (int f = 1; f <= measured.back(); ++f) {
    if (std::binary_search(measured.begin(), measured.end(), f)) start[f] = deformed;
    const LocalGlobalArapSummary summary = reference.Solve(
        ConstrainedTargets(mesh.vertices, constrained, handle_group, path[f - 1]), &deformed);
    if (!std::isfinite(summary.final_energy)) {
      *error = "the reference's energy at frame " + std::to_string(f) + " is not finite";
      return false;
    }
    minimum[f] = summary.final_energy;
  }

  std::vector<int> windows = {0};
  windows.insert(windows.end(), options.anderson_windows.begin(), options.anderson_windows.end());
  for (int window : windows) {
    LocalGlobalArapOptions variant_options;
    variant_options.relative_tolerance = 0.0;
    variant_options.max_iterations = options.max_iterations;
    variant_options.anderson_window = window;
    variant_options.num_threads = options.threads;
    LocalGlobalArap arap;
    if (!arap.Setup(mesh, constrained, variant_options, error)) return false;
    const std::string name = window == 0 ? "plain" : "anderson_" + std::to_string(window);
    for (int f : measured) {
      Eigen::Matrix3Xd x = start[f];
      const LocalGlobalArapSummary summary = arap.Solve(
          ConstrainedTargets(mesh.vertices, constrained, handle_group, path[f - 1]), &x);
      ArapLabFrame frame;
      frame.variant = name;
      frame.frame = f;
      frame.minimum = minimum[f];
      frame.iterations = summary.iterations;
      frame.ms = summary.ms_trace.empty() ? 0.0 : summary.ms_trace.back();
      frame.final_energy = summary.final_energy;
      ReadGaps(summary.energy_trace, summary.ms_trace, &frame);
      frames->push_back(frame);
    }
  }
  return true;
}

// The subspace energy's variants: local/global plain and with each Anderson
// window of the options, and Gauss-Newton; each with its solver-lab variant
// (experiments/solver_lab.h) and its iteration cap.
struct SubspaceVariant {
  std::string name;
  std::string solver_lab_name;
  int anderson_window;
  int cap;
};

std::vector<SubspaceVariant> SubspaceVariants(const ArapLabOptions& options) {
  std::vector<SubspaceVariant> variants = {
      {"local_global", "arap_local_global", 0, options.subspace_local_global_iterations}};
  for (int w : options.anderson_windows) {
    variants.push_back({"local_global_anderson_" + std::to_string(w), "arap_local_global", w,
                        options.subspace_local_global_iterations});
  }
  variants.push_back(
      {"gauss_newton", "arap_gauss_newton", 0, options.subspace_gauss_newton_iterations});
  return variants;
}

bool MeasureSubspaceArap(const Mesh& mesh, const HandleLayout& layout,
                         const std::vector<HandleTransforms>& path, const ArapLabOptions& options,
                         std::vector<ArapLabFrame>* frames, std::string* error) {
  frames->clear();
  const std::vector<int> measured =
      MeasuredFrames(options.measured_frames, static_cast<int>(path.size()));
  if (measured.empty()) {
    *error = "no measured frame lies in the drag of " + std::to_string(path.size()) + " frames";
    return false;
  }
  DeformerOptions base = options.deformer;
  base.energy = Energy::kArap;
  base.num_threads = options.threads;

  // Drags `run_options` through frames 1..last measured; on_frame gets each
  // frame's stats and its energy (EvaluateEnergy, as the solver lab).
  auto drag = [&](const DeformerOptions& run_options,
                  const std::function<void(int, const DragStats&, double)>& on_frame) {
    GraphMethod deformer(run_options.method);
    if (!deformer.Precompute(mesh, run_options, error) || !deformer.SetHandles(layout, error)) {
      return false;
    }
    for (int f = 1; f <= measured.back(); ++f) {
      DragStats stats;
      if (!deformer.Drag(path[f - 1], &stats, error)) {
        *error = "frame " + std::to_string(f) + ": " + *error;
        return false;
      }
      on_frame(f, stats, EvaluateEnergy(deformer.energy(), deformer.transforms(), path[f - 1]));
    }
    return true;
  };

  std::map<int, double> minimum;
  DeformerOptions reference_options = ReferenceOptions(base);
  reference_options.stopping.max_iterations = options.subspace_reference_iterations;
  if (!drag(reference_options, [&](int f, const DragStats&, double energy) {
        minimum[f] = energy;
      })) {
    *error = "reference: " + *error;
    return false;
  }
  const std::vector<SolverVariant> all = SolverVariants();
  for (const SubspaceVariant& subspace_variant : SubspaceVariants(options)) {
    const std::string& lab_name = subspace_variant.solver_lab_name;
    const auto found = std::find_if(all.begin(), all.end(),
                                    [&](const SolverVariant& v) { return v.name == lab_name; });
    CHECK(found != all.end()) << lab_name;
    DeformerOptions run_options = VariantOptions(base, *found, subspace_variant.cap);
    run_options.arap.anderson_window = subspace_variant.anderson_window;
    run_options.stopping.function_tolerance = kSubspaceTolerance;
    run_options.stopping.parameter_tolerance = kSubspaceTolerance;
    run_options.stopping.gradient_tolerance = 0.0;
    const std::string variant = subspace_variant.name;
    if (!drag(run_options, [&](int f, const DragStats& stats, double energy) {
          if (!std::binary_search(measured.begin(), measured.end(), f)) return;
          ArapLabFrame frame;
          frame.variant = variant;
          frame.frame = f;
          frame.minimum = minimum[f];
          frame.iterations = stats.iterations;
          frame.ms = stats.solve_ms;
          frame.final_energy = energy;
          // The solver's costs, shifted by the frame's rounding offset, as
          // the running minimum (the iterate the solver holds).
          const double offset = energy - stats.final_cost;
          std::vector<double> trace_energy, trace_ms;
          double cost = kInf;
          for (const TracePoint& point : stats.trace) {
            cost = std::min(cost, point.cost);
            trace_energy.push_back(cost + offset);
            trace_ms.push_back(point.ms);
          }
          ReadGaps(trace_energy, trace_ms, &frame);
          frames->push_back(frame);
        })) {
      *error = variant + ": " + *error;
      return false;
    }
  }
  return true;
}

namespace {

// The scenario files of options.scenario_dir that options.only names (all
// when empty), and the output folder made; false with a message naming the
// folder otherwise.
bool SelectScenarios(const ArapLabOptions& options, std::vector<std::string>* selected,
                     std::string* error) {
  std::vector<std::string> files;
  if (!ListScenarioFiles(options.scenario_dir, &files, error)) return false;
  for (const std::string& file : files) {
    const std::string stem = fs::path(file).stem().string();
    if (options.only.empty() ||
        std::find(options.only.begin(), options.only.end(), stem) != options.only.end()) {
      selected->push_back(file);
    }
  }
  if (selected->empty()) {
    *error = options.scenario_dir + ": no scenario selected";
    return false;
  }
  std::error_code ec;
  fs::create_directories(options.out_dir, ec);
  if (ec) {
    *error = options.out_dir + ": " + ec.message();
    return false;
  }
  return true;
}

// The tables' header: provenance, then what was run and how it is read.
std::vector<std::string> LabHeader(const ArapLabOptions& options) {
  std::vector<std::string> header = ProvenanceLines();
  header.push_back(
      "settings: measured frames " + Join(options.measured_frames) + " of each drag (" +
      (options.frames == 0 ? std::string("each scenario's frame count") :
                             Int(options.frames) + " frames") +
      "); full_arap: plain and Anderson " + Join(options.anderson_windows) +
      ", tolerance 0, at most " + Int(options.max_iterations) +
      " iterations a frame, each frame from the reference's converged previous frame; "
      "reference Anderson " + Int(options.reference_window) + ", relative tolerance " +
      FormatNumber(options.reference_tolerance) + ", at most " +
      Int(options.reference_max_iterations) + " iterations, through every frame");
  if (options.subspace) {
    header.push_back(
        "subspace (--energy=arap, default settings): local/global, plain and Anderson " +
        Join(options.anderson_windows) + " (arap.anderson_window), at most " +
        Int(options.subspace_local_global_iterations) + " and Gauss-Newton at most " +
        Int(options.subspace_gauss_newton_iterations) +
        " iterations a frame (reference at most " + Int(options.subspace_reference_iterations) +
        "), function and parameter tolerance " +
        FormatNumber(kSubspaceTolerance) +
        ", each from its own previous frame; E*: the solver lab's reference (Gauss-Newton, "
        "tolerances 1e-14)");
  }
  header.push_back(
      "iterations and ms to a relative gap (E - E*) / E* of 1e-3 and 1e-6, medians over the "
      "measured frames ('not reached': the median frame did not reach it within the cap); "
      "ratio_1e-6_vs_baseline: median over frames of the variant's iterations to 1e-6 over the "
      "baseline's (plain / local_global; a baseline that does not reach it counts as the cap); "
      "final_vs_baseline_max: largest (E_final - E_final,baseline) / E* over the frames; threads " +
      Int(options.threads) + " a scenario, " + Int(options.jobs) + " scenario(s) at a time");
  return header;
}

}  // namespace

bool RunArapLab(const ArapLabOptions& options, std::string* error) {
  if (!options.Check(error)) return false;
  auto progress = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  const auto start = Clock::now();
  std::vector<std::string> selected;
  if (!SelectScenarios(options, &selected, error)) return false;

  // One scenario's rows (full_arap's, then the subspace energy's), filled by
  // whichever job takes it.
  std::vector<std::vector<VariantRow>> scenario_rows(selected.size());
  std::vector<std::string> errors(selected.size());
  std::mutex progress_mutex;
  auto say = [&](const std::string& line) {
    std::lock_guard<std::mutex> lock(progress_mutex);
    progress(line);
  };
  auto run_scenario = [&](size_t index, std::string* error) {
    const std::string& file = selected[index];
    std::vector<VariantRow>& rows = scenario_rows[index];
    ExperimentScenario scenario;
    if (!LoadExperimentScenario(file, options.frames, &scenario, error)) return false;
    const bool large = std::find(ArapLabLargeEdits().begin(), ArapLabLargeEdits().end(),
                                 scenario.name) != ArapLabLargeEdits().end();
    // Rows of one energy: one per variant, the first variant the baseline.
    auto add_rows = [&](const std::string& energy, const std::vector<ArapLabFrame>& frames,
                        const std::map<std::string, int>& caps) {
      std::vector<std::string> order;
      for (const ArapLabFrame& f : frames)
        if (std::find(order.begin(), order.end(), f.variant) == order.end())
          order.push_back(f.variant);
      std::vector<ArapLabFrame> baseline;
      for (const ArapLabFrame& f : frames)
        if (f.variant == order.front()) baseline.push_back(f);
      for (const std::string& variant : order) {
        VariantRow row;
        row.scenario = scenario.name;
        row.large = large;
        row.vertices = scenario.mesh.num_vertices();
        row.energy = energy;
        row.variant = variant;
        row.cap = caps.at(variant);
        for (const ArapLabFrame& f : frames)
          if (f.variant == variant) row.frames.push_back(f);
        row.baseline = baseline;
        rows.push_back(row);
      }
    };
    const auto scenario_start = Clock::now();
    std::vector<ArapLabFrame> frames;
    if (options.full_arap) {
      if (!MeasureFullArap(scenario.mesh, scenario.layout, scenario.path, options, &frames,
                           error)) {
        *error = scenario.name + " / full_arap: " + *error;
        return false;
      }
      std::map<std::string, int> caps = {{"plain", options.max_iterations}};
      for (int w : options.anderson_windows)
        caps["anderson_" + std::to_string(w)] = options.max_iterations;
      add_rows("full_arap", frames, caps);
    }
    const double full_seconds = MillisecondsSince(scenario_start) / 1000.0;
    double subspace_seconds = 0.0;
    if (options.subspace) {
      const auto subspace_start = Clock::now();
      if (!MeasureSubspaceArap(scenario.mesh, scenario.layout, scenario.path, options, &frames,
                               error)) {
        *error = scenario.name + " / subspace: " + *error;
        return false;
      }
      std::map<std::string, int> caps;
      for (const SubspaceVariant& v : SubspaceVariants(options)) caps[v.name] = v.cap;
      add_rows("subspace", frames, caps);
      subspace_seconds = MillisecondsSince(subspace_start) / 1000.0;
    }
    std::string lines = scenario.name + " (" + Int(scenario.mesh.num_vertices()) +
                        " vertices): full_arap in " + FormatFixed(full_seconds, 1) +
                        " s, subspace in " + FormatFixed(subspace_seconds, 1) + " s";
    for (const VariantRow& row : rows) {
      const Table one = RowsTable({row});
      lines += "\n  " + row.energy + " " + row.variant + ": 1e-3 at " + one.rows[0][7] +
               ", 1e-6 at " + one.rows[0][10] + " (" + one.rows[0][12] + " reached, ratio " +
               one.rows[0][13] + ")";
    }
    say(lines);
    return true;
  };
  const int jobs = std::min<int>(options.jobs, static_cast<int>(selected.size()));
  std::mutex next_mutex;
  size_t next = 0;
  auto worker = [&] {
    for (;;) {
      size_t index;
      {
        std::lock_guard<std::mutex> lock(next_mutex);
        if (next == selected.size()) return;
        index = next++;
      }
      run_scenario(index, &errors[index]);
    }
  };
  std::vector<std::thread> workers;
  for (int j = 1; j < jobs; ++j) workers.emplace_back(worker);
  worker();
  for (std::thread& t : workers) t.join();
  std::vector<VariantRow> rows;
  for (size_t i = 0; i < selected.size(); ++i) {
    if (!errors[i].empty()) {
      *error = errors[i];
      return false;
    }
    rows.insert(rows.end(), scenario_rows[i].begin(), scenario_rows[i].end());
  }

  const std::vector<std::string> header = LabHeader(options);
  const Table table = RowsTable(rows);
  const std::vector<std::string> targets =
      options.full_arap ? TargetLines(rows, options.anderson_windows)
                        : std::vector<std::string>{
                              "The Anderson target concerns full_arap, not measured in this run."};
  std::string summary;
  for (const std::string& line : targets) summary += line + "\n";
  if (!WriteCsv(options.out_dir, options.stem, table, header, error) ||
      !WriteMarkdown(options.out_dir, options.stem,
                     "ARAP solver lab: iterations to a relative gap of 1e-3 and 1e-6", header,
                     {"## Targets\n\n" + summary, MarkdownTable(table, 2)}, error)) {
    return false;
  }
  for (const std::string& line : targets) progress(line);
  progress("wrote " + options.stem + " (.csv, .md) to " + options.out_dir + " in " +
           FormatFixed(MillisecondsSince(start) / 1000.0, 1) + " s");
  return true;
}

}  // namespace msdeform
