// msdeform.Method (python/method_object.h): construction by name, set_handles,
// drag and drag_along through the one C++ loop (DragAlong), the statistics,
// and the members every method has.

#include <Python.h>

#include <algorithm>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "msdeform/core/drag_path.h"
#include "msdeform/core/option_table.h"
#include "msdeform/core/scenario.h"
#include "msdeform/methods/method_option_table.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/methods/registry.h"
#include "python/method_object.h"

namespace msdeform {
namespace python {

void PyMethod::RequireHandles() const {
  if (!method->handles_set()) {
    ThrowRuntimeError(name() + ": no handle layout: call set_handles (with a valid layout) first");
  }
}

const GraphMethod& PyMethod::Graph(const char* member) const {
  if (!graph) {
    std::string graphs;
    for (const MethodDescriptor& d : RegisteredMethods()) {
      if (d.graph) graphs += (graphs.empty() ? "" : ", ") + d.name;
    }
    ThrowAttributeError(std::string(member) + ": " + name() +
                        " is not a deformation-graph method (those are " + graphs + ")");
  }
  return *method->graph_method();
}

namespace {

py::dict StatsToDict(const MethodStats& stats) {
  py::dict dict;
  dict["frame_ms"] = stats.frame_ms;
  dict["solve_ms"] = stats.solve_ms;
  dict["skin_ms"] = stats.skin_ms;
  dict["iterations"] = stats.iterations;
  dict["factorizations"] = stats.factorizations;
  dict["initial_cost"] = stats.initial_cost;
  dict["final_cost"] = stats.final_cost;
  dict["converged"] = stats.converged;
  py::array_t<double> trace({static_cast<py::ssize_t>(stats.trace.size()), py::ssize_t{2}});
  auto out = trace.mutable_unchecked<2>();
  for (size_t i = 0; i < stats.trace.size(); ++i) {
    out(i, 0) = stats.trace[i].ms;
    out(i, 1) = stats.trace[i].cost;
  }
  dict["trace"] = trace;
  return dict;
}

// The method's name: `method` (a str), or None for the one `options` names
// (DeformerOptions.method, a graph method; 'multiscale' by default).
std::string MethodNameFrom(const py::object& method, const MethodOptions& options) {
  if (method.is_none()) return MethodName(options.deformer.method);
  if (!py::isinstance<py::str>(method)) {
    ThrowTypeError("method: expected a name in msdeform.METHODS (a str) or None, got " +
                   std::string(py::repr(method)));
  }
  return method.cast<std::string>();
}

std::unique_ptr<PyMethod> MakeMethod(const py::object& vertices, const py::object& faces,
                                     const py::object& method, const py::object& options,
                                     const py::kwargs& kwargs) {
  Mesh mesh = MeshFromArrays(vertices, faces);
  const MethodOptions method_options = MethodOptionsFrom(options, kwargs);
  auto self = std::make_unique<PyMethod>();
  std::string error;
  const std::string name = MethodNameFrom(method, method_options);
  self->method = CreateMethod(name, &error);
  if (self->method == nullptr) ThrowValueError("method: " + error);
  CheckKeywordsReadBy(name, options, kwargs);
  bool ok;
  {
    py::gil_scoped_release release;
    ok = self->method->Precompute(mesh, method_options, &error);
  }
  if (!ok) ThrowValueError(error);
  self->graph = self->method->graph_method() != nullptr;
  self->options = self->graph ? self->method->graph_method()->options() : method_options.deformer;
  self->rest = std::move(mesh);
  return self;
}

void SetHandles(PyMethod& self, const py::object& status) {
  const int num_vertices = self.rest.num_vertices();
  HandleLayout layout;
  if (IsPathLike(status)) {
    const std::string path = PathFromObject(status, "status");
    std::string error;
    if (!ReadSel(path, num_vertices, &layout, &error)) ThrowOSError(error);
  } else {
    layout = LayoutFromStatus(status, num_vertices, "status");
  }
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(self.mutex);
    self.frames.clear();
    self.failed_frames.clear();
    self.is_polished = false;
    self.polisher_layout_set = false;
    self.last_transform = HandleTransforms();
    self.last_is_targets = false;
    ok = self.method->SetHandles(layout, &error);
    if (ok) self.layout = std::move(layout);
  }
  if (!ok) ThrowValueError(error);
}

// The rest centroid of handle group g (every moveable vertex for -1): the
// pivot of msdeform's --sel/--def drags and of a scenario handle's motion.
Eigen::Vector3d HandleCentroid(const PyMethod& self, int g = -1) {
  const std::vector<int> vertices =
      g < 0 ? self.layout.moveable : HandleGroupVertices(self.layout, g);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : vertices) centroid += self.rest.vertices.col(v);
  return centroid / static_cast<double>(vertices.size());
}

// `frames` (None: 1) as a frame count in 1..kMaxScenarioFrames.
int FrameCount(const py::object& frames) {
  if (frames.is_none()) return 1;
  PyObject* index = PyBool_Check(frames.ptr()) ? nullptr : PyNumber_Index(frames.ptr());
  if (index == nullptr) {
    PyErr_Clear();
    ThrowTypeError("frames: expected an integer, got " + std::string(py::repr(frames)));
  }
  const py::int_ count = py::reinterpret_steal<py::int_>(index);
  if (count < py::int_(1) || count > py::int_(kMaxScenarioFrames)) {
    ThrowValueError("frames: expected 1.." + std::to_string(kMaxScenarioFrames) + ", got " +
                    std::string(py::repr(count)));
  }
  return count.cast<int>();
}

// drag_along's path (the lock held, a layout set): a path as given (then
// `frames` must be None), or one frame M reached in `frames` equal steps
// (None: 1), each handle group's transform about the group's rest centroid.
std::vector<HandleTransforms> DragAlongPathOf(const PyMethod& self, const py::object& matrix,
                                              const py::object& frames) {
  const int num_groups = self.layout.num_groups();
  std::vector<HandleTransforms> path;
  if (PathFromArray(matrix, "path", num_groups, &path)) {
    if (!frames.is_none()) {
      ThrowValueError("frames: give either a path of transforms (frames, 4, 4), or "
                      "(frames, groups, 4, 4) for several handle groups, or one transform and "
                      "frames, not both");
    }
    return path;
  }
  const HandleTransforms target = FrameFromArray(matrix, "M", num_groups);
  const int count = FrameCount(frames);
  if (target.size() == 1) {
    const std::vector<Eigen::Affine3d> one =
        InterpolateDragPath(target[0], HandleCentroid(self), count);
    return std::vector<HandleTransforms>(one.begin(), one.end());
  }
  std::vector<std::vector<Eigen::Affine3d>> per_group;
  for (int g = 0; g < num_groups; ++g) {
    per_group.push_back(InterpolateDragPath(target[g], HandleCentroid(self, g), count));
  }
  for (int f = 0; f < count; ++f) {
    std::vector<Eigen::Affine3d> transforms;
    for (int g = 0; g < num_groups; ++g) transforms.push_back(per_group[g][f]);
    path.emplace_back(std::move(transforms));
  }
  return path;
}

// The one drag loop of drag and drag_along: the C++ DragAlong (the loop of
// the command line and the runner) with the GIL released; every successful
// frame's statistics appended. Returns a copy of the deformed vertices.
py::array_t<double> DragThrough(const py::object& self_object, PyMethod& self,
                                const std::vector<HandleTransforms>& path,
                                bool continue_after_failure) {
  DragAlongOptions options;
  options.continue_after_failure = continue_after_failure;
  DragLog log;
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(self.mutex);
    ok = DragAlong(self.method.get(), path, options, &log, &error);
    // The last successful frame's transform: the frames are tried in order,
    // the failed ones (1-based) listed, and a failure without
    // continue_after_failure ends the drag.
    size_t successes = 0;
    for (size_t f = 0; f < path.size() && successes < log.frames.size(); ++f) {
      if (std::find(log.failed_frames.begin(), log.failed_frames.end(),
                    static_cast<int>(f) + 1) != log.failed_frames.end()) {
        continue;
      }
      self.last_transform = path[f];
      self.last_is_targets = false;
      ++successes;
    }
    if (!log.frames.empty()) self.is_polished = false;
    for (MethodStats& stats : log.frames) self.frames.push_back(std::move(stats));
    self.failed_frames = log.failed_frames;
  }
  if (!ok) ThrowRuntimeError(error);
  // A new array, as libigl returns: the next drag does not change it.
  std::lock_guard<std::mutex> lock(self.mutex);
  return PositionsToArray(self.shown());
}

