// The experiment runner behind msdeform_experiments: every scenario under a
// folder with each registered editing method (methods/registry.h: the
// multi-scale method, both static baselines, CGAL's ARAP and SR-ARAP,
// FastLSM), all run through the one interface, then the ablations (docs/method.md §7), written as tables
// (experiments/results/README.md explains them):
//   table1      per model: lattice, graphs, scale, optimised nodes, times
//   table2      per scenario x method x energy: size, time, accuracy, distortion,
//               leakage (the graph methods once per energy of RunnerOptions::energies)
//   ablations   per ablation scenario x variant, with the energy each minimises
// The solver variants have their own lab (experiments/solver_lab.h).
//
//   RunnerOptions options;  // defaults: the full run
//   options.out_dir = "experiments/results";
//   RunExperiments(options, &error);

#ifndef MSDEFORM_EXPERIMENTS_RUNNER_H_
#define MSDEFORM_EXPERIMENTS_RUNNER_H_

#include <functional>
#include <string>
#include <vector>

#include "experiments/experiment_scenario.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/scales/deformer_options.h"

namespace msdeform {

// Everything measured on one run of one method on one scenario. NaN marks a
// number that does not apply (no watch region; no node rotations for a method
// that is not a graph; no energy for CGAL's and FastLSM).
struct RunResult {
  std::string scenario;
  std::string method;  // a registered method (methods/registry.h) or a variant name
  std::string energy;  // what the method minimised (MinimisedEnergy)
  int vertices = 0;
  int faces = 0;
  double diagonal = 0.0;
  // Lattice (methods with one) and graphs (graph methods); 0 otherwise.
  double cell_width = 0.0;
  int particles = 0;
  int dg1_nodes = 0;
  int num_scales = 0;
  // Surface particles holding both a fixed and a moveable vertex (should be 0).
  int shared_cells = 0;
  int selected_scale = 0;  // 1-based index of the graph solved on
  int graph_nodes = 0;     // nodes of the active graph
  int totally_free = 0;
  int half_free = 0;
  int nodes_optimized = 0;  // Totally + Half Free (CGAL: ROI vertices)
  int variables = 0;
  // Times (ms): precompute = Init, rigidity and setup = SetHandles' parts
  // (CGAL: setup = mesh conversion + preprocess), medians over frames.
  double precompute_ms = 0.0;
  double rigidity_ms = 0.0;
  double setup_ms = 0.0;
  double frame_ms = 0.0;
  double solve_ms = 0.0;
  double skin_ms = 0.0;
  double solve_total_ms = 0.0;
  // Solver (CGAL: fixed iterations per frame).
  double iterations_median = 0.0;
  int iterations_total = 0;
  double final_cost = 0.0;     // last frame
  int unconverged_frames = 0;  // frames that hit the iteration cap
  // Quality after the last frame.
  double handle_rms_rel = 0.0;
  double fixed_max_rel = 0.0;
  double leakage_rel = 0.0;      // mean watch displacement / diag (NaN: no watch)
  double leakage_max_rel = 0.0;  // max watch displacement / diag (NaN: no watch)
  double arap_energy = 0.0;      // NormalisedArapEnergy over all vertices
  double arap_energy_joint = 0.0;  // over the band near the fixed region (NaN: none)
  double strain = 0.0;
  double orthogonality = 0.0;  // mean |R^T R - I|_F over optimised nodes (NaN for CGAL)
  // Against the reference method's final mesh on the same drag
  // (RunnerOptions::reference_method, the converged full_arap by default);
  // NaN when it was not run. arap_energy over the reference's arap_energy
  // (NaN when that is below 1e-12: a rigid edit, rounding residues):
  double arap_energy_ratio = 0.0;
  // Mean and largest vertex distance to the reference's final vertices, over
  // the diagonal.
  double ref_distance_rel = 0.0;
  double ref_distance_max_rel = 0.0;
  // Median frame time with the other backend (Ceres when the run's backend
  // is Gauss-Newton and the reverse; multiscale and static; NaN when not run).
  double other_backend_frame_ms = 0.0;
  double wall_ms = 0.0;
};

// RunResult's columns, declared once (as OptionTable declares options): the
// name the tables, Python's run_deformer dicts and the sweeps spell
// ("d1" for dg1_nodes, "iterations" for iterations_median), the kind, whether
// it depends on the clock, and the field. The CSV and markdown tables pick
// their columns by name (ResultCells); Python's dicts and the sweeps'
// metric and timing columns are every column in this order. A new column
// is a RunResult field and one row in experiments/runner.cc.
enum class ResultColumnKind { kText, kInt, kNumber };
struct ResultColumn {
  std::string name;
  ResultColumnKind kind = ResultColumnKind::kNumber;
  bool timing = false;  // a time: differs between runs of the same task
  std::string RunResult::*text = nullptr;    // kText
  int RunResult::*integer = nullptr;         // kInt
  double RunResult::*number = nullptr;       // kNumber (NaN: does not apply)
};
const std::vector<ResultColumn>& RunResultColumns();
// The column named `name`, or null.
const ResultColumn* FindResultColumn(const std::string& name);
// The cells of `r` in the named columns as the tables print them: text as
// is, integers in decimal, numbers with FormatNumber (empty for NaN).
std::vector<std::string> ResultCells(const RunResult& r, const std::vector<std::string>& columns);

// The tables' `energy` cell is MinimisedEnergy (methods/registry.h): the
// graph methods' DeformerOptions::energy ("ed": Eq. 17; "arap": the mesh's
// cotangent ARAP energy over the graph's subspace), another method's
// descriptor energy ("arap" for cgal_arap, "sr_arap" for cgal_sr_arap,
// "shape_matching" for fastlsm). Whether a method is a graph is
// IsGraphMethod (methods/registry.h).

// Runs the registered method `method` with `options` over the scenario's drag
// path through the method interface and measures it. `label` names the row
// (the method or a variant). `reference`, when not null, is the reference
// method's final mesh on the same drag (for arap_energy_ratio,
// ref_distance_rel and ref_distance_max_rel; NaN without). The final mesh
// goes to *deformed when not null.
bool RunMethod(const ExperimentScenario& scenario, const std::string& method,
               const MethodOptions& options, const std::string& label,
               const Eigen::Matrix3Xd* reference, RunResult* result, Eigen::Matrix3Xd* deformed,
               std::string* error);

// RunMethod for the graph method options.method.
bool RunDeformer(const ExperimentScenario& scenario, const DeformerOptions& options,
                 const std::string& label, const Eigen::Matrix3Xd* arap_result,
                 RunResult* result, std::string* error);

// RunMethod for cgal_arap, measured against its own result (ratio 1,
// distances 0): the reference of the sweeps that name CGAL's.
bool RunCgalArap(const ExperimentScenario& scenario, const CgalArapOptions& options,
                 RunResult* result, Eigen::Matrix3Xd* deformed, std::string* error);

struct RunnerOptions {
  // Folder of the scenario entries (*.json).
  std::string scenario_dir;
  // Where the tables go (created if missing).
  std::string out_dir;

