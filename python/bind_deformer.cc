// The Deformer (scales/deformer.h) as a Python class: Init in the
// constructor, SetHandles from a status array or a .sel file, Drag and
// DragAlong returning a read-only view of the deformed vertices, and the
// method's intermediate results (e', node classes, the selected scale, the
// per-frame statistics) as arrays and dicts.
//
// The GIL is released around Init, SetHandles, Drag and DragAlong; a mutex
// makes calls on one Deformer from several threads take turns.

#include <Python.h>

#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "msdeform/core/drag_path.h"
#include "msdeform/core/scenario.h"
#include "msdeform/scales/deformer.h"
#include "msdeform/scales/scale_selection.h"
#include "python/bindings.h"

namespace msdeform {
namespace python {
namespace {

// The Deformer and what Python needs beside it: the layout it was given (the
// Deformer keeps its own private), whether SetHandles succeeded since the
// last attempt, and the statistics of the frames dragged since.
struct PyDeformer {
  Deformer deformer;
  std::mutex mutex;
  HandleLayout layout;
  bool has_handles = false;
  std::vector<DragStats> frames;
  std::vector<int> failed_frames;

  void RequireHandles() const {
    if (!has_handles) {
      ThrowRuntimeError("no handle layout: call set_handles (with a valid layout) first");
    }
  }
};

}  // namespace

py::dict StatsToDict(const DragStats& stats) {
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

namespace {

std::unique_ptr<PyDeformer> MakeDeformer(const py::object& vertices, const py::object& faces,
                                         const py::object& options, const py::kwargs& kwargs) {
  const Mesh mesh = MeshFromArrays(vertices, faces);
  const DeformerOptions resolved = DeformerOptionsFrom(options, kwargs);
  auto deformer = std::make_unique<PyDeformer>();
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    ok = deformer->deformer.Init(mesh, resolved, &error);
  }
  if (!ok) ThrowValueError(error);
  return deformer;
}

void SetHandles(PyDeformer& self, const py::object& status) {
  const int num_vertices = self.deformer.rest_mesh().num_vertices();
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
    self.has_handles = false;
    self.frames.clear();
    self.failed_frames.clear();
    ok = self.deformer.SetHandles(layout, &error);
    if (ok) {
      self.layout = std::move(layout);
      self.has_handles = true;
    }
  }
  if (!ok) ThrowValueError(error);
}

py::array_t<double> Drag(const py::object& self_object, const py::object& matrix) {
  PyDeformer& self = self_object.cast<PyDeformer&>();
  self.RequireHandles();
  const Eigen::Affine3d transform = TransformFromArray(matrix, "M");
  DragStats stats;
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(self.mutex);
    ok = self.deformer.Drag(transform, &stats, &error);
    if (ok) self.frames.push_back(std::move(stats));
  }
  if (!ok) ThrowRuntimeError(error);
  return ReadOnlyView(self.deformer.deformed_vertices(), self_object);
}

// The handle's rest centroid: the pivot of msdeform's --sel/--def drags.
Eigen::Vector3d RestCentroid(const Eigen::Matrix3Xd& rest, const std::vector<int>& vertices) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : vertices) centroid += rest.col(v);
  return centroid / static_cast<double>(vertices.size());
}

Eigen::Vector3d HandleCentroid(const PyDeformer& self) {
  self.RequireHandles();
  return RestCentroid(self.deformer.rest_mesh().vertices, self.layout.moveable);
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

}  // namespace

std::vector<Eigen::Affine3d> DragPathFrom(const Eigen::Matrix3Xd& rest,
                                          const std::vector<int>& moveable,
                                          const py::object& matrix, const py::object& frames) {
  const py::array array = py::array::ensure(matrix);
  if (array && array.ndim() == 3) {
    if (!frames.is_none()) {
      ThrowValueError("frames: give either a path of transforms (frames, 4, 4) or one "
                      "transform and frames, not both");
    }
    std::vector<Eigen::Affine3d> path;
    for (py::ssize_t f = 0; f < array.shape(0); ++f) {
      const std::string name = "path[" + std::to_string(f) + "]";
      const py::object transform = array[py::int_(f)];
      path.push_back(TransformFromArray(transform, name.c_str()));
    }
    if (path.empty()) ThrowValueError("path: no transform");
    return path;
  }
  const Eigen::Affine3d transform = TransformFromArray(matrix, "M");
  return InterpolateDragPath(transform, RestCentroid(rest, moveable), FrameCount(frames));
}

