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
#include "scales/deformer_flags.h"

DEFINE_string(scenarios, MSDEFORM_SOURCE_DIR "/experiments/scenarios",
              "[input] Folder of the scenario entries (*.json).");
DEFINE_string(out_dir, MSDEFORM_SOURCE_DIR "/experiments/results", "[output] Where the tables go.");
DEFINE_bool(quick, false, "[input] The CI subset: cactus and hand_finger, 5 frames, ablations "
                          "on the cactus.");
DEFINE_int32(frames, 0, "[input] Drag frames per scenario (0: the scenario's; 5 with --quick).");
DEFINE_string(only, "", "[input] Comma-separated scenario names to run (default: all).");
DEFINE_string(methods, "",
              "[method] Comma-separated methods of table 2: multiscale, static, static_dense, "
              "cgal_arap (default: all four).");
DEFINE_bool(time_other_backend, true,
            "[solver] Also time multiscale and static with the other backend (Ceres when "
            "--solver=gauss_newton, the default).");
DEFINE_int32(cgal_iterations, 20, "[solver] CGAL ARAP iterations per frame.");

namespace msdeform {
namespace {

bool FillOptions(RunnerOptions* options, std::string* error) {
  options->scenario_dir = FLAGS_scenarios;
  options->out_dir = FLAGS_out_dir;
  options->source_dir = MSDEFORM_SOURCE_DIR;
  options->quick = FLAGS_quick;
  options->frames = FLAGS_frames;
  std::stringstream only(FLAGS_only);
  std::string name;
  while (std::getline(only, name, ','))
    if (!name.empty()) options->only.push_back(name);
  std::stringstream methods(FLAGS_methods);
  while (std::getline(methods, name, ','))
    if (!name.empty()) options->methods.push_back(name);
  options->time_other_backend = FLAGS_time_other_backend;
  if (!DeformerOptionsFromFlags(&options->deformer, error)) return false;
  options->threads = options->deformer.num_threads;
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
  // The runner measures one core per run unless told otherwise.
  gflags::SetCommandLineOptionWithMode("threads", "1", gflags::SET_FLAGS_DEFAULT);
  const std::string usage =
      "msdeform_experiments [--quick] [--out_dir=DIR] [--scenarios=DIR] [--only=a,b] "
      "[--frames=N] [--threads=N] [any msdeform method, solver or ablation flag]";
  if (msdeform::HandleHelpRequest(argc, argv, usage, std::cout)) return 0;
  gflags::SetUsageMessage(usage);
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
