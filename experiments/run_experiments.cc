// msdeform_experiments: regenerates every table under experiments/results/
// from the scenarios under experiments/scenarios/ (README.md).
//
//   build/experiments/msdeform_experiments                 # the full run
//   build/experiments/msdeform_experiments --quick --out_dir=/tmp/quick

#include <cstdio>
#include <iostream>
#include <sstream>

#include <gflags/gflags.h>
#include <glog/logging.h>

#include "experiments/runner.h"

DEFINE_string(scenarios, MSDEFORM_SOURCE_DIR "/experiments/scenarios",
              "Folder of the scenario entries (*.json).");
DEFINE_string(out_dir, MSDEFORM_SOURCE_DIR "/experiments/results", "Where the tables go.");
DEFINE_bool(quick, false, "The CI subset: cactus and hand_finger, 5 frames, ablations and solver "
                          "variants on the cactus.");
DEFINE_int32(frames, 0, "Drag frames per scenario (0: the scenario's; 5 with --quick).");
DEFINE_int32(threads, 1, "Threads for the Ceres solve and the skinning.");
DEFINE_string(only, "", "Comma-separated scenario names to run (default: all).");
DEFINE_string(methods, "",
              "Comma-separated methods of table 2: multiscale, static, static_dense, "
              "cgal_arap (default: all four).");
DEFINE_bool(time_gauss_newton, true,
            "Also time multiscale and static with the Gauss-Newton backend.");
DEFINE_string(rigidity, msdeform::RigidityModelName(msdeform::RigidityOptions().model),
              "Rigidity estimate of the multi-scale method: harmonic or paper.");
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
DEFINE_double(threshold_floor, msdeform::ScaleSelectionOptions().threshold_floor,
              "Lower bound of the rigidity threshold T (Eq. 7: 0.1).");
DEFINE_uint64(seed, 1, "Seed of every random choice (DG1 node vertices, handle kick).");
DEFINE_int32(max_iterations, 20, "Ceres iteration cap per frame.");
DEFINE_int32(cgal_iterations, 20, "CGAL ARAP iterations per frame.");

namespace msdeform {
namespace {

bool FillOptions(RunnerOptions* options, std::string* error) {
  options->scenario_dir = FLAGS_scenarios;
  options->out_dir = FLAGS_out_dir;
  options->source_dir = MSDEFORM_SOURCE_DIR;
  options->quick = FLAGS_quick;
  options->frames = FLAGS_frames;
  options->threads = FLAGS_threads;
  std::stringstream only(FLAGS_only);
  std::string name;
  while (std::getline(only, name, ','))
    if (!name.empty()) options->only.push_back(name);
  std::stringstream methods(FLAGS_methods);
  while (std::getline(methods, name, ','))
    if (!name.empty()) options->methods.push_back(name);
  options->time_gauss_newton = FLAGS_time_gauss_newton;
  if (!msdeform::ParseMethodVariant(FLAGS_rigidity, FLAGS_half_free, FLAGS_border,
                                    &options->deformer, error)) {
    return false;
  }
  options->deformer.selection.threshold_floor = FLAGS_threshold_floor;
  options->deformer.hold_fixed_vertices = FLAGS_hold_fixed_vertices;
  options->deformer.graph.seed = FLAGS_seed;
  options->deformer.rigidity.seed = FLAGS_seed;
  options->deformer.solver.max_num_iterations = FLAGS_max_iterations;
  options->cgal.iterations = FLAGS_cgal_iterations;
  options->progress = [](const std::string& line) {
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  };
  return options->Check(error);
}

}  // namespace
}  // namespace msdeform

int main(int argc, char** argv) {
  gflags::SetUsageMessage(
      "msdeform_experiments [--quick] [--out_dir=DIR] [--scenarios=DIR] [--only=a,b] "
      "[--frames=N] [--threads=N]");
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  google::InitGoogleLogging(argv[0]);
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = 1;
  if (argc > 1) {
    std::cerr << "msdeform_experiments: unexpected argument '" << argv[1]
              << "' (flags are --name=value)\n";
    return 1;
  }
  std::string error;
  msdeform::RunnerOptions options;
  if (!msdeform::FillOptions(&options, &error) || !msdeform::RunExperiments(options, &error)) {
    std::cerr << "msdeform_experiments: " << error << "\n";
    return 1;
  }
  return 0;
}
