// Any registered editing method (methods/registry.h) as the Python class
// Method: the one interface (methods/method.h) by name, for the methods the
// Deformer class does not run (cgal_arap, cgal_sr_arap, fastlsm) as well as
// the graph methods. The Deformer class stays the way to the graph methods'
// intermediate results (e', node classes, scales).
//
// The GIL is released around Precompute, SetHandles and Drag; a mutex makes
// calls on one Method from several threads take turns.

#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "msdeform/methods/method_option_table.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/methods/registry.h"
#include "python/bindings.h"

namespace msdeform {
namespace python {
namespace {

struct PyMethod {
  std::unique_ptr<EditingMethod> method;
  std::mutex mutex;
  int num_vertices = 0;
  Eigen::Matrix3Xd rest;  // the mesh's vertices: drag_along's pivot
  HandleLayout layout;    // the last layout set_handles was given
  std::vector<MethodStats> frames;
  std::vector<int> failed_frames;

  void RequireHandles() const {
    if (!method->handles_set()) {
      ThrowRuntimeError("no handle layout: call set_handles (with a valid layout) first");
    }
  }
};

std::unique_ptr<PyMethod> MakeMethod(const py::object& vertices, const py::object& faces,
                                     const std::string& name, const py::object& options,
                                     const py::kwargs& kwargs) {
  const Mesh mesh = MeshFromArrays(vertices, faces);
  const MethodOptions method_options = MethodOptionsFrom(options, kwargs);
  auto self = std::make_unique<PyMethod>();
  std::string error;
  self->method = CreateMethod(name, &error);
  if (self->method == nullptr) ThrowValueError("method: " + error);
  self->num_vertices = mesh.num_vertices();
  self->rest = mesh.vertices;
  bool ok;
  {
    py::gil_scoped_release release;
    ok = self->method->Precompute(mesh, method_options, &error);
  }
  if (!ok) ThrowValueError(error);
  return self;
}

void SetHandles(PyMethod& self, const py::object& status) {
  HandleLayout layout;
  if (IsPathLike(status)) {
    const std::string path = PathFromObject(status, "status");
    std::string error;
    if (!ReadSel(path, self.num_vertices, &layout, &error)) ThrowOSError(error);
  } else {
    layout = LayoutFromStatus(status, self.num_vertices, "status");
  }
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(self.mutex);
    self.frames.clear();
    self.failed_frames.clear();
    self.layout = layout;
    ok = self.method->SetHandles(layout, &error);
  }
  if (!ok) ThrowValueError(error);
}

py::array_t<double> Drag(const py::object& self_object, const py::object& matrix) {
  PyMethod& self = self_object.cast<PyMethod&>();
  std::vector<Eigen::Affine3d> path;
  const py::array array = py::array::ensure(matrix);
  if (array && array.ndim() == 3) {
    for (py::ssize_t f = 0; f < array.shape(0); ++f) {
      const std::string name = "M[" + std::to_string(f) + "]";
      path.push_back(TransformFromArray(array[py::int_(f)], name.c_str()));
    }
  } else {
    path.push_back(TransformFromArray(matrix, "M"));
  }
  std::string error;
  bool ok = true;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(self.mutex);
    for (const Eigen::Affine3d& transform : path) {
      MethodStats stats;
      ok = self.method->Drag(transform, &stats, &error);
      if (!ok) break;
      self.frames.push_back(stats);
    }
  }
  if (!ok) ThrowRuntimeError(error);
  return ReadOnlyView(self.method->deformed_vertices(), self_object);
}

py::array_t<double> DragAlongPath(const py::object& self_object, const py::object& matrix,
                                  const py::object& frames, bool continue_after_failure) {
  PyMethod& self = self_object.cast<PyMethod&>();
  std::vector<Eigen::Affine3d> path;
  {
    std::lock_guard<std::mutex> lock(self.mutex);
    self.RequireHandles();
    path = DragPathFrom(self.rest, self.layout.moveable, matrix, frames);
  }
  DragAlongOptions options;
  options.continue_after_failure = continue_after_failure;
  DragLog log;
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(self.mutex);
    ok = DragAlong(self.method.get(), path, options, &log, &error);
    for (MethodStats& stats : log.frames) self.frames.push_back(std::move(stats));
    self.failed_frames = log.failed_frames;
  }
  if (!ok) ThrowRuntimeError(error);
  return ReadOnlyView(self.method->deformed_vertices(), self_object);
}

