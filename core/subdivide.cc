#include "msdeform/core/subdivide.h"

#include <algorithm>
#include <sstream>
#include <vector>

#include <glog/logging.h>
// OpenMesh's VectorT default constructor leaves its entries uninitialised,
// which GCC reports where OpenMesh grows a property; not ours to fix.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>
#pragma GCC diagnostic pop

namespace msdeform {
namespace {

// Double-precision points: the default OpenMesh traits use float.
struct DoubleTraits : public OpenMesh::DefaultTraits {
  typedef OpenMesh::Vec3d Point;
  typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::TriMesh_ArrayKernelT<DoubleTraits> TriMesh;

}  // namespace

bool LoopSubdivide(const Mesh& mesh, int iterations, Mesh* subdivided,
                   std::string* error) {
  CHECK_GE(iterations, 0);
  CHECK(subdivided != nullptr);
  CHECK(error != nullptr);
  if (!ValidateMesh(mesh, error)) return false;

  TriMesh trimesh;
  trimesh.reserve(mesh.num_vertices(), 3 * mesh.num_faces() / 2, mesh.num_faces());
  std::vector<TriMesh::VertexHandle> handles(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d& p = mesh.vertices.col(v);
    handles[v] = trimesh.add_vertex(TriMesh::Point(p.x(), p.y(), p.z()));
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const TriMesh::FaceHandle face = trimesh.add_face(
        handles[mesh.faces(0, f)], handles[mesh.faces(1, f)], handles[mesh.faces(2, f)]);
    if (!face.is_valid()) {
      std::ostringstream message;
      message << "face " << f << " (" << mesh.faces(0, f) << " " << mesh.faces(1, f)
              << " " << mesh.faces(2, f)
              << ") makes a non-manifold edge or vertex or flips the orientation; "
                 "Loop subdivision needs an oriented manifold mesh";
      *error = message.str();
      return false;
    }
  }

  // LoopT tabulates its weights up to a maximum valence (50 by default) and
  // indexes the table unchecked. Subdivision never raises a vertex's valence
  // (new vertices have valence 6 inside, 4 on a boundary), so the input's
  // maximum bounds every step.
  size_t max_valence = 6;
  for (const TriMesh::VertexHandle vertex : trimesh.vertices()) {
    max_valence = std::max<size_t>(max_valence, trimesh.valence(vertex));
  }
  OpenMesh::Subdivider::Uniform::LoopT<TriMesh> loop;
  loop.init_weights(max_valence + 1);
  loop.attach(trimesh);
  CHECK(loop(iterations)) << "OpenMesh Loop subdivision failed";
  loop.detach();

  // Vertices are only appended (nothing is deleted), so the input's vertices
  // keep their ids and handles run 0..n-1.
  subdivided->vertices.resize(3, trimesh.n_vertices());
  for (const TriMesh::VertexHandle vertex : trimesh.vertices()) {
    const TriMesh::Point& p = trimesh.point(vertex);
    subdivided->vertices.col(vertex.idx()) = Eigen::Vector3d(p[0], p[1], p[2]);
  }
  // LoopT leaves an isolated vertex's new position unset; keep it in place.
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (trimesh.is_isolated(handles[v])) {
      subdivided->vertices.col(v) = mesh.vertices.col(v);
    }
  }
  subdivided->faces.resize(3, trimesh.n_faces());
  for (const TriMesh::FaceHandle face : trimesh.faces()) {
    int corner = 0;
    for (const TriMesh::VertexHandle vertex : trimesh.fv_range(face)) {
      CHECK_LT(corner, 3);
      subdivided->faces(corner++, face.idx()) = vertex.idx();
    }
    CHECK_EQ(corner, 3);
  }
  return true;
}

Mesh LoopSubdivide(const Mesh& mesh, int iterations) {
  Mesh subdivided;
  std::string error;
  CHECK(LoopSubdivide(mesh, iterations, &subdivided, &error)) << error;
  return subdivided;
}

}  // namespace msdeform
