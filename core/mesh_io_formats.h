// The pieces behind ReadMesh and WriteMesh (core/mesh_io.cc, the dispatcher),
// internal to core:
//   - one check per format, each in its own file (core/mesh_io_off.cc,
//     mesh_io_obj.cc, mesh_io_ply.cc, mesh_io_stl.cc), walking the text with
//     the shared TextLines (core/text_lines.h);
//   - the OpenMesh pass that reads the vertices and polygons
//     (core/mesh_io_openmesh.cc);
//   - the writers, which print exact doubles (core/mesh_io_write.cc).
// OpenMesh's readers trust what they read: after a number fails to parse or
// the data ends they keep going with stale values, and some allocate what a
// count says or crash on a malformed header (found by the fuzzers in
// tests/fuzz/). So each file is checked first, with a message naming the
// line, and the check says what OpenMesh must then hand over.
// A format that parses its data itself (text OFF, OBJ, PLY of the common
// layouts) fills the PolygonSoup directly instead of going through ReadWithOpenMesh; everything
// after it (fan split, welding, dropped faces) stays shared.

#ifndef MSDEFORM_CORE_MESH_IO_FORMATS_H_
#define MSDEFORM_CORE_MESH_IO_FORMATS_H_

#include <algorithm>
#include <cstddef>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "msdeform/core/mesh.h"

namespace msdeform {

// A file's vertices and polygons, in the file's order.
struct PolygonSoup {
  std::vector<double> xyz;           // 3 #V
  std::vector<int> face_offsets{0};  // #polygons + 1
  std::vector<int> face_ids;         // vertex ids of all polygons
  int num_vertices() const { return static_cast<int>(xyz.size() / 3); }
  int num_polygons() const { return static_cast<int>(face_offsets.size()) - 1; }
};

// How many items to reserve room for when a header announces `count` of them
// and `bytes_left` bytes of the file remain, each item taking at least
// `min_item_bytes`: a header's counts are not trusted until the data is read,
// so a short file that announces two billion faces reserves nothing of the
// sort (it then fails as truncated, with its one-line message). At most 2^24.
inline size_t ReservationFor(long long count, size_t bytes_left, size_t min_item_bytes) {
  constexpr size_t kCap = size_t{1} << 24;
  if (count <= 0) return 0;
  return std::min({static_cast<size_t>(count), bytes_left / min_item_bytes, kCap});
}

// What a format's check found in the file.
struct FormatCheck {
  // What OpenMesh must hand over; -1: the format does not say.
  int num_vertices = -1;
  int num_faces = -1;
  // Triangles that repeat a vertex which OpenMesh's OBJ and STL readers skip
  // without a word; the notice counts them with those dropped later.
  int dropped_degenerate_faces = 0;
  // True when the check read the data into `soup` itself, in the same pass
  // (text OFF, OBJ, and PLY of a vertex and a face element, ASCII or binary
  // little-endian), so OpenMesh is not run.
  bool read_data = false;
  // True when the check read only the vertices' coordinates into soup.xyz
  // (the other PLY layouts, with float or double x, y, z): OpenMesh's
  // readers take coordinates through single precision, so ReadWithOpenMesh
  // replaces what they hand over with these.
  bool read_coordinates = false;
  PolygonSoup soup;
};

// Each checks the whole (non-empty) text of a file in its format and fills
// *check. Coordinates are read exactly: a text coordinate is the double
// nearest to its decimal (a float property's: the nearest float, widened), a
// binary one the value stored (a float widened). On failure puts one line in *problem, without the file name: "line
// N: ..." or what is wrong with the whole file.
bool CheckOff(std::string_view text, FormatCheck* check, std::string* problem);
bool CheckObj(std::string_view text, FormatCheck* check, std::string* problem);
bool CheckPly(std::string_view text, FormatCheck* check, std::string* problem);
bool CheckStl(std::string_view text, FormatCheck* check, std::string* problem);

// A mesh format ReadMesh and WriteMesh know.
struct MeshFormat {
  const char* extension;  // lower case, without the dot: "off"
  const char* name;       // in messages: "OFF"
  bool (*check)(std::string_view text, FormatCheck* check, std::string* problem);
  // STL has no shared vertices: corners at exactly equal positions are merged.
  bool weld_equal_positions;
  bool writable;  // WriteMeshFile writes it
};

// Reads `path` with OpenMesh's reader for `format` into *soup, compares what
// it handed over with the counts in `check`, and puts the check's exact
// coordinates in place of OpenMesh's when it read them
// (check.read_coordinates). On failure puts one line in *problem, without
// the file name.
bool ReadWithOpenMesh(const std::string& path, const MeshFormat& format, FormatCheck check,
                      PolygonSoup* soup, std::string* problem);

// Writes `mesh` to `out` as `format`'s file: OFF and OBJ as text, each
// coordinate the shortest decimal that reads back as the same double; PLY as
// binary little-endian with double coordinates and int vertex ids. On failure
// puts one line in *problem.
bool WriteMeshFile(const Mesh& mesh, const MeshFormat& format, std::ostream& out,
                   std::string* problem);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_MESH_IO_FORMATS_H_
