// The options structs reachable from DeformerOptions as Python classes: every
// field a read-write attribute, enums as the strings the C++ Name functions
// print, nested structs as attributes that can also be set from a dict, and
// a keyword constructor whose defaults are those of the default-constructed
// C++ struct (never restated here).

#include <Python.h>

#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/lattice.h"
#include "msdeform/scales/ceres_solver.h"
#include "msdeform/scales/deformer.h"
#include "msdeform/scales/frame_solver.h"
#include "msdeform/scales/gauss_newton_solver.h"
#include "msdeform/scales/rigidity.h"
#include "msdeform/scales/scale_selection.h"
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

template <typename Int>
Int IntegerField(const py::handle& value, const std::string& where) {
  const py::int_ integer = Integer(value, where);
  const py::int_ low(std::numeric_limits<Int>::min()), high(std::numeric_limits<Int>::max());
  if (integer < low || integer > high) {
    ThrowValueError(where + ": " + Repr(integer) + " is outside " + Repr(low) + ".." +
                    Repr(high));
  }
  return integer.cast<Int>();
}

template <>
int FieldValue<int>(const py::handle& value, const std::string& where) {
  return IntegerField<int>(value, where);
}

template <>
long long FieldValue<long long>(const py::handle& value, const std::string& where) {
  return IntegerField<long long>(value, where);
}

template <>
std::uint64_t FieldValue<std::uint64_t>(const py::handle& value, const std::string& where) {
  return IntegerField<std::uint64_t>(value, where);
}

// Sets the fields named by `keywords` on `target`, an options object: a
// TypeError names an unknown keyword; each attribute's setter checks its value.
void ApplyKeywords(const py::object& target, const py::dict& keywords) {
  const py::tuple fields = target.attr("fields");
  const std::string name = py::str(py::type::handle_of(target).attr("__name__"));
  for (const auto& [key, value] : keywords) {
    if (!fields.contains(key)) {
      std::vector<std::string> names;
      for (const py::handle field : fields) names.push_back(py::str(field));
      ThrowTypeError(name + ": unknown option " + Repr(key) + "; the options are " +
                     Join(names));
    }
    target.attr(key) = value;
  }
}

// Binds an options struct T field by field, then adds what every options
// class has (Finish): the keyword constructor, `fields`, `choices`,
// to_dict(), copy(), check(), ==, repr().
template <typename T>
class OptionsClass {
 public:
  OptionsClass(py::module_& m, const char* name, const char* doc)
      : class_(m, name, doc), name_(name) {}

  // A number or a bool.
  template <typename V>
  OptionsClass& Field(const char* field, V T::*member, const char* doc) {
    const std::string where = name_ + "." + field;
    class_.def_property(
        field, [member](const T& self) { return self.*member; },
        [member, where](T& self, const py::object& value) {
          self.*member = FieldValue<V>(value, where);
        },
        doc);
    fields_.push_back(field);
    return *this;
  }

  // An enum as a string: `values` lists its values, `name` prints one and
  // `parse` reads one back (the C++ Name / Parse pair).
  template <typename E, typename NameFunction, typename ParseFunction>
  OptionsClass& Choice(const char* field, E T::*member, const std::vector<E>& values,
                       NameFunction name, ParseFunction parse, const char* doc) {
    std::vector<std::string> names;
    for (E value : values) names.push_back(name(value));
    const std::string where = name_ + "." + field;
    class_.def_property(
        field, [member, name](const T& self) { return std::string(name(self.*member)); },
        [member, parse, names, where](T& self, const py::object& value) {
          if (!py::isinstance<py::str>(value)) {
            ThrowTypeError(where + ": expected a string (one of " + Join(names) + "), got " +
                           Repr(value));
          }
          const std::string text = value.cast<std::string>();
          E parsed;
          if (!parse(text, &parsed)) {
            ThrowValueError(where + ": unknown value '" + text + "'; expected one of " +
                            Join(names));
          }
          self.*member = parsed;
        },
        doc);
    fields_.push_back(field);
    choices_.emplace_back(field, names);
    return *this;
  }

