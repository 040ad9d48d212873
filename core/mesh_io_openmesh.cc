// The OpenMesh pass of ReadMesh: OpenMesh's readers hand the file's vertices
// and polygons over as they are (no halfedge structure).

#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include "msdeform/core/mesh_io_formats.h"

namespace msdeform {
namespace {

namespace fs = std::filesystem;
using OpenMesh::EdgeHandle;
using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::Vec2f;
using OpenMesh::Vec3d;
using OpenMesh::Vec3f;
using OpenMesh::Vec3uc;
using OpenMesh::Vec3ui;
using OpenMesh::Vec4f;
using OpenMesh::Vec4uc;
using OpenMesh::Vec4ui;
using OpenMesh::VertexHandle;
using StatusInfo = OpenMesh::Attributes::StatusInfo;

// Turns OpenMesh's own omerr/omlog/omout printing off for its lifetime: our
// errors are the one-line messages of ReadMesh. (A few OpenMesh readers print to
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

// Records what a reader hands over in *soup, in order, and nothing else:
// vertices as they are added and faces as raw index lists. No halfedge
// structure is built, so nothing is dropped or duplicated for non-manifold
// input.
class RawImporter : public OpenMesh::IO::BaseImporter {
 public:
  explicit RawImporter(PolygonSoup* soup) : soup_(*soup) {}

  VertexHandle add_vertex(const Vec3f& p) override { return AddVertex(p[0], p[1], p[2]); }
  VertexHandle add_vertex(const Vec3d& p) override { return AddVertex(p[0], p[1], p[2]); }
  VertexHandle add_vertex() override { return AddVertex(0.0, 0.0, 0.0); }
  void set_point(VertexHandle vh, const Vec3f& p) override {
    const int v = vh.idx();
    if (v < 0 || 3 * static_cast<size_t>(v) >= soup_.xyz.size()) return;
    for (int k = 0; k < 3; ++k) soup_.xyz[3 * v + k] = p[k];
  }
  FaceHandle add_face(const VHandles& ids) override {
    for (const VertexHandle& vh : ids) soup_.face_ids.push_back(vh.idx());
    soup_.face_offsets.push_back(static_cast<int>(soup_.face_ids.size()));
    return FaceHandle(soup_.num_polygons() - 1);
  }
  size_t n_vertices() const override { return soup_.xyz.size() / 3; }
  size_t n_faces() const override { return static_cast<size_t>(soup_.num_polygons()); }
  size_t n_edges() const override { return 0; }
  void reserve(unsigned int num_vertices, unsigned int, unsigned int num_faces) override {
    // Headers may lie (truncated files); cap what we trust them for.
    soup_.xyz.reserve(3 * std::min(num_vertices, 1u << 24));
    soup_.face_offsets.reserve(std::min(num_faces, 1u << 24) + 1);
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
    soup_.xyz.push_back(x);
    soup_.xyz.push_back(y);
    soup_.xyz.push_back(z);
    return VertexHandle(soup_.num_vertices() - 1);
  }

  PolygonSoup& soup_;
};

}  // namespace

bool ReadWithOpenMesh(const std::string& path, const MeshFormat& format, FormatCheck check,
                      PolygonSoup* soup, std::string* problem) {
  const std::string& read_path = path;
  *soup = PolygonSoup();
  RawImporter importer(soup);
  {
    ScopedOpenMeshSilence silence;
    OpenMesh::IO::Options options = OpenMesh::IO::Options::Default;
    if (!OpenMesh::IO::IOManager().read(read_path, importer, options)) {
      *problem = std::string("OpenMesh cannot read it as ") + format.name +
                 " (wrong header or corrupt data)";
      return false;
    }
  }
  if ((check.num_vertices >= 0 && soup->num_vertices() != check.num_vertices) ||
      (check.num_faces >= 0 && soup->num_polygons() != check.num_faces)) {
    std::ostringstream message;
    message << "expected";
    if (check.num_vertices >= 0) message << " " << check.num_vertices << " vertices";
    if (check.num_vertices >= 0 && check.num_faces >= 0) message << " and";
    if (check.num_faces >= 0) message << " " << check.num_faces << " faces";
    message << " from the file, but OpenMesh read " << soup->num_vertices() << " vertices and "
            << soup->num_polygons() << " faces (corrupt file?)";
    *problem = message.str();
    return false;
  }
  if (check.read_coordinates) {
    // The counts agree, so the check read one x, y, z per vertex OpenMesh
    // handed over, in the same order.
    if (check.soup.xyz.size() != soup->xyz.size()) {
      *problem = "the check and OpenMesh read different numbers of coordinates (corrupt file?)";
      return false;
    }
    soup->xyz = std::move(check.soup.xyz);
  }
  return true;
}

}  // namespace msdeform
