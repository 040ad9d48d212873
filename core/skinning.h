// Skinning of mesh vertices and normals by deformation-graph node transforms
// (paper §5.1, Eq. 9-10; docs/method.md §5).
//
// Positions (Eq. 9): v' = sum_j w_j(v) [R_j (v - g_j) + g_j + t_j] over the k
// nearest nodes of v. Evaluated as v' = v + ((sum_j w_j M_j) v + sum_j w_j c_j)
// with M_j = R_j - I and c_j = t_j - M_j g_j precomputed once per call, which
// equals Eq. 9 because the weights sum to one, and gives back the rest
// positions bit for bit under identity transforms (M_j = 0 and c_j = 0
// exactly, so v' = v + 0).
//
// Normals (Eq. 10 as in docs/method.md §5): n' = normalise(sum_j w_j R_j^{-T} n).
// The paper blends R_j n, which is right only for rotations; the inverse
// transpose is the normal transform of a general linear map. Where
// |det R_j| < 1e-12 its cofactor matrix (det R_j * R_j^{-T}, finite) is used.
// normalise(m) = m * (1 / |m|); a blended normal whose length is zero or not
// finite comes out as the zero vector.
//
// Evaluation: per call, one 32-double record per node holds M_j, c_j and
// R_j^{-T}, each column padded to 4 doubles; per vertex the k records are
// blended (sum_j w_j record_j) and applied to v and n. On a CPU with AVX2 and
// FMA (checked at run time; the build itself targets plain x86-64) a kernel
// with 4-wide FMAs does this, normalising 4 normals at a time; elsewhere, or
// with SkinningOptions::use_simd = false, a portable loop does the same
// operations in the same order with separately rounded multiply-adds. The two
// agree to rounding (about 1e-16 relative; both match the plain Eq. 9 and the
// normal formula within 1e-12, tested); each is deterministic and independent
// of the thread count, and SkinPositions, SkinNormals and
// SkinPositionsAndNormals give the same numbers as each other on one kernel.
//
// The vertices are split into chunks run by the caller and persistent helper
// threads (see ChunkPool in skinning.cc).

#ifndef MSDEFORM_CORE_SKINNING_H_
#define MSDEFORM_CORE_SKINNING_H_

#include <string>
#include <vector>

#include <Eigen/Core>

#include "msdeform/core/deformation_graph.h"

namespace msdeform {

struct SkinningOptions {
  // Threads, 0..kMaxThreads; 0 uses the OpenMP default (OMP_NUM_THREADS or all
  // cores).
  int num_threads = 0;
  // Use the AVX2+FMA kernel when the CPU has AVX2 and FMA (see above). false
  // forces the portable kernel (tests compare the two; they agree to rounding).
  bool use_simd = true;

  bool Check(std::string* error) const;
};

// Whether use_simd = true selects the AVX2+FMA kernel on this CPU.
bool SkinningSimdAvailable();

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
// The same numbers as SkinPositions and SkinNormals. Either output may be
// nullptr (not both): then only the other half is computed and its rest
// input is not read (the deformer skins positions every frame and normals
// when they are asked for).
void SkinPositionsAndNormals(const Eigen::Matrix3Xd& rest_vertices,
                             const Eigen::Matrix3Xd& rest_normals, const DeformationGraph& graph,
                             const NodeTransforms& transforms,
                             const std::vector<int>* vertex_subset, Eigen::Matrix3Xd* deformed,
                             Eigen::Matrix3Xd* deformed_normals,
                             const SkinningOptions& options = SkinningOptions());

}  // namespace msdeform

#endif  // MSDEFORM_CORE_SKINNING_H_
