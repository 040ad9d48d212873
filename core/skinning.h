// Skinning of mesh vertices and normals by deformation-graph node transforms
// (paper §5.1, Eq. 9-10; docs/method.md §5).
//
// Positions (Eq. 9): v' = sum_j w_j(v) [R_j (v - g_j) + g_j + t_j] over the k
// nearest nodes of v. Evaluated as v' = v + (sum_j w_j M_j) v + sum_j w_j c_j
// with M_j = R_j - I and c_j = t_j - M_j g_j precomputed once per call, which
// equals Eq. 9 because the weights sum to one, costs 4 x 12 multiply-adds per
// vertex, and gives back the rest positions bit for bit under identity
// transforms.
//
// Normals (Eq. 10 as in docs/method.md §5): n' = normalise(sum_j w_j R_j^{-T} n).
// The paper blends R_j n, which is right only for rotations; the inverse
// transpose is the normal transform of a general linear map. Where
// |det R_j| < 1e-12 its cofactor matrix (det R_j * R_j^{-T}, finite) is used.
// A blended normal of zero length comes out as the zero vector.
//
// Both run in parallel over vertices with OpenMP.

#ifndef MSDEFORM_CORE_SKINNING_H_
#define MSDEFORM_CORE_SKINNING_H_

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/deformation_graph.h"

namespace msdeform {

struct SkinningOptions {
  // OpenMP threads; 0 uses the OpenMP default (OMP_NUM_THREADS or all cores).
  int num_threads = 0;

  bool Check(std::string* error) const;
};

// Deformed positions (3 by #V) of `rest_vertices` (3 by #V, the vertices the
// graph's weights were computed for) under `transforms` (one per graph node).
void SkinPositions(const Eigen::Matrix3Xd& rest_vertices, const DeformationGraph& graph,
                   const NodeTransforms& transforms, Eigen::Matrix3Xd* deformed,
                   const SkinningOptions& options = SkinningOptions());

// Deformed unit normals (3 by #V) of `rest_normals` (3 by #V).
void SkinNormals(const Eigen::Matrix3Xd& rest_normals, const DeformationGraph& graph,
                 const NodeTransforms& transforms, Eigen::Matrix3Xd* deformed_normals,
                 const SkinningOptions& options = SkinningOptions());

// Positions and unit normals in one pass over the vertices, for the vertices
// listed in `vertex_subset` only (all when it is nullptr); the other columns
// of *deformed and *deformed_normals (which must then be 3 by #V already)
// are left as they are. The deformer passes the vertices that have a
// non-Fixed node among their k nearest: every other vertex stays at rest.
// Same numbers as SkinPositions and SkinNormals.
void SkinPositionsAndNormals(const Eigen::Matrix3Xd& rest_vertices,
                             const Eigen::Matrix3Xd& rest_normals, const DeformationGraph& graph,
                             const NodeTransforms& transforms,
                             const std::vector<int>* vertex_subset, Eigen::Matrix3Xd* deformed,
                             Eigen::Matrix3Xd* deformed_normals,
                             const SkinningOptions& options = SkinningOptions());

}  // namespace msdeform

#endif  // MSDEFORM_CORE_SKINNING_H_
