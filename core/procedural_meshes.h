// Meshes made in code, so unit tests and benchmarks need no download.
//
// Most shapes are unions of unit voxels: every boundary face of an occupied
// voxel becomes `subdivisions` x `subdivisions` quads split into triangles,
// with vertices welded, so the result is closed and consistently oriented
// (outward normals). Shapes whose voxels touch only along an edge would be
// non-manifold; the shapes below avoid that.

#ifndef MSDEFORM_CORE_PROCEDURAL_MESHES_H_
#define MSDEFORM_CORE_PROCEDURAL_MESHES_H_

#include <vector>

#include <Eigen/Core>

#include "core/mesh.h"

namespace msdeform {

// Occupancy of a box of nx by ny by nz unit voxels; voxel (i, j, k) spans
// [i, i+1] x [j, j+1] x [k, k+1] times `voxel_size`.
struct VoxelShape {
  int nx = 0, ny = 0, nz = 0;
  std::vector<char> occupied;  // nx * ny * nz, index i + nx * (j + ny * k).

  VoxelShape(int nx, int ny, int nz);
  bool at(int i, int j, int k) const;
  void Set(int i, int j, int k, bool value = true);
  void Fill(const Eigen::Vector3i& from, const Eigen::Vector3i& to_exclusive);
};

// The closed boundary surface of `shape`.
Mesh MakeVoxelMesh(const VoxelShape& shape, double voxel_size, int subdivisions);

// A closed bar of `length` x 1 x 1 voxels along x (solid when filled).
Mesh MakeBar(int length, double voxel_size = 1.0, int subdivisions = 2);

// A comb: a spine along x (num_teeth * 2 - 1 voxels long, 1 voxel high) with
// `num_teeth` teeth of 1 x `tooth_length` voxels rising along +y from it,
// separated by one-voxel gaps. Teeth are geometrically close but only
// connected through the spine.
Mesh MakeComb(int num_teeth, int tooth_length, double voxel_size = 1.0,
              int subdivisions = 4);

// Two disjoint closed bars side by side along y with a gap of `gap` voxels.
Mesh MakeTwoBars(int length, int gap, double voxel_size = 1.0,
                 int subdivisions = 2);

// An open cylinder (no caps) of the given radius and height along z.
Mesh MakeOpenTube(double radius, double height, int segments, int rings);

// The regular octahedron with vertices at +-x, +-y, +-z (ids 0..5 in that
// order), faces outward: 6 vertices, 12 edges, 8 faces.
Mesh MakeOctahedron();

// A closed UV sphere centred at the origin.
Mesh MakeSphere(double radius, int segments, int rings);

// Vertices of a comb made by MakeComb that lie on tooth `tooth` above the
// spine (y > voxel_size).
std::vector<int> CombToothVertices(const Mesh& comb, int tooth, double voxel_size = 1.0);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_PROCEDURAL_MESHES_H_
