#include "apps/flags/deformer_flags.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <set>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include <gflags/gflags.h>

#include "msdeform/core/option_table.h"
#include "msdeform/methods/registry.h"

// The flags are the rows of an options table that have a command-line topic
// (DeformerOptionTable()'s here, the methods' own in apps/flags/method_flags.cc),
// registered with gflags at start-up under each of the row's spellings: its
// name where it has no dot, and its aliases (the legacy spellings: --solver
// for backend, --cell_width for lattice.cell_width). Name, type, default and
// help come from the row; so do parsing and the range check.

// The one flag that is not a row: it sets both seeds.
DEFINE_uint64(seed, msdeform::DeformerOptions().graph.seed,
              "[method] Seed of every random choice (DG1 node vertices, the paper's handle kick).");

namespace msdeform {
namespace {

// One registered spelling of a row and its storage.
struct TableFlag {
  int group;
  std::string row;  // the row's name, the same for each of its spellings
  std::string spelling;
  OptionType type;
  void* value;  // bool, int32, double or std::string
};

std::string SpellingDescription(const FlagRow& row, const std::string& spelling) {
  std::string others;
  for (const std::string& other : row.spellings) {
    if (other != spelling) others += (others.empty() ? "--" : ", --") + other;
  }
  return others.empty() ? row.description : row.description + " (also " + others + ")";
}

template <typename V>
V* Register(const std::string& spelling, const std::string& help, V value) {
  // gflags keeps the pointers for the life of the program: the storage is
  // never freed nor moved (deques grow without moving), and stays reachable
  // from these statics (so the leak checker does not count it).
  static auto* strings = new std::deque<std::string>();
  static auto* values = new std::deque<V>();
  static auto* registerers = new std::deque<gflags::FlagRegisterer>();
  const std::string* name = &strings->emplace_back(spelling);
  const std::string* text = &strings->emplace_back(help);
  V* current = &values->emplace_back(value);
  V* defaults = &values->emplace_back(value);
  registerers->emplace_back(name->c_str(), text->c_str(), __FILE__, current, defaults);
  return current;
}

// Every group's flags, rows in declaration order, a row's spellings together.
std::vector<TableFlag>& TableFlags() {
  static std::vector<TableFlag> flags;
  return flags;
}

// The flag's value as text: numbers as short as reads back exactly.
std::string FlagText(const TableFlag& flag) {
  switch (flag.type) {
    case OptionType::kBool:
      return *static_cast<bool*>(flag.value) ? "true" : "false";
    case OptionType::kInt:
      return std::to_string(*static_cast<gflags::int32*>(flag.value));
    case OptionType::kDouble:
      return OptionShortNumberText(*static_cast<double*>(flag.value));
    case OptionType::kString:
    case OptionType::kEnum:
      return *static_cast<std::string*>(flag.value);
  }
  return "";
}

bool IsDefault(const std::string& spelling) {
  return gflags::GetCommandLineFlagInfoOrDie(spelling.c_str()).is_default;
}

bool SameRow(const TableFlag& a, const TableFlag& b) {
  return a.group == b.group && a.row == b.row;
}

// The graph methods' rows (DeformerOptionTable()), registered before main parses argv. --method takes
// every registered method's name (methods/registry.h): its help lists them.
std::vector<FlagRow> DeformerFlagRows() {
  std::vector<FlagRow> rows = FlagRowsOf(DeformerOptionTable(), DeformerOptions());
  for (FlagRow& row : rows) {
    if (row.name == "method") row.description += " Registered: " + MethodNameList() + ".";
  }
  return rows;
}
const int kDeformerGroup = RegisterFlagRows(DeformerFlagRows());

}  // namespace

int RegisterFlagRows(const std::vector<FlagRow>& rows) {
  static int groups = 0;
  const int group = groups++;
  std::vector<TableFlag>& flags = TableFlags();
  for (const FlagRow& row : rows) {
    for (const std::string& spelling : row.spellings) {
      const std::string help = SpellingDescription(row, spelling);
      TableFlag flag{group, row.name, spelling, row.type, nullptr};
      const std::string& value = row.default_value;
      switch (row.type) {
        case OptionType::kBool:
          flag.value = Register<bool>(spelling, help, value == "true");
          break;
        case OptionType::kInt:
          flag.value = Register<gflags::int32>(spelling, help, std::stoi(value));
          break;
        case OptionType::kDouble:
          flag.value = Register<double>(spelling, help, std::stod(value));
          break;
        case OptionType::kString:
        case OptionType::kEnum:
          flag.value = Register<std::string>(spelling, help, value);
          break;
      }
      flags.push_back(flag);
    }
  }
  return group;
}

bool FlagRowValues(int group, std::vector<FlagValue>* values, std::string* error) {
  values->clear();
  const std::vector<TableFlag>& flags = TableFlags();
  for (size_t i = 0; i < flags.size();) {
    // The spellings of one row are registered together: the one given wins
    // (two given with different values is an error); none given, the first.
    size_t end = i;
    const TableFlag* chosen = nullptr;
    while (end < flags.size() && SameRow(flags[end], flags[i])) {
      if (!IsDefault(flags[end].spelling)) {
        if (chosen != nullptr && FlagText(*chosen) != FlagText(flags[end])) {
          *error = "--" + chosen->spelling + "=" + FlagText(*chosen) + " and --" +
                   flags[end].spelling + "=" + FlagText(flags[end]) +
                   ": one option (" + flags[end].row + "), given twice";
          return false;
        }
        chosen = &flags[end];
      }
      ++end;
    }
    if (chosen == nullptr) chosen = &flags[i];
    if (chosen->group == group) {
      values->push_back({chosen->row, chosen->spelling, FlagText(*chosen)});
    }
    i = end;
  }
  return true;
}

std::vector<FlagValue> GivenFlagRows() {
  std::vector<FlagValue> given;
  for (const TableFlag& flag : TableFlags()) {
    if (IsDefault(flag.spelling)) continue;
    bool seen = false;
    for (const FlagValue& value : given) seen = seen || value.row == flag.row;
    if (!seen) given.push_back({flag.row, flag.spelling, FlagText(flag)});
  }
  return given;
}

std::string MethodFlag() {
  std::string value;
  gflags::GetCommandLineOption("method", &value);
  return value;
}

bool DeformerOptionsFromFlags(DeformerOptions* options, std::string* error,
                              const std::vector<std::string>& other_methods,
                              const std::vector<Energy>& energies) {
  std::vector<FlagValue> values;
  if (!FlagRowValues(kDeformerGroup, &values, error)) return false;
  const OptionTable<DeformerOptions>& table = DeformerOptionTable();
  for (const FlagValue& value : values) {
    const bool other_method =
        value.row == "method" &&
        std::find(other_methods.begin(), other_methods.end(), value.text) != other_methods.end();
    if (!other_method && !table.Set(value.row, value.text, options, error, "--" + value.spelling)) {
      return false;
    }
  }
  options->graph.seed = FLAGS_seed;
  options->rigidity.seed = FLAGS_seed;
  // --threads (or --num_threads) given sets the graphs' count too; left out,
  // graph.num_threads stays 0, which the graph method reads as num_threads (as
  // DeformerOptions() has it).
  if (!IsDefault("threads") || !IsDefault("num_threads")) {
    options->graph.num_threads = options->num_threads;
  }
  std::string check;
  if (!(energies.empty() ? options->Check(&check)
                         : CheckUnderEnergies(*options, energies, &check))) {
    *error = "invalid options: " + check;
    return false;
  }
  return true;
}

namespace {

// The flags with a "[topic] " description: the program's own.
std::vector<gflags::CommandLineFlagInfo> ProgramFlags() {
  std::vector<gflags::CommandLineFlagInfo> all, own;
  gflags::GetAllFlags(&all);
  for (const gflags::CommandLineFlagInfo& flag : all) {
    const std::string& text = flag.description;
    if (text.size() > 3 && text[0] == '[' && text.find("] ") != std::string::npos) {
      own.push_back(flag);
    }
  }
  return own;
}

// A command-line argument that is a flag ("--x", "-x", "--x=text"): its name
// and, after an '=', its text (*has_value); false for any other argument.
bool SplitFlagArgument(const std::string& argument, std::string* name, std::string* text,
                       bool* has_value = nullptr) {
  if (argument.size() < 2 || argument[0] != '-') return false;
  const std::string arg = argument.substr(argument[1] == '-' ? 2 : 1);
  const size_t equals = arg.find('=');
  *name = arg.substr(0, equals);
  if (has_value != nullptr) *has_value = equals != std::string::npos;
  if (text != nullptr && equals != std::string::npos) *text = arg.substr(equals + 1);
  return true;
}

}  // namespace

bool CheckFlagNames(int argc, char** argv, std::string* error) {
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--") break;
    std::string name;
    if (!SplitFlagArgument(argv[i], &name, nullptr)) continue;
    gflags::CommandLineFlagInfo info;
    if (name.empty() || gflags::GetCommandLineFlagInfo(name.c_str(), &info)) continue;
    // gflags's boolean negation --nox.
    if (name.rfind("no", 0) == 0 && gflags::GetCommandLineFlagInfo(name.c_str() + 2, &info) &&
        info.type == "bool") {
      continue;
    }
    std::vector<std::string> names;
    for (const gflags::CommandLineFlagInfo& flag : ProgramFlags()) names.push_back(flag.name);
    const std::string nearest = NearestName(name, names);
    *error = "unknown flag --" + name;
    if (!nearest.empty()) *error += " (did you mean --" + nearest + "?)";
    *error += "; --help lists the flags";
    return false;
  }
  return true;
}

