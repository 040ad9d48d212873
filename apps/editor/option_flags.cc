#include "apps/editor/option_flags.h"

#include <algorithm>
#include <functional>
#include <vector>

#include <gflags/gflags.h>

#include "apps/flags/deformer_flags.h"
#include "apps/flags/method_flags.h"
#include "msdeform/methods/method_option_table.h"
#include "msdeform/methods/registry.h"

namespace msdeform {
namespace editor {
namespace {

using Row = OptionRow<DeformerOptions>;

// Sets every spelling of a row's flag to `value`, then `parse` from the
// flags; on failure all keep their old values.
bool SetSpellings(const std::string& name, const std::vector<std::string>& spellings,
                  const std::string& value, const std::function<bool(std::string*)>& parse,
                  std::string* error) {
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
  if (!parse(error)) {
    restore();
    return false;
  }
  return true;
}

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
  // Leaving the subspace ARAP energy puts its arap.* options back to their
  // defaults, through their flags while arap is still the energy (another
  // energy does not read them, and Check refuses them there).
  Energy energy = Energy::kArap;
  if (row->name == "energy" && EnergyNames().Parse(value, &energy) && energy != Energy::kArap) {
    const DeformerOptions defaults;
    for (const Row& arap_row : DeformerOptionTable().rows()) {
      if (arap_row.name.rfind("arap.", 0) != 0 ||
          arap_row.get(*options) == arap_row.get(defaults)) {
        continue;
      }
      if (!SetDeformerFlag(FlagSpellings(arap_row).front(), arap_row.get(defaults), options,
                           error)) {
        return false;
      }
    }
  }
  DeformerOptions candidate = *options;
  // --method may name any registered method (msdeform's --method).
  const auto parse = [&](std::string* e) {
    return DeformerOptionsFromFlags(&candidate, e, MethodNames());
  };
  if (!SetSpellings(name, spellings, value, parse, error)) return false;
  *options = candidate;
  return true;
}

bool IsMethodOption(const std::string& name) {
  const OptionRow<MethodOptions>* row = MethodOptionTable().Find(name);
  return row != nullptr && IsMethodOwnRow(row->name);
}

bool RowOfMethod(const std::string& row, const std::string& method) {
  const std::vector<std::string> methods = MethodsOfRow(row);
  return std::find(methods.begin(), methods.end(), method) != methods.end();
}

bool SetMethodFlag(const std::string& name, const std::string& value, MethodOptions* options,
                   std::string* error) {
  if (!IsMethodOption(name)) {
    *error = "--" + name + ": not an option of a method";
    return false;
  }
  const OptionRow<MethodOptions>& row = *MethodOptionTable().Find(name);
  MethodOptions candidate = *options;
  const auto parse = [&](std::string* e) { return MethodOwnOptionsFromFlags(&candidate, e); };
  if (!SetSpellings(FlagSpellings(row).front(), FlagSpellings(row), value, parse, error)) {
    return false;
  }
  *options = candidate;
  return true;
}

std::string DeformerFlagValue(const std::string& name) {
  // A row of the Deformer's table or a method's own.
  const Row* row = DeformerOptionTable().Find(name);
  const OptionRow<MethodOptions>* method_row = MethodOptionTable().Find(name);
  if (row == nullptr && method_row == nullptr) return "";
  const std::vector<std::string> spellings =
      row != nullptr ? FlagSpellings(*row) : FlagSpellings(*method_row);
  // The spelling that was given, if any.
  std::string value;
  for (const std::string& spelling : spellings) {
    gflags::CommandLineFlagInfo info;
    if (!gflags::GetCommandLineFlagInfo(spelling.c_str(), &info)) continue;
    if (value.empty() || !info.is_default) value = info.current_value;
    if (!info.is_default) break;
  }
  return value;
}

}  // namespace editor
}  // namespace msdeform
