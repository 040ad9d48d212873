#include "msdeform/scales/deformer_flags.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>
#include <map>
#include <ostream>
#include <vector>

#include <gflags/gflags.h>

namespace {
const msdeform::DeformerOptions kDefaults;
}  // namespace

// Method.
DEFINE_string(method, msdeform::MethodName(kDefaults.method),
              "[method] multiscale (the paper), static (one graph of --static_nodes nodes) or "
              "static_dense (every DG1 node).");
DEFINE_int32(static_nodes, kDefaults.static_nodes,
             "[method] Nodes of the static baseline graph (Sumner et al. 2007: about 220).");
DEFINE_int32(nodes_per_scale, kDefaults.graph.nodes_per_scale,
             "[method] P: nodes per scale step, of the graph stack and of Eq. 6.");
DEFINE_double(cell_width, kDefaults.lattice.cell_width,
              "[method] Lattice cell width in mesh units (0: bounding-box diagonal / 48).");
DEFINE_double(piece_margin, kDefaults.lattice.piece_margin,
              "[method] Pieces of surface in a lattice cell are found within the cell grown by "
              "this many cell widths on each side (--split_cells).");
DEFINE_uint64(seed, kDefaults.graph.seed,
              "[method] Seed of every random choice (DG1 node vertices, the paper's handle kick).");
DEFINE_int32(threads, kDefaults.num_threads,
             "[method] Threads for building the graphs, the skinning and Ceres.");

// Solver.
DEFINE_string(solver, msdeform::SolverName(kDefaults.backend),
              "[solver] Backend: gauss_newton or ceres (docs/performance.md).");
DEFINE_int32(max_iterations, kDefaults.stopping.max_iterations,
             "[solver] Iteration budget per frame (linear solves), >= 1.");
DEFINE_double(function_tolerance, kDefaults.stopping.function_tolerance,
              "[solver] Stop when |cost change| / cost falls to this.");
DEFINE_double(gradient_tolerance, kDefaults.stopping.gradient_tolerance,
              "[solver] Stop when the gradient's max norm falls to this.");
DEFINE_double(parameter_tolerance, kDefaults.stopping.parameter_tolerance,
              "[solver] Stop when |step| <= this * (|x| + this).");
DEFINE_string(initial_guess, msdeform::InitialGuessName(kDefaults.initial_guess),
              "[solver] Start of each frame's solve: previous (warm start), extrapolated (from "
              "the last two frames, where that starts lower) or rest (no warm start).");
DEFINE_string(gn_linear_solver, msdeform::LinearSolverName(kDefaults.gauss_newton.linear_solver),
              "[solver] Gauss-Newton step: cholesky (exact), pcg_jacobi or "
              "pcg_incomplete_cholesky (inexact, forcing-term stop).");
DEFINE_string(gn_cholesky, msdeform::CholeskyName(kDefaults.gauss_newton.cholesky),
              "[solver] Gauss-Newton sparse Cholesky: eigen_llt, eigen_ldlt or cholmod.");
DEFINE_string(gn_factorization,
              msdeform::FactorizationName(kDefaults.gauss_newton.factorization),
              "[solver] When Gauss-Newton refactorises J^T J: every_iteration, per_frame or "
              "lagged (kept while the gradient falls 4x a step, also across frames).");
DEFINE_double(gn_refactor_ratio, kDefaults.gauss_newton.refactor_ratio,
              "[solver] Lagged and per-frame factorisation: refactorise after a step that shrank "
              "the gradient by less than this factor (1: only when it grew).");
DEFINE_string(gn_damping, msdeform::DampingName(kDefaults.gauss_newton.damping),
              "[solver] Gauss-Newton damping: gauss_newton (a 1e-9 floor, raised only after a "
              "rejected step) or levenberg_marquardt (adapted every step).");
DEFINE_string(ceres_trust_region, msdeform::TrustRegionName(kDefaults.ceres.trust_region),
              "[solver] Ceres: levenberg_marquardt or dogleg.");
