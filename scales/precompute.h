// Stage 1 of 3 of an edit (docs/extending.md, "The stages of an edit"): everything that depends
// only on the mesh and the options. Immutable once built.
//
//   std::shared_ptr<const Precompute> precompute = Precompute::Create(mesh, options, &error);
//   std::shared_ptr<const HandleSetup> setup = HandleSetup::Create(precompute, handles, &error);
//   std::unique_ptr<Session> session = Session::Create(setup, &error);
//   session->Drag(deformed_from_rest, &stats, &error);
//
// Each stage is made from the one before it, so a call out of order does not
// compile. A precompute serves any number of set-ups (one a handle layout),
// also from several threads: the two things it changes after Create, the cache
// of connected coarse graphs and the rigidity estimator's scratch, are behind
// locks.

#ifndef MSDEFORM_SCALES_PRECOMPUTE_H_
#define MSDEFORM_SCALES_PRECOMPUTE_H_

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <Eigen/Core>
#include "msdeform/core/cotangent_weights.h"
#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/lattice.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/timing.h"
#include "msdeform/scales/deformer_options.h"
#include "msdeform/scales/rigidity.h"

namespace msdeform {

class Precompute {
 public:
  // The mesh's rest normals, components and diagonal, its lattice, the
  // method's graphs (multi-scale: DG1 connected, the coarse scales' nodes
  // only) and the rigidity estimator. nullptr with a message on invalid
  // options, an invalid mesh or a mesh the lattice cannot take.
  static std::shared_ptr<const Precompute> Create(const Mesh& mesh, const DeformerOptions& options,
                                                  std::string* error);

  Precompute(const Precompute&) = delete;
  Precompute& operator=(const Precompute&) = delete;

  const DeformerOptions& options() const { return options_; }
  const Mesh& mesh() const { return mesh_; }
  const Eigen::Matrix3Xd& rest_normals() const { return rest_normals_; }  // 3 by #V
  const Components& components() const { return components_; }
  double diagonal() const { return diagonal_; }
  const Lattice& lattice() const { return lattice_; }
  // graphs()[i] is DG_{i+1}; the static baselines add their graph last. The
  // multi-scale coarse graphs have edges and weights only while connected
  // (ConnectedGraph; at most options().cached_scales of them and the pinned
  // ones, least recently used dropped first). A graph may be read while
  // another thread connects another; pin it (ConnectAndPin) to read it while
  // other threads use the cache.
  const std::vector<DeformationGraph>& graphs() const { return graphs_; }
  // The mesh's cotangent weights (core/cotangent_weights.h); built when the
  // energy is the subspace ARAP energy (options().energy), empty otherwise.
  const CotangentWeights& cotangent() const { return cotangent_; }
  // The static baselines' graph index; -1 for the multi-scale method.
  int static_graph() const { return static_graph_; }

  // graphs()[index], connected first if it is not. The reference stays
  // connected until the next call on this precompute (from any thread); hold
  // a pin (ConnectAndPin) to keep it longer.
  const DeformationGraph& ConnectedGraph(int index) const;

  // Keeps a graph connected while it lives (a set-up's graph, or the scales
  // a selection tries while other threads use the cache).
  class GraphPin {
   public:
    GraphPin() = default;
    ~GraphPin();
    GraphPin(GraphPin&& other) noexcept;
    GraphPin& operator=(GraphPin&& other) noexcept;
    GraphPin(const GraphPin&) = delete;
    GraphPin& operator=(const GraphPin&) = delete;

   private:
    friend class Precompute;
    // Adopts a pin already counted in precompute->pins_.
    GraphPin(const Precompute* precompute, int index) : precompute_(precompute), index_(index) {}
    const Precompute* precompute_ = nullptr;
    int index_ = -1;
  };

  // ConnectedGraph(index) and a pin on it, in one step: no other thread can
  // drop the graph in between. Read it as graphs()[index].
  GraphPin ConnectAndPin(int index) const;

  // Rigidity (multi-scale only) for the given fixed and moveable particles,
  // as RigidityEstimator::Estimate; one estimate at a time.
  bool EstimateRigidity(const std::vector<int>& fixed_particles,
                        const std::vector<int>& moveable_particles, RigidityEstimate* estimate,
                        std::string* error) const;

  // Milliseconds Create spent (lattice, graphs, rigidity precompute).
  double build_ms() const { return build_ms_; }
  // The same by stage (mesh_copy, normals, components, lattice, dg1_nodes,
  // dg1_nearest_nodes, edge_collapses, ..., rigidity_init).
  const StageTimes& stages() const { return stages_; }

 private:
  Precompute() = default;
  bool Build(const Mesh& mesh, const DeformerOptions& options, std::string* error);
  // ConnectedGraph with graphs_mutex_ held.
  DeformationGraph& ConnectLocked(int index) const;
  // Drops connected coarse graphs beyond cached_scales, least recently used
  // first, but `keep` and pinned ones; graphs_mutex_ held.
  void EvictLocked(int keep) const;
  // options_.graph with num_threads = options_.num_threads where it is 0.
  GraphOptions GraphBuildOptions() const;

  DeformerOptions options_;
  Mesh mesh_;
  Eigen::Matrix3Xd rest_normals_;
  Components components_;
  double diagonal_ = 0.0;
  Lattice lattice_;
  CotangentWeights cotangent_;
  int static_graph_ = -1;
  double build_ms_ = 0.0;
  StageTimes stages_;

  // The graph cache: graphs_' coarse edges and weights come and go.
  mutable std::mutex graphs_mutex_;
  mutable std::vector<DeformationGraph> graphs_;
  mutable std::vector<int> connected_coarse_;  // index > 0, least recently used first
  mutable std::vector<int> pins_;              // per graph

  mutable std::mutex rigidity_mutex_;
  mutable std::unique_ptr<RigidityEstimator> rigidity_estimator_;  // multi-scale only
};

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_PRECOMPUTE_H_
