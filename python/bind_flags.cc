// DeformerOptions from msdeform's command-line flag names (the gflags of
// apps/flags/deformer_flags.h) or any name of the options table: what a sweep
// file or a script that mirrors a command line writes, {"w_con": 1000,
// "backend": "ceres", "selection.member_extent": "mean"}, turned into the
// options the command line would build, by the command line's own code.

#include <cmath>
#include <cstdio>
#include <mutex>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <gflags/gflags.h>
#include <pybind11/stl.h>

#include "apps/flags/deformer_flags.h"
#include "msdeform/methods/method_option_table.h"
#include "python/bindings.h"

namespace msdeform {
namespace python {
namespace {

// A Python value as the command line would spell it.
std::string FlagText(const std::string& name, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(value)) return std::string(py::str(value));
  if (py::isinstance<py::float_>(value)) {
    char buffer[40];
    std::snprintf(buffer, sizeof(buffer), "%.17g", value.cast<double>());
    return buffer;
  }
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  ThrowTypeError("--" + name + ": expected a bool, int, float or str, got " +
                 std::string(py::str(py::type::handle_of(value).attr("__name__"))));
}

std::set<std::string> OptionFlagNames() {
  std::set<std::string> names;
  for (const auto& [name, value] : ProgramFlagValues()) names.insert(name);
  return names;
}

DeformerOptions OptionsFromFlags(const py::dict& flags) {
  // gflags are process-wide: one conversion at a time, each starting from
  // the defaults and leaving them as they were (FlagSaver).
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  gflags::FlagSaver saver;
  const std::set<std::string> known = OptionFlagNames();
  std::vector<std::pair<std::string, std::string>> rows;  // table names that are not flags
  for (const auto& [key, value] : flags) {
    if (!py::isinstance<py::str>(key)) {
      ThrowTypeError("flags: expected flag names as str, got " + std::string(py::repr(key)));
    }
    const std::string name = key.cast<std::string>();
    if (known.count(name) == 0 && DeformerOptionTable().Find(name) != nullptr) {
      rows.emplace_back(name, FlagText(name, value));
      continue;
    }
    if (known.count(name) == 0) {
      std::string argument = "--" + name;
      char program[] = "msdeform";
      char* argv[] = {program, argument.data()};
      std::string error;
      if (CheckFlagNames(2, argv, &error)) {
        error = "--" + name + " is not an option of the Deformer; --help lists the flags";
      }
      ThrowValueError(error);
    }
    const std::string text = FlagText(name, value);
    if (gflags::SetCommandLineOption(name.c_str(), text.c_str()).empty()) {
      ThrowValueError("--" + name + "=" + text + ": not a value of this flag's type");
    }
  }
  DeformerOptions options;
  std::string error;
  if (!DeformerOptionsFromFlags(&options, &error)) ThrowValueError(error);
  for (const auto& [name, text] : rows) {
    if (!DeformerOptionTable().Set(name, text, &options, &error)) ThrowValueError(error);
  }
  if (!rows.empty() && !options.Check(&error)) ThrowValueError("invalid options: " + error);
  return options;
}

// The options table's rows, for front ends that build widgets or docs.
py::list OptionRows() {
  const MethodOptions defaults;
  py::list rows;
  for (const OptionRow<MethodOptions>& row : MethodOptionTable().rows()) {
    py::dict entry;
    entry["name"] = row.name;
    entry["type"] = OptionTypeName(row.type);
    entry["default"] = row.get(defaults);
    entry["help"] = row.help;
    entry["choices"] = row.choices;
    entry["range"] = row.has_range ? py::object(py::str(row.expected)) : py::object(py::none());
    entry["aliases"] = row.aliases;
    entry["flag_topic"] = row.topic;
    entry["keywords"] = IsMethodOwnRow(row.name) ? MethodKeywords(row.name)
                                                 : std::vector<std::string>{};
    entry["methods"] = MethodsOfRow(row.name);
    rows.append(entry);
  }
  return rows;
}

py::list OptionFlags() {
  std::vector<gflags::CommandLineFlagInfo> all;
  gflags::GetAllFlags(&all);
  const std::set<std::string> known = OptionFlagNames();
  py::list flags;
  for (const gflags::CommandLineFlagInfo& info : all) {
    if (known.count(info.name) == 0) continue;
    py::dict flag;
    flag["name"] = info.name;
    flag["type"] = info.type;
    flag["default"] = info.default_value;
    flag["description"] = info.description;
    flags.append(flag);
  }
  return flags;
}

}  // namespace

void BindFlags(py::module_& m) {
  m.def(
      "describe_method_options",
      [](const py::kwargs& kwargs) {
        std::vector<std::pair<std::string, std::string>> fields;
        const MethodOptions options = MethodOptionsFrom(py::none(), kwargs);
        for (const auto& field : MethodOptionTable().Describe(options)) {
          if (IsMethodOwnRow(field.first)) fields.push_back(field);
        }
        return fields;
      },
      "The methods' own options (rows 'cgal.*', 'fastlsm.*' of option_rows()) as (name, value) "
      "string pairs, from Method's keywords (fastlsm_steps=40); raises ValueError naming the "
      "keyword for a bad value, as Method does.");
  m.def("options_from_flags", &OptionsFromFlags, py::arg("flags"),
        "The DeformerOptions the msdeform command line builds from these flags: a dict of "
        "flag name (without '--') or option name to value, e.g. {'w_con': 1000, 'backend': "
        "'ceres', 'method': 'static', 'selection.member_extent': 'mean'}; flags not given keep "
        "their defaults. Parsed and checked by the "
        "command line's own code (apps/flags/deformer_flags.h). Raises ValueError naming the flag "
        "for an unknown name (with the nearest flag) or a bad value, TypeError for a value "
        "that is not a bool, int, float or str.");
  m.def("option_rows", &OptionRows,
        "The one options table of the methods (methods/method_option_table.h): the Deformer's "
        "rows (scales/deformer_options.h), then the methods' own ('cgal.iterations', "
        "'fastlsm.steps_per_frame'; keywords: the Method keywords that set them; methods: the "
        "methods that read them), in "
        "declaration order: a list "
        "of dicts with name ('lattice.cell_width'), type (bool, int, double, enum), default (as "
        "DescribeOptions prints it), help, choices (of an enum), range (its words, or None), "
        "aliases (other spellings every front end accepts, e.g. 'solver' for 'backend') and "
        "flag_topic ('' when it is not a command-line flag).");
  m.def("option_flags", &OptionFlags,
        "The command-line flags of the Deformer's options, in name order: a list of dicts with "
        "name, type, default (as text) and description (its '[topic] ' first).");
}

}  // namespace python
}  // namespace msdeform
