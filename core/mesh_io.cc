#include "msdeform/core/mesh_io.h"

#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <string_view>
#include <vector>

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/exporter/BaseExporter.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "msdeform/core/atomic_file.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;
using OpenMesh::EdgeHandle;
using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::Vec2f;
using OpenMesh::Vec3d;
using OpenMesh::Vec3f;
using OpenMesh::Vec3i;
using OpenMesh::Vec3uc;
using OpenMesh::Vec3ui;
using OpenMesh::Vec4f;
using OpenMesh::Vec4uc;
using OpenMesh::Vec4ui;
using OpenMesh::VertexHandle;
using StatusInfo = OpenMesh::Attributes::StatusInfo;

bool Fail(const std::string& path, const std::string& problem, std::string* error) {
  *error = path + ": " + problem;
  return false;
}

// Lower-case extension without the dot ("" when there is none).
std::string LowerExtension(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  if (!extension.empty()) extension.erase(0, 1);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

// Turns OpenMesh's own omerr/omlog/omout printing off for its lifetime: our
// errors are the one-line messages below. (A few OpenMesh readers print to
// std::cerr directly; those cannot be silenced here.)
class ScopedOpenMeshSilence {
 public:
  ScopedOpenMeshSilence()
      : err_(::omerr().is_enabled()), log_(::omlog().is_enabled()), out_(::omout().is_enabled()) {
    ::omerr().disable();
    ::omlog().disable();
    ::omout().disable();
  }
  ~ScopedOpenMeshSilence() {
    if (err_) ::omerr().enable();
    if (log_) ::omlog().enable();
    if (out_) ::omout().enable();
  }
  ScopedOpenMeshSilence(const ScopedOpenMeshSilence&) = delete;
  ScopedOpenMeshSilence& operator=(const ScopedOpenMeshSilence&) = delete;

 private:
  bool err_, log_, out_;
};

// Records what a reader hands over, in order, and nothing else: vertices as
// they are added and faces as raw index lists. No halfedge structure is built,
// so nothing is dropped or duplicated for non-manifold input.
class RawImporter : public OpenMesh::IO::BaseImporter {
 public:
  std::vector<double> xyz;           // 3 #V
  std::vector<int> face_offsets{0};  // #polygons + 1
  std::vector<int> face_ids;         // vertex ids of all polygons
  int num_polygons() const { return static_cast<int>(face_offsets.size()) - 1; }

  VertexHandle add_vertex(const Vec3f& p) override { return AddVertex(p[0], p[1], p[2]); }
  VertexHandle add_vertex(const Vec3d& p) override { return AddVertex(p[0], p[1], p[2]); }
  VertexHandle add_vertex() override { return AddVertex(0.0, 0.0, 0.0); }
  void set_point(VertexHandle vh, const Vec3f& p) override {
    const int v = vh.idx();
    if (v < 0 || 3 * static_cast<size_t>(v) >= xyz.size()) return;
    for (int k = 0; k < 3; ++k) xyz[3 * v + k] = p[k];
  }
  FaceHandle add_face(const VHandles& ids) override {
    for (const VertexHandle& vh : ids) face_ids.push_back(vh.idx());
    face_offsets.push_back(static_cast<int>(face_ids.size()));
    return FaceHandle(num_polygons() - 1);
  }
  size_t n_vertices() const override { return xyz.size() / 3; }
  size_t n_faces() const override { return static_cast<size_t>(num_polygons()); }
  size_t n_edges() const override { return 0; }
  void reserve(unsigned int num_vertices, unsigned int, unsigned int num_faces) override {
    // Headers may lie (truncated files); cap what we trust them for.
    xyz.reserve(3 * std::min(num_vertices, 1u << 24));
    face_offsets.reserve(std::min(num_faces, 1u << 24) + 1);
  }

  // Everything else a reader may offer is ignored.
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_normal(VertexHandle, const Vec3f&) override {}
  void set_normal(VertexHandle, const Vec3d&) override {}
  void set_color(VertexHandle, const Vec3uc&) override {}
  void set_color(VertexHandle, const Vec4uc&) override {}
  void set_color(VertexHandle, const Vec3f&) override {}
  void set_color(VertexHandle, const Vec4f&) override {}
  void set_texcoord(VertexHandle, const Vec2f&) override {}
  void set_status(VertexHandle, const StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
  void set_texcoord(VertexHandle, const Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
  void set_status(HalfedgeHandle, const StatusInfo&) override {}
  void set_color(EdgeHandle, const Vec3uc&) override {}
  void set_color(EdgeHandle, const Vec4uc&) override {}
  void set_color(EdgeHandle, const Vec3f&) override {}
  void set_color(EdgeHandle, const Vec4f&) override {}
  void set_status(EdgeHandle, const StatusInfo&) override {}
  void set_normal(FaceHandle, const Vec3f&) override {}
  void set_normal(FaceHandle, const Vec3d&) override {}
  void set_color(FaceHandle, const Vec3uc&) override {}
  void set_color(FaceHandle, const Vec4uc&) override {}
  void set_color(FaceHandle, const Vec3f&) override {}
  void set_color(FaceHandle, const Vec4f&) override {}
  void set_status(FaceHandle, const StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}

 private:
  VertexHandle AddVertex(double x, double y, double z) {
    xyz.push_back(x);
    xyz.push_back(y);
    xyz.push_back(z);
    return VertexHandle(static_cast<int>(xyz.size() / 3) - 1);
  }
};

// Presents the Mesh arrays to OpenMesh's writers: positions, triangles, and
// no attributes.
class RawExporter : public OpenMesh::IO::BaseExporter {
 public:
  explicit RawExporter(const Mesh& mesh) : mesh_(mesh) {}

  Vec3f point(VertexHandle vh) const override {
    const auto p = mesh_.vertices.col(vh.idx());
    return Vec3f(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  }
  Vec3d pointd(VertexHandle vh) const override {
    const auto p = mesh_.vertices.col(vh.idx());
    return Vec3d(p.x(), p.y(), p.z());
  }
  bool is_point_double() const override { return true; }
  unsigned int get_vhandles(FaceHandle fh, std::vector<VertexHandle>& ids) const override {
    ids.clear();
    for (int c = 0; c < 3; ++c) ids.emplace_back(mesh_.faces(c, fh.idx()));
    return 3;
  }
  size_t n_vertices() const override { return static_cast<size_t>(mesh_.num_vertices()); }
  size_t n_faces() const override { return static_cast<size_t>(mesh_.num_faces()); }
  size_t n_edges() const override { return 0; }
  bool is_triangle_mesh() const override { return true; }
  // OpenMesh's PLY writer walks the kernel's custom properties without
  // checking for null; an empty kernel has none.
  const OpenMesh::BaseKernel* kernel() override { return &empty_kernel_; }

  // No attributes: writers only ask for them when Options request them.
  Vec3f normal(VertexHandle) const override { return Vec3f(0.f); }
  Vec3d normald(VertexHandle) const override { return Vec3d(0.0); }
  bool is_normal_double() const override { return false; }
  Vec3uc color(VertexHandle) const override { return Vec3uc(0); }
  Vec4uc colorA(VertexHandle) const override { return Vec4uc(0); }
  Vec3ui colori(VertexHandle) const override { return Vec3ui(0); }
  Vec4ui colorAi(VertexHandle) const override { return Vec4ui(0); }
  Vec3f colorf(VertexHandle) const override { return Vec3f(0.f); }
  Vec4f colorAf(VertexHandle) const override { return Vec4f(0.f); }
  Vec2f texcoord(VertexHandle) const override { return Vec2f(0.f); }
  Vec2f texcoord(HalfedgeHandle) const override { return Vec2f(0.f); }
  StatusInfo status(VertexHandle) const override { return StatusInfo(); }
  HalfedgeHandle getHeh(FaceHandle, VertexHandle) const override { return HalfedgeHandle(); }
  unsigned int get_face_texcoords(std::vector<Vec2f>& texcoords) const override {
    texcoords.clear();
    return 0;
  }
  Vec3f normal(FaceHandle) const override { return Vec3f(0.f); }
  Vec3d normald(FaceHandle) const override { return Vec3d(0.0); }
  Vec3uc color(FaceHandle) const override { return Vec3uc(0); }
  Vec4uc colorA(FaceHandle) const override { return Vec4uc(0); }
  Vec3ui colori(FaceHandle) const override { return Vec3ui(0); }
  Vec4ui colorAi(FaceHandle) const override { return Vec4ui(0); }
  Vec3f colorf(FaceHandle) const override { return Vec3f(0.f); }
  Vec4f colorAf(FaceHandle) const override { return Vec4f(0.f); }
  StatusInfo status(FaceHandle) const override { return StatusInfo(); }
  Vec3uc color(EdgeHandle) const override { return Vec3uc(0); }
  Vec4uc colorA(EdgeHandle) const override { return Vec4uc(0); }
  Vec3ui colori(EdgeHandle) const override { return Vec3ui(0); }
  Vec4ui colorAi(EdgeHandle) const override { return Vec4ui(0); }
  Vec3f colorf(EdgeHandle) const override { return Vec3f(0.f); }
  Vec4f colorAf(EdgeHandle) const override { return Vec4f(0.f); }
  StatusInfo status(EdgeHandle) const override { return StatusInfo(); }
  int get_halfedge_id(VertexHandle) override { return -1; }
  int get_halfedge_id(FaceHandle) override { return -1; }
  int get_next_halfedge_id(HalfedgeHandle) override { return -1; }
  int get_to_vertex_id(HalfedgeHandle) override { return -1; }
  int get_face_id(HalfedgeHandle) override { return -1; }
  StatusInfo status(HalfedgeHandle) const override { return StatusInfo(); }

 private:
  const Mesh& mesh_;
  OpenMesh::BaseKernel empty_kernel_;
};

// ---------------------------------------------------------------------------
// OFF pre-check. OpenMesh's OFF reader trusts the header: on a truncated file
// or an unparsable number it keeps calling add_vertex/add_face with stale
// values. So the text is checked here first, line by line, and the counts the
// header announces are compared with what OpenMesh delivers.

struct OffCheck {
  bool binary = false;
  int num_vertices = 0;  // as announced by the header
  int num_faces = 0;
  // Set when the file is valid OFF but laid out in a way OpenMesh's reader
  // does not follow ('#' comments, counts on the header line, leading blank
  // lines, face colours without 'C' in the header); NormalizeOff then writes
  // the same geometry in the plain layout.
  bool needs_normalizing = false;
};

using Tokens = std::vector<std::string_view>;

// Splits one line (without '\n') into whitespace-separated tokens, dropping a
// '#' comment. Sets *had_comment when there was one.
void Tokenize(std::string_view line, Tokens* tokens, bool* had_comment) {
  tokens->clear();
  *had_comment = false;
  const size_t hash = line.find('#');
  if (hash != std::string_view::npos) {
    line = line.substr(0, hash);
    *had_comment = true;
  }
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    size_t j = i;
    while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
    if (j > i) tokens->push_back(line.substr(i, j - i));
    i = j;
  }
}

std::string Quote(std::string_view token) {
  constexpr size_t kMax = 24;
  if (token.size() <= kMax) return "'" + std::string(token) + "'";
  return "'" + std::string(token.substr(0, kMax)) + "...'";
}

bool ParseInt(std::string_view token, long long* value) {
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, *value);
  return result.ec == std::errc() && result.ptr == end;
}

// strtod rather than from_chars so that "nan" and "inf" are recognised and
// reported as non-finite instead of as junk.
bool ParseDouble(std::string_view token, double* value) {
  const std::string copy(token);
  char* end = nullptr;
  *value = std::strtod(copy.c_str(), &end);
  return end == copy.c_str() + copy.size() && !copy.empty();
}

// Reads the next line of `text` starting at *pos; returns false at the end.
bool NextLine(const std::string& text, size_t* pos, std::string_view* line) {
  if (*pos >= text.size()) return false;
  size_t end = text.find('\n', *pos);
  if (end == std::string::npos) end = text.size();
  *line = std::string_view(text).substr(*pos, end - *pos);
  if (!line->empty() && line->back() == '\r') line->remove_suffix(1);
  *pos = end + 1;
  return true;
}

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

bool CheckBinaryOff(const std::string& text, size_t data_start, const std::string& keyword,
                    OffCheck* check, std::string* problem) {
  // OpenMesh's binary reader takes colours, normals and texture coordinates
  // from the keyword with a layout of its own; only plain OFF is checked
  // (and so accepted) here.
  if (keyword != "OFF") {
    *problem = "line 1: binary " + Quote(keyword) + " is not supported; use binary OFF or ASCII";
    return false;
  }
  // Binary OFF: three little-endian uint32 counts follow the header line.
  if (text.size() < data_start + 12) {
    *problem = "truncated: binary OFF ends before the vertex/face/edge counts";
    return false;
  }
  uint32_t counts[3];
  std::memcpy(counts, text.data() + data_start, sizeof(counts));
  if (counts[0] > static_cast<uint32_t>(std::numeric_limits<int>::max()) ||
      counts[1] > static_cast<uint32_t>(std::numeric_limits<int>::max())) {
    *problem = "binary OFF header announces an impossible vertex or face count";
    return false;
  }
  check->num_vertices = static_cast<int>(counts[0]);
  check->num_faces = static_cast<int>(counts[1]);
  // At least 3 floats per vertex and 1 + 3 ints per face.
  const uint64_t minimum = data_start + 12 + 12ull * counts[0] + 16ull * counts[1];
  if (text.size() < minimum) {
    std::ostringstream message;
    message << "truncated: the binary OFF header announces " << counts[0] << " vertices and "
            << counts[1] << " faces, which need at least " << minimum << " bytes, but the file has "
            << text.size();
    *problem = message.str();
    return false;
  }
  // Each face: an int32 vertex count, then that many int32 ids. OpenMesh
  // sizes its id list by the count before reading, so a wild count would
  // allocate gigabytes (found by tests/fuzz/off_fuzzer): walk them first.
  uint64_t offset = data_start + 12 + 12ull * counts[0];
  for (uint32_t face = 0; face < counts[1]; ++face) {
    std::ostringstream message;
    if (text.size() < offset + 4) {
      message << "truncated: binary OFF ends in face " << face << " of " << counts[1];
      *problem = message.str();
      return false;
    }
    int32_t size = 0;
    std::memcpy(&size, text.data() + offset, sizeof(size));
    offset += 4;
    if (size < 3 || text.size() < offset + 4ull * static_cast<uint64_t>(size)) {
      message << "binary OFF face " << face << " announces " << size
              << " vertices; need at least 3, all in the file";
      *problem = message.str();
      return false;
    }
    for (int32_t k = 0; k < size; ++k, offset += 4) {
      int32_t id = 0;
      std::memcpy(&id, text.data() + offset, sizeof(id));
      if (id < 0 || static_cast<uint32_t>(id) >= counts[0]) {
        message << "binary OFF face " << face << " refers to vertex " << id << ", outside 0.."
                << static_cast<int64_t>(counts[0]) - 1;
        *problem = message.str();
        return false;
      }
    }
  }
  return true;
}

// tokens[first], tokens[first + 1], tokens[first + 2]: the coordinates of
// vertex `vertex` on line `line_number` of an OFF or OBJ text; each must be a
// finite number.
bool CheckVertexCoordinates(const Tokens& tokens, size_t first, int line_number,
                            long long vertex, std::string* problem) {
  std::ostringstream message;
  message << "line " << line_number << ": vertex " << vertex;
  if (tokens.size() < first + 3) {
    *problem = message.str() + " has fewer than 3 coordinates";
    return false;
  }
  for (size_t k = first; k < first + 3; ++k) {
    double value = 0.0;
    if (!ParseDouble(tokens[k], &value)) {
      message << " coordinate " << Quote(tokens[k]) << " is not a number";
      *problem = message.str();
      return false;
    }
    if (!std::isfinite(value)) {
      message << " coordinate " << Quote(tokens[k]) << " is not finite";
      *problem = message.str();
      return false;
    }
  }
  return true;
}

// Checks the OFF text; on failure puts "line N: ..." (or a whole-file problem)
// in *problem.
bool CheckOff(const std::string& text, OffCheck* check, std::string* problem) {
  std::ostringstream message;
  size_t pos = 0;
  int line_number = 0;
  std::string_view line;
  Tokens tokens;
  bool had_comment = false;
  // Any '#' comment means OpenMesh needs a cleaned copy (binary OFF aside).
  const bool has_hash = text.find('#') != std::string::npos;

  // Header: first line with content.
  bool found_header = false;
  while (NextLine(text, &pos, &line)) {
    ++line_number;
    Tokenize(line, &tokens, &had_comment);
    if (!tokens.empty()) {
      found_header = true;
      break;
    }
    check->needs_normalizing = true;  // OpenMesh wants the keyword on line 1.
  }
  if (!found_header) {
    *problem = "no OFF header: the file holds only blank or comment lines";
    return false;
  }
  bool other_dimension = false;
  if (!IsOffKeyword(tokens[0], &other_dimension)) {
    message << "line " << line_number << ": expected an OFF header such as 'OFF' or 'COFF', found "
            << Quote(tokens[0]);
    *problem = message.str();
    return false;
  }
  if (other_dimension) {
    message << "line " << line_number << ": " << Quote(tokens[0])
            << " (4D or nD vertices) is not supported; use 3D OFF";
    *problem = message.str();
    return false;
  }
  const std::string keyword(tokens[0]);
  if (tokens.size() >= 2 && tokens[1] == "BINARY") {
    check->binary = true;
    if (line_number != 1 || had_comment) {
      *problem = "binary OFF must start with its header alone on line 1";
      return false;
    }
    return CheckBinaryOff(text, pos, keyword, check, problem);
  }
  check->needs_normalizing |= has_hash;
  // With ST, C or N in the keyword OpenMesh reads texture coordinates,
  // colours and normals token by token across line ends, so a vertex line
  // without them shifts everything after it: a coordinate becomes a face's
  // vertex count, and a count of billions made OpenMesh allocate gigabytes
  // (found by tests/fuzz/off_fuzzer). The plain copy has only what this check
  // read line by line.
  check->needs_normalizing |= keyword != "OFF";

  // Counts "nV nF nE": on the header line after the keyword, or the next line.
  Tokens counts(tokens.begin() + 1, tokens.end());
  int counts_line = line_number;
  if (counts.empty()) {
    bool found = false;
    while (NextLine(text, &pos, &line)) {
      ++line_number;
      Tokenize(line, &tokens, &had_comment);
      if (!tokens.empty()) {
        found = true;
        break;
      }
    }
    if (!found) {
      *problem = "truncated: the file ends before the vertex/face/edge counts";
      return false;
    }
    counts = tokens;
    counts_line = line_number;
  } else {
    check->needs_normalizing = true;  // OpenMesh skips the rest of the header line.
  }
  long long num_vertices = -1, num_faces = -1, num_edges = -1;
  if (counts.size() != 3 || !ParseInt(counts[0], &num_vertices) ||
      !ParseInt(counts[1], &num_faces) || !ParseInt(counts[2], &num_edges) || num_vertices < 0 ||
      num_faces < 0 || num_edges < 0 || num_vertices > std::numeric_limits<int>::max() ||
      num_faces > std::numeric_limits<int>::max()) {
    message << "line " << counts_line
            << ": expected three counts 'vertices faces edges' after the header";
    *problem = message.str();
    return false;
  }
  check->num_vertices = static_cast<int>(num_vertices);
  check->num_faces = static_cast<int>(num_faces);

  const bool has_colors = keyword.find('C') != std::string::npos;
  // The remaining lines: vertices, then faces. Only lines with content count.
  const long long total = num_vertices + num_faces;
  long long item = 0;
  while (item < total && NextLine(text, &pos, &line)) {
    ++line_number;
    Tokenize(line, &tokens, &had_comment);
    if (tokens.empty()) continue;
    if (item < num_vertices) {
      if (!CheckVertexCoordinates(tokens, 0, line_number, item, problem)) return false;
    } else {
      const long long face = item - num_vertices;
      long long size = 0;
      if (!ParseInt(tokens[0], &size) || size < 3) {
        message << "line " << line_number << ": face " << face << " starts with "
                << Quote(tokens[0]) << "; expected its vertex count, at least 3";
        *problem = message.str();
        return false;
      }
      if (static_cast<long long>(tokens.size()) < 1 + size) {
        message << "line " << line_number << ": face " << face << " announces " << size
                << " vertices but lists " << tokens.size() - 1;
        *problem = message.str();
        return false;
      }
      // Without 'C' in the header OpenMesh would read trailing colour values
      // as the next face.
      if (static_cast<long long>(tokens.size()) > 1 + size && !has_colors) {
        check->needs_normalizing = true;
      }
      for (long long k = 1; k <= size; ++k) {
        long long id = 0;
        if (!ParseInt(tokens[k], &id)) {
          message << "line " << line_number << ": face " << face << " vertex id "
                  << Quote(tokens[k]) << " is not an integer";
          *problem = message.str();
          return false;
        }
        if (id < 0 || id >= num_vertices) {
          message << "line " << line_number << ": face " << face << " refers to vertex " << id
                  << ", outside 0.." << num_vertices - 1;
          *problem = message.str();
          return false;
        }
      }
    }
    ++item;
  }
  if (item < total) {
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
  return true;
}

// The geometry of an OFF text that passed CheckOff, in the plain layout
// OpenMesh reads: "OFF", the counts, 3 coordinates per vertex line and the
// ids alone on each face line. Colours, normals and comments are dropped.
std::string NormalizeOff(const std::string& text) {
  std::ostringstream out;
  size_t pos = 0;
  std::string_view line;
  Tokens tokens;
  bool had_comment = false;
  // Header, then the counts (maybe on the header line).
  do {
    NextLine(text, &pos, &line);
    Tokenize(line, &tokens, &had_comment);
  } while (tokens.empty());
  Tokens counts(tokens.begin() + 1, tokens.end());
  while (counts.empty()) {
    NextLine(text, &pos, &line);
    Tokenize(line, &counts, &had_comment);
  }
  out << "OFF\n" << counts[0] << " " << counts[1] << " " << counts[2] << "\n";
  long long num_vertices = 0, num_faces = 0;
  ParseInt(counts[0], &num_vertices);
  ParseInt(counts[1], &num_faces);
  for (long long item = 0; item < num_vertices + num_faces && NextLine(text, &pos, &line);) {
    Tokenize(line, &tokens, &had_comment);
    if (tokens.empty()) continue;
    long long keep = 3;  // x y z
    if (item >= num_vertices) {
      ParseInt(tokens[0], &keep);
      keep += 1;  // the count, then the ids
    }
    for (long long k = 0; k < keep; ++k) out << (k ? " " : "") << tokens[k];
    out << "\n";
    ++item;
  }
  return out.str();
}

// ---------------------------------------------------------------------------
// PLY and OBJ pre-checks, for the same reason: OpenMesh's ASCII readers keep
// going with stale values after a number fails to parse or the data ends.

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

// Checks the PLY header and that the data is all there; sets the vertex and
// face counts it announces (-1 when absent).
bool CheckPly(const std::string& text, int* num_vertices, int* num_faces, std::string* problem) {
  std::ostringstream message;
  *num_vertices = -1;
  *num_faces = -1;
  size_t pos = 0;
  int line_number = 0;
  std::string_view line;
  Tokens tokens;
  bool had_comment = false;
  NextLine(text, &pos, &line);
  ++line_number;
  Tokenize(line, &tokens, &had_comment);
  if (tokens.size() != 1 || tokens[0] != "ply") {
    message << "line 1: expected the PLY magic 'ply', found "
            << (tokens.empty() ? std::string("nothing") : Quote(tokens[0]));
    *problem = message.str();
    return false;
  }
  std::string format;
  struct Property {
    bool is_list = false;
    std::string_view type;        // scalar type, or the list's item type
    std::string_view count_type;  // lists only
  };
  struct Element {
    std::string name;
    long long count = 0;
    std::vector<Property> properties;
  };
  std::vector<Element> elements;
  bool ended = false;
  while (!ended && NextLine(text, &pos, &line)) {
    ++line_number;
    Tokenize(line, &tokens, &had_comment);
    if (!tokens.empty() && (tokens[0] == "comment" || tokens[0] == "obj_info")) continue;
    // PLY has no '#' comments: OpenMesh reads "end_header#" as another
    // header line and then spends minutes on the binary data (found by
    // tests/fuzz/ply_fuzzer).
    if (had_comment) {
      message << "line " << line_number << ": '#' in a PLY header line";
      *problem = message.str();
      return false;
    }
    if (tokens.empty()) continue;
    if (tokens[0] == "format") {
      if (!format.empty()) {
        message << "line " << line_number << ": a second 'format' line";
        *problem = message.str();
        return false;
      }
      // OpenMesh loops forever on a version it cannot parse (found by
      // tests/fuzz/ply_fuzzer: 'format ascii @1.0'); PLY has only 1.0.
      if (tokens.size() != 3 || (tokens[1] != "ascii" && tokens[1] != "binary_little_endian" &&
                                 tokens[1] != "binary_big_endian") || tokens[2] != "1.0") {
        message << "line " << line_number
                << ": expected 'format ascii|binary_little_endian|binary_big_endian 1.0'";
        *problem = message.str();
        return false;
      }
      format = std::string(tokens[1]);
    } else if (tokens[0] == "element") {
      long long count = -1;
      if (tokens.size() != 3 || !ParseInt(tokens[2], &count) || count < 0 ||
          count > std::numeric_limits<int>::max()) {
        message << "line " << line_number << ": expected 'element <name> <count>'";
        *problem = message.str();
        return false;
      }
      elements.push_back({std::string(tokens[1]), count, {}});
      if (tokens[1] == "vertex") *num_vertices = static_cast<int>(count);
      if (tokens[1] == "face") *num_faces = static_cast<int>(count);
    } else if (tokens[0] == "property") {
      // OpenMesh's header parser writes a property into the last element
      // without checking there is one (a segfault, found by
      // tests/fuzz/ply_fuzzer), so the header is checked strictly here.
      if (elements.empty()) {
        message << "line " << line_number << ": 'property' before any 'element'";
        *problem = message.str();
        return false;
      }
      Element& element = elements.back();
      const bool is_list = tokens.size() >= 2 && tokens[1] == "list";
      if (is_list ? (tokens.size() != 5 || PlyTypeSize(tokens[2]) == 0 ||
                     PlyTypeSize(tokens[3]) == 0)
                  : (tokens.size() != 3 || PlyTypeSize(tokens[1]) == 0)) {
        message << "line " << line_number
                << ": expected 'property <type> <name>' or 'property list <count type> <item "
                   "type> <name>' with PLY scalar types";
        *problem = message.str();
        return false;
      }
      element.properties.push_back(is_list ? Property{true, tokens[3], tokens[2]}
                                           : Property{false, tokens[1], {}});
    } else if (tokens[0] == "end_header") {
      // The data starts right after this line's end, so nothing else on it.
      if (line != "end_header") {
        message << "line " << line_number << ": expected 'end_header' alone on its line";
        *problem = message.str();
        return false;
      }
      ended = true;
    } else {
      message << "line " << line_number << ": unknown PLY header keyword " << Quote(tokens[0]);
      *problem = message.str();
      return false;
    }
  }
  if (!ended) {
    *problem = "truncated: the PLY header has no end_header line";
    return false;
  }
  if (format.empty()) {
    *problem = "the PLY header has no 'format' line";
    return false;
  }
  // The data, element by element and property by property, so that a list
  // count cannot promise more items than the file holds (OpenMesh allocates
  // what a face's count says: 3 GB for '3999...9 3 2 3', found by
  // tests/fuzz/ply_fuzzer) and face vertex ids are in range.
  const long long num_vertex_ids = std::max(*num_vertices, 0);
  auto bad_face_id = [&](long long id) { return id < 0 || id >= num_vertex_ids; };
  if (format == "ascii") {
    // One element per line, exactly its values, every value a finite number.
    for (const Element& element : elements) {
      for (long long item = 0; item < element.count; ++item) {
        do {
          if (!NextLine(text, &pos, &line)) {
            message << "truncated: the file ends in element '" << element.name << "' "
                    << item << " of " << element.count;
            *problem = message.str();
            return false;
          }
          ++line_number;
          Tokenize(line, &tokens, &had_comment);
          if (had_comment) {
            message << "line " << line_number << ": '#' in PLY data";
            *problem = message.str();
            return false;
          }
        } while (tokens.empty());
        for (const std::string_view& token : tokens) {
          double value = 0.0;
          if (!ParseDouble(token, &value) || !std::isfinite(value)) {
            message << "line " << line_number << ": " << Quote(token) << " is not a finite number";
            *problem = message.str();
            return false;
          }
        }
        size_t t = 0;
        for (const Property& property : element.properties) {
          if (!property.is_list) {
            ++t;
            continue;
          }
          long long count = -1;
          if (t >= tokens.size() || !ParseInt(tokens[t], &count) || count < 0 ||
              count > static_cast<long long>(tokens.size() - t - 1)) {
            message << "line " << line_number << ": " << element.name << " " << item
                    << ": a list count that is not the number of values after it";
            *problem = message.str();
            return false;
          }
          for (long long k = 0; k < count && element.name == "face"; ++k) {
            long long id = -1;
            if (!ParseInt(tokens[t + 1 + k], &id) || bad_face_id(id)) {
              message << "line " << line_number << ": face " << item << ": vertex id "
                      << Quote(tokens[t + 1 + k]) << " is not in 0.." << num_vertex_ids - 1;
              *problem = message.str();
              return false;
            }
          }
          t += 1 + count;
        }
        if (t != tokens.size()) {
          message << "line " << line_number << ": " << element.name << " " << item << " has "
                  << tokens.size() << " values; its properties take " << t;
          *problem = message.str();
          return false;
        }
      }
    }
  } else {
    const bool big_endian = format == "binary_big_endian";
    // The integer of PLY type `type` at text[at].
    auto read_int = [&](size_t at, std::string_view type) {
      const int size = PlyTypeSize(type);
      unsigned long long bits = 0;
      for (int k = 0; k < size; ++k) {
        const unsigned char byte = static_cast<unsigned char>(text[at + (big_endian ? k : size - 1 - k)]);
        bits = (bits << 8) | byte;
      }
      const bool is_signed = type == "char" || type == "int8" || type == "short" ||
                             type == "int16" || type == "int" || type == "int32";
      if (is_signed && size < 8 && (bits >> (8 * size - 1)) != 0) {
        return static_cast<long long>(bits) - (1LL << (8 * size));
      }
      return static_cast<long long>(bits);
    };
    size_t at = std::min(pos, text.size());  // pos is past the end without a final newline
    for (const Element& element : elements) {
      for (long long item = 0; item < element.count; ++item) {
        for (const Property& property : element.properties) {
          const size_t size = PlyTypeSize(property.is_list ? property.count_type : property.type);
          if (text.size() - at < size) {
            message << "truncated: the binary data ends in element '" << element.name << "' "
                    << item << " of " << element.count;
            *problem = message.str();
            return false;
          }
          if (!property.is_list) {
            at += size;
            continue;
          }
          const long long count = read_int(at, property.count_type);
          at += size;
          const size_t item_size = PlyTypeSize(property.type);
          if (count < 0 || static_cast<unsigned long long>(count) > (text.size() - at) / item_size) {
            message << "binary " << element.name << " " << item << ": list count " << count
                    << " is negative or runs past the end of the file";
            *problem = message.str();
            return false;
          }
          const bool is_float = property.type == "float" || property.type == "float32" ||
                                property.type == "double" || property.type == "float64";
          for (long long k = 0; k < count && element.name == "face" && !is_float; ++k) {
            if (bad_face_id(read_int(at + k * item_size, property.type))) {
              message << "binary face " << item << ": a vertex id is not in 0.."
                      << num_vertex_ids - 1;
              *problem = message.str();
              return false;
            }
          }
          at += count * item_size;
        }
      }
    }
  }
  return true;
}

// What a format pre-check expects OpenMesh to hand over, and what OpenMesh's
// reader drops itself.
struct ExpectedCounts {
  int num_vertices = -1;  // -1: the format does not say
  int num_faces = -1;
  // Triangles that repeat a vertex which OpenMesh's OBJ and STL readers skip
  // without a word; the notice counts them with those dropped here.
  int dropped_degenerate_faces = 0;
};

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

// Checks the "v x y z" and "f ..." lines of an OBJ file, counts the vertices,
// and predicts the faces OpenMesh hands over: its reader removes the repeats
// of a vertex from a face ((a, b, b, c) becomes (a, b, c)) and skips a face
// left with fewer than 3, so the fan triangles lost that way are counted too.
bool CheckObj(const std::string& text, ExpectedCounts* expected, std::string* problem) {
  std::ostringstream message;
  size_t pos = 0;
  int line_number = 0;
  std::string_view line;
  Tokens tokens;
  bool had_comment = false;
  long long count = 0;
  long long num_faces = 0;
  long long dropped_triangles = 0;
  std::vector<long long> ids;
  while (NextLine(text, &pos, &line)) {
    ++line_number;
    Tokenize(line, &tokens, &had_comment);
    if (!tokens.empty() && tokens[0] == "f") {
      if (tokens.size() < 4) {
        message << "line " << line_number << ": a face has " << tokens.size() - 1
                << " vertices; need at least 3";
        *problem = message.str();
        return false;
      }
      ids.clear();
      for (size_t k = 1; k < tokens.size(); ++k) {
        long long id = 0;
        if (!ParseObjFaceCorner(tokens[k], &id)) {
          message << "line " << line_number << ": face corner " << Quote(tokens[k])
                  << " is not v, v/t, v//n or v/t/n with a non-zero vertex number";
          *problem = message.str();
          return false;
        }
        ids.push_back(id < 0 ? count + id + 1 : id);  // as OpenMesh resolves it
      }
      const long long corners = static_cast<long long>(ids.size());
      std::sort(ids.begin(), ids.end());
      const long long distinct = std::unique(ids.begin(), ids.end()) - ids.begin();
      if (distinct >= 3) ++num_faces;
      dropped_triangles += (corners - 2) - std::max(distinct - 2, 0LL);
      continue;
    }
    if (tokens.empty() || tokens[0] != "v") continue;
    if (!CheckVertexCoordinates(tokens, 1, line_number, count, problem)) return false;
    ++count;
  }
  if (count > std::numeric_limits<int>::max() || num_faces > std::numeric_limits<int>::max() ||
      dropped_triangles > std::numeric_limits<int>::max()) {
    *problem = "too many vertices or faces";
    return false;
  }
  expected->num_vertices = static_cast<int>(count);
  expected->num_faces = static_cast<int>(num_faces);
  expected->dropped_degenerate_faces = static_cast<int>(dropped_triangles);
  return true;
}

// ---------------------------------------------------------------------------
// STL pre-check. OpenMesh's STL reader merges corners at equal positions and
// skips, without a word, a facet two of whose corners merge; so the facets are
// walked here as it walks them, to count those for the notice and to compare
// what it hands over. (On the way this refuses what it would misread: it
// takes the three lines after any line holding "outer" as the corners,
// whatever they say, and keeps going with stale values.)

// Single precision, as OpenMesh reads STL, and through strtof as its stream
// input does, so that equal positions here are equal there.
bool ParseFloat(std::string_view token, float* value) {
  const std::string copy(token);
  char* end = nullptr;
  *value = std::strtof(copy.c_str(), &end);
  return end == copy.c_str() + copy.size() && !copy.empty();
}

using StlCorner = std::array<float, 3>;

// OpenMesh's STL reader takes two corners for one vertex when every
// coordinate differs by at most FLT_MIN (its CmpVec).
bool SameStlCorner(const StlCorner& p, const StlCorner& q) {
  for (int k = 0; k < 3; ++k) {
    if (!(std::fabs(p[k] - q[k]) <= std::numeric_limits<float>::min())) return false;
  }
  return true;
}

bool IsCollapsedFacet(const std::array<StlCorner, 3>& corners) {
  return SameStlCorner(corners[0], corners[1]) || SameStlCorner(corners[1], corners[2]) ||
         SameStlCorner(corners[0], corners[2]);
}

// "vertex" in any case (OpenMesh does not look at the word at all).
bool IsStlVertexKeyword(std::string_view token) {
  constexpr std::string_view kVertex = "vertex";
  return token.size() == kVertex.size() &&
         std::equal(token.begin(), token.end(), kVertex.begin(), [](char a, char b) {
           return std::tolower(static_cast<unsigned char>(a)) == b;
         });
}

bool CheckStl(const std::string& text, ExpectedCounts* expected, std::string* problem) {
  std::ostringstream message;
  long long num_facets = 0;
  long long num_collapsed = 0;
  // OpenMesh reads binary STL exactly when the file is as long as the facet
  // count after the 80-byte header says: 84 bytes and 50 per facet.
  uint32_t binary_count = 0;
  if (text.size() >= 84) std::memcpy(&binary_count, text.data() + 80, sizeof(binary_count));
  if (text.size() >= 84 && text.size() == 84 + 50ull * binary_count) {
    for (uint32_t facet = 0; facet < binary_count; ++facet) {
      std::array<StlCorner, 3> corners;
      // After the facet's normal: three corners of three little-endian floats.
      std::memcpy(corners.data(), text.data() + 84 + 50ull * facet + 12, sizeof(corners));
      for (int c = 0; c < 3; ++c) {
        for (float coordinate : corners[c]) {
          if (!std::isfinite(coordinate)) {
            message << "binary facet " << facet << ": corner " << c
                    << " has a non-finite coordinate";
            *problem = message.str();
            return false;
          }
        }
      }
      num_collapsed += IsCollapsedFacet(corners);
    }
    num_facets = binary_count;
  } else {
    size_t pos = 0;
    int line_number = 0;
    std::string_view line;
    Tokens tokens;
    bool had_comment = false;
    while (NextLine(text, &pos, &line)) {
      ++line_number;
      if (line.find("outer") == std::string_view::npos &&
          line.find("OUTER") == std::string_view::npos) {
        continue;
      }
      const int outer_line = line_number;
      std::array<StlCorner, 3> corners;
      for (int c = 0; c < 3; ++c) {
        if (!NextLine(text, &pos, &line)) {
          message << "truncated: the file ends in facet " << num_facets << " (line " << line_number
                  << ")";
          *problem = message.str();
          return false;
        }
        ++line_number;
        Tokenize(line, &tokens, &had_comment);
        if (tokens.size() != 4 || !IsStlVertexKeyword(tokens[0])) {
          message << "line " << line_number << ": facet " << num_facets
                  << ": expected 'vertex x y z' (corner " << c << " after 'outer' on line "
                  << outer_line << ")";
          *problem = message.str();
          return false;
        }
        for (int k = 0; k < 3; ++k) {
          if (!ParseFloat(tokens[1 + k], &corners[c][k]) || !std::isfinite(corners[c][k])) {
            message << "line " << line_number << ": facet " << num_facets << ": "
                    << Quote(tokens[1 + k]) << " is not a finite number";
            *problem = message.str();
            return false;
          }
        }
      }
      ++num_facets;
      num_collapsed += IsCollapsedFacet(corners);
    }
  }
  if (num_facets > std::numeric_limits<int>::max()) {
    *problem = "too many facets";
    return false;
  }
  expected->num_faces = static_cast<int>(num_facets - num_collapsed);
  expected->dropped_degenerate_faces = static_cast<int>(num_collapsed);
  return true;
}

// A file in the system temporary folder holding `text`, removed on scope exit.
class ScopedTemporaryCopy {
 public:
  bool Create(const std::string& text, const std::string& suffix, std::string* problem) {
    std::string pattern = (fs::temp_directory_path() / ("msdeform-XXXXXX" + suffix)).string();
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    const int fd = ::mkstemps(buffer.data(), static_cast<int>(suffix.size()));
    if (fd < 0) {
      *problem =
          "cannot create a temporary copy for OpenMesh (" + std::string(std::strerror(errno)) + ")";
      return false;
    }
    ::close(fd);
    name_ = buffer.data();
    std::ofstream out(name_, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) {
      *problem = "cannot write a temporary copy for OpenMesh";
      return false;
    }
    return true;
  }
  ~ScopedTemporaryCopy() {
    if (!name_.empty()) std::remove(name_.c_str());
  }
  const std::string& name() const { return name_; }

 private:
  std::string name_;
};

// Merges vertices at exactly equal positions (first appearance wins, order
// kept). Triangles that collapse are left to DropDegenerateAndDuplicateFaces.
void WeldExactDuplicates(Mesh* mesh) {
  std::map<std::array<double, 3>, int> id_of_position;
  std::vector<int> new_id(mesh->num_vertices());
  int count = 0;
  for (int v = 0; v < mesh->num_vertices(); ++v) {
    const std::array<double, 3> key{mesh->vertices(0, v), mesh->vertices(1, v),
                                    mesh->vertices(2, v)};
    const auto [it, inserted] = id_of_position.emplace(key, count);
    if (inserted) mesh->vertices.col(count++) = mesh->vertices.col(v);
    new_id[v] = it->second;
  }
  mesh->vertices.conservativeResize(3, count);
  for (int f = 0; f < mesh->num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) mesh->faces(c, f) = new_id[mesh->faces(c, f)];
  }
}

// Drops the triangles that repeat a vertex and the exact duplicates of an
// earlier triangle (same cyclic order; see mesh_io.h), keeping the order of
// the rest, and adds their counts to *report.
void DropDegenerateAndDuplicateFaces(Mesh* mesh, MeshReadReport* report) {
  const int num_faces = mesh->num_faces();
  std::vector<char> drop(num_faces, 0);
  // Each triangle rotated to start at its lowest id: one key for the three
  // rotations of (a, b, c), another for the opposite orientation (a, c, b).
  std::vector<std::array<int, 3>> keys(num_faces);
  std::vector<int> order;  // the triangles that do not repeat a vertex
  order.reserve(num_faces);
  for (int f = 0; f < num_faces; ++f) {
    const int a = mesh->faces(0, f), b = mesh->faces(1, f), c = mesh->faces(2, f);
    if (a == b || b == c || a == c) {
      drop[f] = 1;
      ++report->dropped_degenerate_faces;
      continue;
    }
    const int first = a < b ? (a < c ? 0 : 2) : (b < c ? 1 : 2);
    keys[f] = {mesh->faces(first, f), mesh->faces((first + 1) % 3, f),
               mesh->faces((first + 2) % 3, f)};
    order.push_back(f);
  }
  // Equal keys end up next to each other, the earliest triangle first.
  std::stable_sort(order.begin(), order.end(), [&keys](int f, int g) { return keys[f] < keys[g]; });
  for (size_t i = 1; i < order.size(); ++i) {
    if (keys[order[i]] == keys[order[i - 1]]) {
      drop[order[i]] = 1;
      ++report->dropped_duplicate_faces;
    }
  }
  int kept = 0;
  for (int f = 0; f < num_faces; ++f) {
    if (!drop[f]) mesh->faces.col(kept++) = mesh->faces.col(f);
  }
  mesh->faces.conservativeResize(3, kept);
}

// "3 faces that repeat a vertex and 1 duplicate face" ("" when none).
std::string DescribeDroppedFaces(const MeshReadReport& report) {
  std::ostringstream text;
  const int degenerate = report.dropped_degenerate_faces;
  const int duplicate = report.dropped_duplicate_faces;
  if (degenerate > 0) {
    text << degenerate << (degenerate == 1 ? " face that repeats" : " faces that repeat")
         << " a vertex";
  }
  if (degenerate > 0 && duplicate > 0) text << " and ";
  if (duplicate > 0) text << duplicate << " duplicate face" << (duplicate == 1 ? "" : "s");
  return text.str();
}

std::string FormatName(const std::string& extension) {
  std::string name = extension;
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return name;
}

}  // namespace

bool ReadMesh(const std::string& path, Mesh* mesh, MeshReadReport* report, std::string* error) {
  *report = MeshReadReport();
  const std::string extension = LowerExtension(path);
  if (extension != "off" && extension != "obj" && extension != "ply" && extension != "stl") {
    return Fail(path,
                "unknown mesh format " +
                    (extension.empty() ? "(no extension)" : "'." + extension + "'") +
                    "; use .off, .obj, .ply or .stl",
                error);
  }
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) return Fail(path, "no such file", error);
  if (fs::is_directory(status)) return Fail(path, "is a folder, not a mesh file", error);
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return Fail(path, "cannot open for reading (" + std::string(std::strerror(errno)) + ")", error);
  std::string text(std::istreambuf_iterator<char>(in), {});
  if (in.bad()) return Fail(path, "read error", error);
  in.close();
  if (text.empty()) return Fail(path, "file is empty", error);

  // Check the text first (see CheckOff); remember the counts it announces
  // (or, for OBJ and STL, predicts).
  ExpectedCounts expected;
  ScopedTemporaryCopy normalized_copy;
  std::string read_path = path;
  std::string problem;
  if (extension == "off") {
    OffCheck off;
    if (!CheckOff(text, &off, &problem)) return Fail(path, problem, error);
    expected.num_vertices = off.num_vertices;
    expected.num_faces = off.num_faces;
    if (off.needs_normalizing) {
      if (!normalized_copy.Create(NormalizeOff(text), ".off", &problem))
        return Fail(path, problem, error);
      read_path = normalized_copy.name();
    }
  } else if (extension == "ply") {
    if (!CheckPly(text, &expected.num_vertices, &expected.num_faces, &problem)) {
      return Fail(path, problem, error);
    }
  } else if (extension == "obj") {
    if (!CheckObj(text, &expected, &problem)) return Fail(path, problem, error);
  } else if (extension == "stl") {
    if (!CheckStl(text, &expected, &problem)) return Fail(path, problem, error);
  }
  text.clear();
  text.shrink_to_fit();

  RawImporter importer;
  {
    ScopedOpenMeshSilence silence;
    OpenMesh::IO::Options options = OpenMesh::IO::Options::Default;
    if (!OpenMesh::IO::IOManager().read(read_path, importer, options)) {
      return Fail(
          path,
          "OpenMesh cannot read it as " + FormatName(extension) + " (wrong header or corrupt data)",
          error);
    }
  }

  const int num_vertices = static_cast<int>(importer.n_vertices());
  if ((expected.num_vertices >= 0 && num_vertices != expected.num_vertices) ||
      (expected.num_faces >= 0 && importer.num_polygons() != expected.num_faces)) {
    std::ostringstream message;
    message << "expected";
    if (expected.num_vertices >= 0) message << " " << expected.num_vertices << " vertices";
    if (expected.num_vertices >= 0 && expected.num_faces >= 0) message << " and";
    if (expected.num_faces >= 0) message << " " << expected.num_faces << " faces";
    message << " from the file, but OpenMesh read " << num_vertices << " vertices and "
            << importer.num_polygons() << " faces (corrupt file?)";
    return Fail(path, message.str(), error);
  }

  // Check the polygons as the file numbers them, then fan-triangulate. (A
  // polygon that repeats a vertex is split too; its fan triangles that repeat
  // one are dropped below with the others.)
  int num_triangles = 0;
  for (int p = 0; p < importer.num_polygons(); ++p) {
    const int* ids = importer.face_ids.data() + importer.face_offsets[p];
    const int size = importer.face_offsets[p + 1] - importer.face_offsets[p];
    std::ostringstream message;
    if (size < 3) {
      message << "face " << p << " has " << size << " vertices; need at least 3";
      return Fail(path, message.str(), error);
    }
    for (int k = 0; k < size; ++k) {
      if (ids[k] < 0 || ids[k] >= num_vertices) {
        message << "face " << p << " refers to vertex " << ids[k] << ", outside 0.."
                << num_vertices - 1;
        return Fail(path, message.str(), error);
      }
    }
    num_triangles += size - 2;
  }
  mesh->vertices = Eigen::Map<const Eigen::Matrix3Xd>(importer.xyz.data(), 3, num_vertices);
  mesh->faces.resize(3, num_triangles);
  int t = 0;
  for (int p = 0; p < importer.num_polygons(); ++p) {
    const int* ids = importer.face_ids.data() + importer.face_offsets[p];
    const int size = importer.face_offsets[p + 1] - importer.face_offsets[p];
    for (int k = 1; k + 1 < size; ++k) mesh->faces.col(t++) << ids[0], ids[k], ids[k + 1];
  }

  if (extension == "stl") WeldExactDuplicates(mesh);

  report->dropped_degenerate_faces = expected.dropped_degenerate_faces;
  DropDegenerateAndDuplicateFaces(mesh, report);
  const std::string dropped = DescribeDroppedFaces(*report);
  if (mesh->num_faces() == 0 && !dropped.empty()) {
    return Fail(path, "no face left after dropping " + dropped + "; need at least one triangle",
                error);
  }
  if (!ValidateMesh(*mesh, &problem)) return Fail(path, problem, error);
  if (!dropped.empty()) report->notice = path + ": dropped " + dropped;
  return true;
}

