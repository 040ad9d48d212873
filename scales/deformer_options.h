// The options of the graph methods (GraphMethod, methods/graph_method.h):
// the method, the method's parts (lattice, graphs, rigidity, scale
// selection), the weights of Eq. 17 and the per-frame solve, with their names
// as reports and flags spell them.

#ifndef MSDEFORM_SCALES_DEFORMER_OPTIONS_H_
#define MSDEFORM_SCALES_DEFORMER_OPTIONS_H_

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/lattice.h"
#include "msdeform/core/option_table.h"
#include "msdeform/scales/rigidity.h"
#include "msdeform/scales/scale_selection.h"
#include "msdeform/solvers/ceres_solver.h"
#include "msdeform/solvers/deformation_energy.h"
#include "msdeform/solvers/frame_solver.h"
#include "msdeform/solvers/frame_solver_factory.h"
#include "msdeform/solvers/gauss_newton_solver.h"
#include "msdeform/solvers/subspace_arap.h"

namespace msdeform {

enum class Method { kMultiScale, kStatic, kStaticDense };

// The backend (enum Solver) is declared with the frame solver factory
// (solvers/frame_solver_factory.h).

// What a frame minimises: Eq. 17, the paper's embedded-deformation energy
// (ed), or the mesh's own cotangent ARAP energy over the selected graph's
// subspace (arap; solvers/subspace_arap.h, docs/method.md §9).
enum class Energy { kEd, kArap };

// Where a frame's solve starts: the rest pose (R = I, t = 0: no warm start),
// the previous frame's solution (warm start), or its linear extrapolation
// from the last two frames, x_f + (x_f - x_{f-1}), where that starts with a
// lower energy than x_f (x_f on the first two frames of a layout).
enum class InitialGuess { kRest, kPrevious, kExtrapolated };

// "multiscale", "static", "static_dense".
const EnumNames<Method>& GraphMethodNames();
const char* MethodName(Method method);
bool ParseMethod(const std::string& name, Method* method);
// "gauss_newton", "ceres".
const EnumNames<Solver>& SolverNames();
const char* SolverName(Solver solver);
bool ParseSolver(const std::string& name, Solver* solver);
// "ed", "arap".
const EnumNames<Energy>& EnergyNames();
const char* EnergyName(Energy energy);
// "previous", "extrapolated", "rest".
const EnumNames<InitialGuess>& InitialGuessNames();
const char* InitialGuessName(InitialGuess guess);
bool ParseInitialGuess(const std::string& name, InitialGuess* guess);

struct DeformerOptions;
// Sets the multi-scale method's variant switches (rigidity.model,
// selection.half_free, selection.border) from their names, as the command-line
// flags --rigidity, --half_free and --border spell them; false with
// "--<flag>=<value>: expected ..." when a name is not one.
bool ParseMethodVariant(const std::string& rigidity, const std::string& half_free,
                        const std::string& border, DeformerOptions* options,
                        std::string* error);

struct DeformerOptions {
  Method method = Method::kMultiScale;
  LatticeOptions lattice;            // cell width (default diag / 48)
  GraphOptions graph;                // k = 4, P = 100, seed
  RigidityOptions rigidity;          // S = 20 steps, ...
  ScaleSelectionOptions selection;   // thresholds, alpha, ablation switches
  // Nodes of the static baseline graph (Sumner et al. 2007 used about 220).
  int static_nodes = 220;
  // The energy each frame minimises, and the subspace ARAP energy's options
  // (rotation clusters, exact or soft constraints).
  Energy energy = Energy::kEd;
  ArapOptions arap;
  // Eq. 17 weights (used as sqrt residual scales).
  double w_rot = 1.0;
  double w_coh = 10.0;
  double w_con = 100.0;
  // Unit of length of the coherence and position residuals (they are divided
  // by it), so that the weights above do not depend on the mesh's units; 0
  // means the bounding-box diagonal (docs/decisions/length-unit.md).
  double length_unit = 0.0;
  // Multi-scale: fixed-handle vertices skinned by a non-Fixed node get a
  // Position term to their rest position, as the static baselines' fixed
  // handles do (the paper has none: false; docs/decisions/node-classes.md, "Node classes
  // on large fixed regions").
  bool hold_fixed_vertices = true;
  // Ablation "Deformed 2" (paper Fig. 5): keep E(j, k) for Half Free j.
  bool keep_left_out_terms = false;
  // Ablation "Deformed 3": fixed-handle nodes get no rotation (Fixed, not Half
  // Free); overrides selection.half_free with HalfFreeRule::kNone.
  bool fix_fixed_handle_nodes = false;
  // Threads for skinning, the Ceres solve and, when graph.num_threads is 0,
  // the graph building.
  int num_threads = 2;
  // Multi-scale: coarse scales whose skinning data (nearest nodes, weights,
  // edges: a pass over every vertex each) is kept once built. A scale's data
  // is built when SetHandles first selects (or tries) it, not in Init; beyond
  // this many the least recently used is dropped. DG1's is always kept.
  int cached_scales = 4;
  // Terms beyond Eq. 17, appended to each layout's energy after its own
  // (energies/energy_term.h; docs/extending.md, "Adding an energy term"):
  // called with the active graph (node ids, rest positions). Empty: Eq. 17
  // alone. Code, not an option: no flag, report line or Python keyword.
  std::function<void(const DeformationGraph& graph, DeformationEnergy* energy)> add_energy_terms;

