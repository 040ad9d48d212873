// The writers of WriteMesh (core/mesh_io.cc). Every file holds exactly the
// positions the program had (a deformed mesh compared with another program's
// to 1e-12, say): OFF and OBJ print each coordinate as the shortest decimal
// that reads back as the same double (std::to_chars); PLY is binary
// little-endian with double coordinates, written at disk speed for the large
// meshes. ReadMesh reads them back bit for bit (core/mesh_io.h).

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <string>
#include <system_error>

#include "msdeform/core/mesh_io_formats.h"

namespace msdeform {
namespace {

// Appends `value` and `separator` to *line.
void AppendNumber(double value, char separator, std::string* line) {
  char buffer[32];
  const std::to_chars_result result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  line->append(buffer, result.ptr);
  line->push_back(separator);
}

void AppendNumber(int value, char separator, std::string* line) {
  char buffer[16];
  const std::to_chars_result result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  line->append(buffer, result.ptr);
  line->push_back(separator);
}

// One format's layout: what precedes each vertex and face line, and the
// offset added to vertex ids (OBJ counts from 1).
struct TextLayout {
  const char* vertex_prefix;
  const char* face_prefix;
  int first_id;
};

std::string Header(const Mesh& mesh, const std::string& extension) {
  const std::string vertices = std::to_string(mesh.num_vertices());
  const std::string faces = std::to_string(mesh.num_faces());
  if (extension == "off") return "OFF\n" + vertices + " " + faces + " 0\n";
  return "# written by msdeform: " + vertices + " vertices, " + faces + " faces\n";
}

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the binary PLY writer copies little-endian memory as it is");

// Binary little-endian PLY: doubles x y z per vertex, then per face the count
// 3 (uchar) and three int ids, in blocks of a few thousand items.
bool WriteBinaryPly(const Mesh& mesh, std::ostream& out, std::string* problem) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment written by msdeform\nelement vertex " +
      std::to_string(mesh.num_vertices()) +
      "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
      std::to_string(mesh.num_faces()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  // Matrix3Xd is x y z per column already: the vertex block is its memory.
  out.write(reinterpret_cast<const char*>(mesh.vertices.data()),
            static_cast<std::streamsize>(sizeof(double) * 3 * mesh.num_vertices()));
  constexpr int kFaceBytes = 1 + 3 * sizeof(std::int32_t);
  constexpr int kBlockFaces = 1 << 16;
  std::string block;
  for (int first = 0; first < mesh.num_faces(); first += kBlockFaces) {
    const int count = std::min(kBlockFaces, mesh.num_faces() - first);
    block.resize(static_cast<size_t>(count) * kFaceBytes);
    char* at = block.data();
    for (int f = first; f < first + count; ++f) {
      *at++ = 3;
      std::memcpy(at, mesh.faces.col(f).data(), 3 * sizeof(std::int32_t));
      at += 3 * sizeof(std::int32_t);
    }
    out.write(block.data(), static_cast<std::streamsize>(block.size()));
  }
  if (!out) {
    *problem = "writing the binary PLY data failed";
    return false;
  }
  return true;
}

}  // namespace

bool WriteMeshFile(const Mesh& mesh, const MeshFormat& format, std::ostream& out,
                   std::string* problem) {
  const std::string extension = format.extension;
  if (extension == "ply") return WriteBinaryPly(mesh, out, problem);
  const TextLayout layout = extension == "obj" ? TextLayout{"v ", "f ", 1}
                                               : TextLayout{"", "3 ", 0};
  std::string text = Header(mesh, extension);
  // Flushed every few thousand lines: the whole text of a large mesh is not
  // kept in memory twice.
  constexpr size_t kFlushBytes = 1 << 20;
  const auto flush_if_full = [&text, &out]() {
    if (text.size() >= kFlushBytes) {
      out.write(text.data(), static_cast<std::streamsize>(text.size()));
      text.clear();
    }
  };
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    text += layout.vertex_prefix;
    AppendNumber(mesh.vertices(0, v), ' ', &text);
    AppendNumber(mesh.vertices(1, v), ' ', &text);
    AppendNumber(mesh.vertices(2, v), '\n', &text);
    flush_if_full();
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    text += layout.face_prefix;
    AppendNumber(mesh.faces(0, f) + layout.first_id, ' ', &text);
    AppendNumber(mesh.faces(1, f) + layout.first_id, ' ', &text);
    AppendNumber(mesh.faces(2, f) + layout.first_id, '\n', &text);
    flush_if_full();
  }
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out) {
    *problem = std::string("writing the ") + format.name + " text failed";
    return false;
  }
  return true;
}

}  // namespace msdeform
