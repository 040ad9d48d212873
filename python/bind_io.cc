// Mesh, .sel and .def files (core/mesh_io.h, core/handles.h) and the drag
// path (core/drag_path.h) on NumPy arrays. Files that cannot be read or
// written raise OSError with the C++ message (it names the file, the line
// and the problem); arrays that are wrong before any file is touched raise
// TypeError or ValueError.

#include <Python.h>

#include <limits>
#include <string>
#include <vector>

#include "msdeform/core/drag_path.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/scenario.h"
#include "python/bindings.h"

namespace msdeform {
namespace python {
namespace {

py::object ReadMeshFile(const py::object& path_object, bool with_report) {
  const std::string path = PathFromObject(path_object, "path");
  Mesh mesh;
  MeshReadReport report;
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    ok = ReadMesh(path, &mesh, &report, &error);
  }
  if (!ok) ThrowOSError(error);
  py::tuple result = py::make_tuple(PositionsToArray(mesh.vertices), FacesToArray(mesh.faces));
  if (!with_report) return std::move(result);
  py::dict dropped;
  dropped["dropped_degenerate_faces"] = report.dropped_degenerate_faces;
  dropped["dropped_duplicate_faces"] = report.dropped_duplicate_faces;
  dropped["notice"] = report.notice;
  return py::make_tuple(result[0], result[1], dropped);
}

void WriteMeshFile(const py::object& path_object, const py::object& vertices,
                   const py::object& faces) {
  const std::string path = PathFromObject(path_object, "path");
  const Mesh mesh = MeshFromArrays(vertices, faces);
  ValidateOrThrow(mesh);
  std::string error;
  bool ok;
  {
    py::gil_scoped_release release;
    ok = WriteMesh(path, mesh, &error);
  }
  if (!ok) ThrowOSError(error);
}

py::array_t<int> ReadSelFile(const py::object& path_object, const py::object& count) {
  const std::string path = PathFromObject(path_object, "path");
  if (count.is_none()) {
    // The file's own count: one status a vertex.
    HandleLayout layout;
    int num_vertices = 0;
    std::string error;
    if (!ReadSel(path, &layout, &num_vertices, &error)) ThrowOSError(error);
    return StatusFromLayout(layout, num_vertices);
  }
  // Python's int or anything with __index__ (NumPy integers), never a bool.
  PyObject* index = PyBool_Check(count.ptr()) ? nullptr : PyNumber_Index(count.ptr());
  if (index == nullptr) {
    PyErr_Clear();
    ThrowTypeError("num_vertices: expected an integer (the mesh's vertex count) or None, got " +
                   std::string(py::repr(count)));
  }
  const py::int_ value = py::reinterpret_steal<py::int_>(index);
  if (value < py::int_(1) || value > py::int_(std::numeric_limits<int>::max())) {
    ThrowValueError("num_vertices: expected a vertex count >= 1, got " +
                    std::string(py::repr(value)));
  }
  const int num_vertices = value.cast<int>();
  HandleLayout layout;
  std::string error;
  if (!ReadSel(path, num_vertices, &layout, &error)) ThrowOSError(error);
  return StatusFromLayout(layout, num_vertices);
}

void WriteSelFile(const py::object& path_object, const py::object& status) {
  const std::string path = PathFromObject(path_object, "path");
  // The count is the array's length; LayoutFromStatus checks the rest.
  const py::array array = py::array::ensure(status);
  if (!array) PyErr_Clear();
  const int num_vertices = array && array.ndim() == 1 ? static_cast<int>(array.shape(0)) : 0;
  const HandleLayout layout = LayoutFromStatus(status, num_vertices, "status");
  std::string error;
  if (!ValidateHandles(layout, num_vertices, &error)) ThrowValueError("status: " + error);
  if (!WriteSel(path, layout, num_vertices, &error)) ThrowOSError(error);
}

py::array_t<double> ReadDefFile(const py::object& path_object) {
  const std::string path = PathFromObject(path_object, "path");
  Eigen::Affine3d transform;
  std::string error;
  if (!ReadDef(path, &transform, &error)) ThrowOSError(error);
  return TransformToArray(transform);
}

void WriteDefFile(const py::object& path_object, const py::object& matrix) {
  const std::string path = PathFromObject(path_object, "path");
  const Eigen::Affine3d transform = TransformFromArray(matrix, "M");
  std::string error;
  if (!WriteDef(path, transform, &error)) ThrowOSError(error);
}

py::array_t<double> DragPathOf(const py::object& matrix, const py::object& pivot, int frames) {
  const Eigen::Affine3d transform = TransformFromArray(matrix, "M");
  const py::array pivot_array = py::array::ensure(pivot);
  if (!pivot_array || pivot_array.size() != 3) {
    PyErr_Clear();
    ThrowValueError("pivot: expected 3 numbers");
  }
  const Eigen::Matrix3Xd point =
      PositionsFromArray(pivot_array.attr("reshape")(1, 3), "pivot");
  if (!point.allFinite()) ThrowValueError("pivot: not finite");
  if (frames < 1 || frames > kMaxScenarioFrames) {
    ThrowValueError("frames: expected 1.." + std::to_string(kMaxScenarioFrames) + ", got " +
                    std::to_string(frames));
  }
  return TransformsToArray(InterpolateDragPath(transform, point.col(0), frames));
}

}  // namespace

void BindIo(py::module_& m) {
  m.def("read_mesh", &ReadMeshFile, py::arg("path"), py::arg("with_report") = false,
        "Reads a triangle mesh (.off, .obj, .ply, .stl; docs/formats.md) and returns (V, F): "
        "V float64 (#V, 3), F int32 (#F, 3), both new arrays, vertex i being the file's vertex "
        "i. Coordinates are read exactly (a float in the file, as in STL, widened): what "
        "write_mesh wrote reads back bit for bit. Triangles that repeat a vertex and "
        "exact duplicates are dropped; with with_report=True the result is (V, F, report), "
        "report a dict with dropped_degenerate_faces, dropped_duplicate_faces and notice. "
        "Raises OSError with the C++ message (file, line, problem) on any failure.");
  m.def("write_mesh", &WriteMeshFile, py::arg("path"), py::arg("V"), py::arg("F"),
        "Writes V (#V, 3) and F (#F, 3) to path (.off, .obj or .ply by extension; "
        "every coordinate exact: the shortest decimal of each double in .off and .obj, binary "
        "doubles in .ply) atomically: a failed write leaves no file. Raises "
        "TypeError/ValueError for bad arrays (ValueError with the C++ ValidateMesh message for "
        "out-of-range face indices, non-finite coordinates, ...) and OSError when the file "
        "cannot be written or the extension is not one of those.");
  m.def("read_sel", &ReadSelFile, py::arg("path"), py::arg("num_vertices") = py::none(),
        "Reads a Botsch-Sorkine .sel file and returns the status per vertex as an int32 array: "
        "0 fixed, 1 free, 2 handle. The file has one status a vertex; num_vertices (the mesh's "
        "vertex count, len(V)) checks that it is the mesh's, None takes the file's count. "
        "Raises OSError with the C++ message (file, line, problem): unreadable file, a bad "
        "line or status, a count other than num_vertices, no handle vertex; TypeError or "
        "ValueError for a num_vertices that is not a count >= 1.");
  m.def("write_sel", &WriteSelFile, py::arg("path"), py::arg("status"),
        "Writes a .sel file from a status array (0 fixed, 1 free, 2 handle; one per vertex) "
        "atomically. Raises ValueError for a bad status array (a value outside 0..2, no "
        "handle vertex) and OSError when the file cannot be written.");
  m.def("read_def", &ReadDefFile, py::arg("path"),
        "Reads a .def file: the handle transform as a float64 4x4 array (world coordinates, "
        "last row 0 0 0 1). Raises OSError with the C++ message on any failure.");
  m.def("write_def", &WriteDefFile, py::arg("path"), py::arg("M"),
        "Writes a 4x4 (last row 0 0 0 1) or 3x4 affine transform as a .def file with full "
        "double precision, atomically. Raises ValueError for a bad transform and OSError when "
        "the file cannot be written.");
  m.def("drag_path", &DragPathOf, py::arg("M"), py::arg("pivot"), py::arg("frames"),
        "The drag from the identity to M in `frames` equal steps about `pivot` (3 numbers, "
        "the handle's rest centroid for msdeform's --sel/--def drags) as a (frames, 4, 4) "
        "array; the last equals M (core/drag_path.h: the polar rotation of M slerped, the rest "
        "of M (scale, shear) blended linearly, the pivot moved on a straight line).");
  m.def(
      "bounding_box_diagonal",
      [](const py::object& vertices) {
        Mesh mesh;
        mesh.vertices = PositionsFromArray(vertices, "V");
        return BoundingBoxDiagonal(mesh);
      },
      py::arg("V"),
      "Length of the bounding-box diagonal of V (#V, 3): the unit of every '_rel' number.");
}

}  // namespace python
}  // namespace msdeform
