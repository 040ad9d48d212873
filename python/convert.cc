// NumPy arrays to and from msdeform's types, and the exceptions
// (python/bindings.h).

#include <Python.h>

#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "python/bindings.h"

namespace msdeform {
namespace python {
namespace {

using Int64Array = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>;
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

[[noreturn]] void Throw(PyObject* type, const std::string& message) {
  PyErr_SetString(type, message.c_str());
  throw py::error_already_set();
}

std::string ShapeOf(const py::array& array) {
  std::ostringstream shape;
  shape << "(";
  for (py::ssize_t d = 0; d < array.ndim(); ++d) {
    shape << (d > 0 ? ", " : "") << array.shape(d);
  }
  shape << (array.ndim() == 1 ? ",)" : ")");
  return shape.str();
}

// The argument as a NumPy array (array-likes such as lists are converted),
// checked to hold numbers of the given kinds ("fiu": float, signed, unsigned).
py::array NumericArray(const py::handle& object, const char* name, const char* kinds,
                       const char* expected) {
  py::array array = py::array::ensure(object);
  if (!array) {
    PyErr_Clear();
    ThrowTypeError(std::string(name) + ": expected an array of " + expected + ", got " +
                   std::string(py::str(py::type::handle_of(object).attr("__name__"))));
  }
  // An empty list becomes a float64 array: an empty array of any kind is fine.
  const char kind = array.dtype().kind();
  if (array.size() > 0 && std::strchr(kinds, kind) == nullptr) {
    ThrowTypeError(std::string(name) + ": expected an array of " + expected + ", got dtype " +
                   std::string(py::str(array.dtype())));
  }
  return array;
}

void CheckShape(const py::array& array, const char* name, int columns, const char* expected) {
  if (array.ndim() != 2 || array.shape(1) != columns) {
    ThrowValueError(std::string(name) + ": expected an array of shape " + expected + ", got shape " +
                    ShapeOf(array));
  }
}

// Integers of any dtype as int64 (1-D or 2-D), each checked to fit an int.
Int64Array IntArray(const py::handle& object, const char* name) {
  py::array array = NumericArray(object, name, "iu", "integers");
  Int64Array ints = Int64Array::ensure(array);
  if (!ints) throw py::error_already_set();
  const std::int64_t* data = ints.data();
  for (py::ssize_t i = 0; i < ints.size(); ++i) {
    if (data[i] < std::numeric_limits<int>::min() || data[i] > std::numeric_limits<int>::max()) {
      ThrowValueError(std::string(name) + ": value " + std::to_string(data[i]) +
                      " at flat index " + std::to_string(i) + " does not fit a C++ int");
    }
  }
  return ints;
}

// A new C-order array of the given shape, filled from `data`.
template <typename T>
py::array_t<T> NewArray(std::vector<py::ssize_t> shape, const T* data) {
  py::array_t<T> array(shape);
  if (array.size() > 0) std::memcpy(array.mutable_data(), data, array.size() * sizeof(T));
  return array;
}

template <typename T>
py::array_t<T> View(std::vector<py::ssize_t> shape, const T* data, const py::handle& owner) {
  py::array_t<T> array(shape, data, owner);
  py::detail::array_proxy(array.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return array;
}

}  // namespace

void ThrowValueError(const std::string& message) { Throw(PyExc_ValueError, message); }
void ThrowTypeError(const std::string& message) { Throw(PyExc_TypeError, message); }
void ThrowOSError(const std::string& message) { Throw(PyExc_OSError, message); }
void ThrowRuntimeError(const std::string& message) { Throw(PyExc_RuntimeError, message); }
void ThrowAttributeError(const std::string& message) { Throw(PyExc_AttributeError, message); }

bool IsPathLike(const py::handle& object) {
  return py::isinstance<py::str>(object) || py::isinstance<py::bytes>(object) ||
         py::hasattr(object, "__fspath__");
}

std::string PathFromObject(const py::handle& path, const char* name) {
  if (!IsPathLike(path)) {
    ThrowTypeError(std::string(name) + ": expected a path (str or os.PathLike), got " +
                   std::string(py::str(py::type::handle_of(path).attr("__name__"))));
  }
  py::object fspath = py::module_::import("os").attr("fsdecode")(path);
  return fspath.cast<std::string>();
}

Eigen::Matrix3Xd PositionsFromArray(const py::handle& object, const char* name) {
  py::array array = NumericArray(object, name, "fiu", "real numbers");
  CheckShape(array, name, 3, "(n, 3)");
  DoubleArray values = DoubleArray::ensure(array);
  if (!values) throw py::error_already_set();
  Eigen::Matrix3Xd positions(3, values.shape(0));
  // C-order (n, 3) is column-major 3 by n.
  if (positions.size() > 0) {
    std::memcpy(positions.data(), values.data(), positions.size() * sizeof(double));
  }
  return positions;
}

Eigen::VectorXd ValuesFromArray(const py::handle& object, const char* name) {
  py::array array = NumericArray(object, name, "fiu", "real numbers");
  if (array.ndim() != 1) {
    ThrowValueError(std::string(name) + ": expected a 1-D array, got shape " + ShapeOf(array));
  }
  DoubleArray values = DoubleArray::ensure(array);
  if (!values) throw py::error_already_set();
  return Eigen::Map<const Eigen::VectorXd>(values.data(), values.size());
}

Eigen::Matrix3Xi FacesFromArray(const py::handle& object, const char* name) {
  py::array array = NumericArray(object, name, "iu", "integers");
  CheckShape(array, name, 3, "(m, 3)");
  Int64Array ints = IntArray(array, name);
  Eigen::Matrix3Xi faces(3, ints.shape(0));
  const std::int64_t* data = ints.data();
  for (Eigen::Index i = 0; i < faces.size(); ++i) faces.data()[i] = static_cast<int>(data[i]);
  return faces;
}

Mesh MeshFromArrays(const py::handle& vertices, const py::handle& faces) {
  Mesh mesh;
  mesh.vertices = PositionsFromArray(vertices, "V");
  mesh.faces = FacesFromArray(faces, "F");
  return mesh;
}

void ValidateOrThrow(const Mesh& mesh) {
  std::string error;
  if (!ValidateMesh(mesh, &error)) ThrowValueError(error);
}

Eigen::Affine3d TransformFromArray(const py::handle& object, const char* name) {
  py::array array = NumericArray(object, name, "fiu", "real numbers");
  if (array.ndim() != 2 || (array.shape(0) != 4 && array.shape(0) != 3) || array.shape(1) != 4) {
    ThrowValueError(std::string(name) + ": expected a 4x4 or 3x4 affine transform, got shape " +
                    ShapeOf(array));
  }
  DoubleArray values = DoubleArray::ensure(array);
  if (!values) throw py::error_already_set();
  auto m = values.unchecked<2>();
  Eigen::Affine3d transform = Eigen::Affine3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) transform.matrix()(r, c) = m(r, c);
  }
  if (array.shape(0) == 4 && !(m(3, 0) == 0.0 && m(3, 1) == 0.0 && m(3, 2) == 0.0 &&
                               m(3, 3) == 1.0)) {
    std::ostringstream row;
    row.precision(17);
    row << m(3, 0) << " " << m(3, 1) << " " << m(3, 2) << " " << m(3, 3);
    ThrowValueError(std::string(name) + ": the last row of a 4x4 affine transform must be "
                    "0 0 0 1, got " + row.str());
  }
  if (!transform.matrix().allFinite()) {
    ThrowValueError(std::string(name) + ": the transform is not finite");
  }
  return transform;
}

std::vector<int> IdsFromArray(const py::handle& object, int size, const char* name) {
  Int64Array ints = IntArray(object, name);
  if (ints.ndim() != 1) {
    ThrowValueError(std::string(name) + ": expected a 1-D array of vertex ids, got shape " +
                    ShapeOf(ints));
  }
  std::vector<int> ids(ints.data(), ints.data() + ints.size());
  for (int id : ids) {
    if (id < 0 || id >= size) {
      ThrowValueError(std::string(name) + ": vertex id " + std::to_string(id) + " is outside 0.." +
                      std::to_string(size - 1));
    }
  }
  return ids;
}

HandleLayout LayoutFromStatus(const py::handle& object, int num_vertices, const char* name) {
  Int64Array status = IntArray(object, name);
  if (status.ndim() != 1) {
    ThrowValueError(std::string(name) + ": expected a 1-D array of per-vertex statuses, got shape " +
                    ShapeOf(status));
  }
  if (status.size() != num_vertices) {
    ThrowValueError(std::string(name) + ": " + std::to_string(status.size()) +
                    " statuses for a mesh of " + std::to_string(num_vertices) + " vertices");
  }
  HandleLayout layout;
  const std::int64_t* data = status.data();
  std::int64_t largest = 2;
  for (int v = 0; v < num_vertices; ++v) {
    const std::int64_t s = data[v];
    if (s == 0) {
      layout.fixed.push_back(v);
    } else if (s >= 2 && s < 2 + kMaxHandleGroups) {
      layout.moveable.push_back(v);
      layout.group.push_back(static_cast<int>(s - 2));
      largest = std::max(largest, s);
    } else if (s != 1) {
      ThrowValueError(std::string(name) + ": vertex " + std::to_string(v) + " has status " +
                      std::to_string(s) + "; expected 0 (fixed), 1 (free) or 2.." +
                      std::to_string(1 + kMaxHandleGroups) + " (handle group status - 2)");
    }
  }
  if (largest == 2) {
    layout.group.clear();  // one group
  } else {
    std::vector<char> used(largest - 1, 0);
    for (int g : layout.group) used[g] = 1;
    for (size_t g = 0; g < used.size(); ++g) {
      if (!used[g]) {
        ThrowValueError(std::string(name) + ": no vertex has status " + std::to_string(g + 2) +
                        " (handle group " + std::to_string(g) + "), but " +
                        std::to_string(largest) + " is used: number the groups 2, 3, ... "
                        "without gaps");
      }
    }
  }
  return layout;
}

py::array_t<double> PositionsToArray(const Eigen::Matrix3Xd& positions) {
  return NewArray<double>({positions.cols(), 3}, positions.data());
}

py::array_t<int> FacesToArray(const Eigen::Matrix3Xi& faces) {
  return NewArray<int>({faces.cols(), 3}, faces.data());
}

py::array_t<int> IdsToArray(const std::vector<int>& ids) {
  return NewArray<int>({static_cast<py::ssize_t>(ids.size())}, ids.data());
}

py::array_t<int> StatusFromLayout(const HandleLayout& layout, int num_vertices) {
  std::vector<int> status(num_vertices, 1);
  for (int v : layout.fixed) status[v] = 0;
  for (int i = 0; i < static_cast<int>(layout.moveable.size()); ++i) {
    status[layout.moveable[i]] = 2 + layout.group_of(i);
  }
  return IdsToArray(status);
}

py::array_t<double> TransformToArray(const Eigen::Affine3d& transform) {
  const Eigen::Matrix<double, 4, 4, Eigen::RowMajor> rows = transform.matrix();
  return NewArray<double>({4, 4}, rows.data());
}

py::array_t<double> TransformsToArray(const std::vector<Eigen::Affine3d>& transforms) {
  py::array_t<double> array({static_cast<py::ssize_t>(transforms.size()), py::ssize_t{4},
                             py::ssize_t{4}});
  auto out = array.mutable_unchecked<3>();
  for (size_t f = 0; f < transforms.size(); ++f) {
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) out(f, r, c) = transforms[f].matrix()(r, c);
    }
  }
  return array;
}

