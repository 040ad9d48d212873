// The multi-scale deformer: the method of the paper end to end, and the two
// single-static-graph baselines it is compared against.
//
//   Deformer deformer;
//   deformer.Init(mesh, options, &error);          // lattice, all graphs, weights
//   deformer.SetHandles(layout, &error);           // rigidity, scale, classes, problem
//   deformer.Drag(deformed_from_rest, &stats, &error);  // one frame, warm-started
//   deformer.deformed_vertices();
//
// Method::kMultiScale follows docs/method.md §2-5: rigidity (by default the
// harmonic estimate; the paper's lattice shape matching with
// RigidityModel::kShapeMatching), scale s by Eq. 6-7, node classes as
// parameter-block fixing (Totally Free: R and t, Half Free: R with t = 0,
// Fixed: nothing), the coherence edge set without the left-out terms, alpha
// weights, position constraints on the moveable handle and on the fixed
// vertices a non-Fixed node skins (hold_fixed_vertices).
// Method::kStatic / kStaticDense are embedded deformation as in Sumner et al.
// 2007 on one graph (about 220 nodes, or DG1): all nodes free, every directed
// edge, alpha = 1, and the fixed handles held by position constraints to their
// rest positions.
//
// Energy weights (Eq. 17) are 1 / 10 / 100 as sqrt residual scales. Lengths
// in the coherence and position residuals are measured in bounding-box
// diagonals (the mesh as if scaled to a unit diagonal), so results depend
// neither on the mesh's units nor on the cell width (docs/decisions.md).

#ifndef MSDEFORM_SCALES_DEFORMER_H_
#define MSDEFORM_SCALES_DEFORMER_H_

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/lattice.h"
#include "msdeform/core/mesh.h"
#include "msdeform/scales/ceres_solver.h"
#include "msdeform/scales/deformation_energy.h"
#include "msdeform/scales/deformer_options.h"
#include "msdeform/scales/frame_solver.h"
#include "msdeform/scales/gauss_newton_solver.h"
#include "msdeform/scales/rigidity.h"
#include "msdeform/scales/scale_selection.h"

namespace msdeform {

// Per-frame numbers.
struct DragStats {
  double frame_ms = 0.0;  // the whole Drag
  double solve_ms = 0.0;
  double skin_ms = 0.0;  // positions; normals are skinned when asked for
  int iterations = 0;
  int factorizations = 0;
  double initial_cost = 0.0;  // at the initial guess
  double final_cost = 0.0;
  bool converged = false;
  // The solve's convergence trace (scales/frame_solver.h).
  std::vector<TracePoint> trace;
};

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

