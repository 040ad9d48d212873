// The multi-scale deformer: the method of the paper end to end, and the two
// single-static-graph baselines it is compared against.
//
//   Deformer deformer;
//   deformer.Init(mesh, options, &error);          // lattice, all graphs, weights
//   deformer.SetHandles(layout, &error);           // rigidity, scale, classes, problem
//   deformer.Drag(deformed_from_rest, &stats, &error);  // one frame, warm-started
//   deformer.deformed_vertices();
//
// The Deformer is a facade over the three stages of an edit
// (docs/extending.md, "The stages of an edit"): Init makes a Precompute (mesh, lattice, graphs;
// scales/precompute.h), SetHandles a HandleSetup (rigidity, scale, node classes,
// the energy; scales/handle_setup.h) and a Session (solver, transforms, skinning;
// scales/session.h), Drag drives the session. The stages cannot be made out
// of order; the facade refuses calls out of order at run time. The methods
// (Method::kMultiScale, kStatic, kStaticDense) are described in handle_setup.h.

#ifndef MSDEFORM_SCALES_DEFORMER_H_
#define MSDEFORM_SCALES_DEFORMER_H_

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/lattice.h"
#include "msdeform/core/mesh.h"
#include "msdeform/scales/deformer_options.h"
#include "msdeform/scales/handle_setup.h"
#include "msdeform/scales/node_classes.h"
#include "msdeform/scales/precompute.h"
#include "msdeform/scales/rigidity.h"
#include "msdeform/scales/scale_selection.h"
#include "msdeform/scales/session.h"
#include "msdeform/solvers/ceres_solver.h"
#include "msdeform/solvers/deformation_energy.h"
#include "msdeform/solvers/frame_solver.h"
#include "msdeform/solvers/gauss_newton_solver.h"

namespace msdeform {

class Deformer {
 public:
  Deformer();
  ~Deformer();

  // The calls go Init, SetHandles, then any number of Drags; a new
  // SetHandles or Init starts over from that stage. A call out of order
  // returns false with a message.

  // Builds everything that depends only on the mesh. Returns false with a
  // message on invalid options or a mesh the lattice cannot take: invalid
  // options or an invalid mesh leave the object as it was, a later failure
  // leaves it empty (only Init is accepted).
  bool Init(const Mesh& mesh, const DeformerOptions& options, std::string* error);

  // A new handle layout: rigidity estimation, scale selection and node
  // classes (multi-scale), and the backend's problem (a Ceres problem, or the
  // Gauss-Newton system with its symbolic factorisation) reused by every
  // Drag. Resets the deformation to the rest pose. An invalid layout leaves
  // the previous one in place; a failure after validation (handles in one
  // lattice cell, a moveable vertex no free node skins, a solver that cannot
  // be set up) leaves no layout, and Drag is refused until one succeeds.
  bool SetHandles(const HandleLayout& layout, std::string* error);

  // Moves the moveable handle to deformed_from_rest * (its rest position),
  // solves warm-started from the previous frame and skins the mesh (only the
  // vertices with a non-Fixed node and not in a component without a moveable
  // handle vertex; the others stay at rest).
  bool Drag(const Eigen::Affine3d& deformed_from_rest, DragStats* stats, std::string* error);

  // The stages, for code that works on them directly (a second set-up on the
  // same precompute, a session of its own): null before a successful Init /
  // SetHandles.
  const std::shared_ptr<const Precompute>& precompute() const { return precompute_; }
  const std::shared_ptr<const HandleSetup>& setup() const { return setup_; }
  const Session* session() const { return session_.get(); }

