// msdeform: edit a mesh with the multi-scale method of Liu & Su 2008 (or one
// of the single-static-graph baselines) and write the deformed mesh, a JSON
// report that can repeat the run (--rerun), and optionally every frame's mesh
// and the DG1 nodes with their rigidity and class.
//
// With no arguments it runs the default edit: the armadillo with its feet
// fixed and a claw dragged (data/scenarios/armadillo_claw.json).

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include <gflags/gflags.h>
#include <glog/logging.h>
#include <nlohmann/json.hpp>

#include "apps/flags/deformer_flags.h"
#include "apps/flags/method_flags.h"
#include "apps/flags/program.h"
#include "apps/outputs.h"
#include "msdeform/core/build_info.h"
#include "msdeform/core/drag_path.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/metrics.h"
#include "msdeform/core/scenario.h"
#include "msdeform/core/timing.h"
#include "msdeform/methods/method_option_table.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/methods/polish.h"
#include "msdeform/methods/registry.h"
#include "msdeform/methods/graph_method.h"

DEFINE_string(mesh, "",
              "[input] Input mesh (OFF, OBJ, PLY, STL). Default: the scenario's mesh.");
DEFINE_string(sel, "", "[input] Botsch-Sorkine .sel handle file (with --def and --mesh).");
DEFINE_string(def, "",
              "[input] Botsch-Sorkine .def 4x4 handle transform, world coordinates (with --sel).");
DEFINE_string(scenario, "",
              "[input] JSON scenario (docs/formats.md). Default when neither --sel nor "
              "--scenario is given: data/scenarios/armadillo_claw.json.");
DEFINE_int32(frames, 0,
             "[input] Drag frames from rest to the target, 0..100000 (0: the scenario's, or 1).");
DEFINE_string(rerun, "",
              "[input] Repeat the run a report describes (same inputs, checked by sha256, same "
              "settings); only output and diagnostic flags may be added.");
DEFINE_string(out, "",
              "[output] Deformed mesh (.off, .obj or .ply). Default: "
              "msdeform_out/<name>_<method>_<energy>_<solver>.off for a graph method, "
              "msdeform_out/<name>_<method>.off for another (its name says its energy).");
DEFINE_string(report, "", "[output] JSON report. Default: --out with extension .json.");
DEFINE_string(dump_nodes, "", "[output] CSV of the DG1 nodes: node,x,y,z,e_prime,class.");
DEFINE_string(out_frames, "",
              "[output] Folder for every frame's mesh, <name>_0001.<ext> ... (ext of --out).");
// The non-graph methods' options (methods/method_options.h); --method itself
// is apps/flags/deformer_flags.cc's and takes any registered name here.
// Polish on release (methods/polish.h): the defaults are PolishOptions's.
DEFINE_bool(polish, false,
            "[method] After the last frame, polish the result with a few accelerated full_arap "
            "iterations (handle and fixed vertices exact): --out is the polished mesh, the "
            "report's \"polish\" has the ARAP energy before and after, and a line is printed.");
DEFINE_int32(polish_iterations, 30, "[method] --polish: iterations at most, 0..1000000.");
DEFINE_double(polish_time_ms, 0.0,
              "[method] --polish: milliseconds of iterating at most, 0 for no limit (a limit "
              "makes the result depend on the machine's speed).");
DEFINE_double(polish_tolerance, 1e-7,
              "[method] --polish: stop when a plain step lowers the energy by at most this "
              "fraction of it, in [0, 1].");
DEFINE_int32(polish_anderson_window, 5,
             "[method] --polish: Anderson acceleration's window, 0..50 (0: plain local/global).");
DEFINE_bool(overwrite, false, "[output] Replace outputs that exist (otherwise an error).");
DEFINE_bool(quiet, false, "[diagnostics] Print nothing but errors.");
DEFINE_bool(verbose, false,
            "[diagnostics] Also print the solver's own log (Ceres warnings and errors).");