DEFINE_string(ceres_linear_solver, msdeform::CeresLinearSolverName(kDefaults.ceres.linear_solver),
              "[solver] Ceres: sparse_normal_cholesky or cgnr.");
DEFINE_string(ceres_sparse, msdeform::SparseLibraryName(kDefaults.ceres.sparse_library),
              "[solver] Ceres's sparse Cholesky library: eigen_sparse, suite_sparse or cx_sparse.");

// Weights.
DEFINE_double(w_rot, kDefaults.w_rot, "[weights] w_rot of Eq. 17, >= 0.");
DEFINE_double(w_coh, kDefaults.w_coh, "[weights] w_coh of Eq. 17, >= 0.");
DEFINE_double(w_con, kDefaults.w_con, "[weights] w_con of Eq. 17, > 0.");

// Rigidity and scale selection.
DEFINE_string(rigidity, msdeform::RigidityModelName(kDefaults.rigidity.model),
              "[rigidity] Estimate: harmonic (the driven lattice's rest state) or paper "
              "(S steps of lattice shape matching after a kick).");
DEFINE_double(rigidity_stiffness, kDefaults.rigidity.external_stiffness,
              "[rigidity] k_ext h^2 of the rigidity estimation (docs/method.md §2).");
DEFINE_double(rigidity_damping, kDefaults.rigidity.damping,
              "[rigidity] Velocity damping per shape-matching step, in [0, 1).");
DEFINE_int32(rigidity_steps, kDefaults.rigidity.num_steps,
             "[rigidity] S: shape-matching steps of --rigidity=paper.");
DEFINE_int32(rigidity_region, kDefaults.rigidity.region_half_width,
             "[rigidity] Region half-width r of the shape matching (the paper: 1).");
DEFINE_double(threshold_floor, kDefaults.selection.threshold_floor,
              "[rigidity] Lower bound of the rigidity threshold T (Eq. 7: 0.1).");

// Ablations and the paper's procedure.
DEFINE_string(half_free, msdeform::HalfFreeRuleName(kDefaults.selection.half_free),
              "[ablations] Which fixed-handle nodes are Half Free: next_to_totally_free, "
              "every_fixed_handle_node (the paper) or none.");
DEFINE_string(border, msdeform::BorderRuleName(kDefaults.selection.border),
              "[ablations] What a Fixed node next to a Totally Free one becomes: fixed (the "
              "paper), half_free or totally_free.");
DEFINE_bool(hold_fixed_vertices, kDefaults.hold_fixed_vertices,
            "[ablations] Multi-scale: hold the fixed vertices skinned by a non-Fixed node at rest "
            "with Position terms (the paper: false).");
DEFINE_bool(pin_fixed_region, kDefaults.selection.pin_fixed_region,
            "[ablations] Multi-scale: nodes that skin a fixed-handle vertex are Fixed, so the "
            "fixed region stays exactly at rest (the paper: false).");
DEFINE_bool(split_cells, kDefaults.lattice.split_cells,
            "[ablations] One lattice particle per piece of surface in a cell, interior cells "
            "joined only to surfaces they lie behind: touching parts stay apart (the paper: one "
            "particle per cell, 26 neighbours).");
DEFINE_bool(keep_left_out_terms, kDefaults.keep_left_out_terms,
            "[ablations] Keep E(j,k) for Half Free j (paper Fig. 5, Deformed 2).");
DEFINE_bool(fix_fixed_handle_nodes, kDefaults.fix_fixed_handle_nodes,
            "[ablations] Fixed-handle nodes get no rotation (paper Fig. 5, Deformed 3).");
DEFINE_bool(alpha_all_one, kDefaults.selection.alpha_all_one,
            "[ablations] Every coherence weight alpha = 1.");

