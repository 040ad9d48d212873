// Reading triangle meshes through OpenMesh's file readers, keeping the file's
// vertex order exactly, and writing them with every coordinate exact.
//
// Formats, chosen by extension (case-insensitive):
//   in:  .off (also COFF, NOFF, STOFF, ... and binary OFF in OpenMesh's layout,
//        i.e. without the per-face colour count of the OFF spec), .obj, .ply, .stl
//   out: .off, .obj (text), each coordinate the shortest decimal that reads
//        back as the same double; .ply (binary, double coordinates)
//
// Vertex i of the Mesh is the i-th vertex of the file: Botsch-Sorkine .sel
// files and scenario vertex ids index it. Non-manifold input (an edge shared
// by three faces, a "bowtie" vertex) keeps every vertex and face, since the
// faces are recorded as raw index lists and never pass through a halfedge
// structure. Polygons are split into triangle fans (v0, vk, vk+1).
// STL has no shared vertices: vertices at exactly equal positions are merged,
// in order of first appearance.
//
// Two kinds of triangle are dropped, counted in a MeshReadReport, instead of
// refusing the mesh: nothing is lost with them, and they are a common cause
// of failed factorisations elsewhere.
//   - Triangles that repeat a vertex, (a, a, b): zero area by construction.
//     This includes an STL facet two of whose corners are at one position,
//     and the fan triangles of a polygon that repeats a vertex: (a, b, c, a)
//     reads as the triangle (a, b, c) and one dropped triangle. (OpenMesh's
//     OBJ reader removes a polygon's repeated corners itself, (a, b, c), which
//     gives the same triangles and count when the repeats are neighbours.)
//   - Exact duplicates: the same three vertices in the same cyclic order as an
//     earlier triangle ((a, b, c), (b, c, a) and (c, a, b) are one triangle);
//     the first stays.
// A copy with the opposite orientation, (a, c, b) after (a, b, c), is not a
// duplicate and stays: it is the back of a two-sided sheet (or of a
// zero-thickness wall), a face of its own that the written result keeps so
// that both sides still render; it adds no edge, component or lattice cell,
// so it cannot make the deformation singular. (Its area-weighted normal
// cancels the front's, as it would in any tool.)
// Vertices are never dropped or renumbered: a vertex used only by dropped
// triangles stays as an isolated vertex (a mesh component of its own, which
// the deformer leaves at rest). The kept triangles keep the file's order.
// Counts are of triangles after the fan split; for a triangle mesh they are
// the file's faces.
//
// Coordinates are read exactly, whichever reader parses the rest: a decimal
// is the nearest double (as strtod reads it; one beyond the double range is
// refused as not finite, one below the smallest subnormal is a zero), a
// binary double is itself, and a float (binary PLY or STL, or the decimal of
// an ASCII PLY property declared float) is the nearest float, widened. (PLY
// coordinates of an integer type go through OpenMesh's float, as before.) So
// WriteMesh then ReadMesh gives back every coordinate bit for bit (negative
// zeros and subnormals included) in .off, .obj and .ply.

#ifndef MSDEFORM_CORE_MESH_IO_H_
#define MSDEFORM_CORE_MESH_IO_H_

#include <string>

#include "msdeform/core/mesh.h"

namespace msdeform {

// What ReadMesh dropped (see above).
struct MeshReadReport {
  int dropped_degenerate_faces = 0;  // triangles that repeat a vertex
  int dropped_duplicate_faces = 0;   // exact duplicates of an earlier triangle
  // One line for the user when something was dropped, else empty, e.g.
  // "in.off: dropped 3 faces that repeat a vertex and 1 duplicate face".
  std::string notice;
};

// How ReadMesh reads. The mesh, the report and every message are the same
// for any value of these: they set how the work is shared out, not its result.
struct MeshReadOptions {
  // Threads (OpenMP) for parsing OFF, OBJ and binary PLY, and for the steps
  // after it (fan split, dropped faces, the finiteness check); at least 1.
  int num_threads = 1;
  // A text file (OFF, OBJ) is parsed in pieces of about this many bytes,
  // each ending at a line end; at least 1.
  int text_chunk_bytes = 1 << 20;
  // The steps after parsing, and binary PLY, work in chunks of this many
  // vertices or faces; at least 1. (Tests set both small to take the
  // parallel paths on small meshes.)
  int items_per_chunk = 1 << 14;

  bool Check(std::string* problem) const;
};

// Reads `path` into *mesh, drops the triangles described above (counted in
// *report), and checks the result with ValidateMesh. On failure returns
// false, leaves *mesh and *report unspecified, and puts one line in *error
// naming the file and, where known, the line, vertex or face and what is
// wrong (missing or empty file, wrong header, truncated data, non-finite
// coordinate, face id out of range, no face left after dropping, ...).
// Invalid `options` are refused the same way, with "ReadMesh options: ...".
bool ReadMesh(const std::string& path, const MeshReadOptions& options, Mesh* mesh,
              MeshReadReport* report, std::string* error);

// The same on one thread.
bool ReadMesh(const std::string& path, Mesh* mesh, MeshReadReport* report, std::string* error);

// The same without the report, for callers that do not tell the user.
bool ReadMesh(const std::string& path, Mesh* mesh, std::string* error);

// Writes `mesh` to `path` (format by extension) atomically: a temporary beside
// `path` is renamed over it only when complete. On failure no file is left
// and *error names the file and the problem.
bool WriteMesh(const std::string& path, const Mesh& mesh, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_MESH_IO_H_