namespace {

std::vector<Eigen::Affine3d> PathFromArguments(const PyDeformer& self, const py::object& matrix,
                                               const py::object& frames) {
  self.RequireHandles();
  return DragPathFrom(self.deformer.rest_mesh().vertices, self.layout.moveable, matrix, frames);
}

py::array_t<double> DragAlongPath(const py::object& self_object, const py::object& matrix,
                                  const py::object& frames, bool continue_after_failure) {
  PyDeformer& self = self_object.cast<PyDeformer&>();
  std::vector<Eigen::Affine3d> path;
  {
    std::lock_guard<std::mutex> lock(self.mutex);
    self.RequireHandles();
    path = PathFromArguments(self, matrix, frames);
  }
  DragAlongOptions options;
  options.continue_after_failure = continue_after_failure;
  DragLog log;
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(self.mutex);
    ok = DragAlong(&self.deformer, path, options, &log, &error);
    for (DragStats& stats : log.frames) self.frames.push_back(std::move(stats));
    self.failed_frames = log.failed_frames;
  }
  if (!ok) ThrowRuntimeError(error);
  return ReadOnlyView(self.deformer.deformed_vertices(), self_object);
}

// A read-only property of the Deformer that needs the lock (and, when
// `needs_handles`, a layout).
template <typename Function>
auto Locked(Function function, bool needs_handles) {
  return [function, needs_handles](const py::object& self_object) {
    PyDeformer& self = self_object.cast<PyDeformer&>();
    std::lock_guard<std::mutex> lock(self.mutex);
    if (needs_handles) self.RequireHandles();
    return function(self_object, self);
  };
}