namespace msdeform {
namespace {

template <typename Enum>
bool ParseFlag(const char* flag, const std::string& value, bool (*parse)(const std::string&, Enum*),
               const char* expected, Enum* out, std::string* error) {
  if (parse(value, out)) return true;
  *error = std::string("--") + flag + "=" + value + ": expected " + expected;
  return false;
}

// "--name=value: expected ..." unless lo <= value (< or <=) hi and finite.
bool CheckRange(const char* name, double value, double lo, double hi, bool hi_open,
                const char* expected, std::string* error) {
  if (std::isfinite(value) && value >= lo && (hi_open ? value < hi : value <= hi)) return true;
  std::ostringstream text;
  text << "--" << name << "=";
  // Integer flags as typed: 2147483647, not 2.14748e+09.
  if (std::isfinite(value) && value == std::floor(value) && std::abs(value) < 1e15) {
    text << static_cast<long long>(value);
  } else {
    text << value;
  }
  text << ": expected " << expected;
  *error = text.str();
  return false;
}

// Every numeric flag against its range, so that errors name the flag the
// user typed (the options' own checks name struct fields).
bool CheckNumericFlags(std::string* error) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kIntMax = std::numeric_limits<int>::max();
  struct Range {
    const char* name;
    double value, lo, hi;
    bool hi_open;
    const char* expected;
  };
  const Range ranges[] = {
      {"threads", double(FLAGS_threads), 1, kMaxThreads, false, "an integer in 1..1024"},
      {"static_nodes", double(FLAGS_static_nodes), 1, kIntMax, false, "an integer >= 1"},
      {"nodes_per_scale", double(FLAGS_nodes_per_scale), 1, kIntMax, false, "an integer >= 1"},
      {"cell_width", FLAGS_cell_width, 0, kInf, true,
       "a length >= 0 in mesh units (0: diagonal / 48)"},
      {"piece_margin", FLAGS_piece_margin, 0, 2, false, "a number of cell widths in [0, 2]"},
      {"max_iterations", double(FLAGS_max_iterations), 1, kIntMax, false,
       "an integer >= 1 (a frame with no iteration leaves the handle behind)"},
      {"function_tolerance", FLAGS_function_tolerance, 0, kInf, true, "a finite number >= 0"},
      {"gradient_tolerance", FLAGS_gradient_tolerance, 0, kInf, true, "a finite number >= 0"},
      {"parameter_tolerance", FLAGS_parameter_tolerance, 0, kInf, true, "a finite number >= 0"},
      {"gn_refactor_ratio", FLAGS_gn_refactor_ratio, 1e-300, kInf, true, "a number > 0"},
      {"w_rot", FLAGS_w_rot, 0, kInf, true, "a finite weight >= 0"},
      {"w_coh", FLAGS_w_coh, 0, kInf, true, "a finite weight >= 0"},
      {"w_con", FLAGS_w_con, 1e-300, kInf, true,
       "a finite weight > 0 (at 0 the handle would not follow its target)"},
      {"rigidity_stiffness", FLAGS_rigidity_stiffness, 0, kInf, true, "a finite number >= 0"},
      {"rigidity_damping", FLAGS_rigidity_damping, 0, 1, true, "a number in [0, 1)"},
      {"rigidity_steps", double(FLAGS_rigidity_steps), 1, kIntMax, false, "an integer >= 1"},
      {"rigidity_region", double(FLAGS_rigidity_region), 1, kMaxRegionHalfWidth, false,
       "an integer in 1..8 (cost grows as r^3 per particle)"},
      {"threshold_floor", FLAGS_threshold_floor, 0, 1, true, "a number in [0, 1)"},
  };
  for (const Range& range : ranges) {
    if (!CheckRange(range.name, range.value, range.lo, range.hi, range.hi_open, range.expected,
                    error)) {
      return false;
    }
  }
  return true;
}

bool ParseSolverFlags(DeformerOptions* options, std::string* error) {
  if (!ParseFlag("solver", FLAGS_solver, ParseSolver, "gauss_newton or ceres", &options->backend,
                 error) ||
      !ParseFlag("initial_guess", FLAGS_initial_guess, ParseInitialGuess,
                 "previous, extrapolated or rest", &options->initial_guess, error) ||
      !ParseFlag("gn_linear_solver", FLAGS_gn_linear_solver, ParseLinearSolver,
                 "cholesky, pcg_jacobi or pcg_incomplete_cholesky",
                 &options->gauss_newton.linear_solver, error) ||
      !ParseFlag("gn_cholesky", FLAGS_gn_cholesky, ParseCholesky,
                 "eigen_llt, eigen_ldlt or cholmod", &options->gauss_newton.cholesky, error) ||
      !ParseFlag("gn_factorization", FLAGS_gn_factorization, ParseFactorization,
                 "every_iteration, per_frame or lagged", &options->gauss_newton.factorization,
                 error) ||
      !ParseFlag("gn_damping", FLAGS_gn_damping, ParseDamping,
                 "gauss_newton or levenberg_marquardt", &options->gauss_newton.damping, error) ||
      !ParseFlag("ceres_trust_region", FLAGS_ceres_trust_region, ParseTrustRegion,
                 "levenberg_marquardt or dogleg", &options->ceres.trust_region, error) ||
      !ParseFlag("ceres_linear_solver", FLAGS_ceres_linear_solver, ParseCeresLinearSolver,
                 "sparse_normal_cholesky or cgnr", &options->ceres.linear_solver, error)) {
    return false;
  }
  if (!ParseSparseLibrary(FLAGS_ceres_sparse, &options->ceres.sparse_library)) {
    std::string names;
    for (auto library : CeresSparseLibraries())
      names += (names.empty() ? "" : ", ") + SparseLibraryName(library);
    *error = "--ceres_sparse=" + FLAGS_ceres_sparse + ": expected one this Ceres has: " + names;
    return false;
  }
  options->gauss_newton.refactor_ratio = FLAGS_gn_refactor_ratio;
  options->stopping.max_iterations = FLAGS_max_iterations;
  options->stopping.function_tolerance = FLAGS_function_tolerance;
  options->stopping.gradient_tolerance = FLAGS_gradient_tolerance;
  options->stopping.parameter_tolerance = FLAGS_parameter_tolerance;
  return true;
}

}  // namespace

