// The options structs reachable from DeformerOptions as Python classes, bound
// from their option tables (scales/deformer_options.h): every row a
// read-write attribute with the row's help as its doc, enums as the names of
// the row, nested structs as attributes that can also be set from a dict, a
// keyword constructor whose defaults are those of the default-constructed
// C++ struct (never restated here), and the table's other spellings
// (solver= for backend, cell_width= for lattice.cell_width) as keywords.

#include <Python.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/lattice.h"
#include "msdeform/core/option_table.h"
#include "msdeform/methods/method_option_table.h"
#include "msdeform/methods/graph_method.h"
#include "msdeform/scales/rigidity.h"
#include "msdeform/scales/scale_selection.h"
#include "msdeform/solvers/ceres_solver.h"
#include "msdeform/solvers/frame_solver.h"
#include "msdeform/solvers/gauss_newton_solver.h"
#include "python/bindings.h"

namespace msdeform {
namespace python {
namespace {

std::string Repr(const py::handle& value) { return std::string(py::repr(value)); }

std::string Join(const std::vector<std::string>& names) {
  std::string joined;
  for (size_t i = 0; i < names.size(); ++i) joined += (i > 0 ? ", " : "") + names[i];
  return joined;
}

bool IsBool(const py::handle& value) {
  static const py::object numpy_bool = py::module_::import("numpy").attr("bool_");
  return PyBool_Check(value.ptr()) || py::isinstance(value, numpy_bool);
}

// Python's int, or anything with __index__ (NumPy integers), never a bool.
py::int_ Integer(const py::handle& value, const std::string& where) {
  PyObject* index = IsBool(value) ? nullptr : PyNumber_Index(value.ptr());
  if (index == nullptr) {
    PyErr_Clear();
    ThrowTypeError(where + ": expected an integer, got " + Repr(value));
  }
  return py::reinterpret_steal<py::int_>(index);
}

// A field's value from Python, checked: TypeError for a wrong type, ValueError
// for an integer out of the C++ type's range.
template <typename V>
V FieldValue(const py::handle& value, const std::string& where);

template <>
bool FieldValue<bool>(const py::handle& value, const std::string& where) {
  if (!IsBool(value)) ThrowTypeError(where + ": expected True or False, got " + Repr(value));
  return PyObject_IsTrue(value.ptr()) == 1;
}

template <>
double FieldValue<double>(const py::handle& value, const std::string& where) {
  static const py::object real = py::module_::import("numbers").attr("Real");
  if (IsBool(value) || !py::isinstance(value, real)) {
    ThrowTypeError(where + ": expected a number, got " + Repr(value));
  }
  return PyFloat_AsDouble(value.ptr());
}

// Sets target.<path> (dotted: "lattice.cell_width") to value.
void SetPath(const py::object& target, const std::string& path, const py::handle& value) {
  py::object owner = target;
  size_t start = 0, dot;
  while ((dot = path.find('.', start)) != std::string::npos) {
    owner = owner.attr(path.substr(start, dot - start).c_str());
    start = dot + 1;
  }
  owner.attr(path.substr(start).c_str()) = value;
}

// Sets the fields named by `keywords` on `target`, an options object: a
// keyword is a field, or one of the class's `aliases` (another spelling of a
// row, or a dotted row name); a TypeError names an unknown keyword; each
// attribute's setter checks its value.
void ApplyKeywords(const py::object& target, const py::dict& keywords) {
  const py::tuple fields = target.attr("fields");
  const py::dict aliases = target.attr("aliases");
  const std::string name = py::str(py::type::handle_of(target).attr("__name__"));
  // Two spellings of one option with different values are refused, as the
  // command line refuses them (the same value twice is fine).
  std::map<std::string, std::pair<std::string, py::object>> given;  // path -> keyword, value
  auto check_once = [&](const std::string& path, const std::string& key, const py::handle& value) {
    const auto [it, inserted] = given.emplace(path, std::make_pair(key, py::reinterpret_borrow<py::object>(value)));
    if (!inserted && it->second.second.not_equal(value)) {
      ThrowTypeError(name + ": " + it->second.first + "=" + Repr(it->second.second) + " and " +
                     key + "=" + Repr(value) + ": one option (" + path + "), given twice");
    }
  };
  for (const auto& [key, value] : keywords) {
    const std::string spelling = py::str(key);
    if (fields.contains(key)) {
      check_once(spelling, spelling, value);
      target.attr(key) = value;
    } else if (aliases.contains(key)) {
      const std::string path = py::str(aliases[key]);
      check_once(path, spelling, value);
      SetPath(target, path, value);
    } else {
      std::vector<std::string> names, spellings;
      for (const py::handle field : fields) names.push_back(py::str(field));
      spellings = names;
      for (const auto& alias : aliases) spellings.push_back(py::str(alias.first));
      // "did you mean" as the command line offers it (core/option_table.h).
      const std::string nearest = NearestName(spelling, spellings);
      ThrowTypeError(name + ": unknown option " + Repr(key) +
                     (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)") +
                     "; the options are " + Join(names));
    }
  }
}

// A row's value (text, as the table describes it) as a Python value.
py::object RowValue(OptionType type, const std::string& text) {
  switch (type) {
    case OptionType::kBool:
      return py::bool_(text == "true");
    case OptionType::kInt:
      return py::int_(py::str(text));
    case OptionType::kDouble:
      return py::float_(std::stod(text));
    case OptionType::kString:
    case OptionType::kEnum:
      break;
  }
  return py::str(text);
}

// A Python value as a row's text: TypeError for a wrong type.
template <typename T>
std::string RowText(const OptionRow<T>& row, const py::handle& value, const std::string& where) {
  switch (row.type) {
    case OptionType::kBool:
      return FieldValue<bool>(value, where) ? "true" : "false";
    case OptionType::kInt:
      return std::string(py::str(Integer(value, where)));
    case OptionType::kDouble:
      return OptionNumberText(FieldValue<double>(value, where));
    case OptionType::kString:
    case OptionType::kEnum:
      if (!py::isinstance<py::str>(value)) {
        ThrowTypeError(where + ": expected a string (one of " + Join(row.choices) + "), got " +
                       Repr(value));
      }
      return value.cast<std::string>();
  }
  return "";
}

// Binds an options struct T field by field, then adds what every options
// class has (Finish): the keyword constructor, `fields`, `choices`,
// to_dict(), copy(), check(), ==, repr().
template <typename T>
class OptionsClass {
 public:
  OptionsClass(py::module_& m, const char* name, const char* doc)
      : class_(m, name, doc), name_(name) {}

