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

#include "msdeform/core/mesh.h"

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

// A fork: one closed, manifold mesh whose two prongs are geodesically far
// (joined only through the base) but pass within `gap` of each other. In
// voxels (times `voxel_size`), everything kForkDepth deep along z: a base
// 4 + gap wide (x) and kForkBaseHeight high (y); on it, prong 0 (x in [0, 2])
// and prong 1, each 2 wide and kForkProngLength long along +y. Prong 1's inner
// wall faces prong 0's (x = 2) across a gap of `gap` for the first
// kForkTouchLength above the base, then the gap widens linearly to
// kForkTipGap at the tips (prong 1 leans away, sheared, not bent). Built as a
// voxel comb whose middle column is squeezed (x -> a monotone function of x
// per height), so it is the voxel surface under a homeomorphism: closed,
// oriented and embedded; the prongs' closest points are exactly `gap` apart.
// 0 < gap <= kForkTipGap. The bounding box is (4 + kForkTipGap) x
// (kForkBaseHeight + kForkProngLength) x kForkDepth, whatever the gap: its
// diagonal is sqrt(278) = 16.67 voxels, a default lattice cell (48 per
// diagonal) 0.347 of a voxel.
constexpr int kForkBaseHeight = 3;
constexpr int kForkProngLength = 12;
constexpr int kForkTouchLength = 3;
constexpr int kForkDepth = 2;
constexpr double kForkTipGap = 3.0;
Mesh MakeFork(double gap, double voxel_size = 1.0, int subdivisions = 4);

// Vertices of a fork made by MakeFork: the base (y <= kForkBaseHeight voxels,
// the prongs' roots included), prong 0 or 1 above it, and the top voxel of a
// prong (y >= kForkBaseHeight + kForkProngLength - 1 voxels).
std::vector<int> ForkBaseVertices(const Mesh& fork, double voxel_size = 1.0);
std::vector<int> ForkProngVertices(const Mesh& fork, int prong, double voxel_size = 1.0);
std::vector<int> ForkTipVertices(const Mesh& fork, int prong, double voxel_size = 1.0);

// An open cylinder (no caps) of the given radius and height along z.
Mesh MakeOpenTube(double radius, double height, int segments, int rings);

// A closed cylinder along z from z = 0 to z = height, with flat caps, faces
// outward. The side has rings + 1 circles of `segments` vertices (ids
// r * segments + s, r = 0 at z = 0), each turned half a segment against the
// one below, so a side triangle is equilateral when height / rings is
// sqrt(3) / 2 of the side edge 2 pi radius / segments. Each cap (bottom, then
// top, after the side) is CylinderCapRings(segments) = K concentric circles:
// the side's end circle, circles of radius radius * k / K holding
// round(segments * k / K) vertices (at least 3) for k = K - 1 .. 1, and the
// centre; neighbouring circles are zipped (each step adds the shorter of the
// two possible edges), the innermost fanned to the centre. K makes the
// circles sqrt(3) / 2 of an edge apart, so cap triangles are near-equilateral
// too. Vertices:
//   segments * (rings + 1) + 2 * (1 + sum over k = 1 .. K-1 of max(3, round(segments * k / K))).
Mesh MakeCylinder(double radius, double height, int segments, int rings);

// K of MakeCylinder: round(segments / (pi sqrt(3))), at least 1.
int CylinderCapRings(int segments);

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