// The constructor's doc: the methods' own keywords from their rows.
std::string MethodDoc() {
  std::string doc =
      "Method(V, F, method='multiscale', options=None, **kwargs)\n\n"
      "V float64 (#V, 3), F (#F, 3). `options` and the other keyword arguments are "
      "DeformerOptions, as for Deformer (the graph methods use them, FastLSM its lattice "
      "options). The methods' own options (msdeform.option_rows(), 'cgal.' and 'fastlsm.' "
      "rows) are keywords too:\n";
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
         "Raises ValueError naming the registered methods for an unknown name, and naming the "
         "keyword for an invalid option.";
}

}  // namespace

void BindMethod(py::module_& m) {
  m.attr("METHODS") = py::tuple(py::cast(MethodNames()));
  // The deformation-graph methods, from the registry's descriptors.
  std::vector<std::string> graph_methods;
  for (const MethodDescriptor& method : RegisteredMethods()) {
    if (method.graph) graph_methods.push_back(method.name);
  }
  m.attr("GRAPH_METHODS") = py::tuple(py::cast(graph_methods));
  py::class_<PyMethod> c(
      m, "Method",
      "Any registered editing method by name (msdeform.METHODS; methods/method.h):\n\n"
      "    e = msdeform.Method(V, F, 'fastlsm')  # what depends on the mesh only\n"
      "    e.set_handles(status)                # a handle layout\n"
      "    V2 = e.drag(M)                       # one frame (or a (frames, 4, 4) path)\n\n"
      "Not copyable. Calls from several threads take turns; the GIL is released while it works.");
  c.def(py::init(&MakeMethod), py::arg("V"), py::arg("F"), py::arg("method") = "multiscale",
        py::arg("options") = py::none(),
        MethodDoc().c_str());
  c.def("set_handles", &SetHandles, py::arg("status"),
        "A handle layout: a status array (#V,) with 0 fixed, 1 free, 2 moveable, or a .sel "
        "path. Raises ValueError for an invalid layout.");
  c.def("drag", &Drag, py::arg("M"),
        "Moves the handle by the 4x4 transform M (or each of a (frames, 4, 4) path in turn) "
        "and returns a read-only view (#V, 3) of the deformed vertices.");
  c.def_property_readonly("name", [](const PyMethod& s) { return s.method->name(); });
  c.def_property_readonly("deformed_vertices", [](const py::object& self_object) {
    return ReadOnlyView(self_object.cast<PyMethod&>().method->deformed_vertices(), self_object);
  });
  c.def_property_readonly("nodes_optimized",
                          [](const PyMethod& s) { return s.method->nodes_optimized(); });
  c.def_property_readonly("variables", [](const PyMethod& s) { return s.method->variables(); });
  c.def("drag_along", &DragAlongPath, py::arg("M"), py::arg("frames") = py::none(),
        py::arg("continue_after_failure") = false,
        "Drags through a path with the C++ DragAlong, as Deformer.drag_along: M one transform "
        "reached in `frames` equal steps (default 1) about the handle's rest centroid, or a "
        "(frames, 4, 4) path. continue_after_failure: a failed intermediate frame keeps the "
        "last good pose and the drag goes on. Raises RuntimeError with 'frame F of N: ...'.");
  c.def(
      "drag_path",
      [](PyMethod& self, const py::object& matrix, const py::object& frames) {
        std::lock_guard<std::mutex> lock(self.mutex);
        self.RequireHandles();
        return TransformsToArray(DragPathFrom(self.rest, self.layout.moveable, matrix, frames));
      },
      py::arg("M"), py::arg("frames"),
      "The (frames, 4, 4) path drag_along(M, frames=frames) drags through.");
  c.def_property_readonly("graph", [](const PyMethod& s) { return FindMethod(s.method->name())->graph; },
                          "Whether the method is a deformation graph (its descriptor, methods/registry.h).");
  c.def_property_readonly("energy", [](const PyMethod& s) {
    const MethodDescriptor* d = FindMethod(s.method->name());
    return d->graph ? std::string(EnergyName(s.method->deformer()->options().energy)) : d->energy;
  }, "What the method minimises: ed or arap for a graph method, else its own (arap, sr_arap, shape_matching).");
  c.def_property_readonly("frame_stats", [](const PyMethod& s) {
    py::list frames;
    for (const MethodStats& stats : s.frames) frames.append(StatsToDict(stats));
    return frames;
  }, "The statistics of every successful frame since set_handles (dicts as Deformer.last_stats).");
  c.def_property_readonly("last_stats", [](const PyMethod& s) -> py::object {
    if (s.frames.empty()) return py::none();
    return StatsToDict(s.frames.back());
  }, "The last successful frame's statistics as a dict; None before the first frame.");
  c.def_property_readonly("failed_frames", [](const PyMethod& s) { return s.failed_frames; },
                          "1-based frames of the last drag_along whose solve failed.");
}

}  // namespace python
}  // namespace msdeform