  // One row of the struct's table. The value is parsed by the row; ranges
  // are left to check() (and the Deformer's), as C++ leaves them to Check().
  OptionsClass& Row(const OptionRow<T>& row) {
    const std::string where = name_ + "." + row.name;
    class_.def_property(
        row.name.c_str(),
        [row](const T& self) { return RowValue(row.type, row.get(self)); },
        [row, where](T& self, const py::object& value) {
          const std::string text = RowText(row, value, where);
          std::string what;
          if (row.parse(text, &self, &what)) return;
          if (row.type == OptionType::kEnum) {
            ThrowValueError(where + ": unknown value '" + text + "'; expected one of " +
                            Join(row.choices));
          }
          const std::string prefix = "expected an integer in ";
          ThrowValueError(where + ": " + text + " is outside " +
                          (what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what));
        },
        row.help.c_str());
    fields_.push_back(row.name);
    if (row.type == OptionType::kEnum) choices_.emplace_back(row.name, row.choices);
    return *this;
  }

  // Every row of `table` (a struct without nested options).
  OptionsClass& Rows(const OptionTable<T>& table) {
    for (const OptionRow<T>& row : table.rows()) Row(row);
    return *this;
  }

  // Other spellings a keyword may use: alias -> field path. An alias that is
  // also a field of the class (the command line's --rigidity, rigidity.model)
  // is left to the field. Call after the fields are bound.
  OptionsClass& Aliases(const OptionTable<T>& table) {
    for (const OptionRow<T>& row : table.rows()) {
      for (const std::string& alias : row.aliases) {
        if (std::find(fields_.begin(), fields_.end(), alias) == fields_.end()) {
          aliases_[py::str(alias)] = row.name;
        }
      }
      if (row.name.find('.') != std::string::npos) aliases_[py::str(row.name)] = row.name;
    }
    return *this;
  }