bool DeformerOptionsFromFlags(DeformerOptions* options, std::string* error) {
  if (!CheckNumericFlags(error)) return false;
  if (!ParseFlag("method", FLAGS_method, ParseMethod, "multiscale, static or static_dense",
                 &options->method, error)) {
    return false;
  }
  options->static_nodes = FLAGS_static_nodes;
  options->graph.nodes_per_scale = FLAGS_nodes_per_scale;
  options->lattice.cell_width = FLAGS_cell_width;
  options->lattice.piece_margin = FLAGS_piece_margin;
  options->graph.seed = FLAGS_seed;
  options->rigidity.seed = FLAGS_seed;
  options->num_threads = FLAGS_threads;
  // --threads given sets the graphs' count too; left out, graph.num_threads
  // stays 0, which the Deformer reads as num_threads (as DeformerOptions() has it).
  if (!gflags::GetCommandLineFlagInfoOrDie("threads").is_default) {
    options->graph.num_threads = FLAGS_threads;
  }
  if (!ParseSolverFlags(options, error)) return false;
  options->w_rot = FLAGS_w_rot;
  options->w_coh = FLAGS_w_coh;
  options->w_con = FLAGS_w_con;
  if (!ParseMethodVariant(FLAGS_rigidity, FLAGS_half_free, FLAGS_border, options, error)) {
    return false;
  }
  options->rigidity.external_stiffness = FLAGS_rigidity_stiffness;
  options->rigidity.damping = FLAGS_rigidity_damping;
  options->rigidity.num_steps = FLAGS_rigidity_steps;
  options->rigidity.region_half_width = FLAGS_rigidity_region;
  options->selection.threshold_floor = FLAGS_threshold_floor;
  options->hold_fixed_vertices = FLAGS_hold_fixed_vertices;
  options->selection.pin_fixed_region = FLAGS_pin_fixed_region;
  options->lattice.split_cells = FLAGS_split_cells;
  options->keep_left_out_terms = FLAGS_keep_left_out_terms;
  options->fix_fixed_handle_nodes = FLAGS_fix_fixed_handle_nodes;
  options->selection.alpha_all_one = FLAGS_alpha_all_one;
  std::string check;
  if (!options->Check(&check)) {
    *error = "invalid options: " + check;
    return false;
  }
  return true;
}

