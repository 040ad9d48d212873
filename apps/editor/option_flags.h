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

// Sets flag `name` (one of DeformerOptions's flags) to `value` and fills
// *options from every flag. On failure the flag keeps its old value and
// *error says why ("--method=foo: expected ...", "--foo: not a method,
// solver, weight, rigidity or ablation flag").
bool SetDeformerFlag(const std::string& name, const std::string& value, DeformerOptions* options,
                     std::string* error);

// The flag's current value as text ("" for an unknown flag).
std::string DeformerFlagValue(const std::string& name);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_OPTION_FLAGS_H_