  // A nested options struct: read as a live reference (options.stopping.
  // max_iterations = 5 changes options); set from an instance (replaces it)
  // or a dict (sets the fields it names, keeps the others).
  template <typename S>
  OptionsClass& Nested(const char* field, S T::*member, const char* doc) {
    const std::string where = name_ + "." + field;
    class_.def_property(
        field, [member](T& self) -> S& { return self.*member; },
        [member, where](T& self, const py::object& value) {
          if (py::isinstance<py::dict>(value)) {
            py::object updated = py::cast(S(self.*member));
            ApplyKeywords(updated, py::reinterpret_borrow<py::dict>(value));
            self.*member = updated.cast<S>();
          } else if (py::isinstance<S>(value)) {
            self.*member = value.cast<S>();
          } else {
            const std::string type = py::str(py::type::of<S>().attr("__name__"));
            ThrowTypeError(where + ": expected a " + type + " or a dict of its fields, got " +
                           Repr(value));
          }
        },
        doc);
    fields_.push_back(field);
    return *this;
  }

  void Finish() {
    class_.attr("fields") = py::tuple(py::cast(fields_));
    class_.attr("aliases") = aliases_;
    py::dict choices;
    for (const auto& [field, names] : choices_) choices[py::str(field)] = py::tuple(py::cast(names));
    class_.attr("choices") = choices;

    // The signature's defaults, from a default-constructed struct.
    py::object defaults = py::cast(T());
    std::string signature = name_ + "(";
    for (size_t i = 0; i < fields_.size(); ++i) {
      signature += (i > 0 ? ", " : "") + fields_[i] + "=" + Repr(defaults.attr(fields_[i].c_str()));
    }
    signature += ")";
    const std::string init_doc =
        signature +
        "\n\nEvery field by keyword; the defaults are the C++ struct's. A nested options field "
        "takes an instance or a dict of its fields. An unknown keyword raises TypeError, a value "
        "of the wrong type TypeError, an out-of-range integer or unknown choice ValueError.";
    class_.def(py::init([](const py::kwargs& kwargs) {
                 py::object options = py::cast(T());
                 ApplyKeywords(options, kwargs);
                 return options.cast<T>();
               }),
               init_doc.c_str());
    class_.def(
        "to_dict",
        [](const py::object& self) {
          py::dict values;
          for (const py::handle field : py::tuple(self.attr("fields"))) {
            py::object value = self.attr(field);
            values[field] = py::hasattr(value, "to_dict") ? value.attr("to_dict")() : value;
          }
          return values;
        },
        "The fields as a dict (nested options as nested dicts), in declaration order.");
    class_.def(
        "copy", [](const T& self) { return T(self); }, "An independent copy.");
    class_.def(
        "__copy__", [](const T& self) { return T(self); }, "An independent copy.");
    class_.def(
        "__deepcopy__", [](const T& self, const py::object&) { return T(self); },
        "An independent copy.");
    class_.def(
        "check",
        [](const T& self) {
          std::string error;
          if (!self.Check(&error)) ThrowValueError(error);
        },
        "Raises ValueError with the C++ Check() message when a field is out of range.");
    class_.def(
        "__eq__",
        [](const py::object& self, const py::object& other) {
          if (!py::isinstance<T>(other)) return false;
          return self.attr("to_dict")().equal(other.attr("to_dict")());
        },
        "Equal when every field is.");
    class_.attr("__hash__") = py::none();
    class_.def(
        "__repr__",
        [name = name_](const py::object& self) {
          std::string text = name + "(";
          bool first = true;
          for (const py::handle field : py::tuple(self.attr("fields"))) {
            text += (first ? "" : ", ") + std::string(py::str(field)) + "=" +
                    Repr(self.attr(field));
            first = false;
          }
          return text + ")";
        },
        "The constructor call that makes these options.");
  }