namespace msdeform {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using Json = nlohmann::ordered_json;

const std::vector<std::string> kMeshExtensions = {".off", ".obj", ".ply"};
// Flags a rerun may add: they change where results go or what is printed,
// never a number.
const std::set<std::string> kOutputFlags = {"out",       "report", "dump_nodes", "out_frames",
                                            "overwrite", "quiet",  "verbose",    "rerun"};

// Everything the command line asks for, resolved and checked.
struct Job {
  std::string name;
  std::string mesh_path, scenario_path, sel_path, def_path;  // inputs ("" if none)
  Mesh mesh;
  HandleLayout layout;
  std::vector<int> watch;             // empty without a watch region
  std::vector<HandleTransforms> path;  // one transform per frame
  std::string out_path, report_path, nodes_path, frames_dir;
  MeshReadReport read_report;
  std::string method;  // a registered name (methods/registry.h)
  DeformerOptions options;
  MethodOptions method_options;  // options, and the other methods' own
  double load_ms = 0.0;
};

// --out_frames: frame f (1-based) as <dir>/<name>_0001.<extension of --out>.
std::string FramePath(const Job& job, int frame) {
  char number[16];
  std::snprintf(number, sizeof(number), "_%04d", frame);
  return (fs::path(job.frames_dir) /
          (job.name + number + fs::path(job.out_path).extension().string()))
      .string();
}

std::string Absolute(const std::string& path) {
  return path.empty() ? path : fs::absolute(path).lexically_normal().string();
}

// Reads the mesh; faces it drops (repeated vertex, exact duplicate) are
// noted on stderr (unless --quiet) and in the report.
bool LoadMesh(const std::string& path, int num_threads, Mesh* mesh, MeshReadReport* report,
              std::string* error) {
  MeshReadOptions options;
  options.num_threads = num_threads;
  if (!ReadMesh(path, options, mesh, report, error)) return false;
  if (!report->notice.empty() && !FLAGS_quiet) {
    std::cerr << "msdeform: notice: " << report->notice << "\n";
  }
  return true;
}

// A graph method's per-frame solver; "" for another method (it has its own).
std::string FrameSolver(const Job& job) {
  return IsGraphMethod(job.method) ? SolverName(job.options.backend) : "";
}

// What tells runs on one input apart: the method, then a graph method's
// energy and solver ("multiscale_ed_gauss_newton"); another method's name
// says its energy and solver ("cgal_arap").
std::string RunTag(const Job& job) {
  if (!IsGraphMethod(job.method)) return job.method;
  return job.method + "_" + MinimisedEnergy(job.method, job.options) + "_" + FrameSolver(job);
}

bool PrepareJob(Job* job, std::string* error) {
  // --method names any registered method; MethodOptionsFromFlags leaves
  // deformer.method at its default for a method that is not a graph.
  job->method = MethodFlag();
  if (!IsMethodName(job->method)) {
    *error = "--method=" + job->method + ": expected " + MethodNameList();
    return false;
  }
  // A flag given for a method that does not read it is an error, not
  // silently ignored (a rerun's flags come from a run that was checked).
  if (FLAGS_rerun.empty() && !CheckFlagsReadBy(job->method, error)) return false;
  if (!MethodOptionsFromFlags(&job->method_options, error)) return false;
  job->options = job->method_options.deformer;
  Method graph_method;
  if (!ParseMethod(job->method, &graph_method) && !FLAGS_dump_nodes.empty()) {
    *error = "--dump_nodes: the " + job->method + " method has no deformation graph";
    return false;
  }
  if (FLAGS_frames < 0 || FLAGS_frames > kMaxScenarioFrames) {
    *error = "--frames=" + std::to_string(FLAGS_frames) + ": expected 0.." +
             std::to_string(kMaxScenarioFrames);
    return false;
  }

  // Inputs: names first, so that the outputs can be checked against them
  // before anything is read.
  Scenario scenario;
  if (!FLAGS_sel.empty() || !FLAGS_def.empty()) {
    if (FLAGS_sel.empty() || FLAGS_def.empty() || FLAGS_mesh.empty() || !FLAGS_scenario.empty()) {
      *error = "--sel and --def go together, with --mesh and without --scenario";
      return false;
    }
    job->mesh_path = FLAGS_mesh;
    job->sel_path = FLAGS_sel;
    job->def_path = FLAGS_def;
    job->name = fs::path(FLAGS_mesh).stem().string();
  } else {
    job->scenario_path = FLAGS_scenario.empty() ? DataDir() + "/scenarios/armadillo_claw.json"
                                                : FLAGS_scenario;
    if (!ReadScenario(job->scenario_path, &scenario, error)) return false;
    if (FLAGS_frames > 0) scenario.frames = FLAGS_frames;
    job->name = scenario.name;
    job->mesh_path = FLAGS_mesh.empty() ? scenario.mesh_path : FLAGS_mesh;
    job->sel_path = scenario.sel_path;
    job->def_path = scenario.def_path;
  }

  // Outputs, checked before any work.
  job->out_path =
      FLAGS_out.empty() ? "msdeform_out/" + job->name + "_" + RunTag(*job) + ".off" : FLAGS_out;
  job->report_path = FLAGS_report.empty()
                         ? fs::path(job->out_path).replace_extension(".json").string()
                         : FLAGS_report;
  job->nodes_path = FLAGS_dump_nodes;
  job->frames_dir = FLAGS_out_frames;
  std::vector<OutputCheck> outputs = {{job->out_path, "--out", kMeshExtensions},
                                      {job->report_path, "--report", {".json"}},
                                      {job->nodes_path, "--dump_nodes", {".csv"}}};
  if (!job->frames_dir.empty()) {
    std::error_code ec;
    if (fs::exists(job->frames_dir, ec) && !fs::is_directory(job->frames_dir, ec)) {
      *error = "--out_frames=" + job->frames_dir + ": exists and is not a folder";
      return false;
    }
    const int frames = FLAGS_frames > 0 ? FLAGS_frames : std::max(1, scenario.frames);
    for (int f = 1; f <= frames; ++f) {
      outputs.push_back({FramePath(*job, f), "--out_frames", kMeshExtensions});
    }
  }
  const std::vector<std::string> inputs = {job->mesh_path, job->sel_path, job->def_path,
                                           job->scenario_path};
  if (!CheckOutputs(outputs, inputs, FLAGS_overwrite, error)) return false;

  // Read the inputs.
  const auto load_start = Clock::now();
  // The load uses --threads too (the same mesh and regions for any count).
  const int threads = job->options.num_threads;
  if (!LoadMesh(job->mesh_path, threads, &job->mesh, &job->read_report, error)) return false;
  if (job->scenario_path.empty()) {
    if (!ReadSel(job->sel_path, job->mesh.num_vertices(), &job->layout, error)) return false;
    Eigen::Affine3d deformed_from_rest;
    if (!ReadDef(job->def_path, &deformed_from_rest, error)) return false;
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int v : job->layout.moveable) centroid += job->mesh.vertices.col(v);
    centroid /= static_cast<double>(job->layout.moveable.size());
    const std::vector<Eigen::Affine3d> path =
        InterpolateDragPath(deformed_from_rest, centroid, std::max(FLAGS_frames, 1));
    job->path.assign(path.begin(), path.end());
  } else {
    HandleTransforms deformed_from_rest;
    if (!ResolveScenario(scenario, job->mesh, &job->layout, &job->watch, &deformed_from_rest,
                         error, threads)) {
      return false;
    }
    job->path = DragPath(scenario, job->mesh, job->layout, threads);
  }
  job->load_ms = MillisecondsSince(load_start);
  return true;
}

