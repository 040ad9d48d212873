#include "experiments/runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <sstream>

#include <glog/logging.h>

#include "msdeform/core/scenario.h"
#include "msdeform/core/timing.h"
#include "msdeform/core/metrics.h"
#include "experiments/tables.h"
#include "msdeform/methods/graph_method.h"
#include "msdeform/methods/registry.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The band of vertices near the fixed region where arap_energy_joint is
// measured: geodesic distance (along edges) up to this fraction of the diagonal.
constexpr double kJointBand = 0.05;
// An ARAP energy (normalised: a squared relative length change) below this is
// a rigid motion to rounding (a relative stretch of 1e-6): no reference for a
// ratio. A rigid edit's converged energy is 1e-30 or so, the tables' smallest
// real one 3e-5.
constexpr double kRigidEnergy = 1e-12;

// Accuracy and distortion of the final frame, shared by every method.
void MeasureQuality(const ExperimentScenario& scenario, const Eigen::Matrix3Xd& deformed,
                    RunResult* result) {
  const Mesh& mesh = scenario.mesh;
  const double diag = BoundingBoxDiagonal(mesh);
  result->vertices = mesh.num_vertices();
  result->faces = mesh.num_faces();
  result->diagonal = diag;
  result->handle_rms_rel =
      HandleRmsError(mesh, deformed, scenario.layout, scenario.path.back()) / diag;
  result->fixed_max_rel = VertexDisplacement(mesh, deformed, scenario.layout.fixed).max / diag;
  if (scenario.has_watch) {
    const Displacement watch = VertexDisplacement(mesh, deformed, scenario.watch);
    result->leakage_rel = watch.mean / diag;
    result->leakage_max_rel = watch.max / diag;
  } else {
    result->leakage_rel = result->leakage_max_rel = kNaN;
  }
  const ArapTerms arap = ArapEnergyPerVertex(mesh, deformed);
  result->arap_energy = NormalisedArapEnergy(arap);
  const std::vector<int> band = VerticesNear(mesh, scenario.layout.fixed, kJointBand * diag);
  result->arap_energy_joint = band.empty() ? kNaN : NormalisedArapEnergy(arap, band);
  result->strain = MeanEdgeStrain(mesh, deformed);
}

// The row's ARAP energy over the reference's and its vertices' mean and
// largest distance to the reference's, over the diagonal (MeasureQuality
// first); NaN without a reference, and the ratio NaN when the reference's
// energy is below kRigidEnergy (a rigid edit: a ratio of rounding residues). The reference's
// energy is measured here as arap_energy is, so a row whose vertices equal
// the reference's has ratio exactly 1 and distances 0.
void MeasureAgainstReference(const ExperimentScenario& scenario, const Eigen::Matrix3Xd& deformed,
                             const Eigen::Matrix3Xd* reference, RunResult* result) {
  if (reference == nullptr) {
    result->arap_energy_ratio = result->ref_distance_rel = result->ref_distance_max_rel = kNaN;
    return;
  }
  const double reference_energy =
      NormalisedArapEnergy(ArapEnergyPerVertex(scenario.mesh, *reference));
  result->arap_energy_ratio =
      reference_energy >= kRigidEnergy ? result->arap_energy / reference_energy : kNaN;
  const Eigen::VectorXd distance = (deformed - *reference).colwise().norm().transpose();
  result->ref_distance_rel = distance.size() == 0 ? 0.0 : distance.mean() / result->diagonal;
  result->ref_distance_max_rel =
      distance.size() == 0 ? 0.0 : distance.maxCoeff() / result->diagonal;
}

bool Contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string Int(long long value) { return std::to_string(value); }

}  // namespace