// drag(targets=...) for a method that places the handle vertices one by one:
// EditingMethod::DragTo with the GIL released (then the lock taken, as
// DragThrough does: the GIL is never waited for with the lock held).
py::array_t<double> DragToTargets(PyMethod& self, const Eigen::Matrix3Xd& targets) {
  MethodStats stats;
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(self.mutex);
    ok = self.method->DragTo(targets, &stats, &error);
    self.failed_frames.clear();
    if (ok) {
      self.is_polished = false;
      self.last_is_targets = true;
      self.last_targets = targets;
      self.frames.push_back(std::move(stats));
    } else {
      self.failed_frames.push_back(1);
    }
  }
  if (!ok) ThrowRuntimeError("frame 1 of 1: " + error);
  std::lock_guard<std::mutex> lock(self.mutex);
  return PositionsToArray(self.shown());
}

// Handle-vertex targets within this fraction of the bounding-box diagonal of
// each group's best rigid or affine map are taken as that map.
constexpr double kTargetTolerance = 1e-9;

py::array_t<double> Drag(const py::object& self_object, const py::object& matrix,
                         const py::object& targets) {
  PyMethod& self = self_object.cast<PyMethod&>();
  std::vector<HandleTransforms> path;
  int num_groups, num_moveable;
  {
    std::lock_guard<std::mutex> lock(self.mutex);
    self.RequireHandles();
    num_groups = self.layout.num_groups();
    num_moveable = static_cast<int>(self.layout.moveable.size());
  }
  if (matrix.is_none() == targets.is_none()) {
    ThrowTypeError("drag: give M (the handle transforms) or targets (the handle vertices' "
                   "positions), one of the two");
  }
  if (!targets.is_none()) {
    const Eigen::Matrix3Xd positions = PositionsFromArray(targets, "targets");
    if (positions.cols() != num_moveable) {
      ThrowValueError("targets: " + std::to_string(positions.cols()) + " rows for " +
                      std::to_string(num_moveable) + " handle vertices");
    }
    if (!positions.allFinite()) ThrowValueError("targets: not finite");
    if (self.method->takes_vertex_targets()) return DragToTargets(self, positions);
    // The others move by a transform a group: each group's fit.
    std::lock_guard<std::mutex> lock(self.mutex);
    HandleTransforms fitted;
    std::string error;
    const double tolerance = kTargetTolerance * BoundingBoxDiagonal(self.rest);
    if (!HandleTransformsFromTargets(self.rest.vertices, self.layout, positions, tolerance,
                                     &fitted, &error)) {
      ThrowValueError("targets: " + error + " (" + self.name() +
                      " moves each group by one transform; full_arap, cgal_arap and "
                      "cgal_sr_arap take any targets)");
    }
    path.push_back(std::move(fitted));
  } else if (!PathFromArray(matrix, "M", num_groups, &path)) {
    path.push_back(FrameFromArray(matrix, "M", num_groups));
  }
  return DragThrough(self_object, self, path, /*continue_after_failure=*/false);
}

