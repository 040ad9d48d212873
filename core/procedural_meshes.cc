#include "msdeform/core/procedural_meshes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include <glog/logging.h>

namespace msdeform {
namespace {

// A mesh from lists of vertex positions and triangles.
Mesh MeshFromLists(const std::vector<Eigen::Vector3d>& points,
                   const std::vector<Eigen::Vector3i>& triangles) {
  Mesh mesh;
  mesh.vertices.resize(3, points.size());
  for (size_t p = 0; p < points.size(); ++p) mesh.vertices.col(p) = points[p];
  mesh.faces.resize(3, triangles.size());
  for (size_t f = 0; f < triangles.size(); ++f) mesh.faces.col(f) = triangles[f];
  return mesh;
}

}  // namespace

VoxelShape::VoxelShape(int nx, int ny, int nz)
    : nx(nx), ny(ny), nz(nz), occupied(static_cast<size_t>(nx) * ny * nz, 0) {}

bool VoxelShape::at(int i, int j, int k) const {
  if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return false;
  return occupied[i + nx * (j + ny * k)] != 0;
}

void VoxelShape::Set(int i, int j, int k, bool value) {
  CHECK(i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz);
  occupied[i + nx * (j + ny * k)] = value ? 1 : 0;
}

void VoxelShape::Fill(const Eigen::Vector3i& from, const Eigen::Vector3i& to_exclusive) {
  for (int k = from.z(); k < to_exclusive.z(); ++k)
    for (int j = from.y(); j < to_exclusive.y(); ++j)
      for (int i = from.x(); i < to_exclusive.x(); ++i) Set(i, j, k);
}

Mesh MakeVoxelMesh(const VoxelShape& shape, double voxel_size, int subdivisions) {
  CHECK_GT(subdivisions, 0);
  const int s = subdivisions;
  // Vertices live on a grid s times finer than the voxels; weld by grid key.
  std::map<std::tuple<int, int, int>, int> id_of_point;
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3i> triangles;
  auto vertex = [&](const Eigen::Vector3i& p) {
    auto [it, inserted] = id_of_point.emplace(std::make_tuple(p.x(), p.y(), p.z()),
                                              static_cast<int>(points.size()));
    if (inserted) points.push_back(p.cast<double>() * (voxel_size / s));
    return it->second;
  };
  for (int k = 0; k < shape.nz; ++k) {
    for (int j = 0; j < shape.ny; ++j) {
      for (int i = 0; i < shape.nx; ++i) {
        if (!shape.at(i, j, k)) continue;
        for (int axis = 0; axis < 3; ++axis) {
          for (int side = 0; side < 2; ++side) {
            Eigen::Vector3i neighbor(i, j, k);
            neighbor[axis] += side == 0 ? -1 : 1;
            if (shape.at(neighbor.x(), neighbor.y(), neighbor.z())) continue;
            // Face on the plane axis = voxel + side, spanned by axes u, v with
            // (u, v, axis) right-handed; flip the winding on the negative side.
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            Eigen::Vector3i base = Eigen::Vector3i(i, j, k) * s;
            base[axis] += side * s;
            for (int a = 0; a < s; ++a) {
              for (int b = 0; b < s; ++b) {
                Eigen::Vector3i corner[4];
                for (int c = 0; c < 4; ++c) {
                  corner[c] = base;
                  corner[c][u] += a + (c == 1 || c == 2);
                  corner[c][v] += b + (c >= 2);
                }
                int q[4];
                for (int c = 0; c < 4; ++c) q[c] = vertex(corner[c]);
                if (side == 1) {
                  triangles.emplace_back(q[0], q[1], q[2]);
                  triangles.emplace_back(q[0], q[2], q[3]);
                } else {
                  triangles.emplace_back(q[0], q[2], q[1]);
                  triangles.emplace_back(q[0], q[3], q[2]);
                }
              }
            }
          }
        }
      }
    }
  }
  return MeshFromLists(points, triangles);
}

Mesh MakeBar(int length, double voxel_size, int subdivisions) {
  VoxelShape shape(length, 1, 1);
  shape.Fill({0, 0, 0}, {length, 1, 1});
  return MakeVoxelMesh(shape, voxel_size, subdivisions);
}

Mesh MakeComb(int num_teeth, int tooth_length, double voxel_size, int subdivisions) {
  const int length = 2 * num_teeth - 1;
  VoxelShape shape(length, 1 + tooth_length, 1);
  shape.Fill({0, 0, 0}, {length, 1, 1});
  for (int t = 0; t < num_teeth; ++t) shape.Fill({2 * t, 1, 0}, {2 * t + 1, 1 + tooth_length, 1});
  return MakeVoxelMesh(shape, voxel_size, subdivisions);
}

Mesh MakeTwoBars(int length, int gap, double voxel_size, int subdivisions) {
  VoxelShape shape(length, 2 + gap, 1);
  shape.Fill({0, 0, 0}, {length, 1, 1});
  shape.Fill({0, 1 + gap, 0}, {length, 2 + gap, 1});
  return MakeVoxelMesh(shape, voxel_size, subdivisions);
}

Mesh MakeFork(double gap, double voxel_size, int subdivisions) {
  CHECK(gap > 0.0 && gap <= kForkTipGap) << gap;
  // A comb of two teeth 2 voxels wide with a 1-voxel column between them.
  const int height = kForkBaseHeight + kForkProngLength;
  VoxelShape shape(5, height, kForkDepth);
  shape.Fill({0, 0, 0}, {5, kForkBaseHeight, kForkDepth});
  shape.Fill({0, kForkBaseHeight, 0}, {2, height, kForkDepth});
  shape.Fill({3, kForkBaseHeight, 0}, {5, height, kForkDepth});
  Mesh fork = MakeVoxelMesh(shape, 1.0, subdivisions);
  // The column x in [2, 3] becomes [2, 2 + width(y)]; x >= 3 moves by
  // width(y) - 1. width is piecewise linear in y with its one kink on a
  // grid plane (y = base + touch), so every triangle maps affinely.
  const double touch_top = kForkBaseHeight + kForkTouchLength;
  auto width = [&](double y) {
    if (y <= touch_top) return gap;
    return gap + (kForkTipGap - gap) * (y - touch_top) / (height - touch_top);
  };
  for (int v = 0; v < fork.num_vertices(); ++v) {
    double& x = fork.vertices(0, v);
    const double w = width(fork.vertices(1, v));
    if (x >= 3.0) {
      x += w - 1.0;
    } else if (x > 2.0) {
      x = 2.0 + w * (x - 2.0);
    }
  }
  fork.vertices *= voxel_size;
  return fork;
}

namespace {

// Vertices of a fork above the base (y > kForkBaseHeight) on prong `prong`
// (0: x <= 2, 1: x > 2) and with y >= min_y, all in voxels.
std::vector<int> ForkVertices(const Mesh& fork, int prong, double min_y, double voxel_size) {
  const double tolerance = 1e-9;
  std::vector<int> ids;
  for (int v = 0; v < fork.num_vertices(); ++v) {
    const double x = fork.vertices(0, v) / voxel_size, y = fork.vertices(1, v) / voxel_size;
    if (y <= kForkBaseHeight + tolerance || y < min_y - tolerance) continue;
    if ((x <= 2.0 + tolerance) == (prong == 0)) ids.push_back(v);
  }
  return ids;
}

}  // namespace

std::vector<int> ForkBaseVertices(const Mesh& fork, double voxel_size) {
  std::vector<int> ids;
  for (int v = 0; v < fork.num_vertices(); ++v) {
    if (fork.vertices(1, v) / voxel_size <= kForkBaseHeight + 1e-9) ids.push_back(v);
  }
  return ids;
}

std::vector<int> ForkProngVertices(const Mesh& fork, int prong, double voxel_size) {
  CHECK(prong == 0 || prong == 1) << prong;
  return ForkVertices(fork, prong, 0.0, voxel_size);
}

std::vector<int> ForkTipVertices(const Mesh& fork, int prong, double voxel_size) {
  CHECK(prong == 0 || prong == 1) << prong;
  return ForkVertices(fork, prong, kForkBaseHeight + kForkProngLength - 1, voxel_size);
}

Mesh MakeOpenTube(double radius, double height, int segments, int rings) {
  CHECK_GE(segments, 3);
  CHECK_GE(rings, 1);
  Mesh mesh;
  mesh.vertices.resize(3, segments * (rings + 1));
  for (int r = 0; r <= rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const double angle = 2.0 * M_PI * s / segments;
      mesh.vertices.col(r * segments + s) << radius * std::cos(angle),
          radius * std::sin(angle), height * r / rings;
    }
  }
  mesh.faces.resize(3, 2 * segments * rings);
  int f = 0;
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = r * segments + (s + 1) % segments;
      const int c = a + segments, d = b + segments;
      mesh.faces.col(f++) << a, b, d;
      mesh.faces.col(f++) << a, d, c;
    }
  }
  return mesh;
}

