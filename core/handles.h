// Handle layouts: which vertices are held still and which one region the user
// drags, plus the Botsch-Sorkine file formats that describe them.
//
// .sel (per-vertex status, in the mesh's vertex order):
//   # per vertex status: 0=fixed, 1=deformable-region, 2=handle
//   # 620 vertices
//   1
//   2
//   0
//   ...               exactly one integer per vertex; '#' lines are comments
//
// .def (the handle transform deformed_from_rest, a 4x4 affine matrix, row by
// row; '#' lines are comments; the last row must be 0 0 0 1):
//   # 4x4 handle transformation matrix
//   0.999641 0.021031 0.016579 -0.019322
//   ...
//   0.000000 0.000000 0.000000 1.000000

#ifndef MSDEFORM_CORE_HANDLES_H_
#define MSDEFORM_CORE_HANDLES_H_

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace msdeform {

struct HandleLayout {
  // Vertices held at their rest position: the union of all fixed regions.
  // Sorted, unique; may be empty.
  std::vector<int> fixed;
  // Vertices of the one moveable handle, which follows the handle transform.
  // Sorted, unique, not empty, disjoint from `fixed`.
  std::vector<int> moveable;
};

// Checks a layout against a mesh with `num_vertices` vertices: ids in range,
// both lists sorted and unique, at least one moveable vertex, no vertex both
// fixed and moveable. On failure *error names the first offending vertex.
bool ValidateHandles(const HandleLayout& layout, int num_vertices, std::string* error);

// A valid layout's moveable and fixed vertices as one sorted list, and per
// entry whether it follows the handle (1: moveable) or stays at rest (0:
// fixed): the constrained vertices of the local/global ARAP solvers.
void ConstrainedVertices(const HandleLayout& layout, std::vector<int>* constrained,
                         std::vector<char>* follows_handle);

// Where ConstrainedVertices' vertices go in a frame (3 by #constrained):
// deformed_from_rest * rest for those that follow the handle, rest for the
// fixed ones; `rest` holds every vertex's rest position.
Eigen::Matrix3Xd ConstrainedTargets(const Eigen::Matrix3Xd& rest,
                                    const std::vector<int>& constrained,
                                    const std::vector<char>& follows_handle,
                                    const Eigen::Affine3d& deformed_from_rest);

// Reads a .sel file for a mesh with `num_vertices` vertices: status 0 goes to
// `fixed`, 2 to `moveable`, 1 (free to deform) to neither. Errors (file, line
// and problem in *error): unreadable file, a line that is not one integer,
// a status outside 0..2, more or fewer statuses than vertices, no handle (2).
bool ReadSel(const std::string& path, int num_vertices, HandleLayout* layout, std::string* error);
// The same without a mesh: the vertex count is the file's (one status a
// vertex), returned in *num_vertices; a count is not checked.
bool ReadSel(const std::string& path, HandleLayout* layout, int* num_vertices,
             std::string* error);

// Writes `layout` as a .sel file for a mesh with `num_vertices` vertices,
// atomically. Fails (no file written) when the layout does not validate.
bool WriteSel(const std::string& path, const HandleLayout& layout, int num_vertices,
              std::string* error);

// Reads a .def file: 16 finite numbers, row by row, whose last row is
// 0 0 0 1 within 1e-9.
bool ReadDef(const std::string& path, Eigen::Affine3d* deformed_from_rest, std::string* error);

// Writes a .def file atomically, with full double precision.
bool WriteDef(const std::string& path, const Eigen::Affine3d& deformed_from_rest,
              std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_HANDLES_H_
