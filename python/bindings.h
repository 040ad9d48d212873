// Shared pieces of the Python module _msdeform (python/module.cc): the
// conversions between NumPy arrays and msdeform's types, the Python
// exceptions the C++ error strings become, and one Bind* function per file.
//
// Arrays: vertices are float64 (#V, 3) (row i = vertex i), faces int32
// (#F, 3), vertex id lists 1-D integer arrays, transforms 4x4 (or 3x4)
// float64. msdeform stores positions as Eigen::Matrix3Xd, column-major 3 by
// #V, which is the same memory as a C-order (#V, 3) array, so views need no
// copy.
//
// Errors (README.md, "Python"): a wrong dtype raises TypeError; a wrong shape
// or value (an array, an option, a handle layout) ValueError; a file that
// cannot be read or written OSError; a failed solve RuntimeError; a graph
// accessor of a method that is not a deformation graph AttributeError. Each
// carries the C++ message unchanged where the C++ gives one.

#ifndef MSDEFORM_PYTHON_BINDINGS_H_
#define MSDEFORM_PYTHON_BINDINGS_H_

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/scales/deformer_options.h"

namespace msdeform {
namespace python {

namespace py = pybind11;

// One per file, called by module.cc in this order (options before the
// classes whose methods take them).
void BindIo(py::module_& m);
void BindOptions(py::module_& m);
void BindMethod(py::module_& m);
void BindExperiments(py::module_& m);
void BindFlags(py::module_& m);

// Raise the Python exception with `message` as it is.
[[noreturn]] void ThrowValueError(const std::string& message);
[[noreturn]] void ThrowTypeError(const std::string& message);
[[noreturn]] void ThrowOSError(const std::string& message);
[[noreturn]] void ThrowRuntimeError(const std::string& message);
// A member that the object's method does not have (a graph accessor of a
// method that is not a deformation graph).
[[noreturn]] void ThrowAttributeError(const std::string& message);

// A str or os.PathLike as a path; TypeError naming `name` otherwise.
std::string PathFromObject(const py::handle& path, const char* name);
// True for str, bytes and os.PathLike objects.
bool IsPathLike(const py::handle& object);

// (#V, 3) real numbers -> 3 by #V. `name` is the argument named in errors.
Eigen::Matrix3Xd PositionsFromArray(const py::handle& array, const char* name);
// A 1-D array of real numbers.
Eigen::VectorXd ValuesFromArray(const py::handle& array, const char* name);
// (#F, 3) integers -> 3 by #F (range checked later, by ValidateMesh).
Eigen::Matrix3Xi FacesFromArray(const py::handle& array, const char* name);
// A mesh from V and F, not yet validated.
Mesh MeshFromArrays(const py::handle& vertices, const py::handle& faces);
// ValidateMesh, as ValueError.
void ValidateOrThrow(const Mesh& mesh);
// A 4x4 (last row exactly 0 0 0 1) or 3x4 finite affine transform.
Eigen::Affine3d TransformFromArray(const py::handle& array, const char* name);
// A 1-D integer array of vertex ids, each in [0, size).
std::vector<int> IdsFromArray(const py::handle& array, int size, const char* name);
// A per-vertex status array (0 fixed, 1 free, 2 handle) of length
// num_vertices, as the .sel format has it; not yet validated
// (ValidateHandles: e.g. at least one handle vertex).
HandleLayout LayoutFromStatus(const py::handle& status, int num_vertices, const char* name);

// New arrays (copies).
py::array_t<double> PositionsToArray(const Eigen::Matrix3Xd& positions);
py::array_t<int> FacesToArray(const Eigen::Matrix3Xi& faces);
py::array_t<int> IdsToArray(const std::vector<int>& ids);
py::array_t<int> StatusFromLayout(const HandleLayout& layout, int num_vertices);
py::array_t<double> TransformToArray(const Eigen::Affine3d& transform);
// (#frames, 4, 4).
py::array_t<double> TransformsToArray(const std::vector<Eigen::Affine3d>& transforms);
// One frame's handle transforms named `name` in errors: a 4x4 (or 3x4), or a
// (1, 4, 4), that every handle group follows, or, for a layout of G > 1
// groups, a (G, 4, 4) array, one a group.
HandleTransforms FrameFromArray(const py::handle& matrix, const char* name, int num_groups);
// A path: frames stacked on a first axis, (frames, 4, 4) for a layout of one
// handle group, (frames, G, 4, 4) for G > 1. False (nothing read) when
// `matrix` is one frame.
bool PathFromArray(const py::object& matrix, const char* name, int num_groups,
                   std::vector<HandleTransforms>* path);
// A drag path of a layout with `num_groups` handle groups: (frames, 4, 4) for
// one group, (frames, groups, 4, 4) for several.
py::array_t<double> HandlePathToArray(const std::vector<HandleTransforms>& path, int num_groups);
py::array_t<double> VectorToArray(const Eigen::VectorXd& values);

// Read-only (#V, 3) / (#F, 3) views of C++ storage that `owner` keeps alive.
py::array_t<double> ReadOnlyView(const Eigen::Matrix3Xd& positions, const py::handle& owner);
py::array_t<int> ReadOnlyView(const Eigen::Matrix3Xi& faces, const py::handle& owner);

// DeformerOptions from an optional DeformerOptions object and keyword
// arguments naming its fields (bind_options.cc): TypeError for an unknown
// name, ValueError for a bad value.
DeformerOptions DeformerOptionsFrom(const py::handle& options, const py::kwargs& kwargs);
// A method's options: the keywords that are the methods' own rows of
// MethodOptionTable() (the row's name with '_' for '.', or its flag alias:
// fastlsm_steps_per_frame or fastlsm_steps) set cgal/fastlsm, checked by the
// row (ValueError naming the keyword); the rest are DeformerOptionsFrom's.
MethodOptions MethodOptionsFrom(const py::handle& options, const py::kwargs& kwargs);
// TypeError "w_con: not an option of the cgal_arap method (an option of
// multiscale, static, static_dense)" for a keyword (or a key of a dict
// `options`) that sets only rows `method` does not read (MethodReadsRow,
// methods/method_option_table.h); a DeformerOptions object is not checked
// (its fields are all set, none given by name).
void CheckKeywordsReadBy(const std::string& method, const py::handle& options,
                         const py::kwargs& kwargs);
// The keywords of a method's own row ("fastlsm.steps_per_frame":
// fastlsm_steps_per_frame, fastlsm_steps).
std::vector<std::string> MethodKeywords(const std::string& row_name);

}  // namespace python
}  // namespace msdeform

#endif  // MSDEFORM_PYTHON_BINDINGS_H_