py::array_t<double> DragAlongPath(const py::object& self_object, const py::object& matrix,
                                  const py::object& frames, bool continue_after_failure) {
  PyMethod& self = self_object.cast<PyMethod&>();
  std::vector<HandleTransforms> path;
  {
    std::lock_guard<std::mutex> lock(self.mutex);
    self.RequireHandles();
    path = DragAlongPathOf(self, matrix, frames);
  }
  return DragThrough(self_object, self, path, continue_after_failure);
}

// polish(**budget): PolishOptions from the keywords (the defaults where not
// given; the Method's threads), the polisher set up on the first call for a
// layout, then the polish of the shown frame with the GIL released.
py::dict Polish(const py::object& self_object, const py::kwargs& kwargs) {
  PyMethod& self = self_object.cast<PyMethod&>();
  PolishOptions options;
  options.num_threads = std::max(1, self.options.num_threads);
  const std::vector<std::string> keywords = {"max_iterations", "time_budget_ms",
                                             "relative_tolerance", "anderson_window"};
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key);
    const bool is_bool = py::isinstance<py::bool_>(value);
    auto integer = [&](int* field) {
      if (is_bool || !py::isinstance<py::int_>(value)) {
        ThrowTypeError("polish: " + name + ": expected an integer, got " +
                       std::string(py::repr(value)));
      }
      const py::int_ v = value.cast<py::int_>();
      if (v < py::int_(0) || v > py::int_(1000000)) {
        ThrowValueError("polish: " + name + ": expected 0..1000000, got " +
                        std::string(py::repr(value)));
      }
      *field = v.cast<int>();
    };
    auto number = [&](double* field) {
      if (is_bool || !(py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value))) {
        ThrowTypeError("polish: " + name + ": expected a number, got " +
                       std::string(py::repr(value)));
      }
      *field = value.cast<double>();
    };
    if (name == "max_iterations") {
      integer(&options.max_iterations);
    } else if (name == "anderson_window") {
      integer(&options.anderson_window);
    } else if (name == "time_budget_ms") {
      number(&options.time_budget_ms);
    } else if (name == "relative_tolerance") {
      number(&options.relative_tolerance);
    } else {
      const std::string nearest = NearestName(name, keywords);
      ThrowTypeError("polish: unknown keyword '" + name + "'" +
                     (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)") +
                     "; the keywords are max_iterations, time_budget_ms, relative_tolerance, "
                     "anderson_window");
    }
  }
  std::string error;
  if (!options.Check(&error)) ThrowValueError("polish: " + error);
  {
    std::lock_guard<std::mutex> lock(self.mutex);
    self.RequireHandles();
  }
  PolishReport report;
  bool ok = true;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(self.mutex);
    double setup_ms = 0.0;
    if (!self.polisher_layout_set) {
      ok = self.polisher.Setup(self.rest, self.layout, options, &error);
      setup_ms = self.polisher.setup_ms();
      self.polisher_layout_set = ok;
    } else {
      const PolishOptions& current = self.polisher.options();
      const bool refactor = options.relative_tolerance != current.relative_tolerance ||
                            options.anderson_window != current.anderson_window ||
                            options.num_threads != current.num_threads;
      ok = self.polisher.SetOptions(options, &error);
      if (refactor) setup_ms = self.polisher.setup_ms();
    }
    if (ok) {
      Eigen::Matrix3Xd vertices = self.shown();
      report = self.last_is_targets ? self.polisher.PolishTo(self.last_targets, &vertices)
                                    : self.polisher.Polish(self.last_transform, &vertices);
      report.setup_ms = setup_ms;
      // Copied into the buffer a deformed_vertices view may point at (a move
      // would hand that buffer to `vertices`, freed here, and leave the view
      // dangling); it is allocated once, on the first polish.
      self.polished = vertices;
      self.is_polished = true;
    }
  }
  if (!ok) ThrowValueError("polish: " + error);
  py::dict dict;
  dict["energy_before"] = report.energy_before;
  dict["energy_start"] = report.energy_start;
  dict["energy_after"] = report.energy_after;
  dict["iterations"] = report.iterations;
  dict["converged"] = report.converged;
  dict["ms"] = report.ms;
  dict["setup_ms"] = report.setup_ms;
  return dict;
}