 private:
  py::class_<T> class_;
  std::string name_;
  std::vector<std::string> fields_;
  std::vector<std::pair<std::string, std::vector<std::string>>> choices_;
  py::dict aliases_;
};

void BindSubOptions(py::module_& m) {
  OptionsClass<LatticeOptions>(m, "LatticeOptions",
                               "The lattice the mesh is embedded in (core/lattice.h).")
      .Rows(LatticeOptionTable())
      .Finish();
  OptionsClass<GraphOptions>(m, "GraphOptions",
                             "The multi-scale deformation graphs (core/deformation_graph.h).")
      .Rows(GraphOptionTable())
      .Finish();
  OptionsClass<RigidityOptions>(m, "RigidityOptions",
                                "Rigidity estimation, e' per lattice particle (scales/rigidity.h).")
      .Rows(RigidityOptionTable())
      .Finish();
  OptionsClass<ScaleSelectionOptions>(
      m, "ScaleSelectionOptions",
      "Scale selection, node classes and alpha weights (scales/scale_selection.h).")
      .Rows(ScaleSelectionOptionTable())
      .Finish();
  OptionsClass<StoppingRule>(m, "StoppingRule",
                             "When a frame's solve stops, for both backends (solvers/frame_solver.h).")
      .Rows(StoppingRuleTable())
      .Finish();
  OptionsClass<GaussNewtonOptions>(m, "GaussNewtonOptions",
                                   "The Gauss-Newton backend (solvers/gauss_newton_solver.h).")
      .Rows(GaussNewtonOptionTable())
      .Finish();
  OptionsClass<CeresOptions>(m, "CeresOptions", "The Ceres backend (solvers/ceres_solver.h).")
      .Rows(CeresOptionTable())
      .Finish();
  OptionsClass<ArapOptions>(m, "ArapOptions", "The subspace ARAP energy (solvers/subspace_arap.h).")
      .Rows(ArapOptionTable())
      .Finish();
}

void BindDeformerOptions(py::module_& m) {
  using DO = DeformerOptions;
  OptionsClass<DO> options(m, "DeformerOptions",
                           "Everything the graph methods take (scales/deformer_options.h); Method(V, F, "
                           "method, **kwargs) takes the same fields by keyword.");
  // The table's rows in order; an embedded struct's rows as one nested field.
  const std::map<std::string, std::function<void()>> nested = {
      {"lattice", [&] { options.Nested("lattice", &DO::lattice, "LatticeOptions: the cell width."); }},
      {"graph", [&] { options.Nested("graph", &DO::graph, "GraphOptions: k, P, seed."); }},
      {"rigidity",
       [&] { options.Nested("rigidity", &DO::rigidity, "RigidityOptions: how e' is estimated."); }},
      {"selection",
       [&] {
         options.Nested("selection", &DO::selection,
                        "ScaleSelectionOptions: thresholds, node classes.");
       }},
      {"stopping",
       [&] { options.Nested("stopping", &DO::stopping, "StoppingRule: the per-frame stopping rule."); }},
      {"gauss_newton",
       [&] {
         options.Nested("gauss_newton", &DO::gauss_newton,
                        "GaussNewtonOptions of the default backend.");
       }},
      {"ceres", [&] { options.Nested("ceres", &DO::ceres, "CeresOptions of the Ceres backend."); }},
      {"arap", [&] { options.Nested("arap", &DO::arap, "ArapOptions of --energy=arap."); }},
  };
  std::set<std::string> bound;
  for (const OptionRow<DO>& row : DeformerOptionTable().rows()) {
    const size_t dot = row.name.find('.');
    if (dot == std::string::npos) {
      options.Row(row);
    } else if (bound.insert(row.name.substr(0, dot)).second) {
      nested.at(row.name.substr(0, dot))();
    }
  }
  options.Aliases(DeformerOptionTable()).Finish();

  m.def(
      "describe_options",
      [](const py::object& options) {
        return DescribeOptions(DeformerOptionsFrom(options, py::kwargs()));
      },
      py::arg("options") = py::none(),
      "Every field of `options` (default: DeformerOptions()) as (name, value) string pairs in "
      "declaration order, named as in C++ ('stopping.max_iterations') and printed as the "
      "reports print them (numbers %.17g, booleans true/false): the C++ DescribeOptions.");
  m.def(
      "paper_procedure",
      [](const py::object& options) {
        return PaperProcedure(DeformerOptionsFrom(options, py::kwargs()));
      },
      py::arg("options") = py::none(),
      "A copy of `options` (default: DeformerOptions()) with the multi-scale method as the "
      "paper writes it: shape-matching rigidity, every fixed-handle node Half Free, the border "
      "kept Fixed, no Position terms on fixed vertices (the C++ PaperProcedure).");
}

}  // namespace

DeformerOptions DeformerOptionsFrom(const py::handle& options, const py::kwargs& kwargs) {
  py::object result;
  if (options.is_none()) {
    result = py::cast(DeformerOptions());
  } else if (py::isinstance<DeformerOptions>(options)) {
    result = py::cast(DeformerOptions(options.cast<const DeformerOptions&>()));
  } else if (py::isinstance<py::dict>(options)) {
    result = py::cast(DeformerOptions());
    ApplyKeywords(result, py::reinterpret_borrow<py::dict>(options));
  } else {
    ThrowTypeError("options: expected a DeformerOptions, a dict of its fields or None, got " +
                   Repr(options));
  }
  ApplyKeywords(result, kwargs);
  DeformerOptions resolved = result.cast<DeformerOptions>();
  // `num_threads` is the one thread count, as --threads is: it bounds the
  // graph building too unless `graph` is given with its own.
  const auto given = [&](const char* key) {
    return kwargs.contains(key) ||
           (py::isinstance<py::dict>(options) && options.cast<py::dict>().contains(key));
  };
  if ((given("num_threads") || given("threads")) && !given("graph")) {
    resolved.graph.num_threads = resolved.num_threads;
  }
  return resolved;
}

namespace {

// TypeError for a keyword of a Method (or run_method) that is neither a
// method's own nor a DeformerOptions spelling, offering the nearest of them
// all as the command line does for a flag (apps/flags/deformer_flags.h).
void CheckMethodKeywords(const py::kwargs& deformer_keywords) {
  const py::object type = py::type::of<DeformerOptions>();
  const py::tuple fields = type.attr("fields");
  const py::dict aliases = type.attr("aliases");
  for (const auto& [key, value] : deformer_keywords) {
    if (fields.contains(key) || aliases.contains(key)) continue;
    std::vector<std::string> spellings;
    for (const py::handle field : fields) spellings.push_back(py::str(field));
    for (const auto& alias : aliases) spellings.push_back(py::str(alias.first));
    for (const OptionRow<MethodOptions>& row : MethodOptionTable().rows()) {
      if (!IsMethodOwnRow(row.name)) continue;
      for (const std::string& keyword : MethodKeywords(row.name)) spellings.push_back(keyword);
    }
    const std::string nearest = NearestName(py::str(key), spellings);
    ThrowTypeError("unknown option " + Repr(key) +
                   (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)") +
                   "; the options are the fields of msdeform.DeformerOptions and the methods' "
                   "own keywords (help(msdeform.Method) lists them)");
  }
}

}  // namespace

std::vector<std::string> MethodKeywords(const std::string& row_name) {
  const OptionRow<MethodOptions>* row = MethodOptionTable().Find(row_name);
  std::string underscored = row_name;
  std::replace(underscored.begin(), underscored.end(), '.', '_');
  std::vector<std::string> keywords = {underscored};
  for (const std::string& alias : row->aliases) {
    if (alias != underscored) keywords.push_back(alias);
  }
  return keywords;
}

MethodOptions MethodOptionsFrom(const py::handle& options, const py::kwargs& kwargs) {
  MethodOptions result;
  py::kwargs rest;
  std::set<std::string> used, consumed;  // rows set, keywords read
  for (const OptionRow<MethodOptions>& row : MethodOptionTable().rows()) {
    if (!IsMethodOwnRow(row.name)) continue;
    for (const std::string& keyword : MethodKeywords(row.name)) {
      if (!kwargs.contains(keyword)) continue;
      if (!used.insert(row.name).second) {
        ThrowValueError(keyword + ": one option (" + row.name + "), given twice");
      }
      consumed.insert(keyword);
      const std::string text = RowText(row, kwargs[py::str(keyword)], keyword);
      std::string error;
      if (!MethodOptionTable().Set(row.name, text, &result, &error, keyword)) {
        ThrowValueError(error);
      }
    }
  }
  for (const auto& [key, value] : kwargs) {
    if (consumed.count(py::str(key).cast<std::string>()) == 0) rest[key] = value;
  }
  CheckMethodKeywords(rest);
  result.deformer = DeformerOptionsFrom(options, rest);
  return result;
}

void CheckKeywordsReadBy(const std::string& method, const py::handle& options,
                         const py::kwargs& kwargs) {
  std::vector<std::string> keys;
  for (const auto& [key, value] : kwargs) keys.push_back(py::str(key));
  if (py::isinstance<py::dict>(options)) {
    for (const auto& [key, value] : options.cast<py::dict>()) keys.push_back(py::str(key));
  }
  const py::object type = py::type::of<DeformerOptions>();
  const py::tuple fields = type.attr("fields");
  const py::dict aliases = type.attr("aliases");
  for (const std::string& key : keys) {
    // The rows the keyword sets: a method's own row, a Deformer row by its
    // other spelling, or a field (a nested struct's: every row under it).
    std::vector<std::string> rows;
    for (const OptionRow<MethodOptions>& row : MethodOptionTable().rows()) {
      if (!IsMethodOwnRow(row.name)) continue;
      const std::vector<std::string> keywords = MethodKeywords(row.name);
      if (std::find(keywords.begin(), keywords.end(), key) != keywords.end()) {
        rows.push_back(row.name);
      }
    }
    const py::str py_key(key);
    if (rows.empty() && aliases.contains(py_key)) rows.push_back(py::str(aliases[py_key]));
    if (rows.empty() && fields.contains(py_key)) {
      for (const OptionRow<MethodOptions>& row : MethodOptionTable().rows()) {
        if (!IsMethodOwnRow(row.name) && (row.name == key || row.name.rfind(key + ".", 0) == 0)) {
          rows.push_back(row.name);
        }
      }
    }
    bool read = rows.empty();  // not a row (MethodOptionsFrom judged it)
    for (const std::string& row : rows) read = read || MethodReadsRow(method, row);
    if (!read) ThrowTypeError(key + ": " + NotAnOptionOf(method, rows));
  }
}

void BindOptions(py::module_& m) {
  BindSubOptions(m);
  BindDeformerOptions(m);
}

}  // namespace python
}  // namespace msdeform
