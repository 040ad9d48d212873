// msdeform: edit a mesh with the multi-scale method of Liu & Su 2008 (or one
// of the single-static-graph baselines) and write the deformed mesh, a JSON
// report and optionally the DG1 nodes with their rigidity and class.
//
// With no arguments it runs the default edit: the armadillo with its feet
// fixed and a claw dragged (data/scenarios/armadillo_claw.json).

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <utility>
#include <vector>

#include <gflags/gflags.h>
#include <glog/logging.h>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/drag_path.h"
#include "core/handles.h"
#include "core/mesh_io.h"
#include "core/scenario.h"
#include "core/timing.h"
#include "scales/deformer.h"

DEFINE_string(mesh, "", "Input mesh (OFF, OBJ, PLY, STL). Default: the scenario's mesh.");
DEFINE_string(sel, "", "Botsch-Sorkine .sel handle file (needs --def).");
DEFINE_string(def, "", "Botsch-Sorkine .def 4x4 handle transform (needs --sel).");
DEFINE_string(scenario, "", "JSON scenario (docs/scenarios.md). Default when neither --sel "
                            "nor --scenario is given: data/scenarios/armadillo_claw.json.");
DEFINE_string(method, "multiscale", "multiscale, static or static_dense.");
DEFINE_string(solver, "ceres", "Solver backend: ceres or gauss_newton (docs/performance.md).");
DEFINE_int32(static_nodes, 220, "Nodes of the static baseline graph.");
DEFINE_int32(frames, 0, "Drag frames from rest to the target (0: the scenario's, or 1).");
DEFINE_string(out, "", "Deformed mesh (OFF, OBJ or PLY by extension). Default: "
                       "msdeform_out/<name>_<method>.off.");
DEFINE_string(report, "", "JSON report. Default: next to --out with extension .json.");
DEFINE_string(dump_nodes, "", "CSV of the DG1 nodes: node,x,y,z,e_prime,class.");
DEFINE_uint64(seed, 1, "Seed of every random choice (DG1 node vertices, handle kick).");
DEFINE_double(cell_width, 0.0, "Lattice cell width in mesh units (0: diagonal / 48).");
DEFINE_int32(threads, 2, "Threads for the solve and the skinning.");
DEFINE_int32(max_iterations, 20, "Solver iteration cap per frame.");
DEFINE_double(function_tolerance, msdeform::DeformerOptions().solver.function_tolerance,
              "Stop a frame's solve when |cost change| / cost falls below this.");
DEFINE_string(ceres_sparse, "eigen_sparse",
              "Ceres's sparse Cholesky library: eigen_sparse or suite_sparse.");
DEFINE_double(w_rot, msdeform::DeformerOptions().w_rot, "Weight of E_rot (Eq. 17).");
DEFINE_double(w_coh, msdeform::DeformerOptions().w_coh, "Weight of E_coh (Eq. 17).");
DEFINE_double(w_con, msdeform::DeformerOptions().w_con, "Weight of E_con (Eq. 17).");
DEFINE_bool(keep_left_out_terms, false, "Ablation: keep E(j,k) for Half Free j.");
DEFINE_bool(fix_fixed_handle_nodes, false, "Ablation: fixed-handle nodes get no rotation.");
DEFINE_bool(alpha_all_one, false, "Ablation: every coherence weight alpha = 1.");
DEFINE_string(rigidity, msdeform::RigidityModelName(msdeform::RigidityOptions().model),
              "Rigidity estimate: harmonic (the driven lattice's rest state) or paper "
              "(S steps of lattice shape matching after a kick).");
DEFINE_string(half_free,
              msdeform::HalfFreeRuleName(msdeform::ScaleSelectionOptions().half_free),
              "Which fixed-handle nodes are Half Free: next_to_totally_free, "
              "every_fixed_handle_node (the paper) or none.");
DEFINE_bool(hold_fixed_vertices, msdeform::DeformerOptions().hold_fixed_vertices,
            "Multi-scale: hold the fixed vertices skinned by a non-Fixed node at rest with "
            "Position terms (the paper: false).");
DEFINE_string(border, msdeform::BorderRuleName(msdeform::ScaleSelectionOptions().border),
              "What a Fixed node next to a Totally Free one becomes: fixed (the paper), "
              "half_free or totally_free.");
DEFINE_double(rigidity_stiffness, msdeform::RigidityOptions().external_stiffness,
              "k_ext h^2 of the rigidity estimation (docs/method.md §2).");