// The constructor's doc: the methods' own keywords from their rows.
std::string ConstructorDoc() {
  std::string doc =
      "Method(V, F, method=None, options=None, **kwargs)\n\n"
      "Builds what depends only on the mesh. V float64 (#V, 3) (any real dtype, converted), "
      "F (#F, 3) of any integer dtype. `method` is a name in msdeform.METHODS; None takes "
      "options.method (a graph method, 'multiscale' by default). `options` is a "
      "DeformerOptions (or a dict of its fields); keyword arguments set its fields on top of "
      "it (w_con=1e3, solver='ceres', stopping={'max_iterations': 5}, ...): the graph methods "
      "read them all, the others only these of them:";
  // From the descriptors (methods/registry.h), so a new method is listed.
  for (const MethodDescriptor& d : RegisteredMethods()) {
    if (d.graph) continue;
    std::string rows;
    for (const std::string& row : d.deformer_rows) rows += (rows.empty() ? "" : ", ") + row;
    doc += " " + d.name + ": " + (rows.empty() ? "none" : rows) + ";";
  }
  doc +=
      " a keyword (or a key of a dict `options`) the method does not read raises TypeError "
      "naming it, the method and the methods that read it. The methods' own options "
      "(msdeform.option_rows(), 'cgal.', 'fastlsm.', ... rows) are keywords too:\n";
  const MethodOptions defaults;
  for (const OptionRow<MethodOptions>& row : MethodOptionTable().rows()) {
    if (!IsMethodOwnRow(row.name)) continue;
    std::string keywords;
    for (const std::string& keyword : MethodKeywords(row.name)) {
      keywords += (keywords.empty() ? "" : " or ") + keyword;
    }
    doc += "  " + keywords + " (" + OptionTypeName(row.type) + ", default " + row.get(defaults) +
           "): " + row.help + "\n";
  }
  return doc +
         "Raises TypeError for an unknown keyword (naming the nearest one, as the command line "
         "does for a flag) or a wrong dtype; ValueError for an unknown method (naming the "
         "registered ones), a wrong shape, an out-of-range face index (the C++ ValidateMesh "
         "message) or an invalid option (naming the keyword).";
}