  // The same for an enum without a C++ Parse function: parsed by its names.
  template <typename E, typename NameFunction>
  OptionsClass& Choice(const char* field, E T::*member, const std::vector<E>& values,
                       NameFunction name, const char* doc) {
    auto parse = [values, name](const std::string& text, E* value) {
      for (E candidate : values) {
        if (text == name(candidate)) {
          *value = candidate;
          return true;
        }
      }
      return false;
    };
    return Choice(field, member, values, name, parse, doc);
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
};

const char* RegionSummationName(RegionSummation summation) {
  return summation == RegionSummation::kBox ? "box" : "per_region";
}

const char* MemberExtentName(MemberExtent extent) {
  return extent == MemberExtent::kMax ? "max" : "mean";
}

void BindLatticeOptions(py::module_& m) {
  OptionsClass<LatticeOptions>(m, "LatticeOptions",
                               "The lattice the mesh is embedded in (core/lattice.h).")
      .Field("cell_width", &LatticeOptions::cell_width,
             "Cell width w in mesh units; 0 means diagonal / cells_per_diagonal.")
      .Field("cells_per_diagonal", &LatticeOptions::cells_per_diagonal,
             "Used when cell_width is 0: w = bounding-box diagonal / this.")
      .Field("max_grid_cells", &LatticeOptions::max_grid_cells,
             "Upper bound on the cells of the padded grid (memory guard).")
      .Field("split_cells", &LatticeOptions::split_cells,
             "One particle per piece of surface in a cell (False: one per cell, the paper).")
      .Field("piece_margin", &LatticeOptions::piece_margin,
             "Pieces are found within the cell grown by this many cell widths, in [0, 2].")
      .Finish();
}

void BindGraphOptions(py::module_& m) {
  OptionsClass<GraphOptions>(m, "GraphOptions",
                             "The multi-scale deformation graphs (core/deformation_graph.h).")
      .Field("k", &GraphOptions::k, "Nearest nodes per vertex (paper: 4).")
      .Field("nodes_per_scale", &GraphOptions::nodes_per_scale,
             "P: nodes per scale step; N = max(1, floor(D1 / P)) scales (paper: 100).")
      .Field("seed", &GraphOptions::seed,
             "Seed of the random vertex chosen in each surface cell for DG1.")
      .Field("extra_rings", &GraphOptions::extra_rings,
             "Cell rings searched beyond the first that reaches k + 1 nodes.")
      .Field("num_threads", &GraphOptions::num_threads,
             "OpenMP threads for building; 0 uses the OpenMP default.")
      .Finish();
}

void BindRigidityOptions(py::module_& m) {
  OptionsClass<RigidityOptions>(m, "RigidityOptions",
                                "Rigidity estimation, e' per lattice particle (scales/rigidity.h).")
      .Choice("model", &RigidityOptions::model,
              {RigidityModel::kHarmonic, RigidityModel::kShapeMatching}, RigidityModelName,
              ParseRigidityModel,
              "'harmonic' (the default, a harmonic field on the lattice) or 'paper' (S steps "
              "of lattice shape matching).")
      .Field("num_steps", &RigidityOptions::num_steps, "S: shape-matching steps ('paper').")
      .Field("time_step", &RigidityOptions::time_step, "h: time step, lattice-time units.")
      .Field("external_stiffness", &RigidityOptions::external_stiffness,
             "k_ext, per unit mass, 1 / time^2; k_ext h^2 <= 1.")
      .Field("initial_speed", &RigidityOptions::initial_speed,
             "|v0| of the moveable-handle particles, cell widths per time step.")
      .Field("damping", &RigidityOptions::damping,
             "Fraction of each particle's velocity removed per step, in [0, 1).")
      .Field("region_half_width", &RigidityOptions::region_half_width,
             "r: a region is a particle and its r-ring.")
      .Field("seed", &RigidityOptions::seed, "Seed of the direction of v0.")
      .Choice("region_summation", &RigidityOptions::region_summation,
              {RegionSummation::kBox, RegionSummation::kPerRegion}, RegionSummationName,
              "'box' (FastLSM box sums) or 'per_region'; the same numbers up to rounding.")
      .Field("max_rotation_iterations", &RigidityOptions::max_rotation_iterations,
             "Polar-decomposition updates per region and step, at most.")
      .Field("rotation_tolerance", &RigidityOptions::rotation_tolerance,
             "Stop the updates below this rotation (radians).")
      .Finish();
}

void BindScaleSelectionOptions(py::module_& m) {
  OptionsClass<ScaleSelectionOptions>(
      m, "ScaleSelectionOptions",
      "Scale selection, node classes and alpha weights (scales/scale_selection.h).")
      .Field("threshold_floor", &ScaleSelectionOptions::threshold_floor,
             "Lower bound of the threshold T (Eq. 7: 0.1).")
      .Field("fixed_extent_cutoff", &ScaleSelectionOptions::fixed_extent_cutoff,
             "Fixed-handle nodes with e' below this count towards T (Eq. 7: 0.5).")
      .Choice("member_extent", &ScaleSelectionOptions::member_extent,
              {MemberExtent::kMax, MemberExtent::kMean}, MemberExtentName,
              "A coarse node's e' from its DG1 members: 'max' or 'mean' (an ablation).")
      .Field("local_detail_distance", &ScaleSelectionOptions::local_detail_distance,
             "Local-detail edit within this geodesic distance, over the diagonal.")
      .Field("omega_max", &ScaleSelectionOptions::omega_max,
             "Totally Free nodes map e to omega in [1, omega_max].")
      .Field("alpha_all_one", &ScaleSelectionOptions::alpha_all_one,
             "Ablation: alpha_jk = 1 for every edge.")
      .Choice("half_free", &ScaleSelectionOptions::half_free,
              {HalfFreeRule::kNextToTotallyFree, HalfFreeRule::kEveryFixedHandleNode,
               HalfFreeRule::kNone},
              HalfFreeRuleName, ParseHalfFreeRule, "Which fixed-handle nodes are Half Free.")
      .Choice("border", &ScaleSelectionOptions::border,
              {BorderRule::kTotallyFree, BorderRule::kHalfFree, BorderRule::kFixed},
              BorderRuleName, ParseBorderRule,
              "What a Fixed node next to a Totally Free one becomes.")
      .Field("pin_fixed_region", &ScaleSelectionOptions::pin_fixed_region,
             "Nodes that skin a fixed-handle vertex are Fixed: the fixed region stays exactly "
             "at rest (False: the paper).")
      .Finish();
}

void BindSolverOptions(py::module_& m) {
  OptionsClass<StoppingRule>(m, "StoppingRule",
                             "When a frame's solve stops, for both backends (scales/frame_solver.h).")
      .Field("max_iterations", &StoppingRule::max_iterations,
             "Linear solves per frame, at most (the per-frame budget).")
      .Field("function_tolerance", &StoppingRule::function_tolerance,
             "Stop when |dF| <= this * F after an accepted step.")
      .Field("gradient_tolerance", &StoppingRule::gradient_tolerance,
             "Stop when max |gradient| <= this.")
      .Field("parameter_tolerance", &StoppingRule::parameter_tolerance,
             "Stop when |step| <= this * (|x| + this).")
      .Finish();

  using GN = GaussNewtonOptions;
  OptionsClass<GN>(m, "GaussNewtonOptions",
                   "The Gauss-Newton backend (scales/gauss_newton_solver.h).")
      .Choice("linear_solver", &GN::linear_solver,
              {GN::LinearSolver::kCholesky, GN::LinearSolver::kPcgJacobi,
               GN::LinearSolver::kPcgIncompleteCholesky},
              LinearSolverName, ParseLinearSolver, "How each step's linear system is solved.")
      .Choice("cholesky", &GN::cholesky,
              {GN::Cholesky::kEigenLLT, GN::Cholesky::kEigenLDLT, GN::Cholesky::kCholmod},
              CholeskyName, ParseCholesky, "The sparse Cholesky of linear_solver='cholesky'.")
      .Choice("factorization", &GN::factorization,
              {GN::Factorization::kEveryIteration, GN::Factorization::kPerFrame,
               GN::Factorization::kLagged},
              FactorizationName, ParseFactorization, "When J^T J is factorised.")
      .Field("refactor_ratio", &GN::refactor_ratio,
             "Keep a factorisation while each step shrinks max |gradient| by this.")
      .Choice("damping", &GN::damping,
              {GN::Damping::kGaussNewton, GN::Damping::kLevenbergMarquardt}, DampingName,
              ParseDamping, "Damping rule: Gauss-Newton safeguard or Levenberg-Marquardt.")
      .Field("min_damping", &GN::min_damping, "mu floor, relative to diag(J^T J).")
      .Field("initial_damping", &GN::initial_damping, "Levenberg-Marquardt's first mu.")
      .Field("forcing_term", &GN::forcing_term, "PCG's relative residual bound, at most.")
      .Field("max_cg_iterations", &GN::max_cg_iterations, "PCG iterations per step, at most.")
      .Finish();

  OptionsClass<CeresOptions>(m, "CeresOptions", "The Ceres backend (scales/ceres_solver.h).")
      .Choice("trust_region", &CeresOptions::trust_region,
              {ceres::LEVENBERG_MARQUARDT, ceres::DOGLEG}, TrustRegionName, ParseTrustRegion,
              "Trust-region strategy.")
      .Choice("linear_solver", &CeresOptions::linear_solver,
              {ceres::SPARSE_NORMAL_CHOLESKY, ceres::CGNR}, CeresLinearSolverName,
              ParseCeresLinearSolver, "Ceres's linear solver.")
      .Choice("sparse_library", &CeresOptions::sparse_library, CeresSparseLibraries(),
              SparseLibraryName, ParseSparseLibrary,
              "The sparse Cholesky library (those this Ceres has).")
      .Field("group_position_terms", &CeresOptions::group_position_terms,
             "One exact least-squares block per group of handle vertices sharing nodes.")
      .Finish();
}

void BindDeformerOptions(py::module_& m) {
  using DO = DeformerOptions;
  OptionsClass<DO>(m, "DeformerOptions",
                   "Everything the Deformer takes (scales/deformer.h); Deformer(V, F, **kwargs) "
                   "takes the same fields by keyword.")
      .Choice("method", &DO::method, {Method::kMultiScale, Method::kStatic, Method::kStaticDense},
              MethodName, ParseMethod,
              "'multiscale' (the paper's method) or a single static graph: 'static' (about "
              "static_nodes nodes) or 'static_dense' (DG1).")
      .Nested("lattice", &DO::lattice, "LatticeOptions: the cell width.")
      .Nested("graph", &DO::graph, "GraphOptions: k, P, seed.")
      .Nested("rigidity", &DO::rigidity, "RigidityOptions: how e' is estimated.")
      .Nested("selection", &DO::selection, "ScaleSelectionOptions: thresholds, node classes.")
      .Field("static_nodes", &DO::static_nodes, "Nodes of the static baseline graph.")
      .Field("w_rot", &DO::w_rot, "Eq. 17 weight of E_rot.")
      .Field("w_coh", &DO::w_coh, "Eq. 17 weight of E_coh.")
      .Field("w_con", &DO::w_con, "Eq. 17 weight of E_con.")
      .Field("length_unit", &DO::length_unit,
             "Unit of the coherence and position residuals; 0: the bounding-box diagonal.")
      .Field("hold_fixed_vertices", &DO::hold_fixed_vertices,
             "Multi-scale: Position terms on fixed vertices a non-Fixed node skins.")
      .Field("keep_left_out_terms", &DO::keep_left_out_terms,
             "Ablation: keep E(j, k) for Half Free j.")
      .Field("fix_fixed_handle_nodes", &DO::fix_fixed_handle_nodes,
             "Ablation: fixed-handle nodes are Fixed, not Half Free.")
      .Field("num_threads", &DO::num_threads,
             "Threads for skinning and the Ceres solve; as a keyword, also graph.num_threads.")
      .Field("cached_scales", &DO::cached_scales,
             "Multi-scale: coarse scales whose skinning data is kept once built (when first "
             "used); the least recently used is dropped beyond this.")
      .Choice("backend", &DO::backend, {Solver::kGaussNewton, Solver::kCeres}, SolverName,
              ParseSolver, "The per-frame solver: 'gauss_newton' or 'ceres'.")
      .Nested("stopping", &DO::stopping, "StoppingRule: the per-frame stopping rule.")
      .Choice("initial_guess", &DO::initial_guess,
              {InitialGuess::kRest, InitialGuess::kPrevious, InitialGuess::kExtrapolated},
              InitialGuessName, ParseInitialGuess, "Where a frame's solve starts.")
      .Nested("gauss_newton", &DO::gauss_newton, "GaussNewtonOptions of the default backend.")
      .Nested("ceres", &DO::ceres, "CeresOptions of the Ceres backend.")
      .Finish();

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
  if (given("num_threads") && !given("graph")) resolved.graph.num_threads = resolved.num_threads;
  return resolved;
}

void BindOptions(py::module_& m) {
  BindLatticeOptions(m);
  BindGraphOptions(m);
  BindRigidityOptions(m);
  BindScaleSelectionOptions(m);
  BindSolverOptions(m);
  BindDeformerOptions(m);
}

}  // namespace python
}  // namespace msdeform
