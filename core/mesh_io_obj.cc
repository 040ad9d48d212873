// The OBJ check. OpenMesh's OBJ reader keeps going with stale values after a
// number fails to parse, and asserts on a malformed face corner; so the
// "v x y z" and "f ..." lines are checked here first, and the faces it will
// hand over are predicted.

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

}  // namespace

// Counts the vertices and predicts the faces OpenMesh hands over: its reader
// removes the repeats of a vertex from a face ((a, b, b, c) becomes (a, b,
// c)) and skips a face left with fewer than 3, so the fan triangles lost that
// way are counted too.
bool CheckObj(std::string_view text, FormatCheck* check, std::string* problem) {
  TextLines lines(text);
  long long count = 0;
  long long num_faces = 0;
  long long dropped_triangles = 0;
  std::vector<long long> ids;
  while (lines.NextWithContent()) {
    const TextLines::Tokens& tokens = lines.tokens();
    if (tokens[0] == "v") {
      if (!CheckVertexCoordinates(lines, 1, count, problem)) return false;
      ++count;
      continue;
    }
    if (tokens[0] != "f") continue;
    if (tokens.size() < 4) {
      return lines.Fail(problem, "a face has ", tokens.size() - 1, " vertices; need at least 3");
    }
    ids.clear();
    for (size_t k = 1; k < tokens.size(); ++k) {
      long long id = 0;
      if (!ParseObjFaceCorner(tokens[k], &id)) {
        return lines.Fail(problem, "face corner ", Quote(tokens[k]),
                          " is not v, v/t, v//n or v/t/n with a non-zero vertex number");
      }
      ids.push_back(id < 0 ? count + id + 1 : id);  // as OpenMesh resolves it
    }
    const long long corners = static_cast<long long>(ids.size());
    std::sort(ids.begin(), ids.end());
    const long long distinct = std::unique(ids.begin(), ids.end()) - ids.begin();
    if (distinct >= 3) ++num_faces;
    dropped_triangles += (corners - 2) - std::max(distinct - 2, 0LL);
  }
  if (count > std::numeric_limits<int>::max() || num_faces > std::numeric_limits<int>::max() ||
      dropped_triangles > std::numeric_limits<int>::max()) {
    return SetProblem(problem, "too many vertices or faces");
  }
  check->num_vertices = static_cast<int>(count);
  check->num_faces = static_cast<int>(num_faces);
  check->dropped_degenerate_faces = static_cast<int>(dropped_triangles);
  return true;
}

}  // namespace msdeform