void BindDeformerProperties(py::class_<PyDeformer>& c) {
  c.def_property_readonly(
      "V",
      Locked([](const py::object& o, PyDeformer& s) {
        return ReadOnlyView(s.deformer.rest_mesh().vertices, o);
      }, false),
      "The rest vertices, a read-only float64 (#V, 3) view.");
  c.def_property_readonly(
      "F",
      Locked([](const py::object& o, PyDeformer& s) {
        return ReadOnlyView(s.deformer.rest_mesh().faces, o);
      }, false),
      "The faces, a read-only int32 (#F, 3) view.");
  c.def_property_readonly(
      "deformed_vertices",
      Locked([](const py::object& o, PyDeformer& s) {
        return ReadOnlyView(s.deformer.deformed_vertices(), o);
      }, false),
      "The current deformed vertices, the read-only (#V, 3) view drag() returns (the rest "
      "vertices before the first drag after set_handles).");
  c.def_property_readonly(
      "deformed_normals",
      Locked([](const py::object& o, PyDeformer& s) {
        return ReadOnlyView(s.deformer.deformed_normals(), o);
      }, false),
      "The current deformed unit vertex normals, a read-only (#V, 3) view of the Deformer's "
      "storage. drag() skins positions only; the normals are skinned when this property is "
      "read after a drag, so read it again after each drag (a view kept from before shows "
      "the old normals until then).");
  c.def_property_readonly(
      "options",
      Locked([](const py::object&, PyDeformer& s) { return s.deformer.options(); }, false),
      "A copy of the DeformerOptions this Deformer was made with.");
  c.def_property_readonly(
      "diagonal", Locked([](const py::object&, PyDeformer& s) { return s.deformer.diagonal(); },
                         false),
      "The rest mesh's bounding-box diagonal.");
  c.def_property_readonly(
      "cell_width",
      Locked([](const py::object&, PyDeformer& s) { return s.deformer.lattice().cell_width(); },
             false),
      "The lattice's cell width w.");
  c.def_property_readonly(
      "num_surface_particles",
      Locked([](const py::object&, PyDeformer& s) {
        return s.deformer.lattice().num_surface_particles();
      }, false),
      "Surface particles of the lattice, one per piece of surface in a cell (= DG1 nodes = "
      "the first particles).");
  c.def_property_readonly(
      "particle_positions",
      Locked([](const py::object&, PyDeformer& s) {
        return PositionsToArray(s.deformer.lattice().rest_positions());
      }, false),
      "Rest positions of the lattice particles (cell centres), a new (#particles, 3) array; "
      "particles 0 .. num_surface_particles - 1 are the surface particles.");
  c.def_property_readonly(
      "num_scales",
      Locked([](const py::object&, PyDeformer& s) {
        return s.deformer.options().method == Method::kMultiScale
                   ? static_cast<int>(s.deformer.graphs().size())
                   : 1;
      }, false),
      "N, the number of scales (graphs DG1..DGN) of the multi-scale method; 1 for the static "
      "baselines (as the experiment tables' scales_n).");
  c.def_property_readonly(
      "num_graphs",
      Locked([](const py::object&, PyDeformer& s) {
        return static_cast<int>(s.deformer.graphs().size());
      }, false),
      "Graphs built: DG1..DGN (multi-scale), or DG1 and the static graph.");
  c.def(
      "graph_node_positions",
      [](PyDeformer& s, int graph) {
        std::lock_guard<std::mutex> lock(s.mutex);
        const int count = static_cast<int>(s.deformer.graphs().size());
        if (graph < 1 || graph > count) {
          ThrowValueError("graph: expected 1.." + std::to_string(count) + ", got " +
                          std::to_string(graph));
        }
        return PositionsToArray(s.deformer.graphs()[graph - 1].positions);
      },
      py::arg("graph"),
      "Rest node positions g_j of graph `graph` (1-based: 1 is DG1), a new (#nodes, 3) array.");
  c.def_property_readonly(
      "precompute_ms",
      Locked([](const py::object&, PyDeformer& s) { return s.deformer.precompute_ms(); }, false),
      "Milliseconds of the constructor's lattice and graph build (Init).");
  c.def_property_readonly(
      "rigidity_ms",
      Locked([](const py::object&, PyDeformer& s) { return s.deformer.rigidity_ms(); }, true),
      "Milliseconds of set_handles's rigidity estimation (0 for the baselines).");
  c.def_property_readonly(
      "setup_ms",
      Locked([](const py::object&, PyDeformer& s) { return s.deformer.setup_ms(); }, true),
      "Milliseconds of set_handles's scale selection, classes and problem build.");

  // The handle layout and what set_handles derived from it.
  c.def_property_readonly(
      "status",
      Locked([](const py::object&, PyDeformer& s) {
        return StatusFromLayout(s.layout, s.deformer.rest_mesh().num_vertices());
      }, true),
      "The handle layout as a per-vertex status array (0 fixed, 1 free, 2 handle).");
  c.def_property_readonly(
      "handle_centroid",
      Locked([](const py::object&, PyDeformer& s) {
        const Eigen::Vector3d centroid = HandleCentroid(s);
        return py::array_t<double>(3, centroid.data());
      }, true),
      "The handle's rest centroid: the pivot of drag_along(M, frames=N).");
  c.def_property_readonly(
      "relative_extent",
      Locked([](const py::object&, PyDeformer& s) {
        return VectorToArray(s.deformer.rigidity().relative_extent);
      }, true),
      "e' (paper Eq. 5, normalised): the rigidity estimate per lattice particle, float64 "
      "(#particles,); the first num_surface_particles entries are the DG1 nodes'. Small means "
      "rigid. Empty for the static baselines.");
  c.def_property_readonly(
      "extent",
      Locked([](const py::object&, PyDeformer& s) {
        return VectorToArray(s.deformer.rigidity().extent);
      }, true),
      "e per lattice particle in mesh units (e' = e / handle_extent); empty for the baselines.");
  c.def_property_readonly(
      "handle_extent",
      Locked([](const py::object&, PyDeformer& s) { return s.deformer.rigidity().handle_extent; },
             true),
      "e_h, the moveable handle's extent in mesh units (0 for the baselines).");
  c.def_property_readonly(
      "node_extent",
      Locked([](const py::object&, PyDeformer& s) {
        const std::vector<double>& extent = s.deformer.selection().node_extent;
        return py::array_t<double>(static_cast<py::ssize_t>(extent.size()), extent.data());
      }, true),
      "e' per node of the selected scale (the max over its DG1 members by default); empty for "
      "the baselines.");
  c.def_property_readonly(
      "selection",
      Locked([](const py::object&, PyDeformer& s) {
        const ScaleSelection& selection = s.deformer.selection();
        py::dict dict;
        dict["threshold"] = selection.threshold;
        dict["group1_size"] = selection.group1_size;
        dict["eq6_scale"] = selection.eq6_scale;
        dict["scale"] = selection.scale;
        dict["local_detail_edit"] = selection.local_detail_edit;
        dict["num_pinned"] = selection.num_pinned;
        return dict;
      }, true),
      "The multi-scale scale selection as a dict: threshold (T, Eq. 7), group1_size (P1), "
      "eq6_scale (s of Eq. 6), scale (after conflicts), local_detail_edit, num_pinned (nodes "
      "kept Fixed because they skin a fixed vertex). Zeros for the baselines.");
  c.def_property_readonly(
      "fixed_region_exact",
      Locked([](const py::object&, PyDeformer& s) { return s.deformer.fixed_region_exact(); },
             true),
      "Whether every fixed-handle vertex is skinned only by Fixed nodes, so that it stays "
      "exactly at rest (the multi-scale default; not the static baselines).");
  c.def_property_readonly(
      "selected_scale",
      Locked([](const py::object&, PyDeformer& s) { return s.deformer.active_graph() + 1; },
             true),
      "The 1-based index of the graph solved on (the selected scale s for multi-scale; "
      "graph_node_positions(selected_scale) == node_positions).");
  c.def_property_readonly(
      "node_positions",
      Locked([](const py::object&, PyDeformer& s) {
        return PositionsToArray(s.deformer.active().positions);
      }, true),
      "Rest node positions g_j of the selected scale's graph, a new (#nodes, 3) array.");
  c.def_property_readonly(
      "node_classes",
      Locked([](const py::object&, PyDeformer& s) {
        std::vector<int> classes;
        for (NodeClass c : s.deformer.node_classes()) classes.push_back(static_cast<int>(c));
        return IdsToArray(classes);
      }, true),
      "Class per node of the selected scale as int32: 0 fixed, 1 half_free, 2 totally_free "
      "(msdeform.NODE_CLASSES[c] names class c).");
  c.def_property_readonly(
      "node_rotations",
      Locked([](const py::object&, PyDeformer& s) {
        const NodeTransforms& transforms = s.deformer.transforms();
        py::array_t<double> rotations(
            {static_cast<py::ssize_t>(transforms.num_nodes()), py::ssize_t{3}, py::ssize_t{3}});
        auto out = rotations.mutable_unchecked<3>();
        for (int j = 0; j < transforms.num_nodes(); ++j) {
          for (int r = 0; r < 3; ++r) {
            for (int col = 0; col < 3; ++col) out(j, r, col) = transforms.rotation(j)(r, col);
          }
        }
        return rotations;
      }, true),
      "R_j of the selected scale's nodes after the last drag, a new (#nodes, 3, 3) array.");
  c.def_property_readonly(
      "node_translations",
      Locked([](const py::object&, PyDeformer& s) {
        return PositionsToArray(s.deformer.transforms().translations);
      }, true),
      "t_j of the selected scale's nodes after the last drag, a new (#nodes, 3) array.");
  c.def_property_readonly(
      "num_variables",
      Locked([](const py::object&, PyDeformer& s) { return s.deformer.num_variables(); }, true),
      "Variables optimised: 12 per Totally Free node + 9 per Half Free node.");
  c.def_property_readonly(
      "num_coherence_terms",
      Locked([](const py::object&, PyDeformer& s) { return s.deformer.num_coherence_terms(); },
             true),
      "Directed coherence terms E(j, k) in the energy.");
  c.def_property_readonly(
      "num_position_terms",
      Locked([](const py::object&, PyDeformer& s) { return s.deformer.num_position_terms(); },
             true),
      "Position terms of the moveable handle (one per handle vertex).");
  c.def_property_readonly(
      "num_skinned_vertices",
      Locked([](const py::object&, PyDeformer& s) { return s.deformer.num_skinned_vertices(); },
             true),
      "Vertices drag() moves (the others stay at rest exactly).");

  // Per-frame statistics.
  c.def_property_readonly(
      "last_stats",
      Locked([](const py::object&, PyDeformer& s) -> py::object {
        if (s.frames.empty()) return py::none();
        return StatsToDict(s.frames.back());
      }, true),
      "The last successful frame's statistics as a dict (frame_ms, solve_ms, skin_ms, "
      "iterations, factorizations, initial_cost, final_cost, converged, and trace: the solve's "
      "(ms, cost) points as a (#points, 2) array); None before the first frame.");
  c.def_property_readonly(
      "frame_stats",
      Locked([](const py::object&, PyDeformer& s) {
        py::list frames;
        for (const DragStats& stats : s.frames) frames.append(StatsToDict(stats));
        return frames;
      }, true),
      "The statistics of every successful frame since set_handles, in order (dicts as "
      "last_stats).");
  c.def_property_readonly(
      "failed_frames",
      Locked([](const py::object&, PyDeformer& s) { return s.failed_frames; }, true),
      "1-based frames of the last drag_along whose solve failed (they kept the previous pose).");
}

}  // namespace