const std::vector<ResultColumn>& RunResultColumns() {
  static const std::vector<ResultColumn> columns = [] {
    using R = RunResult;
    using K = ResultColumnKind;
    std::vector<ResultColumn> c;
    const auto text = [&c](const char* name, std::string R::*field) {
      c.push_back({name, K::kText, false, field, nullptr, nullptr});
    };
    const auto integer = [&c](const char* name, int R::*field) {
      c.push_back({name, K::kInt, false, nullptr, field, nullptr});
    };
    const auto number = [&c](const char* name, double R::*field, bool timing = false) {
      c.push_back({name, K::kNumber, timing, nullptr, nullptr, field});
    };
    text("scenario", &R::scenario);
    text("method", &R::method);
    text("energy", &R::energy);
    integer("vertices", &R::vertices);
    integer("faces", &R::faces);
    number("diagonal", &R::diagonal);
    number("cell_width", &R::cell_width);
    integer("particles", &R::particles);
    integer("d1", &R::dg1_nodes);
    integer("scales_n", &R::num_scales);
    integer("shared_cells", &R::shared_cells);
    integer("selected_scale", &R::selected_scale);
    integer("scale_nodes", &R::graph_nodes);
    integer("totally_free", &R::totally_free);
    integer("half_free", &R::half_free);
    integer("nodes_optimized", &R::nodes_optimized);
    integer("variables", &R::variables);
    number("precompute_ms", &R::precompute_ms, /*timing=*/true);
    number("rigidity_ms", &R::rigidity_ms, /*timing=*/true);
    number("setup_ms", &R::setup_ms, /*timing=*/true);
    number("frame_ms", &R::frame_ms, /*timing=*/true);
    number("solve_ms", &R::solve_ms, /*timing=*/true);
    number("skin_ms", &R::skin_ms, /*timing=*/true);
    number("solve_total_ms", &R::solve_total_ms, /*timing=*/true);
    number("iterations", &R::iterations_median);
    integer("iterations_total", &R::iterations_total);
    number("final_cost", &R::final_cost);
    integer("unconverged_frames", &R::unconverged_frames);
    number("handle_rms_rel", &R::handle_rms_rel);
    number("fixed_max_rel", &R::fixed_max_rel);
    number("leakage_rel", &R::leakage_rel);
    number("leakage_max_rel", &R::leakage_max_rel);
    number("arap_energy", &R::arap_energy);
    number("arap_energy_joint", &R::arap_energy_joint);
    number("strain", &R::strain);
    number("orthogonality", &R::orthogonality);
    number("arap_energy_ratio", &R::arap_energy_ratio);
    number("ref_distance_rel", &R::ref_distance_rel);
    number("ref_distance_max_rel", &R::ref_distance_max_rel);
    number("other_backend_frame_ms", &R::other_backend_frame_ms, /*timing=*/true);
    number("wall_ms", &R::wall_ms, /*timing=*/true);
    return c;
  }();
  return columns;
}

const ResultColumn* FindResultColumn(const std::string& name) {
  for (const ResultColumn& column : RunResultColumns()) {
    if (column.name == name) return &column;
  }
  return nullptr;
}

std::vector<std::string> ResultCells(const RunResult& r, const std::vector<std::string>& columns) {
  std::vector<std::string> cells;
  for (const std::string& name : columns) {
    const ResultColumn* column = FindResultColumn(name);
    CHECK(column != nullptr) << "no RunResult column " << name;
    switch (column->kind) {
      case ResultColumnKind::kText:
        cells.push_back(r.*(column->text));
        break;
      case ResultColumnKind::kInt:
        cells.push_back(Int(r.*(column->integer)));
        break;
      case ResultColumnKind::kNumber:
        cells.push_back(FormatNumber(r.*(column->number)));
        break;
    }
  }
  return cells;
}