namespace {

// The flags with a "[topic] " description: the program's own.
std::vector<gflags::CommandLineFlagInfo> ProgramFlags() {
  std::vector<gflags::CommandLineFlagInfo> all, own;
  gflags::GetAllFlags(&all);
  for (const gflags::CommandLineFlagInfo& flag : all) {
    const std::string& text = flag.description;
    if (text.size() > 3 && text[0] == '[' && text.find("] ") != std::string::npos) {
      own.push_back(flag);
    }
  }
  return own;
}

// Levenshtein distance.
int EditDistance(const std::string& a, const std::string& b) {
  std::vector<int> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    int diagonal = row[0];
    row[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const int up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

bool CheckFlagNames(int argc, char** argv, std::string* error) {
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--") break;
    if (arg.size() < 2 || arg[0] != '-') continue;
    arg.erase(0, arg[1] == '-' ? 2 : 1);
    const std::string name = arg.substr(0, arg.find('='));
    gflags::CommandLineFlagInfo info;
    if (name.empty() || gflags::GetCommandLineFlagInfo(name.c_str(), &info)) continue;
    // gflags's boolean negation --nox.
    if (name.rfind("no", 0) == 0 && gflags::GetCommandLineFlagInfo(name.c_str() + 2, &info) &&
        info.type == "bool") {
      continue;
    }
    std::string nearest;
    int best = 1 << 30;
    for (const gflags::CommandLineFlagInfo& flag : ProgramFlags()) {
      const int distance = EditDistance(name, flag.name);
      if (distance < best) {
        best = distance;
        nearest = flag.name;
      }
    }
    *error = "unknown flag --" + name;
    if (!nearest.empty() && best <= std::max<int>(2, static_cast<int>(name.size()) / 3)) {
      *error += " (did you mean --" + nearest + "?)";
    }
    *error += "; --help lists the flags";
    return false;
  }
  return true;
}

std::vector<std::pair<std::string, std::string>> ProgramFlagValues() {
  std::vector<std::pair<std::string, std::string>> values;
  for (const gflags::CommandLineFlagInfo& flag : ProgramFlags())
    values.emplace_back(flag.name, flag.current_value);
  std::sort(values.begin(), values.end());
  return values;
}

bool HandleHelpRequest(int argc, char** argv, const std::string& usage, std::ostream& out) {
  bool asked = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    asked |= arg == "-h" || arg == "--help" || arg == "-help" || arg == "--helpshort" ||
             arg == "-helpshort";
  }
  if (!asked) return false;
  // The program's own flags: those whose description starts with
  // "[topic] ", in the order of kTopics; glog's and gflags's are left out
  // (--helpfull lists them).
  static const char* kTopics[] = {"input",   "output",  "method",    "solver",
                                  "weights", "rigidity", "ablations", "diagnostics"};
  std::map<std::string, std::vector<gflags::CommandLineFlagInfo>> by_topic;
  std::vector<gflags::CommandLineFlagInfo> flags;
  gflags::GetAllFlags(&flags);
  for (const gflags::CommandLineFlagInfo& flag : flags) {
    const std::string& text = flag.description;
    if (text.size() < 3 || text[0] != '[') continue;
    const size_t close = text.find("] ");
    if (close == std::string::npos) continue;
    by_topic[text.substr(1, close - 1)].push_back(flag);
  }
  out << usage << "\n";
  for (const char* topic : kTopics) {
    auto it = by_topic.find(topic);
    if (it == by_topic.end()) continue;
    out << "\n" << topic << ":\n";
    for (const gflags::CommandLineFlagInfo& flag : it->second) {
      const std::string text = flag.description.substr(flag.description.find("] ") + 2);
      std::string value = flag.default_value;
      if (flag.type == "string") value = "\"" + value + "\"";
      out << "  --" << flag.name << " (" << flag.type << ", default " << value << ")\n      "
          << text << "\n";
    }
  }
  out << "\n--helpfull also lists the flags of glog and gflags.\n";
  return true;
}

}  // namespace msdeform
