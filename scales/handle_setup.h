// Stage 2 of 3 of an edit (scales/precompute.h; docs/extending.md, "The stages of an edit"):
// the set-up of one handle layout (core/handles.h's HandleLayout): everything
// that depends on which vertices are handles. Immutable once built.
//
// Multi-scale (docs/method.md §2-5): rigidity (by default the harmonic
// estimate; the paper's lattice shape matching with
// RigidityModel::kShapeMatching), scale s by Eq. 6-7, node classes
// (node_classes.h), the coherence edge set without the left-out terms, alpha
// weights, and position terms on the moveable handle and on the fixed
// vertices a non-Fixed node skins (hold_fixed_vertices). The static baselines
// (Sumner et al. 2007 on one graph): all nodes Totally Free but the still
// components', every directed edge, alpha = 1, and every fixed vertex held by
// a position term. Energy weights (Eq. 17) are 1 / 10 / 100 as sqrt residual
// scales. Lengths in the coherence and position residuals are measured in
// bounding-box diagonals (the mesh as if scaled to a unit diagonal), so
// results depend neither on the mesh's units nor on the cell width
// (docs/decisions/length-unit.md).

#ifndef MSDEFORM_SCALES_HANDLE_SETUP_H_
#define MSDEFORM_SCALES_HANDLE_SETUP_H_

#include <memory>
#include <string>
#include <vector>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/handles.h"
#include "msdeform/scales/precompute.h"
#include "msdeform/scales/rigidity.h"
#include "msdeform/scales/scale_selection.h"
#include "msdeform/solvers/deformation_energy.h"

namespace msdeform {

class HandleSetup {
 public:
  // The set-up of `handles` on `precompute` (not null). nullptr with a
  // message on an invalid handle layout, handles that share a lattice cell, or a
  // moveable vertex that no free node skins. Connects the coarse graphs
  // scale selection tries (Precompute::ConnectedGraph) and keeps the selected
  // one connected for the set-up's life.
  static std::shared_ptr<const HandleSetup> Create(std::shared_ptr<const Precompute> precompute,
                                                   const HandleLayout& handles,
                                                   std::string* error);

  HandleSetup(const HandleSetup&) = delete;
  HandleSetup& operator=(const HandleSetup&) = delete;

  const Precompute& precompute() const { return *precompute_; }
  const HandleLayout& handles() const { return handles_; }
  // Per vertex: in a component with no moveable-handle vertex (node_classes.h);
  // empty for a mesh of one component.
  const std::vector<char>& still_vertices() const { return still_vertices_; }
  // Multi-scale only (empty for the baselines).
  const RigidityEstimate& rigidity() const { return rigidity_; }
  const ScaleSelection& selection() const { return selection_; }
  // The graph solved on, and its index in precompute().graphs().
  int active_graph() const { return active_graph_; }
  const DeformationGraph& graph() const { return precompute_->graphs()[active_graph_]; }
  // Per node of graph().
  const std::vector<NodeClass>& node_classes() const { return node_classes_; }
  int num_variables() const;
  // Eq. 17, backend independent.
  const DeformationEnergy& energy() const { return energy_; }
  int num_coherence_terms() const { return num_coherence_terms_; }
  int num_position_terms() const { return num_position_terms_; }  // the moveable handle's
  // Whether every fixed-handle vertex (outside still components) is skinned
  // only by Fixed nodes, so that it stays exactly at rest.
  bool fixed_region_exact() const { return fixed_region_exact_; }
  // The vertices a frame skins: those with a non-Fixed node among their k
  // nearest, outside still components; empty when skin_all().
  const std::vector<int>& skinned_vertices() const { return skinned_vertices_; }
  bool skin_all() const { return skin_all_; }
  int num_skinned_vertices() const {
    return skin_all_ ? precompute_->mesh().num_vertices()
                     : static_cast<int>(skinned_vertices_.size());
  }
  double rigidity_ms() const { return rigidity_ms_; }
  // Scale selection, classes and the energy.
  double setup_ms() const { return setup_ms_; }
  // Both by stage (rigidity, scale_selection, skinning_data, skinned_vertices,
  // energy).
  const StageTimes& stages() const { return stages_; }

 private:
  explicit HandleSetup(std::shared_ptr<const Precompute> precompute);
  bool Build(const HandleLayout& handles, std::string* error);
  void BuildEnergy();
  bool FindSkinnedVertices(std::string* error);
  // The fixed-handle vertices outside still components that a non-Fixed node
  // skins, in handles_.fixed's order (a free node would carry them along).
  std::vector<int> FixedVerticesWithAFreeNode() const;

  std::shared_ptr<const Precompute> precompute_;
  HandleLayout handles_;
  std::vector<char> still_vertices_;
  RigidityEstimate rigidity_;
  ScaleSelection selection_;
  int active_graph_ = 0;
  Precompute::GraphPin pin_;  // keeps graph() connected
  std::vector<NodeClass> node_classes_;
  DeformationEnergy energy_;
  int num_coherence_terms_ = 0;
  int num_position_terms_ = 0;
  bool fixed_region_exact_ = true;
  std::vector<int> skinned_vertices_;
  bool skin_all_ = true;
  double rigidity_ms_ = 0.0;
  double setup_ms_ = 0.0;
  StageTimes stages_;
};

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_HANDLE_SETUP_H_
