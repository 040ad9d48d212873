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
bool CheckObj(std::string_view text, FormatCheck* check, std::string* problem) {
  TextLines lines(text);
  long long count = 0;
  long long num_faces = 0;
  long long dropped_triangles = 0;
  std::vector<long long> ids;
  std::vector<int> order;
  PolygonSoup& soup = check->soup;
  soup = PolygonSoup();
  while (lines.NextWithContent()) {
    const TextLines::Tokens& tokens = lines.tokens();
    if (tokens[0] == "v") {
      if (!ReadVertexCoordinates(lines, 1, count, &soup.xyz, problem)) return false;
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
      ids.push_back((id < 0 ? count + id + 1 : id) - 1);
    }
    const long long corners = static_cast<long long>(ids.size());
    RemoveRepeats(&ids, &order);
    const long long distinct = static_cast<long long>(ids.size());
    dropped_triangles += (corners - 2) - std::max(distinct - 2, 0LL);
    if (distinct < 3) continue;
    if (num_faces == std::numeric_limits<int>::max() ||
        soup.face_ids.size() + ids.size() > static_cast<size_t>(std::numeric_limits<int>::max())) {
      return SetProblem(problem, "too many vertices or faces");
    }
    ++num_faces;
    for (long long id : ids) soup.face_ids.push_back(static_cast<int>(id));
    soup.face_offsets.push_back(static_cast<int>(soup.face_ids.size()));
  }
  if (count > std::numeric_limits<int>::max() ||
      dropped_triangles > std::numeric_limits<int>::max()) {
    return SetProblem(problem, "too many vertices or faces");
  }
  check->num_vertices = static_cast<int>(count);
  check->num_faces = static_cast<int>(num_faces);
  check->dropped_degenerate_faces = static_cast<int>(dropped_triangles);
  check->read_data = true;
  return true;
}

}  // namespace msdeform
