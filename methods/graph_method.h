// The deformation-graph methods: the multi-scale method of the paper end to
// end (Method::kMultiScale) and the two single-static-graph baselines it is
// compared against (kStatic, kStaticDense; scales/handle_setup.h describes all
// three). The registry makes one per method name.
//
//   GraphMethod method(Method::kMultiScale);
//   method.Precompute(mesh, options, &error);      // lattice, all graphs, weights
//   method.SetHandles(layout, &error);             // rigidity, scale, classes, problem
//   method.Drag(deformed_from_rest, &stats, &error);  // one frame, warm-started
//   method.deformed_vertices();
//
// The method holds the three stages of an edit (docs/extending.md, "The
// stages of an edit"): Precompute makes a Precompute (mesh, lattice, graphs;
// scales/precompute.h), SetHandles a HandleSetup (rigidity, scale, node
// classes, the energy; scales/handle_setup.h) and a Session (solver,
// transforms, skinning; scales/session.h), Drag drives the session. The
// stages cannot be made out of order; EditingMethod's public calls refuse
// calls out of order at run time (methods/method.h), as for every method.

#ifndef MSDEFORM_METHODS_GRAPH_METHOD_H_
#define MSDEFORM_METHODS_GRAPH_METHOD_H_

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/lattice.h"
#include "msdeform/core/mesh.h"
#include "msdeform/methods/method.h"
#include "msdeform/scales/deformer_options.h"
#include "msdeform/scales/handle_setup.h"
#include "msdeform/scales/node_classes.h"
#include "msdeform/scales/precompute.h"
#include "msdeform/scales/rigidity.h"
#include "msdeform/scales/scale_selection.h"
#include "msdeform/scales/session.h"
#include "msdeform/solvers/deformation_energy.h"

namespace msdeform {

class GraphMethod : public EditingMethod {
 public:
  explicit GraphMethod(Method method);
  ~GraphMethod() override;

  // The calls of EditingMethod (Precompute, SetHandles, Drag), and Precompute
  // with the graph methods' options alone (options.method must name this
  // method). A failed Precompute leaves the method empty; a failed
  // SetHandles leaves it with no handle layout (handles in one lattice cell,
  // a moveable vertex no free node skins, a solver that cannot be set up), so
  // Drag is refused until one succeeds.
  using EditingMethod::Precompute;
  bool Precompute(const Mesh& mesh, const DeformerOptions& options, std::string* error);

  // EditingMethod's reports. nodes_optimized: Totally and Half Free nodes of
  // the active graph.
  const Eigen::Matrix3Xd& deformed_vertices() const override;
  int nodes_optimized() const override;
  int variables() const override { return setup_ ? setup_->num_variables() : 0; }
  // Milliseconds of Precompute's lattice and graphs, and of SetHandles's
  // parts (setup: scale selection, classes, energy and the solver's set-up).
  double precompute_ms() const override { return precompute_ms_; }
  double rigidity_ms() const override { return setup_ ? setup_->rigidity_ms() : 0.0; }
  double setup_ms() const override {
    return session_ ? setup_->setup_ms() + session_->setup_ms() : 0.0;
  }
  // The same by stage: the precompute's, the set-up's and the session's,
  // each name prefixed by its stage as the report's keys are
  // ("precompute.lattice", "layout.rigidity", "session.solver_setup").
  StageTimes stages() const override;
  const Lattice* lattice() const override;
  const GraphMethod* graph_method() const override { return this; }

  // The stages, for code that works on them directly (a second set-up on the
  // same precompute, a session of its own): null before a successful
  // Precompute / SetHandles.
  const std::shared_ptr<const msdeform::Precompute>& precompute() const { return precompute_; }
  const std::shared_ptr<const HandleSetup>& setup() const { return setup_; }
  const Session* session() const { return session_.get(); }

  // The accessors below read the last successful stage: after a failed
  // Precompute (the method empty) they read as an empty mesh. Without a
  // handle layout they read as at rest (no classes, no terms, the mesh's
  // vertices and normals).
  const Mesh& rest_mesh() const;
  // The deformed unit normals (Eq. 10) of the last Drag, skinned on the first
  // call after it: a Drag skins positions only, so a program that never asks
  // (the command line, the experiments) does not pay for normals. Safe to
  // call from several threads at once (const readers); not during a Drag.
  const Eigen::Matrix3Xd& deformed_normals() const;
  // The last successful Precompute's options (method set to this method).
  const DeformerOptions& options() const { return options_; }
  // graphs()[i] is DG_{i+1}; the static baselines add their graph last. The
  // multi-scale method's coarse graphs have their nodes from Precompute, and
  // their edges and weights only while connected (is_connected();
  // cached_scales).
  const std::vector<DeformationGraph>& graphs() const;
  // graphs()[index], connected first if it is not (then cached as by
  // SetHandles; Precompute::ConnectedGraph).
  const DeformationGraph& ConnectedGraph(int index) const;
  // The graph being solved on, and its index in graphs().
  int active_graph() const;
  const DeformationGraph& active() const { return graphs()[active_graph()]; }
  const NodeTransforms& transforms() const;
  // Multi-scale only (empty for the baselines).
  const RigidityEstimate& rigidity() const;
  const ScaleSelection& selection() const;
  // Node class per node of the active graph (all Totally Free for baselines).
  const std::vector<NodeClass>& node_classes() const;
  int num_coherence_terms() const { return setup_ ? setup_->num_coherence_terms() : 0; }
  // Position terms of the moveable handle (one per handle vertex).
  int num_position_terms() const { return setup_ ? setup_->num_position_terms() : 0; }
  // Whether every fixed-handle vertex (outside still components) is skinned
  // only by Fixed nodes, so that it stays exactly at rest: the multi-scale
  // default (pin_fixed_region); usually not the static baselines, nor
  // --pin_fixed_region=false.
  bool fixed_region_exact() const { return setup_ ? setup_->fixed_region_exact() : true; }
  // Eq. 17 for the current handle layout, backend independent (tests,
  // benchmarks).
  const DeformationEnergy& energy() const;
  // Vertices skinned by Drag: those with a non-Fixed node among their k
  // nearest, outside components without a moveable-handle vertex.
  int num_skinned_vertices() const {
    return setup_ ? setup_->num_skinned_vertices() : rest_mesh().num_vertices();
  }
  double diagonal() const { return precompute_ ? precompute_->diagonal() : 0.0; }

 protected:
  bool DoPrecompute(const Mesh& mesh, const MethodOptions& options, std::string* error) override;
  bool DoSetHandles(const HandleLayout& layout, std::string* error) override;
  bool DoDrag(const HandleTransforms& deformed_from_rest, MethodStats* stats,
              std::string* error) override;

 private:
  // Drops the set-up and the session (the mesh back at rest).
  void ResetSetup();

  Method method_;
  DeformerOptions options_;  // the last Precompute's that passed Check
  std::shared_ptr<const msdeform::Precompute> precompute_;  // null: empty
  std::shared_ptr<const HandleSetup> setup_;                // null: no handle layout set
  std::unique_ptr<Session> session_;                        // with setup_
  double precompute_ms_ = 0.0;
};

}  // namespace msdeform

#endif  // MSDEFORM_METHODS_GRAPH_METHOD_H_