  // The accessors below read the last successful stage: after a failed Init
  // (the object empty) they are not to be used until an Init succeeds.
  const Mesh& rest_mesh() const { return mesh_; }
  const Eigen::Matrix3Xd& deformed_vertices() const { return deformed_vertices_; }
  // The deformed unit normals (Eq. 10) of the last Drag, skinned on the first
  // call after it: a Drag skins positions only, so a program that never asks
  // (the command line, the experiments) does not pay for normals. Safe to
  // call from several threads at once (const readers); not during a Drag.
  const Eigen::Matrix3Xd& deformed_normals() const;
  const DeformerOptions& options() const { return options_; }
  const Lattice& lattice() const { return lattice_; }
  // graphs()[i] is DG_{i+1}; the static baselines add their graph last. The
  // multi-scale method's coarse graphs have their nodes from Init, and their
  // edges and weights only while connected (is_connected(); cached_scales).
  const std::vector<DeformationGraph>& graphs() const { return graphs_; }
  // graphs()[index], connected first if it is not (then cached as by
  // SetHandles).
  const DeformationGraph& ConnectedGraph(int index);
  // The graph being solved on, and its index in graphs().
  int active_graph() const { return active_graph_; }
  const DeformationGraph& active() const { return graphs_[active_graph_]; }
  const NodeTransforms& transforms() const { return transforms_; }
  // Multi-scale only (empty for the baselines).
  const RigidityEstimate& rigidity() const { return rigidity_; }
  const ScaleSelection& selection() const { return selection_; }
  // Node class per node of the active graph (all Totally Free for baselines).
  const std::vector<NodeClass>& node_classes() const { return node_classes_; }
  int num_variables() const;
  int num_coherence_terms() const { return num_coherence_terms_; }
  // Position terms of the moveable handle (one per handle vertex).
  int num_position_terms() const { return num_position_terms_; }
  // Whether every fixed-handle vertex (outside still components) is skinned
  // only by Fixed nodes, so that it stays exactly at rest: the multi-scale
  // default (pin_fixed_region); usually not the static baselines, nor
  // --pin_fixed_region=false.
  bool fixed_region_exact() const { return fixed_region_exact_; }
  // Eq. 17 for the current layout, backend independent (tests, benchmarks).
  const DeformationEnergy& energy() const { return energy_; }
  // Vertices skinned by Drag: those with a non-Fixed node among their k
  // nearest, outside components without a moveable-handle vertex.
  int num_skinned_vertices() const {
    return skin_all_ ? mesh_.num_vertices() : static_cast<int>(skinned_vertices_.size());
  }
  double diagonal() const { return diagonal_; }
  // Milliseconds spent in Init's graph/lattice build, and SetHandles's parts.
  double precompute_ms() const { return precompute_ms_; }
  double rigidity_ms() const { return rigidity_ms_; }
  double setup_ms() const { return setup_ms_; }

 private:
  enum class Stage { kEmpty, kInitialised, kHandlesSet };
  // Back to "initialised, no layout": the per-layout state cleared and the
  // mesh at rest.
  void ResetLayout();
  bool BuildLayout(const HandleLayout& layout, std::string* error);
  // options_.graph with num_threads = options_.num_threads where it is 0.
  GraphOptions GraphBuildOptions() const;
  bool BuildProblem(std::string* error);
  void BuildEnergy();

  Stage stage_ = Stage::kEmpty;
  DeformerOptions options_;
  Mesh mesh_;
  Eigen::Matrix3Xd rest_normals_;
  Components components_;             // of mesh_
  std::vector<char> still_vertices_;  // per vertex, for the layout; empty: one component
  double diagonal_ = 0.0;
  Lattice lattice_;
  std::vector<DeformationGraph> graphs_;
  // Connected coarse graphs (index > 0), least recently used first.
  std::vector<int> connected_coarse_;
  int static_graph_ = -1;  // index of the static baselines' graph
  std::unique_ptr<RigidityEstimator> rigidity_estimator_;

  HandleLayout layout_;
  RigidityEstimate rigidity_;
  ScaleSelection selection_;
  int active_graph_ = 0;
  std::vector<NodeClass> node_classes_;
  NodeTransforms transforms_;
  DeformationEnergy energy_;
  std::unique_ptr<FrameSolver> solver_;
  NodeTransforms previous_transforms_;  // the frame before, for kExtrapolated
  int frames_since_layout_ = 0;
  std::vector<int> skinned_vertices_;
  bool skin_all_ = true;
  int num_position_terms_ = 0;
  bool fixed_region_exact_ = true;
  int num_coherence_terms_ = 0;
  Eigen::Matrix3Xd deformed_vertices_;
  mutable Eigen::Matrix3Xd deformed_normals_;
  mutable bool normals_stale_ = false;  // a Drag moved the positions since
  std::unique_ptr<std::mutex> normals_mutex_ = std::make_unique<std::mutex>();
  double precompute_ms_ = 0.0;
  double rigidity_ms_ = 0.0;
  double setup_ms_ = 0.0;
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

// Drags `deformer` (SetHandles done) through `path`; false with
// "frame F of N: <what failed>" in *error.
bool DragAlong(Deformer* deformer, const std::vector<Eigen::Affine3d>& path,
               const DragAlongOptions& options, DragLog* log, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_DEFORMER_H_
