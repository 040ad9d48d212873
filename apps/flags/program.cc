#include "apps/flags/program.h"

#include <iostream>
#include <sstream>

#include <gflags/gflags.h>
#include <glog/logging.h>

#include "apps/flags/deformer_flags.h"
#include "msdeform/core/main_guard.h"

namespace msdeform {
namespace {

// The program of the running RunProgram (main() runs one).
const ProgramInfo* g_info = nullptr;
int (*g_body)(const std::vector<std::string>&) = nullptr;

int Fail(const std::string& message) {
  std::cerr << g_info->name << ": " << message << "\n";
  return 1;
}

int Main(int argc, char** argv) {
  const ProgramInfo& info = *g_info;
  if (HandleHelpRequest(argc, argv, info.usage, std::cout)) return 0;
  const std::vector<std::string> command_line(argv, argv + argc);
  std::string error;
  if (!CheckFlagNames(argc, argv, &error) || !CheckFlagValues(argc, argv, &error)) {
    return Fail(error);
  }
  gflags::SetUsageMessage(info.usage);
  if (!info.version.empty()) gflags::SetVersionString(info.version);
  gflags::ParseCommandLineFlags(&argc, &argv, true);
  google::InitGoogleLogging(argv[0]);
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = info.verbose != nullptr && *info.verbose ? 0 : info.quiet_log_level;
  if (argc > 1) {
    return Fail(std::string("unexpected argument '") + argv[1] + "' (flags are --name=value)");
  }
  return g_body(command_line);
}

}  // namespace

int RunProgram(const ProgramInfo& info,
               int (*body)(const std::vector<std::string>& command_line), int argc,
               char** argv) {
  g_info = &info;
  g_body = body;
  return RunReportingOutOfMemory(info.name.c_str(), Main, argc, argv);
}

std::vector<std::string> SplitList(const std::string& list) {
  std::vector<std::string> names;
  std::stringstream stream(list);
  std::string name;
  while (std::getline(stream, name, ','))
    if (!name.empty()) names.push_back(name);
  return names;
}

}  // namespace msdeform
