// The method, solver, weight, rigidity and ablation settings the window and
// scripts change, set through msdeform's own command-line flags
// (scales/deformer_flags.h): a change is parsed and checked exactly as
// `msdeform --name=value` would be, with the same message when it is refused.

#ifndef MSDEFORM_APPS_EDITOR_OPTION_FLAGS_H_
#define MSDEFORM_APPS_EDITOR_OPTION_FLAGS_H_

#include <string>

#include "msdeform/scales/deformer.h"

namespace msdeform {
namespace editor {

// Sets option `name` (a flag or any name of DeformerOptionTable()) to
// `value`: a flag, under every spelling of its row, and *options from every
// flag; an option without a flag, on *options alone. On failure the flags
// keep their old values and *error says why ("--method=foo: expected ...",
// "--foo: not an option ...").
bool SetDeformerFlag(const std::string& name, const std::string& value, DeformerOptions* options,
                     std::string* error);

// The flag's current value as text, of the spelling that was given ("" for
// an unknown flag or an option without one).
std::string DeformerFlagValue(const std::string& name);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_OPTION_FLAGS_H_
