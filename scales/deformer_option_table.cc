// DeformerOptions' table (scales/deformer_options.h): every option declared
// once. A row gives the name (the struct's), the help, the range and, for the
// command line, a topic and the legacy flag spelling as an alias.

#include <limits>
#include <string>

#include "msdeform/core/nearest_nodes.h"
#include "msdeform/scales/deformer_options.h"

namespace msdeform {
namespace {

constexpr double kIntMax = std::numeric_limits<int>::max();
constexpr double kInf = std::numeric_limits<double>::infinity();

template <typename T, typename Build>
const OptionTable<T>& Table(Build build) {
  OptionTable<T> table;
  build(table);
  return *new OptionTable<T>(std::move(table));
}

}  // namespace

const OptionTable<LatticeOptions>& LatticeOptionTable() {
  static const OptionTable<LatticeOptions>& table = Table<LatticeOptions>([](auto& t) {
    using L = LatticeOptions;
    t.Double("cell_width", &L::cell_width,
             "Lattice cell width in mesh units (0: bounding-box diagonal / 48).")
        .AtLeast(0, "a length >= 0 in mesh units (0: diagonal / 48)");
    t.Double("cells_per_diagonal", &L::cells_per_diagonal,
             "Used when cell_width is 0: w = bounding-box diagonal / this.");
    t.Int("max_grid_cells", &L::max_grid_cells,
          "Upper bound on the cells of the padded grid (memory guard).");
    t.Bool("split_cells", &L::split_cells,
           "One lattice particle per piece of surface in a cell, interior cells joined only to "
           "surfaces they lie behind: touching parts stay apart (the paper: one particle per "
           "cell, 26 neighbours).");
    t.Double("piece_margin", &L::piece_margin,
             "Pieces of surface in a lattice cell are found within the cell grown by this many "
             "cell widths on each side (split_cells).")
        .Range(0, 2, "a number of cell widths in [0, 2]");
  });
  return table;
}

const OptionTable<GraphOptions>& GraphOptionTable() {
  static const OptionTable<GraphOptions>& table = Table<GraphOptions>([](auto& t) {
    using G = GraphOptions;
    t.Int("k", &G::k, "Nearest nodes per vertex (paper: 4).");
    t.Int("nodes_per_scale", &G::nodes_per_scale,
          "P: nodes per scale step, of the graph stack and of Eq. 6.")
        .Range(1, kIntMax, "an integer >= 1");
    t.Int("seed", &G::seed, "Seed of the random vertex chosen in each surface cell for DG1.");
    t.Int("extra_rings", &G::extra_rings,
          "Cell rings searched beyond the first that reaches k + 1 nodes.");
    t.Int("num_threads", &G::num_threads,
          "OpenMP threads for building; 0 uses the OpenMP default.")
        .Range(0, kMaxThreads, "an integer in 0..1024 (0: OpenMP default)");
  });
  return table;
}

const OptionTable<RigidityOptions>& RigidityOptionTable() {
  static const OptionTable<RigidityOptions>& table = Table<RigidityOptions>([](auto& t) {
    using R = RigidityOptions;
    t.Enum("model", &R::model, RigidityModelNames(),
           "Estimate: harmonic (the driven lattice's rest state) or paper (S steps of lattice "
           "shape matching after a kick).");
    t.Int("num_steps", &R::num_steps, "S: shape-matching steps of the paper's rigidity.")
        .Range(1, kIntMax, "an integer >= 1");
    t.Double("time_step", &R::time_step, "h: time step, lattice-time units.")
        .Above(0, "a finite number > 0");
    t.Double("external_stiffness", &R::external_stiffness,
             "k_ext h^2 of the rigidity estimation (docs/method.md §2).")
        .AtLeast(0, "a finite number >= 0");
    t.Double("initial_speed", &R::initial_speed,
             "|v0| of the moveable-handle particles, cell widths per time step.")
        .Above(0, "a finite number > 0");
    t.Double("damping", &R::damping, "Velocity damping per shape-matching step, in [0, 1).")
        .Range(0, 1, "a number in [0, 1)", /*high_open=*/true);
    t.Int("region_half_width", &R::region_half_width,
          "Region half-width r of the shape matching (the paper: 1).")
        .Range(1, kMaxRegionHalfWidth, "an integer in 1..8 (cost grows as r^3 per particle)");
    t.Int("seed", &R::seed, "Seed of the direction of v0.");
    t.Enum("region_summation", &R::region_summation, RegionSummationNames(),
           "box (FastLSM box sums) or per_region; the same numbers up to rounding.");
    t.Int("max_rotation_iterations", &R::max_rotation_iterations,
          "Polar-decomposition updates per region and step, at most.")
        .Range(1, kIntMax, "an integer >= 1");
    t.Double("rotation_tolerance", &R::rotation_tolerance,
             "Stop the updates below this rotation (radians).")
        .Above(0, "a finite number > 0");
  });
  return table;
}

const OptionTable<ScaleSelectionOptions>& ScaleSelectionOptionTable() {
  static const OptionTable<ScaleSelectionOptions>& table =
      Table<ScaleSelectionOptions>([](auto& t) {
        using S = ScaleSelectionOptions;
        t.Double("threshold_floor", &S::threshold_floor,
                 "Lower bound of the rigidity threshold T (Eq. 7: 0.1).")
            .Range(0, 1, "a number in [0, 1)", /*high_open=*/true);
        t.Double("fixed_extent_cutoff", &S::fixed_extent_cutoff,
                 "Fixed-handle nodes with e' below this count towards T (Eq. 7: 0.5).")
            .Range(0, 1, "a number in (0, 1]")
            .lo_open = true;
        t.Enum("member_extent", &S::member_extent, MemberExtentNames(),
               "A coarse node's e' from its DG1 members: max or mean (an ablation).");
        t.Double("local_detail_distance", &S::local_detail_distance,
                 "Local-detail edit within this geodesic distance, over the diagonal.")
            .AtLeast(0, "a finite number >= 0");
        t.Double("omega_max", &S::omega_max,
                 "Totally Free nodes map e to omega in [1, omega_max].")
            .AtLeast(1, "a finite number >= 1");
        t.Bool("alpha_all_one", &S::alpha_all_one, "Every coherence weight alpha = 1.");
        t.Enum("half_free", &S::half_free, HalfFreeRuleNames(),
               "Which fixed-handle nodes are Half Free: next_to_totally_free, "
               "every_fixed_handle_node (the paper) or none.");
        t.Enum("border", &S::border, BorderRuleNames(),
               "What a Fixed node next to a Totally Free one becomes: fixed (the paper), "
               "half_free or totally_free.");
        t.Bool("pin_fixed_region", &S::pin_fixed_region,
               "Multi-scale: nodes that skin a fixed-handle vertex are Fixed, so the fixed "
               "region stays exactly at rest (the paper: false).");
      });
  return table;
}

const OptionTable<StoppingRule>& StoppingRuleTable() {
  static const OptionTable<StoppingRule>& table = Table<StoppingRule>([](auto& t) {
    t.Int("max_iterations", &StoppingRule::max_iterations,
          "Iteration budget per frame (linear solves), >= 1.")
        .Range(1, kIntMax, "an integer >= 1 (a frame with no iteration leaves the handle behind)");
    t.Double("function_tolerance", &StoppingRule::function_tolerance,
             "Stop when |cost change| / cost falls to this.")
        .AtLeast(0, "a finite number >= 0");
    t.Double("gradient_tolerance", &StoppingRule::gradient_tolerance,
             "Stop when the gradient's max norm falls to this.")
        .AtLeast(0, "a finite number >= 0");
    t.Double("parameter_tolerance", &StoppingRule::parameter_tolerance,
             "Stop when |step| <= this * (|x| + this).")
        .AtLeast(0, "a finite number >= 0");
  });
  return table;
}

// The energy helper's solver files keep their Name/Parse functions; the
// names here are read from them.
const OptionTable<GaussNewtonOptions>& GaussNewtonOptionTable() {
  using GN = GaussNewtonOptions;
  static const OptionTable<GN>& table = Table<GN>([](auto& t) {
    t.Enum("linear_solver", &GN::linear_solver,
           LinearSolverNames(),
           "Gauss-Newton step: cholesky (exact), pcg_jacobi or pcg_incomplete_cholesky "
           "(inexact, forcing-term stop).");
    t.Enum("cholesky", &GN::cholesky,
           CholeskyNames(),
           "Gauss-Newton sparse Cholesky: supernodal, eigen_llt, eigen_ldlt or cholmod.");
    t.Enum("factorization", &GN::factorization,
           FactorizationNames(),
           "When Gauss-Newton refactorises J^T J: every_iteration, per_frame or lagged (kept "
           "while the gradient falls 4x a step, also across frames).");
    t.Double("refactor_ratio", &GN::refactor_ratio,
             "Lagged and per-frame factorisation: refactorise after a step that shrank the "
             "gradient by less than this factor (1: only when it grew).")
        .Above(0, "a number > 0");
    t.Enum("damping", &GN::damping,
           DampingNames(),
           "Gauss-Newton damping: gauss_newton (a 1e-9 floor, raised only after a rejected "
           "step) or levenberg_marquardt (adapted every step).");
    t.Double("min_damping", &GN::min_damping, "mu floor, relative to diag(J^T J).");
    t.Double("initial_damping", &GN::initial_damping, "Levenberg-Marquardt's first mu.");
    t.Double("forcing_term", &GN::forcing_term, "PCG's relative residual bound, at most.");
    t.Int("max_cg_iterations", &GN::max_cg_iterations, "PCG iterations per step, at most.");
  });
  return table;
}

const OptionTable<CeresOptions>& CeresOptionTable() {
  static const OptionTable<CeresOptions>& table = Table<CeresOptions>([](auto& t) {
    using C = CeresOptions;
    t.Enum("trust_region", &C::trust_region,
           EnumNames<ceres::TrustRegionStrategyType>::FromFunction(
               {ceres::LEVENBERG_MARQUARDT, ceres::DOGLEG}, TrustRegionName),
           "Ceres: levenberg_marquardt or dogleg.");
    t.Enum("linear_solver", &C::linear_solver,
           EnumNames<ceres::LinearSolverType>::FromFunction(
               {ceres::SPARSE_NORMAL_CHOLESKY, ceres::CGNR}, CeresLinearSolverName),
           "Ceres: sparse_normal_cholesky or cgnr.");
    // Only the libraries this Ceres has.
    t.Enum("sparse_library", &C::sparse_library,
           EnumNames<ceres::SparseLinearAlgebraLibraryType>::FromFunction(
               CeresSparseLibraries(), SparseLibraryName),
           "Ceres's sparse Cholesky library: eigen_sparse, suite_sparse or cx_sparse (those "
           "this Ceres has).")
        .ChoiceWords("one this Ceres has: ");
    t.Bool("group_position_terms", &C::group_position_terms,
           "One exact least-squares block per group of handle vertices sharing nodes.");
    t.Enum("jacobians", &C::jacobians,
           JacobiansNames(),
           "Ceres's residual blocks: analytic (the functors' hand-written Jacobians) or autodiff "
           "(the same functors through ceres::AutoDiffCostFunction).");
  });
  return table;
}

const OptionTable<ArapOptions>& ArapOptionTable() {
  static const OptionTable<ArapOptions>& table = Table<ArapOptions>([](auto& t) {
    using A = ArapOptions;
    t.Enum("clusters", &A::clusters, RotationClustersNames(),
           "Rotation clusters of the subspace ARAP energy: weights (k-means on the skinning "
           "weights, FAST), nodes (one per node's support) or vertices (one per vertex).");
    t.Int("num_clusters", &A::num_clusters, "clusters=weights: clusters over the active vertices.")
        .Range(1, kIntMax, "an integer >= 1");
    t.Int("kmeans_iterations", &A::kmeans_iterations,
          "clusters=weights: Lloyd iterations of the k-means.")
        .Range(0, kIntMax, "an integer >= 0");
    t.Enum("constraints", &A::constraints, ArapConstraintsNames(),
           "Handle and fixed vertices of the subspace ARAP energy: exact (constants outside "
           "the subspace) or soft (skinned, pulled by position terms of soft_weight).");
    t.Double("soft_weight", &A::soft_weight,
             "constraints=soft: weight of |x' - q|^2 against the cotangent-weighted edges.")
        .Above(0, "a finite weight > 0");
    t.Enum("solver", &A::solver, ArapSolverNames(),
           "The subspace ARAP energy's solver under backend=gauss_newton: local_global "
           "(rotations fitted, then the nodes solved) or gauss_newton (nodes and cluster "
           "rotations jointly, the rotations eliminated per cluster).");
    t.Int("anderson_window", &A::anderson_window,
          "solver=local_global: Anderson acceleration's window (past iterates combined, "
          "with the energy safeguard); 0 runs plain local/global.")
        .Range(0, 50, "an integer in 0..50");
  });
  return table;
}

const OptionTable<DeformerOptions>& DeformerOptionTable() {
  static const OptionTable<DeformerOptions>& table = Table<DeformerOptions>([](auto& t) {
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
        .Range(1, kIntMax, "an integer >= 1")
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
        .Range(1, kIntMax, "an integer >= 1");
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
  });
  return table;
}

}  // namespace msdeform