  // The per-frame solve. Both backends minimise the same energy and stop on
  // the same rule (solvers/frame_solver.h): at most 20 iterations, function
  // tolerance 1e-8, gradient 1e-10, parameter 1e-10.
  Solver backend = Solver::kGaussNewton;
  StoppingRule stopping;
  // The previous frame's solution. The extrapolated guess saves iterations on
  // some multi-scale edits and costs many on others (the static cactus: 4.5x
  // the factorisations); docs/decisions/solver-seam.md.
  InitialGuess initial_guess = InitialGuess::kPrevious;
  // Gauss-Newton: sparse Cholesky (supernodal), factorisation
  // lagged across iterations and frames (refactorised when a step fails to
  // shrink the gradient), damping only as a safeguard.
  GaussNewtonOptions gauss_newton;
  // Ceres: Levenberg-Marquardt, SPARSE_NORMAL_CHOLESKY on EIGEN_SPARSE,
  // grouped position terms.
  CeresOptions ceres;

  bool Check(std::string* error) const;
};

// Every option of the graph methods is a row of DeformerOptionTable(), whose
// rows are declared at the end of this header (DeclareDeformerOptionRows):
// name as the struct spells it ("stopping.max_iterations"), type, help,
// range, enum names, the command-line topic and the legacy flag spellings
// ("solver" for backend, "cell_width" for lattice.cell_width), which every
// front end accepts as aliases. DescribeOptions, the flags
// (apps/flags/deformer_flags.h), the Python keywords and the editor's panels
// are derived from it; a new option is a struct field plus its row
// (docs/extending.md, "Adding an option"). The embedded structs' rows are at
// the end of their own headers (core/lattice.h, core/deformation_graph.h,
// scales/rigidity.h, scales/scale_selection.h, solvers/frame_solver.h,
// solvers/gauss_newton_solver.h, solvers/ceres_solver.h,
// solvers/subspace_arap.h), with their tables' getters.

// Every field of `options` as (name, value) pairs, in declaration order, with
// names as in the struct ("stopping.max_iterations") and numbers printed
// exactly (%.17g): what reports and table headers record so a run can be
// repeated. DeformerOptionTable().Describe(options).
std::vector<std::pair<std::string, std::string>> DescribeOptions(const DeformerOptions& options);

// `options` with the multi-scale method as the paper writes it: lattice
// shape-matching rigidity, every fixed-handle node Half Free, the Fixed nodes
// at the border kept Fixed, no Position terms on fixed vertices
// (docs/method.md §7; the CLI's --rigidity=paper
// --half_free=every_fixed_handle_node --border=fixed --hold_fixed_vertices=false).
DeformerOptions PaperProcedure(DeformerOptions options);

// `options` minimising `energy`, with the arap.* options, which only
// energy=arap reads (Check refuses a changed one under another energy), back
// at their defaults when it is not arap: for one set of options run under
// several energies (the tables' rows, the solver lab, the editor's switch).
DeformerOptions WithEnergy(DeformerOptions options, Energy energy);

// Check of WithEnergy(options, e) for each of `energies`: the options of a
// front end that sets the energy per row (the tables, the labs), whose
// arap.* options are the arap rows' and are not refused under another.
bool CheckUnderEnergies(const DeformerOptions& options, const std::vector<Energy>& energies,
                        std::string* error);

// DeformerOptions' rows (core/option_table.h), declared in its header beside the fields: a new
// field is the field above and its row here. DeformerOptionTable() (deformer_options.cc) builds the
// table from them once; a template, so that only that file compiles the rows.
template <typename Table>
void DeclareDeformerOptionRows(Table& t) {
  using DO = DeformerOptions;
  t.Enum("method", &DO::method, GraphMethodNames(),
         "multiscale (the paper), static (one graph of static_nodes nodes), static_dense "
         "(every DG1 node); where a program runs any registered method (msdeform, the "
         "editor, the experiments: methods/registry.h) also the others.")
      .Flag("method");
  t.Embed("lattice", &DO::lattice, LatticeOptionTable());
  t.Embed("graph", &DO::graph, GraphOptionTable());
  t.Embed("rigidity", &DO::rigidity, RigidityOptionTable());
  t.Embed("selection", &DO::selection, ScaleSelectionOptionTable());
  t.Int("static_nodes", &DO::static_nodes,
        "Nodes of the static baseline graph (Sumner et al. 2007: about 220).")
      .Range(1, kOptionIntMax, "an integer >= 1")
      .Flag("method");
  t.Enum("energy", &DO::energy, EnergyNames(),
         "What each frame minimises: ed (Eq. 17, the paper's) or arap (the mesh's cotangent "
         "ARAP energy over the selected graph's subspace, docs/method.md §9).")
      .Flag("method");
  t.Embed("arap", &DO::arap, ArapOptionTable());
  t.Double("w_rot", &DO::w_rot, "w_rot of Eq. 17, >= 0.")
      .AtLeast(0, "a finite weight >= 0")
      .Flag("weights");
  t.Double("w_coh", &DO::w_coh, "w_coh of Eq. 17, >= 0.")
      .AtLeast(0, "a finite weight >= 0")
      .Flag("weights");
  t.Double("w_con", &DO::w_con, "w_con of Eq. 17, > 0.")
      .Above(0, "a finite weight > 0 (at 0 the handle would not follow its target)")
      .Flag("weights");
  t.Double("length_unit", &DO::length_unit,
           "Unit of the coherence and position residuals; 0: the bounding-box diagonal.")
      .AtLeast(0, "a finite number >= 0 (0: the bounding-box diagonal)");
  t.Bool("hold_fixed_vertices", &DO::hold_fixed_vertices,
         "Multi-scale: hold the fixed vertices skinned by a non-Fixed node at rest with "
         "Position terms (the paper: false).")
      .Flag("ablations");
  t.Bool("keep_left_out_terms", &DO::keep_left_out_terms,
         "Keep E(j,k) for Half Free j (paper Fig. 5, Deformed 2).")
      .Flag("ablations");
  t.Bool("fix_fixed_handle_nodes", &DO::fix_fixed_handle_nodes,
         "Fixed-handle nodes get no rotation (paper Fig. 5, Deformed 3).")
      .Flag("ablations");
  t.Int("num_threads", &DO::num_threads,
        "Threads for building the graphs, the skinning and Ceres (given, it sets "
        "graph.num_threads too).")
      .Range(1, kMaxThreads, "an integer in 1..1024")
      .Alias("threads")
      .Flag("method");
  t.Int("cached_scales", &DO::cached_scales,
        "Multi-scale: coarse scales whose skinning data is kept once built (when first "
        "used); the least recently used is dropped beyond this.")
      .Range(1, kOptionIntMax, "an integer >= 1");
  t.Enum("backend", &DO::backend, SolverNames(),
         "The per-frame solver: gauss_newton or ceres (docs/performance.md).")
      .Alias("solver")
      .Flag("solver");
  t.Embed("stopping", &DO::stopping, StoppingRuleTable());
  t.Enum("initial_guess", &DO::initial_guess, InitialGuessNames(),
         "Start of each frame's solve: previous (warm start), extrapolated (from the last two "
         "frames, where that starts lower) or rest (no warm start).")
      .Flag("solver");
  t.Embed("gauss_newton", &DO::gauss_newton, GaussNewtonOptionTable());
  t.Embed("ceres", &DO::ceres, CeresOptionTable());

  // The command line's spellings of embedded options (kept as aliases).
  const struct {
    const char* name;
    const char* alias;
    const char* topic;
  } kFlags[] = {
      {"graph.nodes_per_scale", "nodes_per_scale", "method"},
      {"lattice.cell_width", "cell_width", "method"},
      {"lattice.piece_margin", "piece_margin", "method"},
      {"stopping.max_iterations", "max_iterations", "solver"},
      {"stopping.function_tolerance", "function_tolerance", "solver"},
      {"stopping.gradient_tolerance", "gradient_tolerance", "solver"},
      {"stopping.parameter_tolerance", "parameter_tolerance", "solver"},
      {"gauss_newton.linear_solver", "gn_linear_solver", "solver"},
      {"gauss_newton.cholesky", "gn_cholesky", "solver"},
      {"gauss_newton.factorization", "gn_factorization", "solver"},
      {"gauss_newton.refactor_ratio", "gn_refactor_ratio", "solver"},
      {"gauss_newton.damping", "gn_damping", "solver"},
      {"ceres.trust_region", "ceres_trust_region", "solver"},
      {"ceres.linear_solver", "ceres_linear_solver", "solver"},
      {"ceres.sparse_library", "ceres_sparse", "solver"},
      {"ceres.jacobians", "jacobians", "solver"},
      {"arap.clusters", "arap_clusters", "method"},
      {"arap.num_clusters", "arap_num_clusters", "method"},
      {"arap.constraints", "arap_constraints", "method"},
      {"arap.soft_weight", "arap_soft_weight", "method"},
      {"arap.kmeans_iterations", "arap_kmeans_iterations", "method"},
      {"arap.solver", "arap_solver", "solver"},
      {"arap.anderson_window", "arap_anderson_window", "solver"},
      {"rigidity.model", "rigidity", "rigidity"},
      {"rigidity.external_stiffness", "rigidity_stiffness", "rigidity"},
      {"rigidity.damping", "rigidity_damping", "rigidity"},
      {"rigidity.num_steps", "rigidity_steps", "rigidity"},
      {"rigidity.region_half_width", "rigidity_region", "rigidity"},
      {"selection.threshold_floor", "threshold_floor", "rigidity"},
      {"selection.half_free", "half_free", "ablations"},
      {"selection.border", "border", "ablations"},
      {"selection.pin_fixed_region", "pin_fixed_region", "ablations"},
      {"lattice.split_cells", "split_cells", "ablations"},
      {"selection.alpha_all_one", "alpha_all_one", "ablations"},
  };
  for (const auto& flag : kFlags) t.Mutable(flag.name)->Alias(flag.alias).Flag(flag.topic);
}
const OptionTable<DeformerOptions>& DeformerOptionTable();

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_DEFORMER_OPTIONS_H_