bool RunMethod(const ExperimentScenario& scenario, const std::string& method_name,
               const MethodOptions& options, const std::string& label,
               const Eigen::Matrix3Xd* reference, RunResult* result, Eigen::Matrix3Xd* deformed,
               std::string* error) {
  const auto wall_start = Clock::now();
  *result = RunResult();
  result->scenario = scenario.name;
  result->method = label;
  result->energy = MinimisedEnergy(method_name, options.deformer);
  std::unique_ptr<EditingMethod> method = CreateMethod(method_name, error);
  if (method == nullptr || !method->Precompute(scenario.mesh, options, error) ||
      !method->SetHandles(scenario.layout, error)) {
    *error = scenario.name + " / " + label + ": " + *error;
    return false;
  }
  std::vector<double> frame_ms, solve_ms, skin_ms, iterations;
  const int num_frames = static_cast<int>(scenario.path.size());
  for (int f = 0; f < num_frames; ++f) {
    MethodStats stats;
    if (!method->Drag(scenario.path[f], &stats, error)) {
      *error = scenario.name + " / " + label + ": frame " + std::to_string(f + 1) + " of " +
               std::to_string(num_frames) + ": " + *error;
      return false;
    }
    frame_ms.push_back(stats.frame_ms);
    solve_ms.push_back(stats.solve_ms);
    skin_ms.push_back(stats.skin_ms);
    iterations.push_back(stats.iterations);
    result->iterations_total += stats.iterations;
    result->solve_total_ms += stats.solve_ms;
    result->final_cost = stats.final_cost;
    if (!stats.converged) ++result->unconverged_frames;
  }
  if (const Lattice* lattice = method->lattice()) {
    result->cell_width = lattice->cell_width();
    result->particles = lattice->num_particles();
    const int num_particles = lattice->num_surface_particles();
    std::vector<char> holds_fixed(num_particles, 0), counted(num_particles, 0);
    for (int v : scenario.layout.fixed) holds_fixed[lattice->particle_of_vertex(v)] = 1;
    for (int v : scenario.layout.moveable) {
      const int cell = lattice->particle_of_vertex(v);
      if (holds_fixed[cell] && !counted[cell]) {
        counted[cell] = 1;
        ++result->shared_cells;
      }
    }
  }
  const Eigen::Matrix3Xd& final_vertices = method->deformed_vertices();
  result->orthogonality = kNaN;
  if (const GraphMethod* deformer = method->graph_method()) {
    result->dg1_nodes = deformer->graphs()[0].num_nodes();
    result->num_scales = deformer->options().method == Method::kMultiScale
                             ? static_cast<int>(deformer->graphs().size())
                             : 1;
    result->selected_scale = deformer->active_graph() + 1;
    result->graph_nodes = deformer->active().num_nodes();
    std::vector<int> optimised;
    for (int j = 0; j < static_cast<int>(deformer->node_classes().size()); ++j) {
      const NodeClass c = deformer->node_classes()[j];
      result->totally_free += c == NodeClass::kTotallyFree;
      result->half_free += c == NodeClass::kHalfFree;
      if (c != NodeClass::kFixed) optimised.push_back(j);
    }
    result->orthogonality = OrthogonalityError(deformer->transforms(), optimised);
  }
  result->nodes_optimized = method->nodes_optimized();
  result->variables = method->variables();
  result->precompute_ms = method->precompute_ms();
  result->rigidity_ms = method->rigidity_ms();
  result->setup_ms = method->setup_ms();
  result->frame_ms = Median(frame_ms);
  result->solve_ms = Median(solve_ms);
  result->skin_ms = Median(skin_ms);
  result->iterations_median = Median(iterations);
  MeasureQuality(scenario, final_vertices, result);
  MeasureAgainstReference(scenario, final_vertices, reference, result);
  result->other_backend_frame_ms = kNaN;
  if (deformed != nullptr) *deformed = final_vertices;
  result->wall_ms = MillisecondsSince(wall_start);
  return true;
}

bool RunDeformer(const ExperimentScenario& scenario, const DeformerOptions& options,
                 const std::string& label, const Eigen::Matrix3Xd* arap_result,
                 RunResult* result, std::string* error) {
  MethodOptions method_options;
  method_options.deformer = options;
  return RunMethod(scenario, MethodName(options.method), method_options, label, arap_result,
                   result, nullptr, error);
}

bool RunCgalArap(const ExperimentScenario& scenario, const CgalArapOptions& options,
                 RunResult* result, Eigen::Matrix3Xd* deformed, std::string* error) {
  MethodOptions method_options;
  method_options.cgal = options;
  Eigen::Matrix3Xd own;
  if (!RunMethod(scenario, "cgal_arap", method_options, "cgal_arap", nullptr, result, &own,
                 error)) {
    return false;
  }
  MeasureAgainstReference(scenario, own, &own, result);
  if (deformed != nullptr) *deformed = std::move(own);
  return true;
}

