// The OBJ reader: the "v x y z" and "f ..." lines checked and read in one
// pass. (OpenMesh's OBJ reader, used before, kept going with stale values
// after a number failed to parse, asserted on a malformed face corner, took
// coordinates through float and skipped a vertex beyond the float range.)

#include <algorithm>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "msdeform/core/mesh_io_formats.h"
#include "msdeform/core/text_lines.h"

namespace msdeform {
namespace {

// True for an OBJ face corner "v", "v/t", "v//n" or "v/t/n": v a non-zero
// integer (negative counts back from the last vertex), t and n empty or
// integers; sets *vertex to v. OpenMesh's OBJ reader asserts (aborts) on a
// corner without v, e.g. "/1/1" (found by tests/fuzz/obj_fuzzer).
bool ParseObjFaceCorner(std::string_view corner, long long* vertex) {
  std::string_view parts[3];
  int num_parts = 0;
  size_t start = 0;
  while (true) {
    if (num_parts == 3) return false;
    const size_t slash = corner.find('/', start);
    const size_t length = slash == std::string_view::npos ? slash : slash - start;
    parts[num_parts++] = corner.substr(start, length);
    if (slash == std::string_view::npos) break;
    start = slash + 1;
  }
  if (!ParseInt(parts[0], vertex) || *vertex == 0 || *vertex < std::numeric_limits<int>::min() ||
      *vertex > std::numeric_limits<int>::max()) {
    return false;
  }
  long long value = 0;
  for (int k = 1; k < num_parts; ++k) {
    if (!parts[k].empty() && !ParseInt(parts[k], &value)) return false;
  }
  return true;
}

// Removes the repeats of a value from *ids, keeping the first of each in
// place: pairwise for a short list, by a stable sort of the positions for a
// long one (n log n, not n^2, for a face of a million corners). *order is
// scratch space.
void RemoveRepeats(std::vector<long long>* ids, std::vector<int>* order) {
  std::vector<long long>& v = *ids;
  constexpr size_t kScanLimit = 32;
  size_t kept = 0;
  if (v.size() <= kScanLimit) {
    for (size_t i = 0; i < v.size(); ++i) {
      if (std::find(v.begin(), v.begin() + kept, v[i]) == v.begin() + kept) v[kept++] = v[i];
    }
    v.resize(kept);
    return;
  }
  order->resize(v.size());
  for (size_t i = 0; i < v.size(); ++i) (*order)[i] = static_cast<int>(i);
  std::stable_sort(order->begin(), order->end(), [&v](int a, int b) { return v[a] < v[b]; });
  // Mark the repeats (all but the first position of each value), then
  // compact in order.
  std::vector<char> repeat(v.size(), 0);
  for (size_t i = 1; i < order->size(); ++i) {
    if (v[(*order)[i]] == v[(*order)[i - 1]]) repeat[(*order)[i]] = 1;
  }
  for (size_t i = 0; i < v.size(); ++i) {
    if (!repeat[i]) v[kept++] = v[i];
  }
  v.resize(kept);
}

// A piece of an OBJ text (LineChunks), parsed apart from the others once the
// line it starts at and the number of vertices before it are known.
struct ObjPiece {
  std::string_view text;
  int lines_before = 0;         // the number of the line before the piece
  long long vertices_before = 0;  // "v" lines before the piece
  int lines = 0;                // its lines (CountObjPiece)
  long long vertices = 0;       // its "v" lines
  long long faces = 0;          // the faces it read
  long long dropped_triangles = 0;
  SoupPiece soup;               // what it read
  std::string problem;  // its first bad line's message; empty when none
};

// Counts the piece's lines and "v" lines.
void CountObjPiece(ObjPiece* piece) {
  long long vertices = 0;
  piece->lines = ForEachLine(piece->text, [&vertices](std::string_view line) {
    if (FirstToken(line) == "v") ++vertices;
  });
  piece->vertices = vertices;
}

// Reads the piece's "v" and "f" lines (see CheckObj), its faces and ids
// within the limit of an int (the pieces' sums are checked when they are
// joined). Stops at the first bad line, its message in piece->problem.
void ParseObjPiece(ObjPiece* piece) {
  TextLines lines(piece->text, piece->lines_before);
  long long count = piece->vertices_before;
  std::vector<long long> ids;
  std::vector<int> order;
  SoupPiece& soup = piece->soup;
  std::string* problem = &piece->problem;
  while (lines.NextWithContent()) {
    const TextLines::Tokens& tokens = lines.tokens();
    if (tokens[0] == "v") {
      double position[3];
      if (!ReadVertexCoordinates(lines, 1, count, position, problem)) break;
      soup.xyz.insert(soup.xyz.end(), position, position + 3);
      ++count;
      continue;
    }
    if (tokens[0] != "f") continue;
    if (tokens.size() < 4) {
      lines.Fail(problem, "a face has ", tokens.size() - 1, " vertices; need at least 3");
      break;
    }
    ids.clear();
    for (size_t k = 1; k < tokens.size(); ++k) {
      long long id = 0;
      if (!ParseObjFaceCorner(tokens[k], &id)) {
        lines.Fail(problem, "face corner ", Quote(tokens[k]),
                   " is not v, v/t, v//n or v/t/n with a non-zero vertex number");
        break;
      }
      ids.push_back((id < 0 ? count + id + 1 : id) - 1);
    }
    if (!problem->empty()) break;
    const long long corners = static_cast<long long>(ids.size());
    RemoveRepeats(&ids, &order);
    const long long distinct = static_cast<long long>(ids.size());
    piece->dropped_triangles += (corners - 2) - std::max(distinct - 2, 0LL);
    if (distinct < 3) continue;
    if (piece->faces == std::numeric_limits<int>::max() ||
        soup.face_ids.size() + ids.size() >
            static_cast<size_t>(std::numeric_limits<int>::max())) {
      SetProblem(problem, "too many vertices or faces");
      break;
    }
    ++piece->faces;
    for (long long id : ids) soup.face_ids.push_back(static_cast<int>(id));
    soup.face_offsets.push_back(static_cast<int>(soup.face_ids.size()));
  }
  piece->vertices = count - piece->vertices_before;
}

// Reads the pieces of text[begin, end): on one thread (or for one piece)
// one after another, else counted first and then read in parallel (each
// piece's first line and vertex number known from the counts). Returns
// false with the serial reading's message for the first bad line.
bool ReadObjPieces(std::string_view text, const std::vector<size_t>& bounds, int num_threads,
                   FormatCheck* check, std::string* problem) {
  std::vector<ObjPiece> pieces(bounds.size() - 1);
  for (size_t c = 0; c < pieces.size(); ++c) {
    pieces[c].text = text.substr(bounds[c], bounds[c + 1] - bounds[c]);
  }
  ForEachTask(static_cast<int>(pieces.size()) - 1, num_threads,
               [&pieces](int c) { CountObjPiece(&pieces[c]); });
  for (size_t c = 1; c < pieces.size(); ++c) {
    pieces[c].lines_before = pieces[c - 1].lines_before + pieces[c - 1].lines;
    pieces[c].vertices_before = pieces[c - 1].vertices_before + pieces[c - 1].vertices;
  }
  ForEachTask(static_cast<int>(pieces.size()), num_threads,
               [&pieces](int c) { ParseObjPiece(&pieces[c]); });
  constexpr long long kIntMax = std::numeric_limits<int>::max();
  long long vertices = 0, faces = 0, face_ids = 0, dropped_triangles = 0;
  for (const ObjPiece& piece : pieces) {
    vertices += piece.vertices;
    faces += piece.faces;
    face_ids += static_cast<long long>(piece.soup.face_ids.size());
    dropped_triangles += piece.dropped_triangles;
    if (faces > kIntMax || face_ids > kIntMax) {
      // Past an int's limit the message depends on where in the file it
      // was passed: read the whole text as one piece, as on one thread.
      return ReadObjPieces(text, {bounds.front(), bounds.back()}, 1, check, problem);
    }
    if (!piece.problem.empty()) return SetProblem(problem, piece.problem);
  }
  if (vertices > kIntMax || dropped_triangles > kIntMax) {
    return SetProblem(problem, "too many vertices or faces");
  }
  std::vector<SoupPiece*> parts;
  for (ObjPiece& piece : pieces) parts.push_back(&piece.soup);
  if (!ConcatenateSoupPieces(parts, num_threads, &check->soup)) {
    return SetProblem(problem, "too many vertices or faces");
  }
  check->num_vertices = static_cast<int>(vertices);
  check->num_faces = static_cast<int>(faces);
  check->dropped_degenerate_faces = static_cast<int>(dropped_triangles);
  check->read_data = true;
  return true;
}

}  // namespace

// Reads the file into check->soup in the same pass: each "v" line's first
// three numbers as doubles, each "f" line's vertex numbers as ids from 0
// (negative ones counted back from the last vertex so far). A face is what
// OpenMesh's reader, used before, handed over (the tests compare the two):
// the repeats of a vertex removed, the first of each kept ((a, b, b, c) and
// (a, b, c, a) become (a, b, c)), and a face left with fewer than 3 skipped;
// the fan triangles lost that way are counted. Ids out of range are refused
// later, with the face's number (SplitIntoTriangles). (OpenMesh took
// coordinates through float, and skipped a vertex beyond the float range.)
// On more than one thread the text is read in pieces of about
// options.text_chunk_bytes, in parallel (ReadObjPieces).
bool CheckObj(std::string_view text, FormatCheck* check, std::string* problem) {
  check->soup = PolygonSoup();
  const MeshReadOptions& options = check->options;
  const std::vector<size_t> bounds =
      options.num_threads > 1 ? LineChunks(text, 0, text.size(), options.text_chunk_bytes)
                              : std::vector<size_t>{0, text.size()};
  return ReadObjPieces(text, bounds, options.num_threads, check, problem);
}

}  // namespace msdeform
