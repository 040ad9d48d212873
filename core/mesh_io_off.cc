// The OFF reader. Text OFF is checked and read in one pass, line by line, by
// msdeform's own parser ('#' comments, counts on the header line, leading
// blank lines, colours and normals after the coordinates are accepted); the
// counts the header announces are what the file must deliver. Binary OFF is
// checked here and read by OpenMesh.

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "msdeform/core/mesh_io_formats.h"
#include "msdeform/core/text_lines.h"

namespace msdeform {
namespace {

using Tokens = TextLines::Tokens;

// Header keyword [ST][C][N][4][n]OFF; sets *dimension_other_than_3.
bool IsOffKeyword(std::string_view keyword, bool* dimension_other_than_3) {
  *dimension_other_than_3 = false;
  if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF") return false;
  std::string_view prefix = keyword.substr(0, keyword.size() - 3);
  auto take = [&prefix](std::string_view part) {
    if (prefix.substr(0, part.size()) == part) {
      prefix.remove_prefix(part.size());
      return true;
    }
    return false;
  };
  take("ST");
  take("C");
  take("N");
  if (take("4")) *dimension_other_than_3 = true;
  if (take("n")) *dimension_other_than_3 = true;
  return prefix.empty();
}

bool CheckBinaryOff(std::string_view text, size_t data_start, std::string_view keyword,
                    FormatCheck* check, std::string* problem) {
  // OpenMesh's binary reader takes colours, normals and texture coordinates
  // from the keyword with a layout of its own; only plain OFF is checked
  // (and so accepted) here.
  if (keyword != "OFF") {
    return SetProblem(problem, "line 1: binary ", Quote(keyword),
                      " is not supported; use binary OFF or ASCII");
  }
  // Binary OFF: three little-endian uint32 counts follow the header line.
  if (text.size() < data_start + 12) {
    return SetProblem(problem, "truncated: binary OFF ends before the vertex/face/edge counts");
  }
  uint32_t counts[3];
  std::memcpy(counts, text.data() + data_start, sizeof(counts));
  if (counts[0] > static_cast<uint32_t>(std::numeric_limits<int>::max()) ||
      counts[1] > static_cast<uint32_t>(std::numeric_limits<int>::max())) {
    return SetProblem(problem, "binary OFF header announces an impossible vertex or face count");
  }
  check->num_vertices = static_cast<int>(counts[0]);
  check->num_faces = static_cast<int>(counts[1]);
  // At least 3 floats per vertex and 1 + 3 ints per face.
  const uint64_t minimum = data_start + 12 + 12ull * counts[0] + 16ull * counts[1];
  if (text.size() < minimum) {
    return SetProblem(problem, "truncated: the binary OFF header announces ", counts[0],
                      " vertices and ", counts[1], " faces, which need at least ", minimum,
                      " bytes, but the file has ", text.size());
  }
  // Each face: an int32 vertex count, then that many int32 ids. OpenMesh
  // sizes its id list by the count before reading, so a wild count would
  // allocate gigabytes (found by tests/fuzz/off_fuzzer): walk them first.
  uint64_t offset = data_start + 12 + 12ull * counts[0];
  for (uint32_t face = 0; face < counts[1]; ++face) {
    if (text.size() < offset + 4) {
      return SetProblem(problem, "truncated: binary OFF ends in face ", face, " of ", counts[1]);
    }
    int32_t size = 0;
    std::memcpy(&size, text.data() + offset, sizeof(size));
    offset += 4;
    if (size < 3 || text.size() < offset + 4ull * static_cast<uint64_t>(size)) {
      return SetProblem(problem, "binary OFF face ", face, " announces ", size,
                        " vertices; need at least 3, all in the file");
    }
    for (int32_t k = 0; k < size; ++k, offset += 4) {
      int32_t id = 0;
      std::memcpy(&id, text.data() + offset, sizeof(id));
      if (id < 0 || static_cast<uint32_t>(id) >= counts[0]) {
        return SetProblem(problem, "binary OFF face ", face, " refers to vertex ", id,
                          ", outside 0..", static_cast<int64_t>(counts[0]) - 1);
      }
    }
  }
  return true;
}

// With `lines` on the header line, sets *counts to the "nV nF nE" tokens:
// the rest of the header line, else the next line with content (false when
// there is none).
bool FindOffCounts(TextLines* lines, Tokens* counts) {
  counts->assign(lines->tokens().begin() + 1, lines->tokens().end());
  if (!counts->empty()) return true;
  if (!lines->NextWithContent()) return false;
  *counts = lines->tokens();
  return true;
}

// A piece of an OFF text's vertex and face lines (LineChunks), parsed apart
// from the others once the line and the item (vertex, then face) it starts
// at are known.
struct OffPiece {
  std::string_view text;
  int lines_before = 0;      // the number of the line before the piece
  long long first_item = 0;  // the item of its first line with content
  int lines = 0;             // its lines (CountOffPiece)
  long long items = 0;       // its lines with content (counted), or the items read
  SoupPiece soup;       // what it read
  // Where vertex v goes, at xyz_out[3 v] (when the pieces were counted);
  // nullptr: to soup.xyz.
  double* xyz_out = nullptr;
  std::string problem;  // the piece's first bad line, "line N: ..."; empty when none
};

// Counts the piece's lines and those with content.
void CountOffPiece(OffPiece* piece) {
  const LineCount count = CountLines(piece->text);
  piece->lines = count.lines;
  piece->items = count.with_content;
}

// Reads the piece's lines with content as items first_item, first_item + 1,
// ..., up to item num_vertices + num_faces - 1: a vertex is the first three
// numbers of its line, a face the ids after its count; colours, normals and
// texture coordinates after them are skipped. Stops at the first bad line,
// its message in piece->problem; piece->items is the number of items read.
void ParseOffPiece(long long num_vertices, long long num_faces, OffPiece* piece) {
  TextLines lines(piece->text, piece->lines_before);
  const long long total = num_vertices + num_faces;
  long long item = piece->first_item;
  std::string& problem = piece->problem;
  for (; item < total && lines.NextWithContent(); ++item) {
    const Tokens& tokens = lines.tokens();
    if (item < num_vertices) {
      double position[3];
      if (!ReadVertexCoordinates(lines, 0, item, position, &problem)) break;
      if (piece->xyz_out != nullptr) {
        std::copy(position, position + 3, piece->xyz_out + 3 * item);
      } else {
        piece->soup.xyz.insert(piece->soup.xyz.end(), position, position + 3);
      }
      continue;
    }
    const long long face = item - num_vertices;
    long long size = 0;
    if (!ParseInt(tokens[0], &size) || size < 3) {
      lines.Fail(&problem, "face ", face, " starts with ", Quote(tokens[0]),
                 "; expected its vertex count, at least 3");
      break;
    }
    if (static_cast<long long>(tokens.size()) < 1 + size) {
      lines.Fail(&problem, "face ", face, " announces ", size, " vertices but lists ",
                 tokens.size() - 1);
      break;
    }
    for (long long k = 1; k <= size && problem.empty(); ++k) {
      long long id = 0;
      if (!ParseInt(tokens[k], &id)) {
        lines.Fail(&problem, "face ", face, " vertex id ", Quote(tokens[k]), " is not an integer");
      } else if (id < 0 || id >= num_vertices) {
        lines.Fail(&problem, "face ", face, " refers to vertex ", id, ", outside 0..",
                   num_vertices - 1);
      } else {
        piece->soup.face_ids.push_back(static_cast<int>(id));
      }
    }
    if (!problem.empty()) break;
    piece->soup.face_offsets.push_back(static_cast<int>(piece->soup.face_ids.size()));
  }
  piece->items = item - piece->first_item;
}

// Checks the OFF text and reads it into check->soup in the same pass, line by
// line (ParseOffPiece). (OpenMesh's reader, used before, reads ST/C/N values
// token by token across line ends, so one vertex line without them shifted
// everything after it: a coordinate became a face's vertex count, and a count
// of billions made it allocate gigabytes, found by tests/fuzz/off_fuzzer.)
// Binary OFF is checked here and read by OpenMesh. On more than one thread a
// text of more than one piece (LineChunks of options.text_chunk_bytes) is
// read piece by piece in parallel: the pieces' lines and items are counted
// first (in parallel), so each piece knows its first line and item; the
// first bad line of the first piece that has one is the serial reading's.
bool CheckOffText(std::string_view text, FormatCheck* check, std::string* problem) {
  TextLines lines(text);
  // Header: first line with content.
  if (!lines.NextWithContent()) {
    return SetProblem(problem, "no OFF header: the file holds only blank or comment lines");
  }
  const std::string_view keyword = lines.tokens()[0];
  bool other_dimension = false;
  if (!IsOffKeyword(keyword, &other_dimension)) {
    return lines.Fail(problem, "expected an OFF header such as 'OFF' or 'COFF', found ",
                      Quote(keyword));
  }
  if (other_dimension) {
    return lines.Fail(problem, Quote(keyword), " (4D or nD vertices) is not supported; use 3D OFF");
  }
  if (lines.tokens().size() >= 2 && lines.tokens()[1] == "BINARY") {
    if (lines.line_number() != 1 || lines.had_comment()) {
      return SetProblem(problem, "binary OFF must start with its header alone on line 1");
    }
    return CheckBinaryOff(text, lines.next_offset(), keyword, check, problem);
  }

  // Counts "nV nF nE": on the header line after the keyword, or the next line.
  Tokens counts;
  if (!FindOffCounts(&lines, &counts)) {
    return SetProblem(problem, "truncated: the file ends before the vertex/face/edge counts");
  }
  const int counts_line = lines.line_number();
  long long num_vertices = -1, num_faces = -1, num_edges = -1;
  if (counts.size() != 3 || !ParseInt(counts[0], &num_vertices) ||
      !ParseInt(counts[1], &num_faces) || !ParseInt(counts[2], &num_edges) || num_vertices < 0 ||
      num_faces < 0 || num_edges < 0 || num_vertices > std::numeric_limits<int>::max() ||
      num_faces > std::numeric_limits<int>::max()) {
    return lines.Fail(problem, "expected three counts 'vertices faces edges' after the header");
  }
  check->num_vertices = static_cast<int>(num_vertices);
  check->num_faces = static_cast<int>(num_faces);

  // The remaining lines: vertices, then faces. Only lines with content count.
  const long long total = num_vertices + num_faces;
  const MeshReadOptions& options = check->options;
  const std::vector<size_t> bounds =
      options.num_threads > 1
          ? LineChunks(text, lines.next_offset(), text.size(), options.text_chunk_bytes)
          : std::vector<size_t>{lines.next_offset(), text.size()};
  std::vector<OffPiece> pieces(bounds.size() - 1);
  for (size_t c = 0; c < pieces.size(); ++c) {
    pieces[c].text = text.substr(bounds[c], bounds[c + 1] - bounds[c]);
  }
  // Several pieces are counted first; their vertices then go straight to
  // their place in `xyz` (as many as the lines can hold).
  const bool counted = pieces.size() > 1;
  UninitializedVector<double> xyz;
  if (counted) {
    ForEachTask(static_cast<int>(pieces.size()), options.num_threads,
                 [&pieces](int c) { CountOffPiece(&pieces[c]); });
    long long lines_with_content = 0;
    for (const OffPiece& piece : pieces) lines_with_content += piece.items;
    xyz.resize(3 * static_cast<size_t>(std::min(num_vertices, lines_with_content)));
  }
  for (size_t c = 0; c < pieces.size(); ++c) {
    OffPiece& piece = pieces[c];
    piece.lines_before = c == 0 ? counts_line : pieces[c - 1].lines_before + pieces[c - 1].lines;
    piece.first_item = c == 0 ? 0 : pieces[c - 1].first_item + pieces[c - 1].items;
    // Room for what the piece holds: its items when counted, else what its
    // bytes can hold ("0 0 0" and "3 0 1 2" with their line ends): the
    // header's counts are not trusted yet.
    if (counted) piece.xyz_out = xyz.data();
    const long long items = counted
                                ? piece.items
                                : static_cast<long long>(
                                      ReservationFor(total, piece.text.size(), 6));
    const long long vertices =
        std::clamp(num_vertices - piece.first_item, 0LL, std::min(items, num_vertices));
    const size_t faces = ReservationFor(std::min(items - vertices, num_faces), piece.text.size(),
                                        8);
    if (!counted) piece.soup.xyz.reserve(3 * static_cast<size_t>(vertices));
    piece.soup.face_offsets.reserve(faces + 1);
    piece.soup.face_ids.reserve(3 * faces);
  }
  ForEachTask(static_cast<int>(pieces.size()), options.num_threads, [&](int c) {
    if (pieces[c].first_item < total) ParseOffPiece(num_vertices, num_faces, &pieces[c]);
  });
  long long item = 0;
  for (const OffPiece& piece : pieces) {
    if (!piece.problem.empty()) return SetProblem(problem, piece.problem);
    if (piece.first_item < total) item += piece.items;
  }
  if (item < total) {
    std::ostringstream message;
    message << "truncated: the header (line " << counts_line << ") announces " << num_vertices
            << " vertices and " << num_faces << " faces, but the file ends after ";
    if (item < num_vertices) {
      message << item << " of " << num_vertices << " vertices";
    } else {
      message << item - num_vertices << " of " << num_faces << " faces";
    }
    *problem = message.str();
    return false;
  }
  std::vector<SoupPiece*> parts;
  for (OffPiece& piece : pieces) parts.push_back(&piece.soup);
  if (!ConcatenateSoupPieces(parts, options.num_threads, &check->soup)) {
    return SetProblem(problem, "too many vertices or faces");
  }
  if (counted) check->soup.xyz = std::move(xyz);
  check->read_data = true;
  return true;
}

}  // namespace

bool CheckOff(std::string_view text, FormatCheck* check, std::string* problem) {
  return CheckOffText(text, check, problem);
}

}  // namespace msdeform