  // The CI subset: cactus and hand_finger with 5 frames, ablations on the
  // cactus only.
  bool quick = false;
  // Drag frames per scenario; 0 = the scenario's (quick: 5).
  int frames = 0;
  // Threads for Ceres and the skinning (CGAL is single-threaded).
  int threads = 1;
  // Only these scenario names (empty: all).
  std::vector<std::string> only;
  // Methods of table 2, any registered names (empty: every registered
  // method). Rows follow the registry's order.
  std::vector<std::string> methods;
  // The energies the graph methods of table 2 run with, side by side (one
  // row each, in this order; deformer.energy is set per row). The other
  // methods run once. Table 1 takes the first energy's run.
  std::vector<Energy> energies = {Energy::kEd, Energy::kArap};
  // The method whose final mesh is the reference of arap_energy_ratio,
  // ref_distance_rel and ref_distance_max_rel of every row of table 2 and the
  // ablations (run once per scenario, first, when it is among `methods`; its
  // own row then has ratio 1 and distances 0; empty: none). The default is
  // the converged ARAP energy the tables measure (methods/full_arap.h).
  std::string reference_method = "full_arap";
  // The method of table 1 (one row per scenario when it is run).
  std::string table1_method = "multiscale";
  // Also time these methods with the other backend of options.deformer
  // (other_backend_frame_ms) when time_other_backend, on the energy ed only
  // (the Ceres backend does not run energy arap).
  bool time_other_backend = true;
  std::vector<std::string> other_backend_methods = {"multiscale", "static"};
  // Scenarios of the ablation table (full run); camel_hoof_lift_free_leg is
  // the edit with a free limb that touches the lifted one (its leakage).
  std::vector<std::string> ablation_scenarios = {"man_knee_bend", "armadillo_arm_raise",
                                                "man_leg_lift", "cactus", "cylinder_bend",
                                                "armadillo_hand_drag", "camel_hoof_drag",
                                                "camel_hoof_lift_free_leg"};
  // Base settings of every method: method_options.deformer (seed, lattice,
  // ...; method, energy (table 2) and ablation switches are set per run; the
  // ablations start from its energy, ed by default, and energy_arap and the
  // arap_* variants set arap) and each method's own rows (cgal, fastlsm).
  MethodOptions method_options;
  // Called with one line per finished scenario (and per table); may be empty.
  std::function<void(const std::string&)> progress;

  bool Check(std::string* error) const;
};

// Runs everything and writes table1, table2 and ablations (.csv and .md)
// into out_dir. False with a message on a scenario that does not load
// or a run that fails.
bool RunExperiments(const RunnerOptions& options, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_EXPERIMENTS_RUNNER_H_
