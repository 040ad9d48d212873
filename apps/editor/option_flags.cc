#include "apps/editor/option_flags.h"

#include <gflags/gflags.h>

#include "msdeform/scales/deformer_flags.h"

namespace msdeform {
namespace editor {
namespace {

// DeformerOptions's flags are the ones scales/deformer_flags.cc defines.
bool IsDeformerFlag(const std::string& name, gflags::CommandLineFlagInfo* info) {
  if (!gflags::GetCommandLineFlagInfo(name.c_str(), info)) return false;
  const std::string& file = info->filename;
  const std::string suffix = "deformer_flags.cc";
  return file.size() >= suffix.size() &&
         file.compare(file.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

bool SetDeformerFlag(const std::string& name, const std::string& value, DeformerOptions* options,
                     std::string* error) {
  gflags::CommandLineFlagInfo info;
  if (!IsDeformerFlag(name, &info)) {
    *error = "--" + name + ": not a method, solver, weight, rigidity or ablation flag of msdeform";
    return false;
  }
  const std::string old_value = info.current_value;
  if (gflags::SetCommandLineOption(name.c_str(), value.c_str()).empty()) {
    *error = "--" + name + "=" + value + ": expected a " + info.type;
    return false;
  }
  DeformerOptions candidate = *options;
  if (!DeformerOptionsFromFlags(&candidate, error)) {
    gflags::SetCommandLineOption(name.c_str(), old_value.c_str());
    return false;
  }
  *options = candidate;
  return true;
}

std::string DeformerFlagValue(const std::string& name) {
  gflags::CommandLineFlagInfo info;
  return IsDeformerFlag(name, &info) ? info.current_value : "";
}

}  // namespace editor
}  // namespace msdeform
