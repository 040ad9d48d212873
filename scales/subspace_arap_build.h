// Builds one handle layout's subspace ARAP energy (solvers/subspace_arap.h)
// from the mesh, its cotangent weights, the selected graph, its node classes
// and the handle layout: the vertex kinds, the rotation clusters, Q, K_c and
// C of the Kronecker form. The solvers read the result; only the set-up
// (scales/handle_setup.h) builds it.

#ifndef MSDEFORM_SCALES_SUBSPACE_ARAP_BUILD_H_
#define MSDEFORM_SCALES_SUBSPACE_ARAP_BUILD_H_

#include <memory>
#include <vector>

#include "msdeform/core/cotangent_weights.h"
#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"
#include "msdeform/solvers/node_class.h"
#include "msdeform/solvers/subspace_arap.h"

namespace msdeform {

// What one layout's subspace energy is built from. The energy keeps the
// mesh, cotangent and graph pointers (Gather, Scatter, Basis and cotangent()
// read them): they must outlive it, which `owner`, kept by the energy, can
// guarantee (the layout passes its precompute and a pin on its graph, so a
// copy of the energy outlives the layout safely).
struct SubspaceArapInput {
  std::shared_ptr<const void> owner;
  const Mesh* mesh = nullptr;
  const CotangentWeights* cotangent = nullptr;
  const DeformationGraph* graph = nullptr;  // connected: weights and positions
  const std::vector<NodeClass>* node_class = nullptr;
  const HandleLayout* handles = nullptr;
  const std::vector<char>* still_vertices = nullptr;  // per vertex, or empty
  double length_unit = 1.0;                            // > 0
  // Threads of the build (the sums do not depend on it).
  int num_threads = 1;
};

std::shared_ptr<const SubspaceArap> BuildSubspaceArap(const SubspaceArapInput& input,
                                                      const ArapOptions& options);

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_SUBSPACE_ARAP_BUILD_H_
