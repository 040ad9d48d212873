#include "apps/flags/method_flags.h"

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

}  // namespace msdeform
