// The Python class msdeform.Method: any registered editing method
// (methods/registry.h) by name, through the one interface (methods/method.h).
// bind_method.cc binds what every method has (construction, set_handles, the
// one drag loop, statistics, the rest mesh, timings, the lattice);
// bind_method_graph.cc the deformation-graph methods' intermediate results
// (e', scales, node classes, transforms), which raise AttributeError naming
// the method for a method that is not a graph.
//
// The GIL is released around Precompute, SetHandles and the drags; a mutex
// makes calls on one Method from several threads take turns.

#ifndef MSDEFORM_PYTHON_METHOD_OBJECT_H_
#define MSDEFORM_PYTHON_METHOD_OBJECT_H_

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "msdeform/methods/graph_method.h"
#include "msdeform/methods/method.h"
#include "msdeform/methods/polish.h"
#include "python/bindings.h"

namespace msdeform {
namespace python {

struct PyMethod {
  std::unique_ptr<EditingMethod> method;
  bool graph = false;  // the descriptor's: method->graph_method() is not null
  std::mutex mutex;
  Mesh rest;                 // V and F as given: drag_along's pivot, the normals' faces
  DeformerOptions options;   // as resolved (a graph method's with its method set)
  HandleLayout layout;       // the last layout set_handles accepted
  std::vector<MethodStats> frames;  // every successful frame since set_handles
  std::vector<int> failed_frames;   // of the last drag or drag_along, 1-based
  Eigen::Matrix3Xd normals;  // deformed_normals of a method that is not a graph
  // The last successful frame's handle transforms (identity after set_handles),
  // or, after a drag to vertex targets (last_is_targets), those targets.
  HandleTransforms last_transform;
  bool last_is_targets = false;
  Eigen::Matrix3Xd last_targets;
  // polish(): set up on the first call for a layout (polisher_layout_set);
  // `polished` replaces the method's frame as the deformed vertices until the
  // next drag or set_handles (`is_polished`).
  Polisher polisher;
  bool polisher_layout_set = false;
  Eigen::Matrix3Xd polished;
  bool is_polished = false;

  const std::string& name() const { return method->name(); }
  // What deformed_vertices, drag and drag_along show: the polished mesh
  // after polish(), else the method's own frame.
  const Eigen::Matrix3Xd& shown() const {
    return is_polished ? polished : method->deformed_vertices();
  }
  // RuntimeError "<name>: no handle layout: call set_handles ..." unless a
  // layout is set.
  void RequireHandles() const;
  // The GraphMethod of a graph method; AttributeError naming `member` and the
  // method for a method that is not a deformation graph.
  const GraphMethod& Graph(const char* member) const;
};

// A read-only member of a Method: `function(self_object, self)` under the
// lock, after RequireHandles when `needs_handles`.
template <typename Function>
auto Locked(Function function, bool needs_handles) {
  return [function, needs_handles](const py::object& self_object) {
    PyMethod& self = self_object.cast<PyMethod&>();
    std::lock_guard<std::mutex> lock(self.mutex);
    if (needs_handles) self.RequireHandles();
    return function(self_object, self);
  };
}

// The graph methods' members of `c` and msdeform.NODE_CLASSES
// (bind_method_graph.cc).
void BindGraphMembers(py::module_& m, py::class_<PyMethod>& c);

}  // namespace python
}  // namespace msdeform

#endif  // MSDEFORM_PYTHON_METHOD_OBJECT_H_