  // The accessors below read the last successful stage: after a failed Init
  // (the object empty) they are not to be used until an Init succeeds.
  // Without a layout they read as at rest (no classes, no terms, the mesh's
  // vertices and normals).
  const Mesh& rest_mesh() const;
  const Eigen::Matrix3Xd& deformed_vertices() const;
  // The deformed unit normals (Eq. 10) of the last Drag, skinned on the first
  // call after it: a Drag skins positions only, so a program that never asks
  // (the command line, the experiments) does not pay for normals. Safe to
  // call from several threads at once (const readers); not during a Drag.
  const Eigen::Matrix3Xd& deformed_normals() const;
  const DeformerOptions& options() const { return options_; }
  const Lattice& lattice() const;
  // graphs()[i] is DG_{i+1}; the static baselines add their graph last. The
  // multi-scale method's coarse graphs have their nodes from Init, and their
  // edges and weights only while connected (is_connected(); cached_scales).
  const std::vector<DeformationGraph>& graphs() const;
  // graphs()[index], connected first if it is not (then cached as by
  // SetHandles; Precompute::ConnectedGraph).
  const DeformationGraph& ConnectedGraph(int index);
  // The graph being solved on, and its index in graphs().
  int active_graph() const;
  const DeformationGraph& active() const { return graphs()[active_graph()]; }
  const NodeTransforms& transforms() const;
  // Multi-scale only (empty for the baselines).
  const RigidityEstimate& rigidity() const;
  const ScaleSelection& selection() const;
  // Node class per node of the active graph (all Totally Free for baselines).
  const std::vector<NodeClass>& node_classes() const;
  int num_variables() const { return setup_ ? setup_->num_variables() : 0; }
  int num_coherence_terms() const { return setup_ ? setup_->num_coherence_terms() : 0; }
  // Position terms of the moveable handle (one per handle vertex).
  int num_position_terms() const { return setup_ ? setup_->num_position_terms() : 0; }
  // Whether every fixed-handle vertex (outside still components) is skinned
  // only by Fixed nodes, so that it stays exactly at rest: the multi-scale
  // default (pin_fixed_region); usually not the static baselines, nor
  // --pin_fixed_region=false.
  bool fixed_region_exact() const { return setup_ ? setup_->fixed_region_exact() : true; }
  // Eq. 17 for the current layout, backend independent (tests, benchmarks).
  const DeformationEnergy& energy() const;
  // Vertices skinned by Drag: those with a non-Fixed node among their k
  // nearest, outside components without a moveable-handle vertex.
  int num_skinned_vertices() const {
    return setup_ ? setup_->num_skinned_vertices() : rest_mesh().num_vertices();
  }
  double diagonal() const { return precompute_ ? precompute_->diagonal() : 0.0; }
  // Milliseconds spent in Init's graph/lattice build, and SetHandles's parts
  // (setup: scale selection, classes, energy and the solver's setup).
  double precompute_ms() const { return precompute_ms_; }
  double rigidity_ms() const { return setup_ ? setup_->rigidity_ms() : 0.0; }
  double setup_ms() const {
    return session_ ? setup_->setup_ms() + session_->setup_ms() : 0.0;
  }
  // The same by stage: the precompute's, the layout's and the session's, each
  // name prefixed by its stage ("precompute.lattice", "layout.rigidity",
  // "session.solver_setup").
  StageTimes stages() const;

 private:
  // Drops the set-up and the session (the mesh back at rest).
  void ResetSetup();

  DeformerOptions options_;  // the last Init's that passed Check
  std::shared_ptr<const Precompute> precompute_;  // null: empty
  std::shared_ptr<const HandleSetup> setup_;      // null: no handle layout set
  std::unique_ptr<Session> session_;              // with setup_
  double precompute_ms_ = 0.0;
};

// A drag along a path of handle transforms: the per-frame loop of msdeform,
// the experiment runner, the figure data and the benchmarks.
struct DragAlongOptions {
  // A frame whose solve fails keeps the last good node transforms (Drag
  // restores them). false: stop at the first failure. true: go on from the
  // last good frame; only a failure of the last frame, the result, is an
  // error.
  bool continue_after_failure = false;
  // Called after each successful frame (1-based frame number), e.g. for
  // progress lines or to write the frame's mesh.
  std::function<void(int frame, const DragStats& stats)> on_frame;
};

struct DragLog {
  std::vector<DragStats> frames;   // successful frames, in order
  std::vector<int> failed_frames;  // 1-based
};

// Drags `editor` through `path`: a Deformer (SetHandles done) or anything
// with its Drag(transform, DragStats*, std::string* error), such as an
// editing method (methods/method.h); false with "frame F of N: <what
// failed>" in *error.
template <typename Editor>
bool DragAlong(Editor* editor, const std::vector<Eigen::Affine3d>& path,
               const DragAlongOptions& options, DragLog* log, std::string* error) {
  *log = DragLog();
  const int num_frames = static_cast<int>(path.size());
  for (int f = 0; f < num_frames; ++f) {
    DragStats stats;
    std::string frame_error;
    if (!editor->Drag(path[f], &stats, &frame_error)) {
      log->failed_frames.push_back(f + 1);
      if (options.continue_after_failure && f + 1 < num_frames) continue;
      *error = "frame " + std::to_string(f + 1) + " of " + std::to_string(num_frames) +
               (options.continue_after_failure ? " (the result)" : "") + ": " + frame_error;
      return false;
    }
    if (options.on_frame) options.on_frame(f + 1, stats);
    log->frames.push_back(std::move(stats));
  }
  return true;
}

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_DEFORMER_H_
