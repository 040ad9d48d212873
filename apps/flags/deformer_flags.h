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

#ifndef MSDEFORM_APPS_FLAGS_DEFORMER_FLAGS_H_
#define MSDEFORM_APPS_FLAGS_DEFORMER_FLAGS_H_

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "msdeform/core/option_table.h"
#include "msdeform/methods/graph_method.h"

namespace msdeform {

// Sets every field of *options the flags cover from the flags (the others
// keep their values) and checks the result; false with a message naming the
// flag as typed and what it accepts. --method names a graph method
// (DeformerOptions::method), or one of `other_methods` (the editing methods
// that are not graphs, methods/registry.h), which leaves options->method as
// it was: the caller runs that method by name. A front end that sets the
// energy per row passes `energies`: the result is checked under each
// (CheckUnderEnergies), so the arap.* flags are the arap rows'.
bool DeformerOptionsFromFlags(DeformerOptions* options, std::string* error,
                              const std::vector<std::string>& other_methods = {},
                              const std::vector<Energy>& energies = {});

// The text of --method as given (or its default).
std::string MethodFlag();

// When argv asks for help (-h, --help, --helpshort, --helpfull is left to
// gflags), prints `usage` and the program's flags grouped by topic to `out`
// and returns true; the caller exits 0. Call before gflags parses argv.
bool HandleHelpRequest(int argc, char** argv, const std::string& usage, std::ostream& out);

// The command-line spellings of a row of an options table: its name where
// it has no dot, then its aliases; none when the row has no topic (not a
// flag). The first is the one --help lists first.
template <typename T>
std::vector<std::string> FlagSpellings(const OptionRow<T>& row) {
  std::vector<std::string> spellings;
  if (row.topic.empty()) return spellings;
  if (row.name.find('.') == std::string::npos) spellings.push_back(row.name);
  spellings.insert(spellings.end(), row.aliases.begin(), row.aliases.end());
  return spellings;
}

// The flags of any options table's rows (the Deformer's here; the methods'
// own in apps/flags/method_flags.cc): what gflags needs of a row.
struct FlagRow {
  std::string name;  // the row's ("fastlsm.steps_per_frame")
  OptionType type = OptionType::kDouble;
  std::string description;  // "[topic] help (also --x)" for each spelling
  std::vector<std::string> spellings;
  std::string default_value;  // the row's text of the default
};
template <typename T>
std::vector<FlagRow> FlagRowsOf(const OptionTable<T>& table, const T& defaults,
                                bool (*keep)(const std::string& name) = nullptr) {
  std::vector<FlagRow> rows;
  for (const OptionRow<T>& row : table.rows()) {
    if (keep != nullptr && !keep(row.name)) continue;
    FlagRow flag{row.name, row.type, "[" + row.topic + "] " + row.help, FlagSpellings(row),
                 row.get(defaults)};
    if (!flag.spellings.empty()) rows.push_back(flag);
  }
  return rows;
}
// Registers every spelling of `rows` with gflags (call during static
// initialisation, before main parses argv); returns the group's id.
int RegisterFlagRows(const std::vector<FlagRow>& rows);
// Of each row of the group: the spelling given (the first when none was)
// and its text; false with "--a=1 and --b=2: one option (x), given twice".
struct FlagValue {
  std::string row, spelling, text;
};
bool FlagRowValues(int group, std::vector<FlagValue>* values, std::string* error);
// Sets *options from the group's flags through `table` (ranges checked);
// false with "--flag=value: expected ..." naming the spelling given.
template <typename T>
bool OptionsFromFlagRows(const OptionTable<T>& table, int group, T* options, std::string* error) {
  std::vector<FlagValue> values;
  if (!FlagRowValues(group, &values, error)) return false;
  for (const FlagValue& value : values) {
    if (!table.Set(value.row, value.text, options, error, "--" + value.spelling)) return false;
  }
  return true;
}

// Before gflags parses argv: false with "unknown flag --x (did you mean
// --y?)" naming the nearest of the program's flags when argv has a flag
// gflags does not know (gflags itself would only say it is unknown).
bool CheckFlagNames(int argc, char** argv, std::string* error);

// Before gflags parses argv: false with "--w_con=abc: expected a number"
// (the tables' words) when a flag's value is not of its type (gflags itself
// would print its own multi-word "ERROR: illegal value ..." and exit).
bool CheckFlagValues(int argc, char** argv, std::string* error);

// The rows of the tables' flags given on the command line (not left at
// their defaults), each once: the spelling given and its text.
std::vector<FlagValue> GivenFlagRows();

// The program's own flags (those with a "[topic] " description) and their
// current values, in name order: what a report records to repeat a run.
std::vector<std::pair<std::string, std::string>> ProgramFlagValues();

}  // namespace msdeform

#endif  // MSDEFORM_APPS_FLAGS_DEFORMER_FLAGS_H_