void BindDragging(py::class_<PyMethod>& c) {
  c.def(py::init(&MakeMethod), py::arg("V"), py::arg("F"), py::arg("method") = py::none(),
        py::arg("options") = py::none(), ConstructorDoc().c_str());
  c.def("set_handles", &SetHandles, py::arg("status"),
        "Sets the handle layout from a per-vertex status array (0 fixed, 1 free, 2 handle; "
        "length #V; 3, 4, ... give more handles that move independently: status 2 + g is "
        "handle group g, numbered without gaps) or the path of a .sel file (for the multi-scale method: rigidity "
        "estimation, scale selection and node classes). Resets the deformation to the rest "
        "pose and the frame statistics. Raises ValueError for a bad array or layout (the C++ "
        "message, e.g. 'the moveable handle has no vertex') and OSError for a bad .sel file; "
        "after a failure, drag raises until a layout is set.");
  c.def("drag", &Drag, py::arg("M") = py::none(), py::kw_only(),
        py::arg("targets") = py::none(),
        "Moves the handle to M @ (its rest positions) (M: 4x4 with last row 0 0 0 1, or 3x4) "
        "and deforms the mesh warm-started from the previous frame; or, for a (frames, 4, 4) "
        "M, each transform in turn. With several handle groups (set_handles' statuses 3, "
        "4, ...), a 4x4 M moves them all, a (groups, 4, 4) M moves group g by M[g], and a "
        "path is (frames, groups, 4, 4). targets= instead of M: a (#handle vertices, 3) array "
        "of where the handle vertices go (in vertex order, as libigl's bc). full_arap, "
        "cgal_arap and cgal_sr_arap take any targets; the other methods move each group by "
        "one transform, the rigid motion, or else the affine map, that reaches its targets "
        "to within 1e-9 of the diagonal, and raise ValueError for targets that bend a group "
        "(give those parts their own groups). Returns the deformed vertices as a new float64 (#V, 3) "
        "array (as libigl returns one): the next drag or drag_along does not change it "
        "(deformed_vertices is the read-only view that follows the current frame). "
        "Raises RuntimeError before set_handles and when a frame fails ('frame F of N: ' and "
        "the C++ message; the last good pose is kept).");
  c.def("drag_along", &DragAlongPath, py::arg("M"), py::arg("frames") = py::none(),
        py::arg("continue_after_failure") = false,
        "Drags through a path with the C++ DragAlong, the loop of the msdeform command line and "
        "the experiment runner. M is either one transform, dragged to in `frames` equal steps "
        "(default 1) about the handle's rest centroid as msdeform --sel/--def --frames=N does "
        "(drag_path; with several handle groups, one frame as drag takes it, each group about "
        "its own centroid), or a path as drag takes one (then frames must be None). "
        "continue_after_failure: a failed intermediate frame keeps the last good pose and the "
        "drag goes on (the command line's behaviour); otherwise the first failure raises. "
        "Returns a new (#V, 3) array as drag() does; frame_stats gains every frame's statistics and "
        "failed_frames lists the failed ones. Raises RuntimeError with 'frame F of N: ...' on "
        "failure.");
  c.def("polish", &Polish,
        "polish(max_iterations=30, time_budget_ms=0, relative_tolerance=1e-7, "
        "anderson_window=5) -> dict\n\n"
        "Polishes the current frame with a few accelerated full_arap iterations (the mesh's "
        "own ARAP energy, cotangent weights), the handle at the last frame's transform and "
        "the fixed vertices at rest, exactly. The polished mesh then replaces the frame as "
        "deformed_vertices (and what drag returned) until the next drag or set_handles; the "
        "next drag continues from the method's own frame. time_budget_ms=0: no limit. The "
        "first call for a layout factorises (setup_ms); a new tolerance or window "
        "factorises again. Returns {energy_before, energy_after (core/metrics.h's normalised "
        "ARAP energy of the frame as given and of the polished one), energy_start (with the "
        "handle and fixed vertices moved onto their targets, where the iterations start: "
        "higher than energy_before for a method with soft handles), iterations, converged, ms, "
        "setup_ms}. Raises RuntimeError before "
        "set_handles, TypeError for an unknown keyword (naming the nearest) or a wrong type, "
        "ValueError for a value out of range (naming the keyword).");
  c.def(
      "drag_path",
      [](PyMethod& self, const py::object& matrix, const py::object& frames) {
        std::lock_guard<std::mutex> lock(self.mutex);
        self.RequireHandles();
        return HandlePathToArray(DragAlongPathOf(self, matrix, frames), self.layout.num_groups());
      },
      py::arg("M"), py::arg("frames"),
      "The path drag_along(M, frames=frames) drags through: (frames, 4, 4), or (frames, groups, "
      "4, 4) for several handle groups.");
}