namespace {

// What is wrong with `text` as a value of a gflags flag of `type` ("double",
// "int32", ...), in the tables' words; "" when gflags will take it.
std::string FlagValueProblem(const std::string& type, const std::string& text) {
  if (type == "double") {
    double value = 0.0;
    return ParseOptionDouble(text, &value) ? "" : "expected a number";
  }
  if (type == "int32" || type == "int64") {
    long long value = 0;
    const bool ok = ParseOptionInteger(text, &value) &&
                    (type == "int64" || (value >= std::numeric_limits<int32_t>::min() &&
                                         value <= std::numeric_limits<int32_t>::max()));
    return ok ? "" : "expected an integer";
  }
  if (type == "uint32" || type == "uint64") {
    unsigned long long value = 0;
    const bool ok = ParseOptionUnsigned(text, &value) &&
                    (type == "uint64" || value <= std::numeric_limits<uint32_t>::max());
    return ok ? "" : "expected an integer >= 0";
  }
  if (type == "bool") {
    // gflags's spellings of a bool.
    static const std::set<std::string> kBools = {"true", "t", "yes", "y", "1",
                                                 "false", "f", "no", "n", "0"};
    std::string lower = text;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return kBools.count(lower) ? "" : "expected true or false";
  }
  return "";
}

}  // namespace

