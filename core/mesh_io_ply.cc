// The PLY check. OpenMesh's PLY reader keeps going with stale values after a
// number fails to parse or the data ends, and its header parser crashes,
// hangs or allocates gigabytes on malformed input (found by
// tests/fuzz/ply_fuzzer). So the header is checked strictly here, then the
// data element by element: ASCII line by line, binary byte by byte.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "msdeform/core/mesh_io_formats.h"
#include "msdeform/core/text_lines.h"

namespace msdeform {
namespace {

using Tokens = TextLines::Tokens;

// Size in bytes of a PLY scalar type, 0 if unknown.
int PlyTypeSize(std::string_view type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" ||
      type == "float32") {
    return 4;
  }
  if (type == "double" || type == "float64") return 8;
  return 0;
}

struct PlyProperty {
  bool is_list = false;
  std::string_view type;        // scalar type, or the list's item type
  std::string_view count_type;  // lists only
  std::string_view name;
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  std::string format;  // "ascii", "binary_little_endian" or "binary_big_endian"
  std::vector<PlyElement> elements;
  int num_vertices = -1;  // the counts of the "vertex" and "face" elements; -1 when absent
  int num_faces = -1;
};

// Reads the header from the text's first line up to end_header, leaving
// `lines` on the end_header line.
bool ParsePlyHeader(TextLines* lines, PlyHeader* header, std::string* problem) {
  lines->Next();
  const Tokens& tokens = lines->tokens();
  if (tokens.size() != 1 || tokens[0] != "ply") {
    return SetProblem(problem, "line 1: expected the PLY magic 'ply', found ",
                      tokens.empty() ? std::string("nothing") : Quote(tokens[0]));
  }
  while (lines->Next()) {
    if (!tokens.empty() && (tokens[0] == "comment" || tokens[0] == "obj_info")) continue;
    // PLY has no '#' comments: OpenMesh reads "end_header#" as another
    // header line and then spends minutes on the binary data (found by
    // tests/fuzz/ply_fuzzer).
    if (lines->had_comment()) return lines->Fail(problem, "'#' in a PLY header line");
    if (tokens.empty()) continue;
    if (tokens[0] == "format") {
      if (!header->format.empty()) return lines->Fail(problem, "a second 'format' line");
      // OpenMesh loops forever on a version it cannot parse (found by
      // tests/fuzz/ply_fuzzer: 'format ascii @1.0'); PLY has only 1.0.
      if (tokens.size() != 3 ||
          (tokens[1] != "ascii" && tokens[1] != "binary_little_endian" &&
           tokens[1] != "binary_big_endian") ||
          tokens[2] != "1.0") {
        return lines->Fail(problem,
                           "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      }
      header->format = std::string(tokens[1]);
    } else if (tokens[0] == "element") {
      long long count = -1;
      if (tokens.size() != 3 || !ParseInt(tokens[2], &count) || count < 0 ||
          count > std::numeric_limits<int>::max()) {
        return lines->Fail(problem, "expected 'element <name> <count>'");
      }
      header->elements.push_back({std::string(tokens[1]), count, {}});
      if (tokens[1] == "vertex") header->num_vertices = static_cast<int>(count);
      if (tokens[1] == "face") header->num_faces = static_cast<int>(count);
    } else if (tokens[0] == "property") {
      // OpenMesh's header parser writes a property into the last element
      // without checking there is one (a segfault, found by
      // tests/fuzz/ply_fuzzer), so the header is checked strictly here.
      if (header->elements.empty()) return lines->Fail(problem, "'property' before any 'element'");
      const bool is_list = tokens.size() >= 2 && tokens[1] == "list";
      if (is_list
              ? (tokens.size() != 5 || PlyTypeSize(tokens[2]) == 0 || PlyTypeSize(tokens[3]) == 0)
              : (tokens.size() != 3 || PlyTypeSize(tokens[1]) == 0)) {
        return lines->Fail(problem,
                           "expected 'property <type> <name>' or 'property list <count type> "
                           "<item type> <name>' with PLY scalar types");
      }
      header->elements.back().properties.push_back(
          is_list ? PlyProperty{true, tokens[3], tokens[2], tokens[4]}
                  : PlyProperty{false, tokens[1], {}, tokens[2]});
    } else if (tokens[0] == "end_header") {
      // The data starts right after this line's end, so nothing else on it.
      if (lines->line() != "end_header") {
        return lines->Fail(problem, "expected 'end_header' alone on its line");
      }
      if (header->format.empty()) return SetProblem(problem, "the PLY header has no 'format' line");
      return true;
    } else {
      return lines->Fail(problem, "unknown PLY header keyword ", Quote(tokens[0]));
    }
  }
  return SetProblem(problem, "truncated: the PLY header has no end_header line");
}

bool IsFloatType(std::string_view type) {
  return type == "float" || type == "float32" || type == "double" || type == "float64";
}

// Which coordinate (0, 1, 2) each property of `element` is, -1 for the
// others, when `element` is "vertex" and has scalar float or double x, y
// and z (the last of a repeated name); else empty (OpenMesh's values are
// then kept).
std::vector<int> CoordinateSlots(const PlyElement& element) {
  if (element.name != "vertex") return {};
  int property_of[3] = {-1, -1, -1};
  for (size_t p = 0; p < element.properties.size(); ++p) {
    const PlyProperty& property = element.properties[p];
    for (int k = 0; k < 3; ++k) {
      if (property.name == std::string_view("xyz" + k, 1)) {
        property_of[k] = property.is_list || !IsFloatType(property.type) ? -2 : static_cast<int>(p);
      }
    }
  }
  if (property_of[0] < 0 || property_of[1] < 0 || property_of[2] < 0) return {};
  std::vector<int> slots(element.properties.size(), -1);
  for (int k = 0; k < 3; ++k) slots[property_of[k]] = k;
  return slots;
}

// True for the layout msdeform reads itself: a "vertex" element with float
// or double x, y, z (CoordinateSlots), then a "face" element whose one
// property is an integer list named vertex_indices (or vertex_index).
bool IsVertexFaceLayout(const PlyHeader& header) {
  if (header.elements.size() != 2 || header.elements[0].name != "vertex" ||
      header.elements[1].name != "face" || CoordinateSlots(header.elements[0]).empty() ||
      header.elements[1].properties.size() != 1) {
    return false;
  }
  const PlyProperty& list = header.elements[1].properties[0];
  return list.is_list && (list.name == "vertex_indices" || list.name == "vertex_index") &&
         !IsFloatType(list.type) && !IsFloatType(list.count_type);
}

// ASCII data after the header: one element per line, exactly its values,
// every value a finite number, a list count the number of values after it,
// face vertex ids in 0..num_vertex_ids - 1. The vertices' x, y, z (when
// CoordinateSlots finds them) go to soup->xyz: a double property's decimal as
// the nearest double, a float property's as the nearest float, widened. With
// `read_faces` (IsVertexFaceLayout) the faces go to the soup too; else
// OpenMesh reads the file after this check, and a value beyond the float
// range, which its stream input cannot take (it then reads the rest of the
// file out of step), is refused.
bool CheckAsciiPlyData(TextLines* lines, const PlyHeader& header, long long num_vertex_ids,
                       bool read_faces, PolygonSoup* soup, std::string* problem) {
  const Tokens& tokens = lines->tokens();
  UninitializedVector<double>* xyz = &soup->xyz;
  for (const PlyElement& element : header.elements) {
    const bool faces = read_faces && element.name == "face";
    const std::vector<int> slots = CoordinateSlots(element);
    const bool has_coordinates = !slots.empty();
    // Grown as the items are read: the header's count is not trusted yet.
    if (has_coordinates) xyz->clear();
    for (long long item = 0; item < element.count; ++item) {
      do {
        if (!lines->Next()) {
          return SetProblem(problem, "truncated: the file ends in element '", element.name, "' ",
                            item, " of ", element.count);
        }
        if (lines->had_comment()) return lines->Fail(problem, "'#' in PLY data");
      } while (tokens.empty());
      if (has_coordinates) xyz->insert(xyz->end(), 3, 0.0);
      for (const std::string_view& token : tokens) {
        double value = 0.0;
        if (!ParseDouble(token, &value) || !std::isfinite(value)) {
          return lines->Fail(problem, Quote(token), " is not a finite number");
        }
        float single = 0.0f;
        if (!read_faces && std::abs(value) > std::numeric_limits<float>::max() &&
            (!ParseFloat(token, &single) || !std::isfinite(single))) {
          return lines->Fail(problem, Quote(token),
                             " is beyond the float range, which OpenMesh's reader of this PLY "
                             "layout cannot take; keep only a vertex and a face element");
        }
      }
      size_t t = 0;
      for (size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        if (!property.is_list) {
          if (has_coordinates && slots[p] >= 0 && t < tokens.size()) {
            // (Beyond the float range a float property is infinite, refused
            // with the mesh's "non-finite coordinate", as OpenMesh's was.)
            double& coordinate = (*xyz)[3 * item + slots[p]];
            float single = 0.0f;
            if (PlyTypeSize(property.type) == 8) {
              ParseDouble(tokens[t], &coordinate);
            } else {
              ParseFloat(tokens[t], &single);
              coordinate = single;
            }
          }
          ++t;
          continue;
        }
        long long count = -1;
        if (t >= tokens.size() || !ParseInt(tokens[t], &count) || count < 0 ||
            count > static_cast<long long>(tokens.size() - t - 1)) {
          return lines->Fail(problem, element.name, " ", item,
                             ": a list count that is not the number of values after it");
        }
        for (long long k = 0; k < count && element.name == "face"; ++k) {
          long long id = -1;
          if (!ParseInt(tokens[t + 1 + k], &id) || id < 0 || id >= num_vertex_ids) {
            return lines->Fail(problem, "face ", item, ": vertex id ", Quote(tokens[t + 1 + k]),
                               " is not in 0..", num_vertex_ids - 1);
          }
          if (faces) soup->face_ids.push_back(static_cast<int>(id));
        }
        t += 1 + count;
      }
      if (faces) soup->face_offsets.push_back(static_cast<int>(soup->face_ids.size()));
      if (t != tokens.size()) {
        return lines->Fail(problem, element.name, " ", item, " has ", tokens.size(),
                           " values; its properties take ", t);
      }
    }
  }
  return true;
}

// The integer of PLY type `type` at text[at].
long long ReadPlyInt(std::string_view text, size_t at, std::string_view type, bool big_endian) {
  const int size = PlyTypeSize(type);
  unsigned long long bits = 0;
  for (int k = 0; k < size; ++k) {
    const size_t byte = at + (big_endian ? k : size - 1 - k);
    bits = (bits << 8) | static_cast<unsigned char>(text[byte]);
  }
  const bool is_signed = type == "char" || type == "int8" || type == "short" || type == "int16" ||
                         type == "int" || type == "int32";
  if (is_signed && size < 8 && (bits >> (8 * size - 1)) != 0) {
    return static_cast<long long>(bits) - (1LL << (8 * size));
  }
  return static_cast<long long>(bits);
}

// The float (size 4) or double (size 8) at text[at], widened to double.
double ReadPlyReal(std::string_view text, size_t at, int size, bool big_endian) {
  unsigned long long bits = 0;
  for (int k = 0; k < size; ++k) {
    const size_t byte = at + (big_endian ? k : size - 1 - k);
    bits = (bits << 8) | static_cast<unsigned char>(text[byte]);
  }
  if (size == 8) {
    double value;
    std::memcpy(&value, &bits, sizeof(value));
    return value;
  }
  const uint32_t low = static_cast<uint32_t>(bits);
  float value;
  std::memcpy(&value, &low, sizeof(value));
  return value;
}

// Binary data from text[at]: every element's properties within the file, a
// list count within the rest of the file, integer face vertex ids in
// 0..num_vertex_ids - 1. The vertices' x, y, z (when CoordinateSlots finds
// them) go to *xyz as they are stored (a float widened).
bool CheckBinaryPlyData(std::string_view text, size_t at, const PlyHeader& header,
                        long long num_vertex_ids, UninitializedVector<double>* xyz,
                        std::string* problem) {
  const bool big_endian = header.format == "binary_big_endian";
  for (const PlyElement& element : header.elements) {
    const std::vector<int> slots = CoordinateSlots(element);
    // Grown as the items are read: the header's count is not trusted yet.
    if (!slots.empty()) xyz->clear();
    for (long long item = 0; item < element.count; ++item) {
      if (!slots.empty()) xyz->insert(xyz->end(), 3, 0.0);
      for (size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        const size_t size = PlyTypeSize(property.is_list ? property.count_type : property.type);
        if (text.size() - at < size) {
          return SetProblem(problem, "truncated: the binary data ends in element '", element.name,
                            "' ", item, " of ", element.count);
        }
        if (!property.is_list) {
          if (!slots.empty() && slots[p] >= 0) {
            (*xyz)[3 * item + slots[p]] = ReadPlyReal(text, at, static_cast<int>(size), big_endian);
          }
          at += size;
          continue;
        }
        const long long count = ReadPlyInt(text, at, property.count_type, big_endian);
        at += size;
        const size_t item_size = PlyTypeSize(property.type);
        if (count < 0 || static_cast<unsigned long long>(count) > (text.size() - at) / item_size) {
          return SetProblem(problem, "binary ", element.name, " ", item, ": list count ", count,
                            " is negative or runs past the end of the file");
        }
        const bool is_float = property.type == "float" || property.type == "float32" ||
                              property.type == "double" || property.type == "float64";
        for (long long k = 0; k < count && element.name == "face" && !is_float; ++k) {
          const long long id = ReadPlyInt(text, at + k * item_size, property.type, big_endian);
          if (id < 0 || id >= num_vertex_ids) {
            return SetProblem(problem, "binary face ", item, ": a vertex id is not in 0..",
                              num_vertex_ids - 1);
          }
        }
        at += count * item_size;
      }
    }
  }
  return true;
}

bool IsSignedType(std::string_view type) {
  return type == "char" || type == "int8" || type == "short" || type == "int16" ||
         type == "int" || type == "int32";
}

// A little-endian integer of `size` bytes at `at`.
long long LoadInt(const char* at, int size, bool is_signed) {
  switch (size) {
    case 1:
      return is_signed ? static_cast<long long>(static_cast<signed char>(*at))
                       : static_cast<long long>(static_cast<unsigned char>(*at));
    case 2: {
      uint16_t bits;
      std::memcpy(&bits, at, 2);
      return is_signed ? static_cast<long long>(static_cast<int16_t>(bits)) : bits;
    }
    default: {
      uint32_t bits;
      std::memcpy(&bits, at, 4);
      return is_signed ? static_cast<long long>(static_cast<int32_t>(bits)) : bits;
    }
  }
}

// A coordinate as it is stored: a double, or a float widened (exactly).
double LoadCoordinate(const char* at, bool is_double) {
  if (is_double) {
    double value;
    std::memcpy(&value, at, sizeof(value));
    return value;
  }
  float value;
  std::memcpy(&value, at, sizeof(value));
  return value;
}

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the binary PLY reader loads little-endian values as they are");

// Binary faces that all have the first face's vertex count k >= 1, so that
// face i starts at at + i * (count_size + k * item_size): sets *read and
// reads them into soup->face_ids and face_offsets, or returns false with the
// walk's message for the first face with an id out of range. Leaves *read
// false when the faces are not of that kind or do not fit the file (the walk
// one by one then reads them, with its messages).
bool ReadUniformBinaryFaces(std::string_view text, size_t at, long long num_faces,
                            int count_size, bool count_signed, int item_size, bool item_signed,
                            long long num_vertices, const MeshReadOptions& options,
                            PolygonSoup* soup, bool* read, std::string* problem) {
  *read = false;
  const size_t bytes_left = text.size() - at;
  if (num_faces <= 0 || bytes_left < static_cast<size_t>(count_size)) return true;
  const long long k = LoadInt(text.data() + at, count_size, count_signed);
  if (k < 1 || k > std::numeric_limits<int>::max() / num_faces) return true;
  const size_t face_bytes = count_size + static_cast<size_t>(k) * item_size;
  if (static_cast<unsigned long long>(num_faces) > bytes_left / face_bytes) return true;
  const char* data = text.data() + at;
  const long long per = ChunkItems(num_faces, options.items_per_chunk);
  const int chunks = NumChunks(num_faces, per);
  std::vector<char> uniform(chunks, 1);
  ForEachTask(chunks, options.num_threads, [&](int c) {
    const long long end = std::min(num_faces, (c + 1) * per);
    for (long long i = c * per; i < end; ++i) {
      if (LoadInt(data + i * face_bytes, count_size, count_signed) != k) {
        uniform[c] = 0;
        return;
      }
    }
  });
  if (std::find(uniform.begin(), uniform.end(), 0) != uniform.end()) return true;
  *read = true;
  soup->face_ids.resize(static_cast<size_t>(k * num_faces));
  soup->face_offsets.resize(static_cast<size_t>(num_faces) + 1);
  soup->face_offsets[0] = 0;
  // Each chunk's first face with an id out of range; -1 when none.
  std::vector<long long> first_bad(chunks, -1);
  ForEachTask(chunks, options.num_threads, [&](int c) {
    const long long end = std::min(num_faces, (c + 1) * per);
    for (long long i = c * per; i < end; ++i) {
      const char* ids = data + i * face_bytes + count_size;
      for (long long j = 0; j < k; ++j) {
        const long long id = LoadInt(ids + j * item_size, item_size, item_signed);
        if (id < 0 || id >= num_vertices) {
          first_bad[c] = i;
          return;
        }
        soup->face_ids[k * i + j] = static_cast<int>(id);
      }
      soup->face_offsets[i + 1] = static_cast<int>(k * (i + 1));
    }
  });
  for (long long bad : first_bad) {
    if (bad >= 0) {
      return SetProblem(problem, "binary face ", bad, ": a vertex id is not in 0..",
                        num_vertices - 1);
    }
  }
  return true;
}

// The common binary layout, read in the check's one pass: little-endian, a
// "vertex" element of scalar properties with float or double x, y, z, then a
// "face" element whose one property is an integer list named vertex_indices
// (or vertex_index). Returns false without a problem when the file has
// another layout (CheckBinaryPlyData and OpenMesh take it); with a problem
// when the data is bad. The checks are CheckBinaryPlyData's, with its
// messages.
// The vertices and faces are decoded in chunks of
// ChunkItems(options.items_per_chunk) on options.num_threads threads: a
// vertex's bytes are at a fixed stride, and so are a face's when every face
// has the first face's vertex count (checked in parallel first, then each
// face is where the walk one by one would find it); otherwise the faces are
// walked one by one.
bool ReadCommonBinaryPly(std::string_view text, size_t at, const PlyHeader& header,
                         const MeshReadOptions& options, PolygonSoup* soup, bool* handled,
                         std::string* problem) {
  *handled = false;
  if (header.format != "binary_little_endian" || header.elements.size() != 2 ||
      header.elements[0].name != "vertex" || header.elements[1].name != "face") {
    return true;
  }
  const PlyElement& vertex = header.elements[0];
  const PlyElement& face = header.elements[1];
  int offset[3] = {-1, -1, -1};
  bool is_double[3] = {false, false, false};
  size_t stride = 0;
  for (const PlyProperty& property : vertex.properties) {
    if (property.is_list) return true;
    for (int k = 0; k < 3; ++k) {
      if (property.name == std::string_view("xyz" + k, 1) && IsFloatType(property.type)) {
        offset[k] = static_cast<int>(stride);
        is_double[k] = PlyTypeSize(property.type) == 8;
      }
    }
    stride += PlyTypeSize(property.type);
  }
  if (offset[0] < 0 || offset[1] < 0 || offset[2] < 0 || face.properties.size() != 1) return true;
  const PlyProperty& list = face.properties[0];
  if (!list.is_list || (list.name != "vertex_indices" && list.name != "vertex_index") ||
      IsFloatType(list.type) || PlyTypeSize(list.type) > 4 || PlyTypeSize(list.count_type) > 4 ||
      IsFloatType(list.count_type)) {
    return true;
  }
  *handled = true;

  const long long num_vertices = vertex.count;
  if (static_cast<unsigned long long>(num_vertices) > (text.size() - at) / std::max<size_t>(stride, 1) ||
      (stride == 0 && num_vertices > 0)) {
    // Where the data ends, as the element walk reports it.
    const long long complete = stride == 0 ? 0 : static_cast<long long>((text.size() - at) / stride);
    return SetProblem(problem, "truncated: the binary data ends in element 'vertex' ", complete,
                      " of ", num_vertices);
  }
  const int threads = options.num_threads;
  soup->xyz.resize(3 * static_cast<size_t>(num_vertices));
  const long long vertex_per = ChunkItems(num_vertices, options.items_per_chunk);
  ForEachTask(NumChunks(num_vertices, vertex_per), threads, [&](int c) {
    const long long end = std::min(num_vertices, (c + 1) * vertex_per);
    for (long long v = c * vertex_per; v < end; ++v) {
      const char* data = text.data() + at + v * stride;
      for (int k = 0; k < 3; ++k) {
        soup->xyz[3 * v + k] = LoadCoordinate(data + offset[k], is_double[k]);
      }
    }
  });
  at += static_cast<size_t>(num_vertices) * stride;

  const int count_size = PlyTypeSize(list.count_type);
  const bool count_signed = IsSignedType(list.count_type);
  const int item_size = PlyTypeSize(list.type);
  const bool item_signed = IsSignedType(list.type);
  bool read = false;
  if (!ReadUniformBinaryFaces(text, at, face.count, count_size, count_signed, item_size,
                              item_signed, num_vertices, options, soup, &read, problem)) {
    return false;
  }
  if (read) return true;
  soup->face_offsets.assign(1, 0);
  // A face takes at least its count and three ids; the header's count is not
  // trusted before the faces are read.
  const size_t max_faces =
      ReservationFor(face.count, text.size() - at, count_size + 3 * static_cast<size_t>(item_size));
  soup->face_offsets.reserve(max_faces + 1);
  soup->face_ids.reserve(3 * max_faces);
  for (long long item = 0; item < face.count; ++item) {
    if (text.size() - at < static_cast<size_t>(count_size)) {
      return SetProblem(problem, "truncated: the binary data ends in element 'face' ", item,
                        " of ", face.count);
    }
    const long long count = LoadInt(text.data() + at, count_size, count_signed);
    at += count_size;
    if (count < 0 || static_cast<unsigned long long>(count) > (text.size() - at) / item_size) {
      return SetProblem(problem, "binary face ", item, ": list count ", count,
                        " is negative or runs past the end of the file");
    }
    for (long long k = 0; k < count; ++k, at += item_size) {
      const long long id = LoadInt(text.data() + at, item_size, item_signed);
      if (id < 0 || id >= num_vertices) {
        return SetProblem(problem, "binary face ", item, ": a vertex id is not in 0..",
                          num_vertices - 1);
      }
      soup->face_ids.push_back(static_cast<int>(id));
    }
    soup->face_offsets.push_back(static_cast<int>(soup->face_ids.size()));
  }
  return true;
}

}  // namespace

// The data is walked element by element and property by property so that a
// list count cannot promise more items than the file holds (OpenMesh
// allocates what a face's count says: 3 GB for '3999...9 3 2 3', found by
// tests/fuzz/ply_fuzzer) and face vertex ids are in range.
bool CheckPly(std::string_view text, FormatCheck* check, std::string* problem) {
  TextLines lines(text);
  PlyHeader header;
  if (!ParsePlyHeader(&lines, &header, problem)) return false;
  check->num_vertices = header.num_vertices;
  check->num_faces = header.num_faces;
  const long long num_vertex_ids = std::max(header.num_vertices, 0);
  // Outside the common binary layout OpenMesh reads the file, and the
  // coordinates the check reads (exact, where OpenMesh's go through float)
  // replace its own when the vertex element has float or double x, y, z.
  check->soup = PolygonSoup();
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex") check->read_coordinates = !CoordinateSlots(element).empty();
  }
  if (header.format == "ascii") {
    const bool read_faces = IsVertexFaceLayout(header);
    if (!CheckAsciiPlyData(&lines, header, num_vertex_ids, read_faces, &check->soup, problem)) {
      return false;
    }
    check->read_data = read_faces;
    check->read_coordinates = check->read_coordinates && !read_faces;
    return true;
  }
  bool handled = false;
  if (!ReadCommonBinaryPly(text, lines.next_offset(), header, check->options, &check->soup,
                           &handled, problem)) {
    return false;
  }
  if (handled) {
    check->read_data = true;
    check->read_coordinates = false;
    return true;
  }
  return CheckBinaryPlyData(text, lines.next_offset(), header, num_vertex_ids, &check->soup.xyz,
                            problem);
}

}  // namespace msdeform