// One frame's handle transforms named `name` in errors: a 4x4 (or 3x4) that
// every handle group follows, or, for a layout of G > 1 groups, a (G, 4, 4)
// array, one a group.
HandleTransforms FrameFromArray(const py::handle& matrix, const char* name, int num_groups) {
  const py::array array = py::array::ensure(matrix);
  if (num_groups > 1 && array && array.ndim() == 3 && array.shape(0) != 1) {
    if (array.shape(0) != num_groups) {
      ThrowValueError(std::string(name) + ": " + std::to_string(array.shape(0)) +
                      " transforms for a layout of " + std::to_string(num_groups) +
                      " handle groups (give one 4x4, or one a group)");
    }
    std::vector<Eigen::Affine3d> transforms;
    for (int g = 0; g < num_groups; ++g) {
      const std::string at = std::string(name) + "[" + std::to_string(g) + "]";
      transforms.push_back(TransformFromArray(array[py::int_(g)], at.c_str()));
    }
    return HandleTransforms(std::move(transforms));
  }
  if (num_groups > 1 && array && array.ndim() == 3) {  // (1, 4, 4): one for all
    return TransformFromArray(array[py::int_(0)], name);
  }
  return TransformFromArray(matrix, name);
}

// A path: frames stacked on a first axis, (frames, 4, 4) for a layout of one
// handle group, (frames, G, 4, 4) for G > 1; frame f named `name`[f] in
// errors. False (nothing read) when `matrix` is one frame.
bool PathFromArray(const py::object& matrix, const char* name, int num_groups,
                   std::vector<HandleTransforms>* path) {
  const py::array array = py::array::ensure(matrix);
  if (!array || array.ndim() != (num_groups > 1 ? 4 : 3)) return false;
  for (py::ssize_t f = 0; f < array.shape(0); ++f) {
    const std::string frame = std::string(name) + "[" + std::to_string(f) + "]";
    path->push_back(FrameFromArray(array[py::int_(f)], frame.c_str(), num_groups));
  }
  if (path->empty()) ThrowValueError(std::string(name) + ": no transform");
  return true;
}

