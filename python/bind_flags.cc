// DeformerOptions from msdeform's command-line flag names (the gflags of
// scales/deformer_flags.h): what a sweep file or a script that mirrors a
// command line writes, {"w_con": 1000, "solver": "ceres"}, turned into the
// options the command line would build, by the command line's own code.

#include <cmath>
#include <cstdio>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include <gflags/gflags.h>

#include "msdeform/scales/deformer_flags.h"
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
  for (const auto& [key, value] : flags) {
    if (!py::isinstance<py::str>(key)) {
      ThrowTypeError("flags: expected flag names as str, got " + std::string(py::repr(key)));
    }
    const std::string name = key.cast<std::string>();
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
  return options;
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
  m.def("options_from_flags", &OptionsFromFlags, py::arg("flags"),
        "The DeformerOptions the msdeform command line builds from these flags: a dict of "
        "flag name (without '--') to value, e.g. {'w_con': 1000, 'solver': 'ceres', "
        "'method': 'static'}; flags not given keep their defaults. Parsed and checked by the "
        "command line's own code (scales/deformer_flags.h). Raises ValueError naming the flag "
        "for an unknown name (with the nearest flag) or a bad value, TypeError for a value "
        "that is not a bool, int, float or str.");
  m.def("option_flags", &OptionFlags,
        "The command-line flags of the Deformer's options, in name order: a list of dicts with "
        "name, type, default (as text) and description (its '[topic] ' first).");
}

}  // namespace python
}  // namespace msdeform