int CylinderCapRings(int segments) {
  return std::max(1, static_cast<int>(std::lround(segments / (M_PI * std::sqrt(3.0)))));
}

Mesh MakeCylinder(double radius, double height, int segments, int rings) {
  CHECK_GE(segments, 3);
  CHECK_GE(rings, 1);
  const int cap_rings = CylinderCapRings(segments);
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3i> faces;
  // A circle of `count` vertices at height z, the first at angle `start`.
  auto add_circle = [&](double circle_radius, double z, int count, double start) {
    const int first = static_cast<int>(points.size());
    for (int s = 0; s < count; ++s) {
      const double angle = start + 2.0 * M_PI * s / count;
      points.emplace_back(circle_radius * std::cos(angle), circle_radius * std::sin(angle), z);
    }
    return first;
  };
  // Side: circle r starts at r half segments.
  const double segment_angle = 2.0 * M_PI / segments;
  for (int r = 0; r <= rings; ++r) {
    add_circle(radius, height * r / rings, segments, 0.5 * r * segment_angle);
  }
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const int a = r * segments + s, b = r * segments + (s + 1) % segments;
      const int c = a + segments, d = b + segments;  // c sits half a segment past a.
      faces.emplace_back(a, b, c);
      faces.emplace_back(b, d, c);
    }
  }
  // A cap: triangles between circles made outward (+z on top, -z below).
  auto add_face = [&](bool top, int a, int b, int c) {
    if (top) {
      faces.emplace_back(a, b, c);
    } else {
      faces.emplace_back(a, c, b);
    }
  };
  for (const bool top : {false, true}) {
    // Every circle of a cap starts at the angle of the side's end circle.
    const double z = top ? height : 0.0;
    const double start = top ? 0.5 * rings * segment_angle : 0.0;
    int outer = top ? rings * segments : 0;
    int outer_count = segments;
    for (int k = cap_rings - 1; k >= 1; --k) {
      const int inner_count = std::max(
          3, static_cast<int>(std::lround(static_cast<double>(segments) * k / cap_rings)));
      const int inner = add_circle(radius * k / cap_rings, z, inner_count, start);
      // Zip the two circles (both counterclockwise seen from +z) from their
      // first vertices: from edge (a, b), step on the circle whose step
      // leaves the shorter new edge. Both (a, b, next outer) and (a, b, next
      // inner) are counterclockwise.
      int i = 0, j = 0;
      while (i < inner_count || j < outer_count) {
        const int a = inner + i % inner_count, next_a = inner + (i + 1) % inner_count;
        const int b = outer + j % outer_count, next_b = outer + (j + 1) % outer_count;
        const double outer_edge = (points[next_b] - points[a]).squaredNorm();
        const double inner_edge = (points[next_a] - points[b]).squaredNorm();
        const bool step_outer = i == inner_count || (j < outer_count && outer_edge < inner_edge);
        if (step_outer) {
          add_face(top, a, b, next_b);
          ++j;
        } else {
          add_face(top, a, b, next_a);
          ++i;
        }
      }
      outer = inner;
      outer_count = inner_count;
    }
    const int centre = static_cast<int>(points.size());
    points.emplace_back(0.0, 0.0, z);
    for (int s = 0; s < outer_count; ++s) {
      add_face(top, centre, outer + s, outer + (s + 1) % outer_count);
    }
  }
  return MeshFromLists(points, faces);
}

