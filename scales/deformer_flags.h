// The command-line flags of DeformerOptions, shared by every executable that
// runs the Deformer (msdeform, msdeform_figure_data, msdeform_experiments):
// each flag's default is the options struct's default, so the two cannot
// disagree.
//
//   DeformerOptions options;
//   if (!DeformerOptionsFromFlags(&options, &error)) ...  // "--flag=value: expected ..."
//
// PrintFlagHelp lists msdeform's own flags (not glog's or gflags's), grouped
// by topic, for --help, --helpshort and -h.

#ifndef MSDEFORM_SCALES_DEFORMER_FLAGS_H_
#define MSDEFORM_SCALES_DEFORMER_FLAGS_H_

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "msdeform/scales/deformer.h"

namespace msdeform {

// Sets every field of *options the flags cover from the flags (the others
// keep their values) and checks the result; false with a message naming the
// flag as typed and what it accepts. --method names a graph method
// (DeformerOptions::method), or one of `other_methods` (the editing methods
// that are not graphs, methods/registry.h), which leaves options->method as
// it was: the caller runs that method by name.
bool DeformerOptionsFromFlags(DeformerOptions* options, std::string* error,
                              const std::vector<std::string>& other_methods = {});

// The text of --method as given (or its default).
std::string MethodFlag();

// When argv asks for help (-h, --help, --helpshort, --helpfull is left to
// gflags), prints `usage` and the program's flags grouped by topic to `out`
// and returns true; the caller exits 0. Call before gflags parses argv.
bool HandleHelpRequest(int argc, char** argv, const std::string& usage, std::ostream& out);

// The command-line spellings of a row of DeformerOptionTable(): its name
// where it has no dot, then its aliases; none when the row has no topic
// (not a flag). The first is the one --help lists first.
std::vector<std::string> FlagSpellings(const OptionRow<DeformerOptions>& row);

// Before gflags parses argv: false with "unknown flag --x (did you mean
// --y?)" naming the nearest of the program's flags when argv has a flag
// gflags does not know (gflags itself would only say it is unknown).
bool CheckFlagNames(int argc, char** argv, std::string* error);

// The program's own flags (those with a "[topic] " description) and their
// current values, in name order: what a report records to repeat a run.
std::vector<std::pair<std::string, std::string>> ProgramFlagValues();

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_DEFORMER_FLAGS_H_