DEFINE_double(rigidity_damping, msdeform::RigidityOptions().damping,
              "Velocity damping per shape-matching step, in [0, 1).");
DEFINE_int32(rigidity_steps, msdeform::RigidityOptions().num_steps,
             "S: shape-matching steps of the rigidity estimation.");
DEFINE_int32(rigidity_region, msdeform::RigidityOptions().region_half_width,
             "Region half-width r of the shape matching (the paper: 1).");
DEFINE_double(threshold_floor, msdeform::ScaleSelectionOptions().threshold_floor,
              "Lower bound of the rigidity threshold T (Eq. 7: 0.1).");
DEFINE_bool(quiet, false, "Print nothing but errors.");
DEFINE_bool(verbose, false, "Also print the solver's own log (Ceres warnings and errors).");

namespace msdeform {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Everything the command line asks for, resolved and checked.
struct Job {
  std::string name;
  std::string mesh_path;
  Mesh mesh;
  HandleLayout layout;
  std::vector<Eigen::Affine3d> path;  // one transform per frame
  std::string out_path, report_path, nodes_path;
  DeformerOptions options;
  double load_ms = 0.0;
};

bool FillOptions(DeformerOptions* options, std::string* error) {
  if (!ParseMethod(FLAGS_method, &options->method)) {
    *error = "--method=" + FLAGS_method + ": expected multiscale, static or static_dense";
    return false;
  }
  if (!ParseSolver(FLAGS_solver, &options->backend)) {
    *error = "--solver=" + FLAGS_solver + ": expected ceres or gauss_newton";
    return false;
  }
  options->static_nodes = FLAGS_static_nodes;
  options->lattice.cell_width = FLAGS_cell_width;
  options->graph.seed = FLAGS_seed;
  options->rigidity.seed = FLAGS_seed;
  if (!ParseMethodVariant(FLAGS_rigidity, FLAGS_half_free, FLAGS_border, options, error)) {
    return false;
  }
  options->rigidity.external_stiffness = FLAGS_rigidity_stiffness;
  options->rigidity.damping = FLAGS_rigidity_damping;
  options->rigidity.num_steps = FLAGS_rigidity_steps;
  options->rigidity.region_half_width = FLAGS_rigidity_region;
  options->num_threads = FLAGS_threads;
  options->solver.max_num_iterations = FLAGS_max_iterations;
  options->solver.function_tolerance = FLAGS_function_tolerance;
  if (FLAGS_ceres_sparse == "suite_sparse") {
    options->solver.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  } else if (FLAGS_ceres_sparse != "eigen_sparse") {
    *error = "--ceres_sparse=" + FLAGS_ceres_sparse + ": expected eigen_sparse or suite_sparse";
    return false;
  }
  options->w_rot = FLAGS_w_rot;
  options->w_coh = FLAGS_w_coh;
  options->w_con = FLAGS_w_con;
  options->keep_left_out_terms = FLAGS_keep_left_out_terms;
  options->fix_fixed_handle_nodes = FLAGS_fix_fixed_handle_nodes;
  options->selection.alpha_all_one = FLAGS_alpha_all_one;
  options->selection.threshold_floor = FLAGS_threshold_floor;
  options->hold_fixed_vertices = FLAGS_hold_fixed_vertices;
  if (FLAGS_frames < 0 || FLAGS_frames > kMaxScenarioFrames) {
    *error = "--frames must be in 0.." + std::to_string(kMaxScenarioFrames);
    return false;
  }
  return options->Check(error);
}

bool PrepareJob(Job* job, std::string* error) {
  if (!FillOptions(&job->options, error)) return false;
  const auto load_start = Clock::now();
  if (!FLAGS_sel.empty() || !FLAGS_def.empty()) {
    if (FLAGS_sel.empty() || FLAGS_def.empty() || FLAGS_mesh.empty() || !FLAGS_scenario.empty()) {
      *error = "--sel and --def go together, with --mesh and without --scenario";
      return false;
    }
    job->mesh_path = FLAGS_mesh;
    job->name = fs::path(FLAGS_mesh).stem().string();
    if (!ReadMesh(job->mesh_path, &job->mesh, error)) return false;
    if (!ReadSel(FLAGS_sel, job->mesh.num_vertices(), &job->layout, error)) return false;
    Eigen::Affine3d deformed_from_rest;
    if (!ReadDef(FLAGS_def, &deformed_from_rest, error)) return false;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int v : job->layout.moveable) centroid += job->mesh.vertices.col(v);
    centroid /= static_cast<double>(job->layout.moveable.size());
    job->path = InterpolateDragPath(deformed_from_rest, centroid, std::max(FLAGS_frames, 1));
  } else {
    const std::string scenario_path =
        FLAGS_scenario.empty() ? std::string(MSDEFORM_DATA_DIR) + "/scenarios/armadillo_claw.json"
                               : FLAGS_scenario;
    Scenario scenario;
    if (!ReadScenario(scenario_path, &scenario, error)) return false;
    if (FLAGS_frames > 0) scenario.frames = FLAGS_frames;
    job->name = scenario.name;
    job->mesh_path = FLAGS_mesh.empty() ? scenario.mesh_path : FLAGS_mesh;
    if (!ReadMesh(job->mesh_path, &job->mesh, error)) return false;
    std::vector<int> watch;
    Eigen::Affine3d deformed_from_rest;
    if (!ResolveScenario(scenario, job->mesh, &job->layout, &watch, &deformed_from_rest, error)) {
      return false;
    }
    job->path = DragPath(scenario, job->mesh, job->layout);
  }
  job->load_ms = MillisecondsSince(load_start);