std::string NodesCsv(const GraphMethod& deformer) {
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

// What the run was made with: enough to repeat it (--rerun) and to know where
// its numbers come from.
bool Provenance(const Job& job, const std::vector<std::string>& command_line, Json* report,
                std::string* error) {
  (*report)["msdeform"] = {{"version", MsdeformVersion()},
                           {"commit", MsdeformCommit()},
                           {"ceres", CeresVersion()},
                           {"eigen", EigenVersion()},
                           {"openmesh", OpenMeshVersion()}};
  (*report)["machine"] = {{"cores", NumCores()}, {"cpu", CpuModel()}};
  (*report)["date"] = UtcNow();
  (*report)["command_line"] = command_line;
  // Every flag that can change a number, as resolved (input paths absolute).
  Json flags = Json::object();
  for (const auto& [name, value] : ProgramFlagValues()) {
    if (kOutputFlags.count(name)) continue;
    // The polish flags only when polishing, so a run without it records what
    // it did before they existed.
    if (!FLAGS_polish && name.rfind("polish", 0) == 0) continue;
    flags[name] = value;
  }
  flags["mesh"] = FLAGS_mesh.empty() ? "" : Absolute(job.mesh_path);
  flags["sel"] = Absolute(FLAGS_sel);
  flags["def"] = Absolute(FLAGS_def);
  flags["scenario"] = Absolute(job.scenario_path);
  (*report)["flags"] = flags;
  Json inputs = Json::array();
  const std::pair<const char*, std::string> files[] = {{"scenario", job.scenario_path},
                                                       {"mesh", job.mesh_path},
                                                       {"sel", job.sel_path},
                                                       {"def", job.def_path}};
  for (const auto& [role, path] : files) {
    if (path.empty()) continue;
    std::string digest;
    if (!Sha256File(path, &digest, error)) return false;
    inputs.push_back({{"role", role}, {"path", Absolute(path)}, {"sha256", digest}});
  }
  (*report)["inputs"] = inputs;
  Json options = Json::object();
  for (const auto& [name, value] : DescribeOptions(job.options)) options[name] = value;
  // The methods' own (cgal.iterations, fastlsm.steps_per_frame, ...).
  for (const auto& [name, value] : MethodOptionTable().Describe(job.method_options)) {
    if (IsMethodOwnRow(name)) options[name] = value;
  }
  (*report)["options"] = options;
  return true;
}

// --rerun: sets every recorded flag from the report and checks that the
// inputs are the bytes the report was made from.
bool ApplyRerun(const std::string& report_path, std::string* error) {
  for (const auto& [name, value] : ProgramFlagValues()) {
    gflags::CommandLineFlagInfo info;
    gflags::GetCommandLineFlagInfo(name.c_str(), &info);
    if (!info.is_default && !kOutputFlags.count(name)) {
      *error = "--rerun=" + report_path + ": --" + name +
               " would change the run; only output and diagnostic flags may be added";
      return false;
    }
  }
  std::ifstream in(report_path);
  if (!in) {
    *error = "--rerun=" + report_path + ": cannot open for reading";
    return false;
  }
  Json report;
  try {
    report = Json::parse(in);
  } catch (const std::exception& e) {
    *error = "--rerun=" + report_path + ": not a JSON report (" + e.what() + ")";
    return false;
  }
  if (!report.is_object() || !report.contains("flags") || !report["flags"].is_object() ||
      !report.contains("inputs")) {
    *error = "--rerun=" + report_path + ": no \"flags\" and \"inputs\" (not an msdeform report)";
    return false;
  }
  const Json& inputs = report["inputs"];
  if (!inputs.is_array()) {
    *error = "--rerun=" + report_path + ": inputs: expected an array of {\"path\": string, " +
             "\"sha256\": string}";
    return false;
  }
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const Json& input = inputs[i];
    if (!input.is_object() || !input.contains("path") || !input["path"].is_string() ||
        !input.contains("sha256") || !input["sha256"].is_string()) {
      *error = "--rerun=" + report_path + ": inputs[" + std::to_string(i) +
               "]: expected {\"path\": string, \"sha256\": string}";
      return false;
    }
  }
  // Only msdeform's own flags: not gflags's --flagfile or --fromenv, which
  // would read further files, nor glog's.
  std::set<std::string> own_flags;
  for (const auto& [name, value] : ProgramFlagValues()) own_flags.insert(name);
  for (const auto& [name, value] : report["flags"].items()) {
    if (!value.is_string() || !own_flags.count(name) ||
        gflags::SetCommandLineOption(name.c_str(), value.get<std::string>().c_str()).empty()) {
      *error = "--rerun=" + report_path + ": flags." + name + ": not a flag of this msdeform";
      return false;
    }
  }
  for (const Json& input : inputs) {
    const std::string path = input["path"].get<std::string>();
    const std::string recorded = input["sha256"].get<std::string>();
    std::string digest;
    if (!Sha256File(path, &digest, error)) {
      *error = "--rerun=" + report_path + ": " + *error;
      return false;
    }
    if (digest != recorded) {
      *error = "--rerun=" + report_path + ": " + path +
               " changed since the report (sha256 " + digest + ", recorded " + recorded + ")";
      return false;
    }
  }
  return true;
}

