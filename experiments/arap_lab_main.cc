// msdeform_arap_lab: the ARAP solver lab (experiments/arap_lab.h): plain
// local/global against Anderson acceleration on full_arap's energy, and the
// subspace ARAP energy's local/global against its Gauss-Newton, as
// iterations and milliseconds to a relative gap of 1e-3 and 1e-6 per frame.
//
//   build/experiments/msdeform_arap_lab --out_dir=experiments/results
//   build/experiments/msdeform_arap_lab --only=cactus --measured_frames=1,30 --out_dir=/tmp/lab

#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <gflags/gflags.h>

#include "apps/flags/deformer_flags.h"
#include "apps/flags/program.h"
#include "experiments/arap_lab.h"
#include "msdeform/core/build_info.h"

DEFINE_string(scenarios, "",
              "[input] Folder of the scenario entries (*.json). Default: experiments/scenarios "
              "of the source tree.");
DEFINE_string(out_dir, "arap_lab_out",
              "[output] Where arap_solvers.{csv,md} go (created if missing). The committed "
              "tables are regenerated with --out_dir=experiments/results.");
DEFINE_string(only, "", "[input] Comma-separated scenario names to run (default: all).");
DEFINE_int32(frames, 0, "[input] Drag frames per scenario (0: the scenario's).");
DEFINE_string(measured_frames, "1,10,20,30",
              "[input] Comma-separated 1-based frames measured in each drag.");
DEFINE_string(anderson_windows, "3,5,10",
              "[solver] full_arap: comma-separated Anderson windows compared with plain "
              "local/global.");
DEFINE_int32(frame_cap, 3000,
             "[solver] full_arap: iterations per measured frame at most, every variant alike.");
DEFINE_int32(local_global_cap, 2000,
             "[solver] Subspace energy: local/global iterations per frame at most.");
DEFINE_int32(gauss_newton_cap, 100,
             "[solver] Subspace energy: Gauss-Newton iterations per frame at most.");
DEFINE_int32(jobs, 1, "[solver] Scenarios measured at the same time (one thread each unless "
                     "--threads says more).");
DEFINE_bool(full_arap, true, "[solver] The full_arap rows (plain and Anderson).");
DEFINE_bool(subspace, true, "[solver] The subspace ARAP energy's rows (its two solvers).");
DEFINE_int32(reference_cap, 500,
             "[solver] Subspace energy: the Gauss-Newton reference's iterations per frame at "
             "most.");
DEFINE_string(stem, "arap_solvers", "[output] File stem of the tables (<stem>.csv, <stem>.md).");

namespace {

bool ParseInts(const std::string& flag, const std::string& list, std::vector<int>* values,
               std::string* error) {
  values->clear();
  std::stringstream stream(list);
  std::string item;
  while (std::getline(stream, item, ',')) {
    if (item.empty()) continue;
    try {
      size_t used = 0;
      values->push_back(std::stoi(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      *error = "--" + flag + ": '" + item + "' is not an integer";
      return false;
    }
  }
  return true;
}

bool FillOptions(msdeform::ArapLabOptions* options, std::string* error) {
  options->scenario_dir = FLAGS_scenarios.empty()
                              ? msdeform::SourceTreePath("experiments/scenarios")
                              : FLAGS_scenarios;
  options->out_dir = FLAGS_out_dir;
  options->only = msdeform::SplitList(FLAGS_only);
  options->frames = FLAGS_frames;
  if (!ParseInts("measured_frames", FLAGS_measured_frames, &options->measured_frames, error) ||
      !ParseInts("anderson_windows", FLAGS_anderson_windows, &options->anderson_windows,
                 error)) {
    return false;
  }
  options->max_iterations = FLAGS_frame_cap;
  options->subspace_local_global_iterations = FLAGS_local_global_cap;
  options->subspace_gauss_newton_iterations = FLAGS_gauss_newton_cap;
  options->subspace = FLAGS_subspace;
  options->jobs = FLAGS_jobs;
  options->full_arap = FLAGS_full_arap;
  options->subspace_reference_iterations = FLAGS_reference_cap;
  options->stem = FLAGS_stem;
  if (!msdeform::DeformerOptionsFromFlags(&options->deformer, error, {},
                                          {msdeform::Energy::kArap})) {
    return false;
  }
  options->threads = options->deformer.num_threads;
  options->progress = [](const std::string& line) {
    std::printf("%s\n", line.c_str());
    std::fflush(stdout);
  };
  return options->Check(error);
}

int Body(const std::vector<std::string>&) {
  std::string error;
  msdeform::ArapLabOptions options;
  if (!FillOptions(&options, &error) || !msdeform::RunArapLab(options, &error)) {
    std::cerr << "msdeform_arap_lab: " << error << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // One core unless told otherwise, as msdeform_experiments.
  for (const char* spelling : {"num_threads", "threads"}) {
    gflags::SetCommandLineOptionWithMode(spelling, "1", gflags::SET_FLAGS_DEFAULT);
  }
  msdeform::ProgramInfo info;
  info.name = "msdeform_arap_lab";
  info.usage =
      "msdeform_arap_lab [--out_dir=DIR] [--scenarios=DIR] [--only=a,b] "
      "[--measured_frames=1,10,20,30] [--anderson_windows=3,5,10] [--frame_cap=N] "
      "[--local_global_cap=N] [--gauss_newton_cap=N] [--subspace=false] [--threads=N] [--jobs=N] "
      "[any msdeform energy flag for the subspace energy]";
  return msdeform::RunProgram(info, Body, argc, argv);
}
