#include "apps/flags/method_flags.h"

#include <vector>

#include <gflags/gflags.h>

#include "apps/flags/deformer_flags.h"
#include "msdeform/methods/method_option_table.h"
#include "msdeform/methods/registry.h"

namespace msdeform {
namespace {

// The methods' own rows, registered before main parses argv.
const int kMethodGroup =
    RegisterFlagRows(FlagRowsOf(MethodOptionTable(), MethodOptions(), &IsMethodOwnRow));

}  // namespace

bool MethodOptionsFromFlags(MethodOptions* options, std::string* error) {
  if (!DeformerOptionsFromFlags(&options->deformer, error, MethodNames())) return false;
  return MethodOwnOptionsFromFlags(options, error);
}

bool MethodOwnOptionsFromFlags(MethodOptions* options, std::string* error) {
  return OptionsFromFlagRows(MethodOptionTable(), kMethodGroup, options, error);
}

bool CheckFlagsReadBy(const std::string& method, std::string* error) {
  std::vector<FlagValue> given = GivenFlagRows();
  gflags::CommandLineFlagInfo seed;
  if (gflags::GetCommandLineFlagInfo("seed", &seed) && !seed.is_default) {
    given.push_back({"graph.seed", "seed", seed.current_value});
  }
  for (const FlagValue& flag : given) {
    if (MethodReadsRow(method, flag.row)) continue;
    *error = "--" + flag.spelling + "=" + flag.text + ": " + NotAnOptionOf(method, {flag.row});
    return false;
  }
  return true;
}

}  // namespace msdeform
