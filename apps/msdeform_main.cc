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
#include "scales/deformer_flags.h"

DEFINE_string(mesh, "", "[input] Input mesh (OFF, OBJ, PLY, STL). Default: the scenario's mesh.");
DEFINE_string(sel, "", "[input] Botsch-Sorkine .sel handle file (needs --def).");
DEFINE_string(def, "", "[input] Botsch-Sorkine .def 4x4 handle transform (needs --sel).");
DEFINE_string(scenario, "", "[input] JSON scenario (docs/scenarios.md). Default when neither "
                            "--sel nor --scenario is given: data/scenarios/armadillo_claw.json.");
DEFINE_int32(frames, 0, "[input] Drag frames from rest to the target (0: the scenario's, or 1).");
DEFINE_string(out, "", "[output] Deformed mesh (OFF, OBJ or PLY by extension). Default: "
                       "msdeform_out/<name>_<method>.off.");
DEFINE_string(report, "", "[output] JSON report. Default: next to --out with extension .json.");
DEFINE_string(dump_nodes, "", "[output] CSV of the DG1 nodes: node,x,y,z,e_prime,class.");
DEFINE_bool(quiet, false, "[diagnostics] Print nothing but errors.");
DEFINE_bool(verbose, false,
            "[diagnostics] Also print the solver's own log (Ceres warnings and errors).");

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
  if (!DeformerOptionsFromFlags(options, error)) return false;
  if (FLAGS_frames < 0 || FLAGS_frames > kMaxScenarioFrames) {
    *error = "--frames=" + std::to_string(FLAGS_frames) + ": expected 0.." +
             std::to_string(kMaxScenarioFrames);
    return false;
  }
  return true;
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
                      ? "msdeform_out/" + job->name + "_" + MethodName(job->options.method) + ".off"
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
  // A frame whose solve fails keeps the last good node transforms and the
  // drag goes on from there; only the last frame is the result the user asked
  // for, so only its failure is an error.
  DragAlongOptions drag_options;
  drag_options.continue_after_failure = true;
  DragLog log;
  if (!DragAlong(&deformer, job.path, drag_options, &log, &error)) {
    std::cerr << "msdeform: " << job.mesh_path << ": " << error << "; "
              << log.failed_frames.size() << " failed frame(s); no output written\n";
    return 1;
  }
  std::vector<double> frame_ms, solve_ms, skin_ms, iterations, factorizations;
  for (const DragStats& stats : log.frames) {
    frame_ms.push_back(stats.frame_ms);
    solve_ms.push_back(stats.solve_ms);
    skin_ms.push_back(stats.skin_ms);
    iterations.push_back(stats.iterations);
    factorizations.push_back(stats.factorizations);
  }
  const double final_cost = log.frames.back().final_cost;
  const std::vector<int>& failed_frames = log.failed_frames;

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
  report["method"] = MethodName(job.options.method);
  report["solver"] = SolverName(job.options.backend);
  report["seed"] = job.options.graph.seed;
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
  double iterations_total = 0.0, factorizations_total = 0.0;
  for (double value : iterations) iterations_total += value;
  for (double value : factorizations) factorizations_total += value;
  report["solve"] = {{"iterations_median", Median(iterations)},
                     {"iterations_total", iterations_total},
                     {"factorizations_total", factorizations_total},
                     {"final_cost", final_cost}};
  report["failed_frames"] = failed_frames;
  report["output"] = job.out_path;
  if (!staged.Stage(job.report_path, &staged_path, &error) ||
      !WriteText(staged_path, report.dump(2) + "\n", &error) || !staged.Commit(&error)) {
    std::cerr << "msdeform: " << error << "\n";
    return 1;
  }

  if (!FLAGS_quiet) {
    std::printf("msdeform: %s (%d vertices) %s, scale %d of %zu, %d+%d free nodes, %d variables\n",
                job.name.c_str(), job.mesh.num_vertices(), MethodName(job.options.method),
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
  const std::string usage =
      "msdeform: edit a mesh with the multi-scale method of Liu & Su 2008.\n"
      "  msdeform [--scenario=PATH | --mesh=PATH --sel=PATH --def=PATH] [flags]\n"
      "With no arguments: the default armadillo edit (data/scenarios/armadillo_claw.json).";
  if (msdeform::HandleHelpRequest(argc, argv, usage, std::cout)) return 0;
  gflags::SetUsageMessage(usage);
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