void BindStatistics(py::class_<PyMethod>& c) {
  c.def_property_readonly(
      "last_stats",
      Locked([](const py::object&, PyMethod& s) -> py::object {
        if (s.frames.empty()) return py::none();
        return StatsToDict(s.frames.back());
      }, false),
      "The last successful frame's statistics as a dict (frame_ms, solve_ms, skin_ms, "
      "iterations, factorizations, initial_cost, final_cost (NaN for a method without an "
      "energy it minimises), converged, and trace: the solve's (ms, cost) points as a "
      "(#points, 2) array); None before the first frame.");
  c.def_property_readonly(
      "frame_stats",
      Locked([](const py::object&, PyMethod& s) {
        py::list frames;
        for (const MethodStats& stats : s.frames) frames.append(StatsToDict(stats));
        return frames;
      }, false),
      "The statistics of every successful frame since set_handles, in order (dicts as "
      "last_stats).");
  c.def_property_readonly(
      "failed_frames",
      Locked([](const py::object&, PyMethod& s) { return s.failed_frames; }, false),
      "1-based frames of the last drag or drag_along whose solve failed (they kept the "
      "previous pose).");
  c.def_property_readonly(
      "precompute_ms",
      Locked([](const py::object&, PyMethod& s) { return s.method->precompute_ms(); }, false),
      "Milliseconds of the constructor's work (Precompute: the lattice and graphs of a graph "
      "method).");
  c.def_property_readonly(
      "rigidity_ms",
      Locked([](const py::object&, PyMethod& s) { return s.method->rigidity_ms(); }, true),
      "Milliseconds of set_handles's rigidity estimation (0 without one).");
  c.def_property_readonly(
      "setup_ms",
      Locked([](const py::object&, PyMethod& s) { return s.method->setup_ms(); }, true),
      "Milliseconds of the rest of set_handles (scale selection, classes and problem build).");
  c.def_property_readonly(
      "num_variables",
      Locked([](const py::object&, PyMethod& s) { return s.method->variables(); }, true),
      "Unknowns of the per-frame problem (a graph method: 12 per Totally Free node + 9 per "
      "Half Free node; the runner's `variables` column).");
  c.def_property_readonly(
      "nodes_optimized",
      Locked([](const py::object&, PyMethod& s) { return s.method->nodes_optimized(); }, true),
      "The elements that carry the unknowns: graph nodes optimised, ROI vertices or free "
      "lattice particles (the runner's column).");
}