void BindDeformer(py::module_& m) {
  py::class_<PyDeformer> c(
      m, "Deformer",
      "The multi-scale deformer of Liu & Su 2008, or a single-static-graph baseline "
      "(scales/deformer.h):\n\n"
      "    d = msdeform.Deformer(V, F, method='multiscale')  # lattice, graphs\n"
      "    d.set_handles(status)    # rigidity, scale, node classes\n"
      "    V2 = d.drag(M)           # one frame, warm-started\n\n"
      "Not copyable. Calls from several threads take turns; the GIL is released while it works.");
  c.def(py::init(&MakeDeformer), py::arg("V"), py::arg("F"), py::arg("options") = py::none(),
        "Deformer(V, F, options=None, **kwargs)\n\n"
        "Builds everything that depends only on the mesh: V float64 (#V, 3) (any real dtype, "
        "converted), F (#F, 3) of any integer dtype. `options` is a DeformerOptions (or a dict "
        "of its fields); keyword arguments set DeformerOptions fields on top of it "
        "(method='static', w_con=1e3, stopping={'max_iterations': 5}, ...). Raises TypeError "
        "for an unknown keyword or a wrong dtype, ValueError for a wrong shape, an out-of-range "
        "face index (the C++ ValidateMesh message) or an invalid option (the C++ "
        "DeformerOptions::Check message).");
  c.def("set_handles", &SetHandles, py::arg("status"),
        "Sets the handle layout from a per-vertex status array (0 fixed, 1 free, 2 handle; "
        "length #V) or the path of a .sel file: rigidity estimation, scale selection and node "
        "classes (multi-scale), and the solver's problem. Resets the deformation to the rest "
        "pose and the frame statistics. Raises ValueError for a bad array or layout (the C++ "
        "message, e.g. 'the moveable handle has no vertex') and OSError for a bad .sel file; "
        "after a failure, drag raises until a layout is set.");
  c.def("drag", &Drag, py::arg("M"),
        "Moves the handle to M @ (its rest positions) (M: 4x4 with last row 0 0 0 1, or 3x4), "
        "solves warm-started from the previous frame and skins the mesh. Returns the deformed "
        "vertices as a read-only float64 (#V, 3) view of the Deformer's own storage (no copy); "
        "the view keeps the Deformer alive, and the next drag or drag_along updates it in "
        "place: use .copy() to keep a frame. Raises RuntimeError before set_handles and when "
        "the solve fails (the C++ message; the previous pose is kept).");
  c.def("drag_along", &DragAlongPath, py::arg("M"), py::arg("frames") = py::none(),
        py::arg("continue_after_failure") = false,
        "Drags through a path with the C++ DragAlong, the loop of the msdeform command line and "
        "the experiment runner. M is either one transform, dragged to in `frames` equal steps "
        "(default 1) about the handle's rest centroid as msdeform --sel/--def --frames=N does "
        "(msdeform.drag_path), or a (frames, 4, 4) array of transforms (then frames must be "
        "None). continue_after_failure: a failed intermediate frame keeps the last good pose "
        "and the drag goes on (the command line's behaviour); otherwise the first failure "
        "raises. Returns the same view as drag(); frame_stats gains every frame's statistics "
        "and failed_frames lists the failed ones. Raises RuntimeError with 'frame F of N: ...' "
        "on failure.");
  c.def(
      "drag_path",
      [](PyDeformer& self, const py::object& matrix, const py::object& frames) {
        std::lock_guard<std::mutex> lock(self.mutex);
        self.RequireHandles();
        return TransformsToArray(PathFromArguments(self, matrix, frames));
      },
      py::arg("M"), py::arg("frames"),
      "The (frames, 4, 4) path drag_along(M, frames=frames) drags through.");
  BindDeformerProperties(c);

  py::list names;
  for (NodeClass node_class : {NodeClass::kFixed, NodeClass::kHalfFree, NodeClass::kTotallyFree}) {
    names.append(NodeClassName(node_class));
  }
  m.attr("NODE_CLASSES") = py::tuple(names);
}

}  // namespace python
}  // namespace msdeform