// --polish's options from its flags (checked even without --polish, so a
// typo is not silently ignored); false with one line naming the flag.
bool PolishOptionsFromFlags(int num_threads, PolishOptions* options, std::string* error) {
  for (const char* flag : {"polish_iterations", "polish_time_ms", "polish_tolerance",
                           "polish_anderson_window"}) {
    gflags::CommandLineFlagInfo info;
    gflags::GetCommandLineFlagInfo(flag, &info);
    if (!info.is_default && !FLAGS_polish) {
      *error = std::string("--") + flag + "=" + info.current_value + " needs --polish";
      return false;
    }
  }
  if (FLAGS_polish_iterations < 0 || FLAGS_polish_iterations > 1000000) {
    *error = "--polish_iterations=" + std::to_string(FLAGS_polish_iterations) +
             ": expected an integer in 0..1000000";
    return false;
  }
  if (!(FLAGS_polish_time_ms >= 0.0) || !std::isfinite(FLAGS_polish_time_ms)) {
    *error = "--polish_time_ms=" + gflags::GetCommandLineFlagInfoOrDie("polish_time_ms").current_value +
             ": expected a number >= 0 (0: no limit)";
    return false;
  }
  if (!(FLAGS_polish_tolerance >= 0.0 && FLAGS_polish_tolerance <= 1.0)) {
    *error = "--polish_tolerance=" +
             gflags::GetCommandLineFlagInfoOrDie("polish_tolerance").current_value +
             ": expected a number in [0, 1]";
    return false;
  }
  if (FLAGS_polish_anderson_window < 0 || FLAGS_polish_anderson_window > 50) {
    *error = "--polish_anderson_window=" + std::to_string(FLAGS_polish_anderson_window) +
             ": expected an integer in 0..50";
    return false;
  }
  options->max_iterations = FLAGS_polish_iterations;
  options->time_budget_ms = FLAGS_polish_time_ms;
  options->relative_tolerance = FLAGS_polish_tolerance;
  options->anderson_window = FLAGS_polish_anderson_window;
  options->num_threads = std::max(1, num_threads);
  return options->Check(error);
}

