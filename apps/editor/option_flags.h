// The method, solver, weight, rigidity and ablation settings the window and
// scripts change, set through msdeform's own command-line flags
// (apps/flags/deformer_flags.h): a change is parsed and checked exactly as
// `msdeform --name=value` would be, with the same message when it is refused.

#ifndef MSDEFORM_APPS_EDITOR_OPTION_FLAGS_H_
#define MSDEFORM_APPS_EDITOR_OPTION_FLAGS_H_

#include <string>

#include "msdeform/methods/method_options.h"
#include "msdeform/methods/graph_method.h"

namespace msdeform {
namespace editor {

// Sets option `name` (a flag or any name of DeformerOptionTable()) to
// `value`: a flag, under every spelling of its row, and *options from every
// flag; an option without a flag, on *options alone. On failure the flags
// keep their old values and *error says why ("--method=foo: expected ...",
// "--foo: not an option ..."). Setting the energy to one other than arap
// first puts the arap.* flags, which only arap reads, back to their defaults.
bool SetDeformerFlag(const std::string& name, const std::string& value, DeformerOptions* options,
                     std::string* error);

// A method's own option (a row of MethodOptionTable(): "fastlsm.damping" or
// its flag, "fastlsm_damping"), set as SetDeformerFlag sets the Deformer's:
// through every spelling of its flag, then options->cgal and ->fastlsm from
// the flags ("--fastlsm_damping=1: expected a number in [0, 1)").
bool SetMethodFlag(const std::string& name, const std::string& value, MethodOptions* options,
                   std::string* error);
// True when `name` is a method's own option or its flag.
bool IsMethodOption(const std::string& name);
// True when a method's own row ("fastlsm.damping") is one of method `method`'s.
bool RowOfMethod(const std::string& row, const std::string& method);

// The flag's current value as text, of the spelling that was given ("" for
// an unknown flag or an option without one); a Deformer's or a method's.
std::string DeformerFlagValue(const std::string& name);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_OPTION_FLAGS_H_