bool RunnerOptions::Check(std::string* error) const {
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
  if (energies.empty()) {
    *error = "energies: give at least one of " + EnergyNames().Expected();
    return false;
  }
  for (size_t i = 0; i < energies.size(); ++i) {
    if (std::find(energies.begin(), energies.begin() + i, energies[i]) != energies.begin() + i) {
      *error = std::string("energies: '") + EnergyName(energies[i]) + "' is given twice";
      return false;
    }
  }
  for (const std::string& method : methods) {
    if (!IsMethodName(method)) {
      *error = "methods: unknown method '" + method + "' (expected " + MethodNameList() + ")";
      return false;
    }
  }
  for (const std::string& method : other_backend_methods) {
    if (!IsMethodName(method)) {
      *error = "other_backend_methods: unknown method '" + method + "' (expected " +
               MethodNameList() + ")";
      return false;
    }
  }
  for (const std::string* method : {&reference_method, &table1_method}) {
    if (!method->empty() && !IsMethodName(*method)) {
      *error = "unknown method '" + *method + "' (expected " + MethodNameList() + ")";
      return false;
    }
  }
  // The graph methods' rows run under each of `energies` (WithEnergy), and
  // the others under the base energy.
  MethodOptions row = method_options;
  row.deformer = WithEnergy(row.deformer, row.deformer.energy);
  if (!row.Check(error)) return false;
  for (const Energy energy : energies) {
    row.deformer = WithEnergy(method_options.deformer, energy);
    if (!row.Check(error)) return false;
  }
  return true;
}

namespace {

// A named change of the base options: an ablation.
struct Variant {
  std::string name;
  std::function<void(DeformerOptions*)> apply;
};

std::vector<Variant> Ablations() {
  return {
      {"multiscale", [](DeformerOptions*) {}},
      // The paper's procedure as written (PaperProcedure).
      {"paper", [](DeformerOptions* o) { *o = PaperProcedure(*o); }},
      // One change of the default each.
      {"rigidity_paper",
       [](DeformerOptions* o) { o->rigidity.model = RigidityModel::kShapeMatching; }},
      {"half_free_every_fixed_node",
       [](DeformerOptions* o) { o->selection.half_free = HalfFreeRule::kEveryFixedHandleNode; }},
      {"border_fixed", [](DeformerOptions* o) { o->selection.border = BorderRule::kFixed; }},
      {"border_half_free", [](DeformerOptions* o) { o->selection.border = BorderRule::kHalfFree; }},
      {"no_fixed_vertex_terms", [](DeformerOptions* o) { o->hold_fixed_vertices = false; }},
      {"no_pin_fixed_region",
       [](DeformerOptions* o) { o->selection.pin_fixed_region = false; }},
      {"no_split_cells", [](DeformerOptions* o) { o->lattice.split_cells = false; }},
      // The paper's Fig. 5 ablations. They act on Half Free nodes, which only
      // an unpinned fixed region has: compare them with no_pin_fixed_region.
      {"keep_left_out_terms",
       [](DeformerOptions* o) {
         o->selection.pin_fixed_region = false;
         o->keep_left_out_terms = true;
       }},
      {"fix_fixed_handle_nodes",
       [](DeformerOptions* o) {
         o->selection.pin_fixed_region = false;
         o->fix_fixed_handle_nodes = true;
       }},
      {"alpha_all_one", [](DeformerOptions* o) { o->selection.alpha_all_one = true; }},
      {"member_extent_mean",
       [](DeformerOptions* o) { o->selection.member_extent = MemberExtent::kMean; }},
      // A stiffer handle (Eq. 17's w_con, default 100): the handle error
      // against the distortion it costs, for comparing with static_dense at
      // equal handle error.
      {"w_con_1e3", [](DeformerOptions* o) { o->w_con = 1e3; }},
      {"w_con_1e4", [](DeformerOptions* o) { o->w_con = 1e4; }},
      // The subspace ARAP energy (--energy=arap, solvers/subspace_arap.h) on
      // the default, then one of its options changed each: the rotation
      // clusters (default: k-means on the skinning weights) and the handle
      // and fixed vertices (default: exact).
      {"energy_arap", [](DeformerOptions* o) { o->energy = Energy::kArap; }},
      {"arap_clusters_nodes",
       [](DeformerOptions* o) {
         o->energy = Energy::kArap;
         o->arap.clusters = RotationClusters::kNodes;
       }},
      {"arap_clusters_vertices",
       [](DeformerOptions* o) {
         o->energy = Energy::kArap;
         o->arap.clusters = RotationClusters::kVertices;
       }},
      {"arap_soft_constraints",
       [](DeformerOptions* o) {
         o->energy = Energy::kArap;
         o->arap.constraints = ArapConstraints::kSoft;
       }},
  };
}

std::string Describe(const RunResult& r) {
  std::ostringstream line;
  line << r.method;
  if (IsGraphMethod(r.method)) line << "/" << r.energy;
  line << " " << FormatNumber(r.frame_ms, 3) << " ms/frame ("
       << r.nodes_optimized << " nodes)";
  return line.str();
}

}  // namespace