Mesh MakeOctahedron() {
  Mesh mesh;
  mesh.vertices.resize(3, 6);
  mesh.vertices << 1, -1, 0, 0, 0, 0,  //
      0, 0, 1, -1, 0, 0,               //
      0, 0, 0, 0, 1, -1;
  mesh.faces.resize(3, 8);
  mesh.faces << 0, 2, 1, 3, 2, 0, 3, 1,  //
      2, 1, 3, 0, 0, 3, 1, 2,            //
      4, 4, 4, 4, 5, 5, 5, 5;
  return mesh;
}

Mesh MakeSphere(double radius, int segments, int rings) {
  CHECK_GE(segments, 3);
  CHECK_GE(rings, 2);
  // Vertex 0 is the south pole, then rings - 1 latitude circles, then north.
  const int num_vertices = 2 + segments * (rings - 1);
  Mesh mesh;
  mesh.vertices.resize(3, num_vertices);
  mesh.vertices.col(0) << 0, 0, -radius;
  for (int r = 1; r < rings; ++r) {
    const double polar = M_PI * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double azimuth = 2.0 * M_PI * s / segments;
      mesh.vertices.col(1 + (r - 1) * segments + s)
          << radius * std::sin(polar) * std::cos(azimuth),
          radius * std::sin(polar) * std::sin(azimuth), -radius * std::cos(polar);
    }
  }
  mesh.vertices.col(num_vertices - 1) << 0, 0, radius;
  std::vector<Eigen::Vector3i> faces;
  auto ring_vertex = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) faces.emplace_back(0, ring_vertex(1, s + 1), ring_vertex(1, s));
  for (int r = 1; r + 1 < rings; ++r) {
    for (int s = 0; s < segments; ++s) {
      const int a = ring_vertex(r, s), b = ring_vertex(r, s + 1);
      const int c = ring_vertex(r + 1, s), d = ring_vertex(r + 1, s + 1);
      faces.emplace_back(a, b, d);
      faces.emplace_back(a, d, c);
    }
  }
  for (int s = 0; s < segments; ++s) {
    faces.emplace_back(num_vertices - 1, ring_vertex(rings - 1, s), ring_vertex(rings - 1, s + 1));
  }
  mesh.faces.resize(3, faces.size());
  for (size_t f = 0; f < faces.size(); ++f) mesh.faces.col(f) = faces[f];
  return mesh;
}

std::vector<int> CombToothVertices(const Mesh& comb, int tooth, double voxel_size) {
  std::vector<int> ids;
  for (int v = 0; v < comb.num_vertices(); ++v) {
    const Eigen::Vector3d p = comb.vertices.col(v);
    if (p.y() > voxel_size * (1.0 + 1e-9) && p.x() >= 2 * tooth * voxel_size - 1e-9 &&
        p.x() <= (2 * tooth + 1) * voxel_size + 1e-9) {
      ids.push_back(v);
    }
  }
  return ids;
}

}  // namespace msdeform
