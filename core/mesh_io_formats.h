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
#include <cstdint>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "msdeform/core/mesh.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/parallel.h"
#include "msdeform/core/uninitialized_vector.h"

namespace msdeform {

// A file's vertices and polygons, in the file's order.
struct PolygonSoup {
  UninitializedVector<double> xyz;           // 3 #V
  UninitializedVector<int> face_offsets{0};  // #polygons + 1
  UninitializedVector<int> face_ids;         // vertex ids of all polygons
  int num_vertices() const { return static_cast<int>(xyz.size() / 3); }
  int num_polygons() const { return static_cast<int>(face_offsets.size()) - 1; }
};

// What a piece of a text file holds (its vertices' x, y, z and its
// polygons, face_offsets into its face_ids), read apart from the others.
struct SoupPiece {
  UninitializedVector<double> xyz;
  UninitializedVector<int> face_offsets{0};
  UninitializedVector<int> face_ids;
};

// Puts the pieces' vertices and polygons in *soup, in order: the only piece's
// moved, several pieces' copied on up to `num_threads` threads (each piece
// freed once copied). Returns false, *soup unspecified, when the ids or
// polygons would be more than an int counts.
bool ConcatenateSoupPieces(const std::vector<SoupPiece*>& pieces, int num_threads,
                           PolygonSoup* soup);

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

// How many items a chunk holds when `count` items are cut into chunks of
// `per_chunk` (at least 1): `per_chunk`, or more where that would make over
// kMaxChunks chunks (so that tables with a row per chunk stay small whatever
// the options). Depends only on the two numbers; NumChunks (core/parallel.h)
// then gives the number of chunks.
constexpr long long kMaxChunks = 1024;
inline long long ChunkItems(long long count, long long per_chunk) {
  return std::max({per_chunk, (count + kMaxChunks - 1) / kMaxChunks, 1LL});
}

// Calls body(c) for c in 0..num_tasks - 1 on up to `num_threads` threads:
// ForEachChunk (core/parallel.h) with one task per chunk, for work already
// cut into chunks (pieces of text, chunks of ChunkItems). Each body writes
// only its own task's outputs, so the result does not depend on the threads.
template <typename Body>
void ForEachTask(int num_tasks, int num_threads, const Body& body) {
  ForEachChunk(num_tasks, 1, num_threads,
               [&body](int64_t c, int64_t, int64_t) { body(static_cast<int>(c)); });
}

// What a format's check found in the file.
struct FormatCheck {
  // In: how to read (threads, chunk sizes); the rest is out.
  MeshReadOptions options;
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

// The steps after a format's check (core/mesh_io_soup.cc), in chunks of
// options.items_per_chunk on options.num_threads threads, with the same
// result for any options:
//   - SplitIntoTriangles checks the polygons as the file numbers them (at
//     least 3 vertices, ids in range; *problem names the first bad one) and
//     splits each into the triangle fan (v0, vk, vk+1);
//   - DropDegenerateAndDuplicateFaces drops the triangles that repeat a
//     vertex and the exact duplicates of an earlier one (mesh_io.h), keeping
//     the order of the rest, and adds their counts to *report;
//   - AllVerticesFinite is true when every coordinate is finite.
bool SplitIntoTriangles(const PolygonSoup& soup, const MeshReadOptions& options, Mesh* mesh,
                        std::string* problem);
void DropDegenerateAndDuplicateFaces(const MeshReadOptions& options, Mesh* mesh,
                                     MeshReadReport* report);
bool AllVerticesFinite(const Mesh& mesh, const MeshReadOptions& options);

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