int Fail(const std::string& message) {
  std::cerr << "msdeform: " << message << "\n";
  return 1;
}

// The method precomputed on the job's mesh with its handles set; false with
// the line Fail prints.
bool StartMethod(const Job& job, std::unique_ptr<EditingMethod>* method, std::string* error) {
  *method = CreateMethod(job.method, error);
  if (*method == nullptr) {
    *error = "--method=" + job.method + ": " + *error;
    return false;
  }
  if (!(*method)->Precompute(job.mesh, job.method_options, error)) {
    *error = job.mesh_path + ": " + *error;
    return false;
  }
  const GraphMethod* deformer = (*method)->graph_method();  // null: not a graph method
  if (deformer != nullptr && job.options.method == Method::kStatic &&
      deformer->graphs().back().num_nodes() < job.options.static_nodes && !FLAGS_quiet) {
    std::cerr << "msdeform: notice: --static_nodes=" << job.options.static_nodes
              << " is more than the mesh's " << deformer->graphs().back().num_nodes()
              << " DG1 nodes; the static graph has " << deformer->graphs().back().num_nodes()
              << "\n";
  }
  if (!(*method)->SetHandles(job.layout, error)) {
    *error = "handles: " + *error;
    return false;
  }
  return true;
}

// Drags the method along the job's path, staging every frame's mesh
// (--out_frames) with the other outputs; false with the line Fail prints.
bool DragJob(const Job& job, EditingMethod* method, StagedOutputs* staged, DragLog* log,
             std::string* error) {
  std::string frame_error;
  Mesh deformed = job.mesh;
  DragAlongOptions drag_options;
  // A frame whose solve fails keeps the last good node transforms and the
  // drag goes on from there; only the last frame is the result the user asked
  // for, so only its failure is an error.
  drag_options.continue_after_failure = true;
  const auto drag_start = Clock::now();
  auto last_progress = drag_start;
  const int num_frames = static_cast<int>(job.path.size());
  drag_options.on_frame = [&](int frame, const DragStats& stats) {
    if (!job.frames_dir.empty() && frame_error.empty()) {
      const std::string path = FramePath(job, frame);
      std::string staged_path;
      deformed.vertices = method->deformed_vertices();
      if (!staged->Stage(path, &staged_path, &frame_error) ||
          !WriteMesh(staged_path, deformed, &frame_error)) {
        frame_error = staged->Translate(frame_error);
      }
    }
    // Progress on long drags: a line every 2 seconds.
    if (!FLAGS_quiet && MillisecondsSince(last_progress) > 2000.0) {
      last_progress = Clock::now();
      std::cerr << "msdeform: frame " << frame << " of " << num_frames << ", "
                << MillisecondsSince(drag_start) / 1000.0 << " s\n";
    }
  };
  if (!DragAlong(method, job.path, drag_options, log, error)) {
    *error = job.mesh_path + ": " + *error + "; " + std::to_string(log->failed_frames.size()) +
             " failed frame(s); no output written";
    return false;
  }
  if (!frame_error.empty()) {
    *error = frame_error;
    return false;
  }
  return true;
}

// The drag's numbers for the report and the summary lines.
struct DragSummary {
  std::vector<double> frame_ms, solve_ms, skin_ms, iterations;
  double iterations_total = 0.0, factorizations_total = 0.0;
  double final_cost = 0.0;
  double diagonal = 0.0;
  double handle_rms = 0.0;
  Displacement leakage;  // of the watch region
};

DragSummary Summarise(const Job& job, const EditingMethod& method, const DragLog& log,
                      const Eigen::Matrix3Xd& result) {
  DragSummary summary;
  for (const DragStats& stats : log.frames) {
    summary.frame_ms.push_back(stats.frame_ms);
    summary.solve_ms.push_back(stats.solve_ms);
    summary.skin_ms.push_back(stats.skin_ms);
    summary.iterations.push_back(stats.iterations);
    summary.iterations_total += stats.iterations;
    summary.factorizations_total += stats.factorizations;
  }
  summary.final_cost = log.frames.back().final_cost;
  const GraphMethod* deformer = method.graph_method();
  summary.diagonal = deformer != nullptr ? deformer->diagonal() : BoundingBoxDiagonal(job.mesh);
  // The quality measures of core/metrics.h, as the experiments compute them.
  summary.handle_rms =
      HandleRmsError(job.mesh, result, job.layout, job.path.back());
  summary.leakage = VertexDisplacement(job.mesh, result, job.watch);
  return summary;
}

