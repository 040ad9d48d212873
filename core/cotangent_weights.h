// Cotangent weights of a triangle mesh's edges (Pinkall & Polthier 1993), as
// the ARAP energy uses them (Sorkine & Alexa 2007): for edge (i, k),
//   w_ik = (cot a_ik + cot b_ik) / 2, clamped at 0,
// with a_ik and b_ik the angles opposite the edge in its (one or two) faces;
// a degenerate corner adds 0. The clamp keeps every ARAP term >= 0 on meshes
// with obtuse triangles. core/metrics.h measures the ARAP energy with
// these weights, and the subspace ARAP energy (solvers/subspace_arap.h)
// minimises it.

#ifndef MSDEFORM_CORE_COTANGENT_WEIGHTS_H_
#define MSDEFORM_CORE_COTANGENT_WEIGHTS_H_

#include <vector>

#include "msdeform/core/mesh.h"

namespace msdeform {

// Per half-edge weights aligned with a VertexAdjacency: the weight of (v,
// neighbors[s]) is weight[s] for s in [offsets[v], offsets[v + 1]), and
// w_ik = w_ki.
struct CotangentWeights {
  VertexAdjacency adjacency;
  std::vector<double> weight;  // 2 #E
};

CotangentWeights ComputeCotangentWeights(const Mesh& mesh);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_COTANGENT_WEIGHTS_H_