// The lattice of a method that has one; AttributeError naming the method
// otherwise.
const Lattice& LatticeOf(const PyMethod& self, const char* member) {
  const Lattice* lattice = self.method->lattice();
  if (lattice == nullptr) {
    ThrowAttributeError(std::string(member) + ": " + self.name() + " has no lattice");
  }
  return *lattice;
}

void BindMeshAndLattice(py::class_<PyMethod>& c) {
  c.def_property_readonly(
      "V",
      Locked([](const py::object& o, PyMethod& s) { return ReadOnlyView(s.rest.vertices, o); },
             false),
      "The rest vertices, a read-only float64 (#V, 3) view.");
  c.def_property_readonly(
      "F", Locked([](const py::object& o, PyMethod& s) { return ReadOnlyView(s.rest.faces, o); },
                  false),
      "The faces, a read-only int32 (#F, 3) view.");
  c.def_property_readonly(
      "deformed_vertices",
      Locked([](const py::object& o, PyMethod& s) {
        return ReadOnlyView(s.shown(), o);
      }, false),
      "The current deformed vertices, a read-only float64 (#V, 3) view of the Method's "
      "storage that the next drag updates in place (drag() returns a copy); the rest "
      "vertices before the first drag after set_handles.");
  c.def_property_readonly(
      "deformed_normals",
      Locked([](const py::object& o, PyMethod& s) {
        if (s.graph) return ReadOnlyView(s.method->graph_method()->deformed_normals(), o);
        Mesh deformed;
        deformed.vertices = s.method->deformed_vertices();
        deformed.faces = s.rest.faces;
        s.normals = VertexNormals(deformed);
        return ReadOnlyView(s.normals, o);
      }, false),
      "The current deformed unit vertex normals, a read-only (#V, 3) view of the Method's "
      "storage: a graph method's skinned normals (Eq. 10), another's area-weighted normals of "
      "the deformed mesh (as the editor shows them). drag() moves positions only; the normals "
      "are made when this property is read, so read it again after each drag (a view kept "
      "from before shows the old normals until then).");
  c.def_property_readonly(
      "options",
      Locked([](const py::object&, PyMethod& s) { return s.options; }, false),
      "A copy of the DeformerOptions this Method was made with (a graph method's `method` is "
      "its name; the other methods read its lattice and thread rows only).");
  c.def_property_readonly(
      "diagonal",
      Locked([](const py::object&, PyMethod& s) {
        return s.graph ? s.method->graph_method()->diagonal() : BoundingBoxDiagonal(s.rest);
      }, false),
      "The rest mesh's bounding-box diagonal.");
  c.def_property_readonly(
      "cell_width",
      Locked([](const py::object&, PyMethod& s) {
        return LatticeOf(s, "cell_width").cell_width();
      }, false),
      "The lattice's cell width w (a method with a lattice: the graph methods, fastlsm, "
      "rigid_cells).");
  c.def_property_readonly(
      "num_surface_particles",
      Locked([](const py::object&, PyMethod& s) {
        return LatticeOf(s, "num_surface_particles").num_surface_particles();
      }, false),
      "Surface particles of the lattice, one per piece of surface in a cell (= DG1 nodes = "
      "the first particles).");
  c.def_property_readonly(
      "particle_positions",
      Locked([](const py::object&, PyMethod& s) {
        return PositionsToArray(LatticeOf(s, "particle_positions").rest_positions());
      }, false),
      "Rest positions of the lattice particles (cell centres), a new (#particles, 3) array; "
      "particles 0 .. num_surface_particles - 1 are the surface particles.");
  c.def_property_readonly(
      "status",
      Locked([](const py::object&, PyMethod& s) {
        return StatusFromLayout(s.layout, s.rest.num_vertices());
      }, true),
      "The handle layout as a per-vertex status array (0 fixed, 1 free, 2 + g handle group "
      "g).");
  c.def_property_readonly(
      "handle_centroid",
      Locked([](const py::object&, PyMethod& s) {
        const Eigen::Vector3d centroid = HandleCentroid(s);
        return py::array_t<double>(3, centroid.data());
      }, true),
      "The handle's rest centroid: the pivot of drag_along(M, frames=N).");
}

}  // namespace

