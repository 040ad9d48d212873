// The ARAP solver lab (issue 38): how many iterations, and how many
// milliseconds, each way of minimising an ARAP energy needs to come within a
// relative gap of 1e-3 and of 1e-6 of a frame's minimum.
//
// Two energies:
//   full_arap  the mesh's own ARAP energy (solvers/local_global_arap.h):
//              plain local/global against Anderson acceleration of windows
//              3, 5 and 10 (there is no Gauss-Newton solver for it).
//   subspace   the subspace ARAP energy of --energy=arap
//              (solvers/arap_solver.h): its local/global solver, plain and
//              with the Anderson windows (arap.anderson_window), against its
//              Gauss-Newton solver, run through GraphMethod.
//
// full_arap, per scenario: a reference run (Anderson 5, relative tolerance
// `reference_tolerance`, i.e. until an iteration no longer lowers the energy)
// drags through every frame from the rest pose, each frame warm-started from
// the previous one's converged result; its energy at frame f is E*_f. Then
// every variant solves each measured frame f once, from the reference's
// converged frame f - 1 (the rest pose for f = 1), with tolerance 0 and
// `max_iterations`, and its energy trace gives the first iteration (and the
// milliseconds) where (E - E*_f) / E*_f <= 1e-3 and <= 1e-6.
//
// subspace, per scenario: the solver lab's reference (experiments/
// solver_lab.h ReferenceOptions: Gauss-Newton, tolerances 1e-14) gives E*_f;
// each variant drags through every frame warm-started from its own previous
// frame (the GraphMethod keeps its own state; each frame runs to the cap or
// to function and parameter tolerances of 1e-12, so the previous frame is
// converged wherever the variant converges) and the measured frames' traces are read as above.
//
//   ArapLabOptions options;
//   options.scenario_dir = "experiments/scenarios";
//   options.out_dir = "experiments/results";
//   RunArapLab(options, &error);  // arap_solvers.csv, arap_solvers.md
//
// (the CLI: msdeform_arap_lab, experiments/arap_lab_main.cc.)

#ifndef MSDEFORM_EXPERIMENTS_ARAP_LAB_H_
#define MSDEFORM_EXPERIMENTS_ARAP_LAB_H_

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"
#include "msdeform/methods/graph_method.h"

namespace msdeform {

// The two relative gaps the lab times.
constexpr double kArapLabLooseGap = 1e-3;
constexpr double kArapLabTightGap = 1e-6;

// The edits the results README calls large (experiments/results/README.md).
const std::vector<std::string>& ArapLabLargeEdits();

struct ArapLabOptions {
  // Folder of the scenario entries (*.json).
  std::string scenario_dir;
  // Where arap_solvers.{csv,md} go (created if missing).
  std::string out_dir;
  // Only these scenario names (file stems; empty: all).
  std::vector<std::string> only;
  // Drag frames per scenario; 0 = the scenario's.
  int frames = 0;
  // The 1-based frames measured (those beyond the drag are left out); the
  // reference still runs through every frame up to the last measured one.
  std::vector<int> measured_frames = {1, 10, 20, 30};
  // full_arap: Anderson windows compared with plain local/global (window 0).
  std::vector<int> anderson_windows = {3, 5, 10};
  // full_arap: iterations per measured frame at most, every variant alike.
  int max_iterations = 3000;
  // full_arap reference: Anderson window, relative tolerance, cap.
  int reference_window = 5;
  double reference_tolerance = 1e-13;
  int reference_max_iterations = 20000;
  // The full_arap rows (plain and Anderson) and the subspace energy's rows
  // (local/global and Gauss-Newton); at least one.
  bool full_arap = true;
  bool subspace = true;
  // Subspace reference: Gauss-Newton iterations per frame at most.
  int subspace_reference_iterations = 500;
  // The file stem of the tables (<stem>.csv, <stem>.md).
  std::string stem = "arap_solvers";
  // Subspace: iterations per frame at most, local/global and Gauss-Newton.
  int subspace_local_global_iterations = 2000;
  int subspace_gauss_newton_iterations = 100;
  // Threads of the local/global steps and the GraphMethod, per scenario.
  int threads = 1;
  // Scenarios measured at the same time (each on its own thread(s); the
  // timings then share the machine's memory bandwidth).
  int jobs = 1;
  // The subspace energy's settings (the solver fields are the lab's).
  DeformerOptions deformer;
  // Called with one line per scenario x variant; may be empty.
  std::function<void(const std::string&)> progress;

  bool Check(std::string* error) const;
};

// The first iteration i of `energy_trace` (entry 0: the start) with
// (energy_trace[i] - minimum) / minimum <= gap (the absolute difference when
// minimum is 0), and ms_trace[i]; false when none is.
bool FirstIterationWithin(const std::vector<double>& energy_trace,
                          const std::vector<double>& ms_trace, double minimum, double gap,
                          int* iteration, double* ms);

// One measured frame of one variant.
struct ArapLabFrame {
  std::string variant;
  int frame = 0;              // 1-based
  double minimum = 0.0;       // E*_f
  int iterations = 0;         // iterations run (to the cap or no decrease)
  double ms = 0.0;            // the whole solve
  double final_energy = 0.0;
  // -1 where the gap is not reached within the cap.
  int loose_iterations = -1;
  double loose_ms = -1.0;
  int tight_iterations = -1;
  double tight_ms = -1.0;
};

// The full_arap part on one edit: the reference through the frames, then
// every variant (plain, then anderson_windows in order; names "plain",
// "anderson_3", ...) on each measured frame. Frames in variant order, then
// frame order. False with one line on a bad layout or a reference frame that
// does not finish.
bool MeasureFullArap(const Mesh& mesh, const HandleLayout& layout,
                     const std::vector<HandleTransforms>& path, const ArapLabOptions& options,
                     std::vector<ArapLabFrame>* frames, std::string* error);

// The subspace part on one edit: names "local_global" and "gauss_newton".
bool MeasureSubspaceArap(const Mesh& mesh, const HandleLayout& layout,
                         const std::vector<HandleTransforms>& path, const ArapLabOptions& options,
                         std::vector<ArapLabFrame>* frames, std::string* error);

// Runs both parts on every selected scenario and writes arap_solvers.csv
// (one row per scenario x energy x variant, medians over the measured
// frames) and arap_solvers.md (the targets' summary lines, then the table).
bool RunArapLab(const ArapLabOptions& options, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_EXPERIMENTS_ARAP_LAB_H_