bool ReadMesh(const std::string& path, Mesh* mesh, std::string* error) {
  MeshReadReport report;
  return ReadMesh(path, mesh, &report, error);
}

bool WriteMesh(const std::string& path, const Mesh& mesh, std::string* error) {
  const std::string extension = LowerExtension(path);
  if (extension != "off" && extension != "obj" && extension != "ply") {
    return Fail(path,
                "cannot write format " +
                    (extension.empty() ? "(no extension)" : "'." + extension + "'") +
                    "; use .off, .obj or .ply",
                error);
  }
  std::string problem;
  if (!ValidateMesh(mesh, &problem)) return Fail(path, "refusing to write: " + problem, error);

  return WriteFileAtomically(
      path,
      [&](std::ostream& out, std::string* write_error) {
        RawExporter exporter(mesh);
        ScopedOpenMeshSilence silence;
        // OpenMesh's writers print single-precision values; 9 significant
        // digits reproduce every float exactly.
        const std::streamsize precision = std::numeric_limits<float>::max_digits10;
        if (!OpenMesh::IO::IOManager().write(out, extension, exporter,
                                             OpenMesh::IO::Options::Default, precision)) {
          *write_error = "OpenMesh's " + FormatName(extension) + " writer failed";
          return false;
        }
        return true;
      },
      error);
}

}  // namespace msdeform