py::array_t<double> HandlePathToArray(const std::vector<HandleTransforms>& path,
                                      int num_groups) {
  if (num_groups == 1) {
    std::vector<Eigen::Affine3d> transforms;
    for (const HandleTransforms& frame : path) transforms.push_back(frame[0]);
    return TransformsToArray(transforms);
  }
  py::array_t<double> array({static_cast<py::ssize_t>(path.size()),
                             static_cast<py::ssize_t>(num_groups), py::ssize_t{4}, py::ssize_t{4}});
  auto out = array.mutable_unchecked<4>();
  for (size_t f = 0; f < path.size(); ++f) {
    for (int g = 0; g < num_groups; ++g) {
      for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) out(f, g, r, c) = path[f][g].matrix()(r, c);
      }
    }
  }
  return array;
}

py::array_t<double> VectorToArray(const Eigen::VectorXd& values) {
  return NewArray<double>({values.size()}, values.data());
}

py::array_t<double> ReadOnlyView(const Eigen::Matrix3Xd& positions, const py::handle& owner) {
  return View<double>({positions.cols(), 3}, positions.data(), owner);
}

py::array_t<int> ReadOnlyView(const Eigen::Matrix3Xi& faces, const py::handle& owner) {
  return View<int>({faces.cols(), 3}, faces.data(), owner);
}

}  // namespace python
}  // namespace msdeform