  job->out_path = FLAGS_out.empty()
                      ? "msdeform_out/" + job->name + "_" + FLAGS_method + ".off"
                      : FLAGS_out;
  job->report_path = FLAGS_report.empty()
                         ? fs::path(job->out_path).replace_extension(".json").string()
                         : FLAGS_report;
  job->nodes_path = FLAGS_dump_nodes;
  {
    std::string extension = fs::path(job->out_path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (extension != ".off" && extension != ".obj" && extension != ".ply") {
      *error = "--out=" + job->out_path + ": cannot write format '" + extension +
               "'; use .off, .obj or .ply";
      return false;
    }
  }
  const std::vector<std::string> outputs = {job->out_path, job->report_path, job->nodes_path};
  for (size_t i = 0; i < outputs.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      std::error_code ec_i, ec_j;
      if (!outputs[i].empty() && fs::weakly_canonical(outputs[i], ec_i) ==
                                     fs::weakly_canonical(outputs[j], ec_j)) {
        *error = outputs[i] + ": given as two different outputs (--out, --report, --dump_nodes)";
        return false;
      }
    }
  }
  for (const std::string& output : outputs) {
    if (output.empty()) continue;
    for (const std::string& input : {job->mesh_path, FLAGS_sel, FLAGS_def, FLAGS_scenario}) {
      if (!input.empty() && SameFile(output, input)) {
        *error = output + ": refusing to overwrite an input file";
        return false;
      }
    }
  }
  return true;
}

// All outputs of a run appear together or not at all: each is written
// (atomically) to a hidden sibling of its final path, and only when every one
// is complete are they renamed into place. Staged files left by a failed run
// are removed by the destructor.
class StagedOutputs {
 public:
  ~StagedOutputs() {
    std::error_code ignored;
    for (const auto& [staged, final_path] : files_) fs::remove(staged, ignored);
  }
  // Where to write `path` for now: ".<name>.partial<ext>" in its folder,
  // which is created if needed (and fails there when it cannot be).
  bool Stage(const std::string& path, std::string* staged, std::string* error) {
    const fs::path final_path(path);
    const fs::path parent = final_path.parent_path();
    std::error_code ec;
    if (!parent.empty() && !fs::is_directory(parent, ec)) {
      fs::create_directories(parent, ec);
      if (ec) {
        *error = path + ": cannot create its folder (" + ec.message() + ")";
        return false;
      }
    }
    *staged = (parent / ("." + final_path.stem().string() + ".partial" +
                         final_path.extension().string()))
                  .string();
    files_.emplace_back(*staged, path);
    return true;
  }
  // Renames every staged file to its final path.
  bool Commit(std::string* error) {
    for (const auto& [staged, final_path] : files_) {
      std::error_code ec;
      fs::rename(staged, final_path, ec);
      if (ec) {
        *error = final_path + ": cannot move the finished output into place (" + ec.message() + ")";
        return false;
      }
    }
    files_.clear();
    return true;
  }

 private:
  std::vector<std::pair<std::string, std::string>> files_;  // staged, final
};