// The deformed mesh (`result`) and --nodes, staged; false with the line Fail prints.
bool StageMeshes(const Job& job, const EditingMethod& method, const Eigen::Matrix3Xd& result,
                 StagedOutputs* staged, std::string* error) {
  Mesh deformed = job.mesh;
  deformed.vertices = result;
  if (!deformed.vertices.allFinite()) {
    *error = job.mesh_path + ": the deformed mesh has non-finite coordinates; no output written";
    return false;
  }
  std::string staged_path;
  if (!staged->Stage(job.out_path, &staged_path, error) ||
      !WriteMesh(staged_path, deformed, error)) {
    *error = staged->Translate(*error);
    return false;
  }
  if (!job.nodes_path.empty() && (!staged->Stage(job.nodes_path, &staged_path, error) ||
                                  !WriteText(staged_path, NodesCsv(*method.graph_method()), error))) {
    *error = staged->Translate(*error);
    return false;
  }
  return true;
}

// The report (--report): the run's inputs, provenance, sizes, scales,
// classes, timings and quality, and the polish when there was one.
bool BuildReport(const Job& job, const EditingMethod* method, const DragLog& log,
                 const DragSummary& summary, const PolishReport* polish,
                 const std::vector<std::string>& command_line,
                 Clock::time_point total_start, Json* report_out, std::string* error) {
  Json& report = *report_out;
  const GraphMethod* deformer = method->graph_method();
  const double diagonal = summary.diagonal;
  const double handle_rms = summary.handle_rms;
  const Displacement& leakage = summary.leakage;
  const std::vector<double>& frame_ms = summary.frame_ms;
  const std::vector<double>& solve_ms = summary.solve_ms;
  const std::vector<double>& skin_ms = summary.skin_ms;
  const std::vector<double>& iterations = summary.iterations;
  const double iterations_total = summary.iterations_total;
  const double factorizations_total = summary.factorizations_total;
  const double final_cost = summary.final_cost;
  report["name"] = job.name;
  report["mesh"] = job.mesh_path;
  report["method"] = job.method;
  report["energy"] = MinimisedEnergy(job.method, job.options);
  // A graph method's per-frame solver; null for a method with its own.
  report["solver"] = IsGraphMethod(job.method) ? Json(FrameSolver(job)) : Json(nullptr);
  report["seed"] = job.options.graph.seed;
  if (!Provenance(job, command_line, &report, error)) return false;
  report["vertices"] = job.mesh.num_vertices();
  report["faces"] = job.mesh.num_faces();
  report["dropped_faces"] = {{"repeat_a_vertex", job.read_report.dropped_degenerate_faces},
                             {"duplicates", job.read_report.dropped_duplicate_faces}};
  report["diag"] = diagonal;
  report["handle_vertices"] = {{"fixed", job.layout.fixed.size()},
                               {"moveable", job.layout.moveable.size()}};
  if (const Lattice* lattice = method->lattice()) {
    report["lattice"] = {{"cell_width", lattice->cell_width()},
                         {"surface_particles", lattice->num_surface_particles()},
                         {"num_split_cells", lattice->num_split_cells()},
                         {"interior_particles", lattice->num_interior_particles()},
                         {"particles", lattice->num_particles()}};
  }
  int totally_free = 0, half_free = 0, fixed = 0;
  if (deformer != nullptr) {
    report["scales"] = Json::array();
    for (size_t i = 0; i < deformer->graphs().size(); ++i) {
      // Edges only where the scale was connected (built when used; null otherwise).
      const DeformationGraph& graph = deformer->graphs()[i];
      report["scales"].push_back(
          {{"scale", i + 1},
           {"nodes", graph.num_nodes()},
           {"edges", graph.is_connected() ? Json(graph.edges.size()) : Json(nullptr)}});
    }
    for (NodeClass c : deformer->node_classes()) {
      totally_free += c == NodeClass::kTotallyFree;
      half_free += c == NodeClass::kHalfFree;
      fixed += c == NodeClass::kFixed;
    }
    const ScaleSelection& selection = deformer->selection();
    report["rigidity"] = {{"threshold", selection.threshold},
                          {"group1", selection.group1_size},
                          {"eq6_scale", selection.eq6_scale},
                          {"local_detail_edit", selection.local_detail_edit}};
    report["selected_scale"] = deformer->active_graph() + 1;
    report["nodes"] = {{"totally_free", totally_free}, {"half_free", half_free}, {"fixed", fixed}};
    // Pinned: kept Fixed because they skin a fixed vertex (scale_selection.h).
    if (job.options.method == Method::kMultiScale) {
      report["nodes"]["pinned"] = selection.num_pinned;
    }
    report["fixed_region_exact"] = deformer->fixed_region_exact();
  } else {
    // What the method optimises (ROI vertices, free lattice particles).
    report["nodes_optimized"] = method->nodes_optimized();
  }
  report["variables"] = method->variables();
  if (deformer != nullptr) report["coherence_terms"] = deformer->num_coherence_terms();
  report["frames"] = job.path.size();
  report["timings_ms"] = {{"load", job.load_ms},
                          {"precompute", method->precompute_ms()},
                          {"rigidity", method->rigidity_ms()},
                          {"setup", method->setup_ms()},
                          {"frame_median", Median(frame_ms)},
                          {"solve_median", Median(solve_ms)},
                          {"skin_median", Median(skin_ms)},
                          {"total", MillisecondsSince(total_start)}};
  // Milliseconds by stage (EditingMethod::stages; none for the methods without them).
  Json stages = Json::object();
  const StageTimes stage_times = method->stages();
  for (const auto& [name, ms] : stage_times.entries()) stages[name] = ms;
  report["timings_ms"]["stages"] = stages;
  report["handle_rms"] = handle_rms;
  report["handle_rms_rel"] = handle_rms / diagonal;
  if (!job.watch.empty()) {
    report["watch"] = {{"vertices", job.watch.size()},
                       {"leakage_rel", leakage.mean / diagonal},
                       {"leakage_max_rel", leakage.max / diagonal}};
  }
  report["solve"] = {{"iterations_median", Median(iterations)},
                     {"iterations_total", iterations_total},
                     {"factorizations_total", factorizations_total},
                     {"final_cost", final_cost}};
  report["failed_frames"] = log.failed_frames;
  if (polish != nullptr) {
    report["polish"] = {{"energy_before", polish->energy_before},
                        {"energy_start", polish->energy_start},
                        {"energy_after", polish->energy_after},
                        {"iterations", polish->iterations},
                        {"converged", polish->converged},
                        {"ms", polish->ms},
                        {"setup_ms", polish->setup_ms}};
  }
  report["output"] = job.out_path;
  return true;
}