void BindMethod(py::module_& m) {
  m.attr("METHODS") = py::tuple(py::cast(MethodNames()));
  std::vector<std::string> graph_methods;
  for (const MethodDescriptor& method : RegisteredMethods()) {
    if (method.graph) graph_methods.push_back(method.name);
  }
  m.attr("GRAPH_METHODS") = py::tuple(py::cast(graph_methods));
  py::class_<PyMethod> c(
      m, "Method",
      "Any registered editing method by name (msdeform.METHODS; methods/method.h): the "
      "multi-scale method of Liu & Su 2008, its static-graph baselines and the other "
      "methods:\n\n"
      "    e = msdeform.Method(V, F, 'multiscale', w_con=1e3)  # what depends on the mesh\n"
      "    e.set_handles(status)     # a handle layout (rigidity, scale, node classes)\n"
      "    V2 = e.drag(M)            # one frame, warm-started\n"
      "    V2 = e.drag_along(M, frames=30)  # the command line's --frames path\n\n"
      "Every method has the members below; those of a deformation graph (msdeform."
      "GRAPH_METHODS: node_classes, relative_extent, selected_scale, ...) raise "
      "AttributeError naming the method for the others. Not copyable. Calls from several "
      "threads take turns; the GIL is released while it works.");
  BindDragging(c);
  BindStatistics(c);
  BindMeshAndLattice(c);
  c.def_property_readonly(
      "name", [](const PyMethod& s) { return s.name(); }, "The registered name.");
  c.def_property_readonly(
      "graph", [](const PyMethod& s) { return s.graph; },
      "Whether the method is a deformation graph (its descriptor, methods/registry.h).");
  c.def_property_readonly(
      "energy", [](const PyMethod& s) { return MinimisedEnergy(s.name(), s.options); },
      "What the method minimises: ed or arap for a graph method, else its own (arap, "
      "sr_arap, shape_matching, ...).");
  BindGraphMembers(m, c);
}

}  // namespace python
}  // namespace msdeform
