// A triangle mesh as two dense arrays, libigl-style, plus the few derived
// quantities every stage of msdeform needs (bounding box, edges, adjacency,
// connected components).
//
// Each derived quantity takes num_threads (OpenMP threads, default 1; a mesh
// of fewer than about 16K items is done on one): the results are the same
// bits for every thread count.
//
// Vertex order is the order of the input file: Botsch-Sorkine .sel files and
// scenario vertex ids index it.

#ifndef MSDEFORM_CORE_MESH_H_
#define MSDEFORM_CORE_MESH_H_

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace msdeform {

struct Mesh {
  Eigen::Matrix3Xd vertices;  // 3 by #V, one column per vertex.
  Eigen::Matrix3Xi faces;     // 3 by #F, counter-clockwise vertex ids.

  int num_vertices() const { return static_cast<int>(vertices.cols()); }
  int num_faces() const { return static_cast<int>(faces.cols()); }
};

// Axis-aligned bounding box of the vertices (empty box for an empty mesh).
Eigen::AlignedBox3d BoundingBox(const Mesh& mesh, int num_threads = 1);

// Length of the bounding-box diagonal, the unit of every relative number.
double BoundingBoxDiagonal(const Mesh& mesh, int num_threads = 1);

// Undirected edges (a < b), each once, sorted. #E pairs.
std::vector<std::pair<int, int>> UniqueEdges(const Mesh& mesh, int num_threads = 1);

// Vertex-vertex adjacency in compressed form: the neighbours of vertex v are
// neighbors[offsets[v] .. offsets[v + 1]), sorted, without v itself.
struct VertexAdjacency {
  std::vector<int> offsets;    // #V + 1
  std::vector<int> neighbors;  // 2 #E
};
VertexAdjacency ComputeVertexAdjacency(const Mesh& mesh, int num_threads = 1);

// Connected component id per vertex (0..count-1, numbered by lowest vertex
// id), through face connectivity. Isolated vertices are their own component.
struct Components {
  std::vector<int> component_of_vertex;  // #V
  int count = 0;
};
Components ConnectedComponents(const Mesh& mesh, int num_threads = 1);

// Area-weighted unit vertex normals (zero for isolated vertices). 3 by #V.
// A vertex's face terms are summed in face order on any number of threads.
Eigen::Matrix3Xd VertexNormals(const Mesh& mesh, int num_threads = 1);

// Checks the invariants the rest of msdeform relies on: at least one face,
// finite coordinates, face ids in range, no face repeating a vertex. On
// failure returns false and says what is wrong in *error.
bool ValidateMesh(const Mesh& mesh, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_MESH_H_