// Where the handle is a soft constraint, the words the summary adds to its
// error: a graph method under the ed energy (Position terms weighed by w_con
// against the others) or under arap with soft constraints; "" where the
// method holds the handle exactly.
std::string SoftHandleNote(const Job& job) {
  if (!IsGraphMethod(job.method)) return "";
  if (job.options.energy == Energy::kEd) {
    return "; under the ed energy the handle is a soft constraint, weighed by --w_con=" +
           OptionShortNumberText(job.options.w_con);
  }
  if (job.options.arap.constraints == ArapConstraints::kSoft) {
    return "; with --arap_constraints=soft the handle is a soft constraint, weighed by "
           "--arap_soft_weight=" + OptionShortNumberText(job.options.arap.soft_weight);
  }
  return "";
}

// The lines msdeform prints on success (none with --quiet).
void PrintSummary(const Job& job, const EditingMethod& method, const DragLog& log,
                  const DragSummary& summary, const PolishReport* polish) {
  if (FLAGS_quiet) return;
  const GraphMethod* deformer = method.graph_method();
  const double diagonal = summary.diagonal;
  if (deformer != nullptr) {
    int totally_free = 0, half_free = 0;
    for (NodeClass c : deformer->node_classes()) {
      totally_free += c == NodeClass::kTotallyFree;
      half_free += c == NodeClass::kHalfFree;
    }
    std::printf("msdeform: %s (%d vertices), %s method, %s energy, %s solver: scale %d of %zu; "
                "%d Totally Free + %d Half Free nodes optimised (%d variables)\n",
                job.name.c_str(), job.mesh.num_vertices(), job.method.c_str(),
                MinimisedEnergy(job.method, job.options).c_str(), FrameSolver(job).c_str(),
                deformer->active_graph() + 1,
                deformer->graphs().size(), totally_free, half_free, deformer->variables());
  } else {
    std::printf("msdeform: %s (%d vertices), %s method, %s energy: %d elements optimised (%d "
                "variables)\n",
                job.name.c_str(), job.mesh.num_vertices(), job.method.c_str(),
                MinimisedEnergy(job.method, job.options).c_str(), method.nodes_optimized(),
                method.variables());
  }
  std::printf("  %zu frame%s: median frame %.2f ms (solve %.2f, skin %.2f); handle rms %.3g = "
              "%.2g of the bbox diagonal (distance of the handle vertices from their targets%s)\n",
              job.path.size(), job.path.size() == 1 ? "" : "s", Median(summary.frame_ms),
              Median(summary.solve_ms), Median(summary.skin_ms), summary.handle_rms,
              summary.handle_rms / diagonal, SoftHandleNote(job).c_str());
  if (!job.watch.empty()) {
    std::printf("  watch region (%zu vertices) moved %.2g of the diagonal on average, %.2g at "
                "most\n",
                job.watch.size(), summary.leakage.mean / diagonal, summary.leakage.max / diagonal);
  }
  if (polish != nullptr) {
    std::printf("  polish: ARAP energy %.6g -> %.6g (%.4fx) in %d iterations, %.1f ms (setup "
                "%.1f ms)%s\n",
                polish->energy_before, polish->energy_after,
                polish->energy_before > 0.0 ? polish->energy_after / polish->energy_before : 1.0,
                polish->iterations, polish->ms, polish->setup_ms,
                polish->converged ? ", converged" : "");
  }
  std::printf("  wrote %s and %s%s\n", job.out_path.c_str(), job.report_path.c_str(),
              job.frames_dir.empty() ? "" : (" and the frames in " + job.frames_dir).c_str());
  if (!log.failed_frames.empty()) {
    std::printf("  %zu intermediate frame(s) failed to solve and kept the previous pose "
                "(failed_frames in the report)\n",
                log.failed_frames.size());
  }
}

