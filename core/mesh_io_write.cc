// The writers of WriteMesh (core/mesh_io.cc): OFF, OBJ and ASCII PLY, every
// coordinate printed as the shortest decimal that reads back as the same
// double (std::to_chars), so a written mesh holds exactly the positions the
// program had (a deformed mesh compared with another program's to 1e-12, say).
// msdeform's reader still takes coordinates through single precision
// (core/mesh_io.h), as OpenMesh does; other readers get the doubles.

#include <charconv>
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
  if (extension == "ply") {
    return "ply\nformat ascii 1.0\ncomment written by msdeform\nelement vertex " + vertices +
           "\nproperty double x\nproperty double y\nproperty double z\nelement face " + faces +
           "\nproperty list uchar int vertex_indices\nend_header\n";
  }
  return "# written by msdeform: " + vertices + " vertices, " + faces + " faces\n";
}

}  // namespace

bool WriteMeshText(const Mesh& mesh, const MeshFormat& format, std::ostream& out,
                   std::string* problem) {
  const std::string extension = format.extension;
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
