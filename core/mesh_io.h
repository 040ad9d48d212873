// Reading and writing triangle meshes through OpenMesh's file readers and
// writers, keeping the file's vertex order exactly.
//
// Formats, chosen by extension (case-insensitive):
//   in:  .off (also COFF, NOFF, STOFF, ... and binary OFF in OpenMesh's layout,
//        i.e. without the per-face colour count of the OFF spec), .obj, .ply, .stl
//   out: .off, .obj, .ply (ASCII)
//
// Vertex i of the Mesh is the i-th vertex of the file: Botsch-Sorkine .sel
// files and scenario vertex ids index it. Non-manifold input (an edge shared
// by three faces, a "bowtie" vertex) keeps every vertex and face, since the
// faces are recorded as raw index lists and never pass through a halfedge
// structure. Polygons are split into triangle fans (v0, vk, vk+1).
// STL has no shared vertices: vertices at exactly equal positions are merged,
// in order of first appearance.
//
// Coordinates pass through OpenMesh as single precision both ways: reading
// rounds to float, writing prints floats with 9 significant digits, which
// reproduces every float exactly, so a write-read round trip is within float
// rounding (about 6e-8 relative) and a second round trip is exact.

#ifndef MSDEFORM_CORE_MESH_IO_H_
#define MSDEFORM_CORE_MESH_IO_H_

#include <string>

#include "core/mesh.h"

namespace msdeform {

// Reads `path` into *mesh and checks it with ValidateMesh. On failure returns
// false, leaves *mesh unspecified, and puts one line in *error naming the file
// and, where known, the line, vertex or face and what is wrong (missing or
// empty file, wrong header, truncated data, non-finite coordinate, face id out
// of range, ...).
bool ReadMesh(const std::string& path, Mesh* mesh, std::string* error);

// Writes `mesh` to `path` (format by extension) atomically: a temporary beside
// `path` is renamed over it only when complete. On failure no file is left
// and *error names the file and the problem.
bool WriteMesh(const std::string& path, const Mesh& mesh, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_MESH_IO_H_