bool CheckFlagValues(int argc, char** argv, std::string* error) {
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--") break;
    std::string name, text;
    bool has_value = false;
    if (!SplitFlagArgument(argv[i], &name, &text, &has_value)) continue;
    gflags::CommandLineFlagInfo info;
    if (name.empty() || !gflags::GetCommandLineFlagInfo(name.c_str(), &info)) continue;
    if (!has_value) {
      // --x alone is true for a bool; otherwise gflags takes the next
      // argument (--x value) or says the value is missing.
      if (info.type == "bool" || i + 1 >= argc) continue;
      text = argv[++i];
    }
    const std::string problem = FlagValueProblem(info.type, text);
    if (!problem.empty()) {
      *error = "--" + name + "=" + text + ": " + problem;
      return false;
    }
  }
  return true;
}

std::vector<std::pair<std::string, std::string>> ProgramFlagValues() {
  // The spellings of one option record the value it took (that of the
  // spelling given), so that --rerun sets them all alike.
  std::map<std::string, std::string> effective;
  const std::vector<TableFlag>& flags = TableFlags();
  for (size_t i = 0; i < flags.size();) {
    size_t end = i;
    std::string chosen = flags[i].spelling;
    for (; end < flags.size() && SameRow(flags[end], flags[i]); ++end) {
      if (!IsDefault(flags[end].spelling)) chosen = flags[end].spelling;
    }
    const std::string value = gflags::GetCommandLineFlagInfoOrDie(chosen.c_str()).current_value;
    for (; i < end; ++i) effective[flags[i].spelling] = value;
  }
  std::vector<std::pair<std::string, std::string>> values;
  for (const gflags::CommandLineFlagInfo& flag : ProgramFlags()) {
    const auto it = effective.find(flag.name);
    values.emplace_back(flag.name, it == effective.end() ? flag.current_value : it->second);
  }
  std::sort(values.begin(), values.end());
  return values;
}

bool HandleHelpRequest(int argc, char** argv, const std::string& usage, std::ostream& out) {
  bool asked = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    asked |= arg == "-h" || arg == "--help" || arg == "-help" || arg == "--helpshort" ||
             arg == "-helpshort";
  }
  if (!asked) return false;
  // The program's own flags: those whose description starts with
  // "[topic] ", in the order of kTopics; glog's and gflags's are left out
  // (--helpfull lists them).
  // A row's other spellings are named in its first one's help ("also
  // --solver"), not listed again.
  std::set<std::string> later_spellings;
  const std::vector<TableFlag>& table_flags = TableFlags();
  for (size_t i = 1; i < table_flags.size(); ++i) {
    if (SameRow(table_flags[i - 1], table_flags[i])) {
      later_spellings.insert(table_flags[i].spelling);
    }
  }
  static const char* kTopics[] = {"input",   "output",  "method",    "solver",
                                  "weights", "rigidity", "ablations", "diagnostics"};
  std::map<std::string, std::vector<gflags::CommandLineFlagInfo>> by_topic;
  std::vector<gflags::CommandLineFlagInfo> flags;
  gflags::GetAllFlags(&flags);
  for (const gflags::CommandLineFlagInfo& flag : flags) {
    const std::string& text = flag.description;
    if (text.size() < 3 || text[0] != '[') continue;
    const size_t close = text.find("] ");
    if (close == std::string::npos || later_spellings.count(flag.name)) continue;
    by_topic[text.substr(1, close - 1)].push_back(flag);
  }
  out << usage << "\n";
  for (const char* topic : kTopics) {
    auto it = by_topic.find(topic);
    if (it == by_topic.end()) continue;
    out << "\n" << topic << ":\n";
    for (const gflags::CommandLineFlagInfo& flag : it->second) {
      const std::string text = flag.description.substr(flag.description.find("] ") + 2);
      std::string value = flag.default_value;
      double number = 0.0;
      if (flag.type == "string") value = "\"" + value + "\"";
      // gflags prints a double to 17 digits (0.10000000000000001).
      if (flag.type == "double" && ParseOptionDouble(value, &number)) {
        value = OptionShortNumberText(number);
      }
      out << "  --" << flag.name << " (" << flag.type << ", default " << value << ")\n      "
          << text << "\n";
    }
  }
  out << "\n--helpfull also lists the flags of glog and gflags.\n";
  return true;
}

}  // namespace msdeform