bool WriteText(const std::string& path, const std::string& text, std::string* error) {
  return WriteFileAtomically(
      path,
      [&](std::ostream& out, std::string*) {
        out << text;
        return static_cast<bool>(out);
      },
      error);
}

std::string NodesCsv(const Deformer& deformer) {
  std::ostringstream csv;
  csv.precision(9);
  csv << "node,x,y,z,e_prime,class\n";
  const DeformationGraph& dg1 = deformer.graphs()[0];
  const DeformationGraph& active = deformer.active();
  const bool has_rigidity = deformer.rigidity().relative_extent.size() > 0;
  for (int i = 0; i < dg1.num_nodes(); ++i) {
    const Eigen::Vector3d g = dg1.positions.col(i);
    csv << i << ',' << g.x() << ',' << g.y() << ',' << g.z() << ',';
    if (has_rigidity) csv << deformer.rigidity().relative_extent[i];
    csv << ',' << NodeClassName(deformer.node_classes()[active.node_of_dg1[i]]) << '\n';
  }
  return csv.str();
}

int Run() {
  const auto total_start = Clock::now();
  std::string error;
  Job job;
  if (!PrepareJob(&job, &error)) {
    std::cerr << "msdeform: " << error << "\n";
    return 1;
  }
  Deformer deformer;
  if (!deformer.Init(job.mesh, job.options, &error)) {
    std::cerr << "msdeform: " << job.mesh_path << ": " << error << "\n";
    return 1;
  }
  if (!deformer.SetHandles(job.layout, &error)) {
    std::cerr << "msdeform: handles: " << error << "\n";
    return 1;
  }
  std::vector<double> frame_ms, solve_ms, skin_ms, iterations;
  double final_cost = 0.0;
  // A frame whose solve fails keeps the last good node transforms (Drag
  // restores them) and the drag goes on from there; only the last frame is
  // the result the user asked for, so only its failure is an error.
  std::vector<int> failed_frames;
  for (size_t f = 0; f < job.path.size(); ++f) {
    DragStats stats;
    const auto frame_start = Clock::now();
    if (!deformer.Drag(job.path[f], &stats, &error)) {
      failed_frames.push_back(static_cast<int>(f) + 1);
      if (f + 1 < job.path.size()) continue;
      std::cerr << "msdeform: " << job.mesh_path << ": frame " << f + 1 << " of "
                << job.path.size() << " (the result): " << error << "; "
                << failed_frames.size() << " failed frame(s); no output written\n";
      return 1;
    }
    frame_ms.push_back(MillisecondsSince(frame_start));
    solve_ms.push_back(stats.solve_ms);
    skin_ms.push_back(stats.skin_ms);
    iterations.push_back(stats.iterations);
    final_cost = stats.final_cost;
  }

  double handle_sq = 0.0;
  for (int v : job.layout.moveable) {
    handle_sq += (deformer.deformed_vertices().col(v) - job.path.back() * job.mesh.vertices.col(v))
                     .squaredNorm();
  }
  const double handle_rms = std::sqrt(handle_sq / job.layout.moveable.size());

  Mesh deformed = job.mesh;
  deformed.vertices = deformer.deformed_vertices();
  if (!deformed.vertices.allFinite()) {
    std::cerr << "msdeform: " << job.mesh_path
              << ": the deformed mesh has non-finite coordinates; no output written\n";
    return 1;
  }
  StagedOutputs staged;
  std::string staged_path;
  if (!staged.Stage(job.out_path, &staged_path, &error) ||
      !WriteMesh(staged_path, deformed, &error)) {
    std::cerr << "msdeform: " << error << "\n";
    return 1;
  }
  if (!job.nodes_path.empty() && (!staged.Stage(job.nodes_path, &staged_path, &error) ||
                                  !WriteText(staged_path, NodesCsv(deformer), &error))) {
    std::cerr << "msdeform: " << error << "\n";
    return 1;
  }

  const Lattice& lattice = deformer.lattice();
  const ScaleSelection& selection = deformer.selection();
  nlohmann::ordered_json report;
  report["name"] = job.name;
  report["mesh"] = job.mesh_path;
  report["method"] = FLAGS_method;
  report["seed"] = FLAGS_seed;
  report["vertices"] = job.mesh.num_vertices();
  report["faces"] = job.mesh.num_faces();
  report["diag"] = deformer.diagonal();
  report["handle_vertices"] = {{"fixed", job.layout.fixed.size()},
                               {"moveable", job.layout.moveable.size()}};
  report["lattice"] = {{"cell_width", lattice.cell_width()},
                       {"surface_cells", lattice.num_surface_cells()},
                       {"interior_cells", lattice.num_interior_cells()},
                       {"particles", lattice.num_particles()}};
  report["scales"] = nlohmann::ordered_json::array();
  for (size_t i = 0; i < deformer.graphs().size(); ++i) {
    report["scales"].push_back({{"scale", i + 1},
                                {"nodes", deformer.graphs()[i].num_nodes()},
                                {"edges", deformer.graphs()[i].edges.size()}});
  }
  int totally_free = 0, half_free = 0, fixed = 0;
  for (NodeClass c : deformer.node_classes()) {
    totally_free += c == NodeClass::kTotallyFree;
    half_free += c == NodeClass::kHalfFree;
    fixed += c == NodeClass::kFixed;
  }
  report["rigidity"] = {{"threshold", selection.threshold},
                        {"group1", selection.group1_size},
                        {"eq6_scale", selection.eq6_scale},
                        {"local_detail_edit", selection.local_detail_edit}};
  report["selected_scale"] = deformer.active_graph() + 1;
  report["nodes"] = {{"totally_free", totally_free}, {"half_free", half_free}, {"fixed", fixed}};
  report["variables"] = deformer.num_variables();
  report["coherence_terms"] = deformer.num_coherence_terms();
  report["frames"] = job.path.size();
  report["timings_ms"] = {{"load", job.load_ms},
                          {"precompute", deformer.precompute_ms()},
                          {"rigidity", deformer.rigidity_ms()},
                          {"setup", deformer.setup_ms()},
                          {"frame_median", Median(frame_ms)},
                          {"solve_median", Median(solve_ms)},
                          {"skin_median", Median(skin_ms)},
                          {"total", MillisecondsSince(total_start)}};
  report["handle_rms"] = handle_rms;
  report["solver"] = {{"iterations_median", Median(iterations)}, {"final_cost", final_cost}};
  report["failed_frames"] = failed_frames;
  report["output"] = job.out_path;
  if (!staged.Stage(job.report_path, &staged_path, &error) ||
      !WriteText(staged_path, report.dump(2) + "\n", &error) || !staged.Commit(&error)) {
    std::cerr << "msdeform: " << error << "\n";
    return 1;
  }

  if (!FLAGS_quiet) {
    std::printf("msdeform: %s (%d vertices) %s, scale %d of %zu, %d+%d free nodes, %d variables\n",
                job.name.c_str(), job.mesh.num_vertices(), FLAGS_method.c_str(),
                deformer.active_graph() + 1, deformer.graphs().size(), totally_free, half_free,
                deformer.num_variables());
    std::printf("  %zu frames: median frame %.2f ms (solve %.2f, skin %.2f), handle rms %.3g "
                "(%.2g of diag)\n",
                job.path.size(), Median(frame_ms), Median(solve_ms), Median(skin_ms), handle_rms,
                handle_rms / deformer.diagonal());
    std::printf("  wrote %s and %s\n", job.out_path.c_str(), job.report_path.c_str());
    if (!failed_frames.empty()) {
      std::printf("  %zu intermediate frame(s) failed to solve and kept the previous pose "
                  "(failed_frames in the report)\n",
                  failed_frames.size());
    }
  }
  return 0;
}

}  // namespace
}  // namespace msdeform

int main(int argc, char** argv) {
  gflags::SetUsageMessage(
      "msdeform --mesh=PATH (--sel=PATH --def=PATH | --scenario=PATH) "
      "[--method=multiscale|static|static_dense] [--static_nodes=220] [--frames=N] "
      "[--out=PATH] [--report=PATH] [--dump_nodes=PATH] [--seed=N] [--cell_width=W] "
      "[--threads=N]\nWith no arguments: the default armadillo edit.");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  google::InitGoogleLogging(argv[0]);
  FLAGS_logtostderr = true;
  // Errors are the one-line messages of Run(); Ceres's own log (e.g. an
  // "invalid steps" error on a diverging solve) only with --verbose.
  FLAGS_minloglevel = FLAGS_verbose ? 0 : 3;
  if (argc > 1) {
    std::cerr << "msdeform: unexpected argument '" << argv[1] << "' (flags are --name=value)\n";
    return 1;
  }
  return msdeform::Run();
}
