// The main() every msdeform program shares: --help from the flags' topics,
// unknown flags named with the nearest one, a value not of its flag's type
// named in one line, gflags's usage and version,
// glog to standard error, no stray argument, and out of memory reported in
// one line (core/main_guard.h). A program states what differs and its body:
//
//   int main(int argc, char** argv) {
//     msdeform::ProgramInfo info;
//     info.name = "msdeform";
//     info.usage = "msdeform: edit a mesh ...";
//     return msdeform::RunProgram(info, Run, argc, argv);
//   }
//
// Every error before the body is one line "<name>: <message>" and exit 1.

#ifndef MSDEFORM_APPS_FLAGS_PROGRAM_H_
#define MSDEFORM_APPS_FLAGS_PROGRAM_H_

#include <string>
#include <vector>

namespace msdeform {

struct ProgramInfo {
  // The program as its messages start ("msdeform_experiments").
  std::string name;
  // Printed by --help above the program's flags, and gflags's usage message.
  std::string usage;
  // --version's text (gflags's flag); empty: gflags's default.
  std::string version;
  // glog's minimum level once the flags are read: `quiet_log_level`, or 0
  // (everything) when `verbose` is set and true after parsing.
  int quiet_log_level = 1;
  const bool* verbose = nullptr;
};

// Runs the prologue on argv, then body(command line as given); returns the
// exit status: 0 after --help, 1 with one line on standard error for an
// unknown flag, a stray argument or running out of memory, else the body's.
int RunProgram(const ProgramInfo& info,
               int (*body)(const std::vector<std::string>& command_line), int argc,
               char** argv);

// A list flag's names: "a,b,,c" -> {"a", "b", "c"} (empty items dropped).
std::vector<std::string> SplitList(const std::string& list);

}  // namespace msdeform

#endif  // MSDEFORM_APPS_FLAGS_PROGRAM_H_
