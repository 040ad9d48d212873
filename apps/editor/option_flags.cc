#include "apps/editor/option_flags.h"

#include <vector>

#include <gflags/gflags.h>

#include "msdeform/scales/deformer_flags.h"

namespace msdeform {
namespace editor {
namespace {

using Row = OptionRow<DeformerOptions>;

}  // namespace

bool SetDeformerFlag(const std::string& name, const std::string& value, DeformerOptions* options,
                     std::string* error) {
  const Row* row = DeformerOptionTable().Find(name);
  if (row == nullptr) {
    *error = "--" + name + ": not an option of msdeform's method, solver, weights, rigidity or "
             "ablations";
    return false;
  }
  const std::vector<std::string> spellings = FlagSpellings(*row);
  if (spellings.empty()) {
    // Not a command-line flag: set on the options alone.
    return DeformerOptionTable().Set(row->name, value, options, error, "--" + name);
  }
  // Every spelling of the row (--solver and --backend) gets the value, so
  // that the flags never disagree; on failure all keep their old values.
  std::vector<gflags::CommandLineFlagInfo> old(spellings.size());
  for (size_t i = 0; i < spellings.size(); ++i) {
    gflags::GetCommandLineFlagInfo(spellings[i].c_str(), &old[i]);
  }
  auto restore = [&] {
    for (size_t i = 0; i < spellings.size(); ++i) {
      gflags::SetCommandLineOption(spellings[i].c_str(), old[i].current_value.c_str());
    }
  };
  for (const std::string& spelling : spellings) {
    if (gflags::SetCommandLineOption(spelling.c_str(), value.c_str()).empty()) {
      restore();
      *error = "--" + name + "=" + value + ": expected a " + old[0].type;
      return false;
    }
  }
  DeformerOptions candidate = *options;
  if (!DeformerOptionsFromFlags(&candidate, error)) {
    restore();
    return false;
  }
  *options = candidate;
  return true;
}

std::string DeformerFlagValue(const std::string& name) {
  const Row* row = DeformerOptionTable().Find(name);
  if (row == nullptr) return "";
  // The spelling that was given, if any.
  std::string value;
  for (const std::string& spelling : FlagSpellings(*row)) {
    gflags::CommandLineFlagInfo info;
    if (!gflags::GetCommandLineFlagInfo(spelling.c_str(), &info)) continue;
    if (value.empty() || !info.is_default) value = info.current_value;
    if (!info.is_default) break;
  }
  return value;
}

}  // namespace editor
}  // namespace msdeform