// One run: the method on the job, the drag, the outputs staged and
// committed together, then the summary.
int Run(const std::vector<std::string>& command_line) {
  const auto total_start = Clock::now();
  std::string error;
  Job job;
  if (!PrepareJob(&job, &error)) return Fail(error);
  PolishOptions polish_options;
  if (!PolishOptionsFromFlags(job.options.num_threads, &polish_options, &error)) {
    return Fail(error);
  }
  std::unique_ptr<EditingMethod> method;
  if (!StartMethod(job, &method, &error)) return Fail(error);
  // Every output (frames, mesh, nodes, report) is staged and committed together.
  StagedOutputs staged;
  DragLog log;
  if (!DragJob(job, method.get(), &staged, &log, &error)) return Fail(error);
  Eigen::Matrix3Xd result = method->deformed_vertices();
  PolishReport polish;
  if (FLAGS_polish) {
    if (!PolishOnce(job.mesh, job.layout, job.path.back(), polish_options, &result, &polish,
                    &error)) {
      return Fail("--polish: " + error);
    }
  }
  const PolishReport* polished = FLAGS_polish ? &polish : nullptr;
  const DragSummary summary = Summarise(job, *method, log, result);
  if (!StageMeshes(job, *method, result, &staged, &error)) return Fail(error);
  Json report;
  if (!BuildReport(job, method.get(), log, summary, polished, command_line, total_start, &report,
                   &error)) {
    return Fail(error);
  }
  std::string staged_path;
  if (!staged.Stage(job.report_path, &staged_path, &error) ||
      !WriteText(staged_path, report.dump(2) + "\n", &error)) {
    return Fail(staged.Translate(error));
  }
  if (!staged.Commit(&error)) return Fail(error);
  PrintSummary(job, *method, log, summary, polished);
  return 0;
}

}  // namespace
}  // namespace msdeform

// The program after the shared prologue (apps/flags/program.h): --rerun, then the run.
static int Body(const std::vector<std::string>& command_line) {
  std::string error;
  if (!FLAGS_rerun.empty() && !msdeform::ApplyRerun(FLAGS_rerun, &error)) {
    return msdeform::Fail(error);
  }
  return msdeform::Run(command_line);
}

int main(int argc, char** argv) {
  msdeform::ProgramInfo info;
  info.name = "msdeform";
  info.usage =
      "msdeform: edit a mesh with the multi-scale method of Liu & Su 2008.\n"
      "  msdeform [--scenario=PATH | --mesh=PATH --sel=PATH --def=PATH] [flags]\n"
      "  msdeform --rerun=REPORT.json --out=PATH     (repeat a run from its report)\n"
      "With no arguments: the default armadillo edit (data/scenarios/armadillo_claw.json).";
  // --version (gflags's own flag) prints "msdeform version <this>" and exits 0.
  info.version = std::string(msdeform::MsdeformVersion()) + " (commit " +
                 msdeform::MsdeformCommit() + "); Ceres " + msdeform::CeresVersion() +
                 ", Eigen " + msdeform::EigenVersion() + ", OpenMesh " +
                 msdeform::OpenMeshVersion();
  // Errors are the one-line messages of Run(); Ceres's own log (e.g. an
  // "invalid steps" error on a diverging solve) only with --verbose.
  info.quiet_log_level = 3;
  info.verbose = &FLAGS_verbose;
  return msdeform::RunProgram(info, Body, argc, argv);
}
