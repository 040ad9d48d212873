// The command-line flags of every editing method: the Deformer's
// (apps/flags/deformer_flags.h) and the methods' own rows of MethodOptionTable()
// (--cgal_iterations, --fastlsm_steps, ...), registered from the rows, so an
// executable that links this has them all and --help lists them under
// "method".
//
//   MethodOptions options;
//   if (!MethodOptionsFromFlags(&options, &error)) ...  // "--fastlsm_steps=0: expected ..."

#ifndef MSDEFORM_APPS_FLAGS_METHOD_FLAGS_H_
#define MSDEFORM_APPS_FLAGS_METHOD_FLAGS_H_

#include <string>

#include "msdeform/methods/method_options.h"

namespace msdeform {

// options->deformer from the Deformer's flags (--method may name any
// registered method; a method that is not a graph leaves deformer.method as
// it was), then the methods' own fields from theirs; false with one line
// naming the flag as typed.
bool MethodOptionsFromFlags(MethodOptions* options, std::string* error);
// The methods' own fields only (options->cgal, options->fastlsm), for a
// program that reads the Deformer's flags itself.
bool MethodOwnOptionsFromFlags(MethodOptions* options, std::string* error);

// False with "--w_con=5: not an option of the cgal_arap method (an option of
// multiscale, static, static_dense)" when a flag given on the command line
// (not one left at its default) sets a row that `method` does not read
// (MethodReadsRow, methods/method_option_table.h); --seed counts as
// graph.seed.
bool CheckFlagsReadBy(const std::string& method, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_APPS_FLAGS_METHOD_FLAGS_H_