namespace {

// The columns of the three tables, by RunResult column name (RunResultColumns).
const std::vector<std::string>& Table1Columns() {
  static const std::vector<std::string> columns = {
      "scenario",      "vertices",       "faces",        "cell_width",   "particles",
      "d1",            "scales_n",       "precompute_ms", "rigidity_ms", "setup_ms",
      "selected_scale", "scale_nodes",   "totally_free", "half_free",    "nodes_optimized",
      "variables",     "frame_ms"};
  return columns;
}
const std::vector<std::string>& Table2Columns() {
  static const std::vector<std::string> columns = {
      "scenario",          "method",          "energy",          "vertices",
      "nodes_optimized",   "variables",       "frame_ms",        "solve_ms",
      "skin_ms",           "setup_ms",        "iterations",      "unconverged_frames",
      "handle_rms_rel",    "fixed_max_rel",   "arap_energy",     "arap_energy_ratio",
      "arap_energy_joint", "strain",          "leakage_rel",     "leakage_max_rel",
      "orthogonality",     "ref_distance_rel", "ref_distance_max_rel",
      "other_backend_frame_ms", "precompute_ms", "rigidity_ms"};
  return columns;
}
const std::vector<std::string>& AblationColumns() {
  static const std::vector<std::string> columns = {
      "scenario",       "method",          "energy",        "selected_scale", "nodes_optimized",
      "variables",      "frame_ms",        "iterations",    "handle_rms_rel", "fixed_max_rel",
      "arap_energy",    "arap_energy_ratio", "arap_energy_joint", "strain",   "leakage_rel",
      "leakage_max_rel", "orthogonality",  "ref_distance_rel", "ref_distance_max_rel"};
  return columns;
}

// What a run covers once the options are resolved: the scenario files, the
// methods of table 2, the ablation scenarios and the frame count.
struct RunPlan {
  std::vector<std::string> scenario_files;
  std::vector<std::string> methods;
  std::vector<std::string> ablation_scenarios;
  int frames = 0;
};

bool PlanRun(const RunnerOptions& options, RunPlan* plan, std::string* error) {
  // The scenario entries, in name order.
  std::vector<std::string> files;
  if (!ListScenarioFiles(options.scenario_dir, &files, error)) return false;
  std::vector<std::string> only = options.only;
  plan->methods = options.methods;
  if (plan->methods.empty()) plan->methods = MethodNames();
  plan->ablation_scenarios = options.ablation_scenarios;
  plan->frames = options.frames;
  if (options.quick) {
    if (only.empty()) only = {"cactus", "hand_finger"};
    plan->ablation_scenarios = {"cactus"};
    if (plan->frames == 0) plan->frames = 5;
  }
  for (const std::string& file : files) {
    if (only.empty() || Contains(only, fs::path(file).stem().string())) {
      plan->scenario_files.push_back(file);
    }
  }
  if (plan->scenario_files.empty()) {
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

struct ExperimentTables {
  Table table1{"Table 1: the multi-scale method per model (paper Table 1)", {}, {}, {}};
  Table table2{"Table 2: multi-scale against the single static graphs, CGAL's ARAP and SR-ARAP, "
               "FastLSM, rigid cells and the converged ARAP energy",
               Table2Columns(), {}, {}};
  Table ablations{"Ablations (docs/method.md §7; paper Fig. 5 and 7)", {}, {}, {}};

  ExperimentTables() {
    table1.columns = {"model"};
    table1.columns.insert(table1.columns.end(), Table1Columns().begin(), Table1Columns().end());
    // The ablations name a row's method its variant.
    ablations.columns = AblationColumns();
    ablations.columns[1] = "variant";
  }
};

// Table 2's rows of one scenario (every method of the plan, the graph
// methods once per energy; the reference method first) and its table 1 row.
bool RunScenarioMethods(const ExperimentScenario& scenario, const RunnerOptions& options,
                        const RunPlan& plan, const MethodOptions& method_base,
                        Eigen::Matrix3Xd* reference_result, ExperimentTables* tables,
                        std::ostringstream* line, std::string* error) {
  const DeformerOptions& base = method_base.deformer;
  // The reference method first, once: its final mesh is the reference of
  // every row's arap_energy_ratio and ref_distance_*; its own row is measured
  // against itself (ratio 1, distances 0).
  const bool run_reference =
      !options.reference_method.empty() && Contains(plan.methods, options.reference_method);
  RunResult reference_row;
  if (run_reference) {
    if (!RunMethod(scenario, options.reference_method, method_base, options.reference_method,
                   nullptr, &reference_row, reference_result, error)) {
      return false;
    }
    MeasureAgainstReference(scenario, *reference_result, reference_result, &reference_row);
  }
  const Eigen::Matrix3Xd* reference = run_reference ? reference_result : nullptr;
  for (const std::string& method : MethodNames()) {
    if (!Contains(plan.methods, method)) continue;
    // The graph methods once per energy, the others once.
    const std::vector<Energy> row_energies =
        IsGraphMethod(method) ? options.energies : std::vector<Energy>{base.energy};
    for (const Energy energy : row_energies) {
      MethodOptions run_options = method_base;
      run_options.deformer = WithEnergy(run_options.deformer, energy);
      RunResult r;
      if (method == options.reference_method && energy == base.energy) {
        r = reference_row;
      } else if (!RunMethod(scenario, method, run_options, method, reference, &r, nullptr,
                            error)) {
        return false;
      }
      if (options.time_other_backend && Contains(options.other_backend_methods, method) &&
          energy == Energy::kEd) {
        MethodOptions other_options = run_options;
        other_options.deformer.backend =
            base.backend == Solver::kCeres ? Solver::kGaussNewton : Solver::kCeres;
        RunResult other;
        if (!RunMethod(scenario, method, other_options, method, nullptr, &other, nullptr,
                       error)) {
          return false;
        }
        r.other_backend_frame_ms = other.frame_ms;
      }
      tables->table2.AddRow(ResultCells(r, Table2Columns()));
      *line << " " << Describe(r) << ";";
      if (method == options.table1_method && energy == row_energies.front()) {
        *line << " [scale " << r.selected_scale << "/" << r.num_scales << ", "
              << r.shared_cells << " particles shared by handle and fixed]";
        std::vector<std::string> row = {fs::path(scenario.mesh_path).stem().string()};
        const std::vector<std::string> cells = ResultCells(r, Table1Columns());
        row.insert(row.end(), cells.begin(), cells.end());
        tables->table1.AddRow(row);
      }
    }
  }
  return true;
}

// The ablation rows of one scenario: the multi-scale method with each variant.
bool RunScenarioAblations(const ExperimentScenario& scenario, const DeformerOptions& base,
                          const Eigen::Matrix3Xd* reference, ExperimentTables* tables,
                          std::string* error) {
  for (const Variant& variant : Ablations()) {
    DeformerOptions run_options = base;
    run_options.method = Method::kMultiScale;
    variant.apply(&run_options);
    run_options = WithEnergy(run_options, run_options.energy);  // arap.* for arap variants only
    RunResult r;
    if (!RunDeformer(scenario, run_options, variant.name, reference, &r, error)) return false;
    tables->ablations.AddRow(ResultCells(r, AblationColumns()));
  }
  return true;
}

// The tables' headers (provenance, settings, base options) and notes, then
// the three tables as .csv and .md.
bool WriteExperimentTables(const RunnerOptions& options, const RunPlan& plan,
                           const DeformerOptions& base, ExperimentTables* tables,
                           std::string* error) {
  const int frames = plan.frames;
  Table& table1 = tables->table1;
  Table& table2 = tables->table2;
  Table& ablations = tables->ablations;
  std::ostringstream settings;
  settings << "settings: " << (options.quick ? "quick subset, " : "full run, ")
           << (frames > 0 ? std::to_string(frames) + " frames per drag"
                          : std::string("each scenario's frames"))
           << ", " << options.threads << " thread(s), " << SolverName(base.backend)
           << " backend, max " << base.stopping.max_iterations << " iterations per frame, CGAL "
           << options.method_options.cgal.iterations << " iterations per frame, FastLSM "
           << options.method_options.fastlsm.steps_per_frame << " steps per frame (r = "
           << options.method_options.fastlsm.region_half_width << ", damping " << options.method_options.fastlsm.damping
           << "), seed " << base.graph.seed << ", graph methods with energies";
  for (size_t i = 0; i < options.energies.size(); ++i) {
    settings << (i == 0 ? " " : ", ") << EnergyName(options.energies[i]);
  }
  std::vector<std::string> header = ProvenanceLines();
  header.push_back(settings.str());
  // Every setting that changes a number: the base options each row starts
  // from (a row then sets its method, backend or one ablation).
  std::string described = "base options:";
  for (const auto& [name, value] : DescribeOptions(base)) described += " " + name + "=" + value;
  header.push_back(described);
  const std::string units =
      "Times in ms (medians over the drag frames); *_rel lengths are divided by the bounding-box "
      "diagonal; arap_energy is the cotangent ARAP energy over the rest edge energy "
      "(core/metrics.h); arap_energy_joint is the same over the vertices within 5% of the "
      "diagonal (along edges) of the fixed region. Empty cells: not applicable.";
  const std::string against_reference =
      options.reference_method.empty() || !Contains(plan.methods, options.reference_method)
          ? std::string("arap_energy_ratio, ref_distance_rel and ref_distance_max_rel: empty (no "
                        "reference method run).")
          : "arap_energy_ratio = arap_energy over the " + options.reference_method +
                " row's of the same scenario (the reference, run once per scenario); "
                "ref_distance_rel / ref_distance_max_rel = mean / largest vertex distance to "
                "its final mesh over the diagonal (its own row: 1, 0, 0; the ratio is empty "
                "where the reference's energy is below 1e-12, a rigid motion).";
  table1.notes.push_back(std::string("The run of table 2 with energy ") +
                         EnergyName(options.energies.front()) + ".");
  table1.notes.push_back("nodes_optimized = Totally + Half Free nodes of the selected scale; "
                         "variables = 12 per Totally Free + 9 per Half Free node.");
  table2.notes.push_back(units);
  table2.notes.push_back(against_reference);
  table2.notes.push_back(
      "energy: what the row minimised. multiscale, static and static_dense run once per energy: "
      "ed (Eq. 17, the paper's) and arap (the mesh's cotangent ARAP energy over the selected "
      "graph's subspace, --energy=arap, solvers/subspace_arap.h); cgal_arap: arap (the same "
      "energy, one rotation per vertex, every non-fixed vertex free); cgal_sr_arap: sr_arap "
      "(ARAP with rotation smoothing); fastlsm: shape_matching (lattice shape matching, no "
      "energy minimised). other_backend_frame_ms: energy ed only (Ceres does not run arap).");
  table2.notes.push_back("cgal_arap: nodes_optimized = ROI vertices (all but the fixed), "
                         "variables = 3 per ROI vertex; setup_ms = conversion + factorisation; "
                         "precompute_ms and rigidity_ms = 0 (it has neither step). cgal_sr_arap: "
                         "the same with CGAL's SR-ARAP.");
  table2.notes.push_back("fastlsm: nodes_optimized = free lattice particles (neither handle nor "
                         "fixed), variables = 3 per free particle, iterations = shape-matching "
                         "steps per frame, precompute_ms = lattice and regions, setup_ms = the "
                         "layout's particles.");
  table2.notes.push_back("rigid_cells (Botsch et al. 2007, the paper's [15]): energy rigid_cells "
                         "(their volumetric coupling of rigid lattice cells), nodes_optimized = "
                         "free cells, variables = 6 per free cell, precompute_ms = lattice, cells "
                         "and the RBF's factorisation, frame_ms with the RBF's evaluation at every "
                         "vertex. full_arap: arap (the energy arap_energy measures, one rotation "
                         "per vertex, minimised by accelerated local/global to a relative change "
                         "of 1e-9 a frame), nodes_optimized = free vertices, variables = 3 per "
                         "free vertex, setup_ms = the Laplacian's factorisation.");
  table2.notes.push_back("precompute_ms = GraphMethod::Precompute (lattice, graphs, weights); rigidity_ms = "
                         "the shape-matching estimate in SetHandles (multiscale only); setup_ms = "
                         "the rest of SetHandles (scale selection, classes, problem).");
  ablations.notes.push_back(units);
  ablations.notes.push_back(against_reference);
  ablations.notes.push_back(
      "energy: the variants before energy_arap change the default with energy ed; energy_arap "
      "is the default with --energy=arap, and the arap_* variants change one option of it "
      "(--arap_clusters=nodes or vertices, --arap_constraints=soft).");
  for (const auto& [stem, table] :
       {std::make_pair("table1", &table1), std::make_pair("table2", &table2),
        std::make_pair("ablations", &ablations)}) {
    if (!WriteTable(options.out_dir, stem, *table, header, error)) return false;
  }
  return true;
}

}  // namespace

bool RunExperiments(const RunnerOptions& options, std::string* error) {
  if (!options.Check(error)) return false;
  auto progress = [&](const std::string& line) {
    if (options.progress) options.progress(line);
  };
  const auto start = Clock::now();
  RunPlan plan;
  if (!PlanRun(options, &plan, error)) return false;

  MethodOptions method_base = options.method_options;
  method_base.deformer.num_threads = options.threads;
  method_base.deformer.graph.num_threads = options.threads;
  const DeformerOptions& base = method_base.deformer;

  ExperimentTables tables;
  int index = 0;
  for (const std::string& file : plan.scenario_files) {
    ++index;
    const auto scenario_start = Clock::now();
    ExperimentScenario scenario;
    if (!LoadExperimentScenario(file, plan.frames, &scenario, error)) return false;
    std::ostringstream line;
    line << "[" << index << "/" << plan.scenario_files.size() << "] " << scenario.name << " ("
         << scenario.mesh.num_vertices() << " vertices, " << scenario.layout.fixed.size()
         << " fixed, " << scenario.layout.moveable.size() << " handle, "
         << (scenario.has_watch ? std::to_string(scenario.watch.size()) : std::string("no"))
         << " watch, " << scenario.path.size() << " frames):";
    Eigen::Matrix3Xd reference_result;
    if (!RunScenarioMethods(scenario, options, plan, method_base, &reference_result, &tables,
                            &line, error)) {
      return false;
    }
    if (Contains(plan.ablation_scenarios, scenario.name)) {
      const bool run_reference = !options.reference_method.empty() &&
                                 Contains(plan.methods, options.reference_method);
      if (!RunScenarioAblations(scenario, base, run_reference ? &reference_result : nullptr,
                                &tables, error)) {
        return false;
      }
      line << " ablations;";
    }
    line << " " << FormatFixed(MillisecondsSince(scenario_start) / 1000.0, 1) << " s";
    progress(line.str());
  }

  if (!WriteExperimentTables(options, plan, base, &tables, error)) return false;
  progress("wrote table1, table2 and ablations (.csv, .md) to " + options.out_dir +
           " in " + FormatFixed(MillisecondsSince(start) / 1000.0, 1) + " s");
  return true;
}

}  // namespace msdeform
