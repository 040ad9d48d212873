#include "msdeform/scales/precompute.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include <glog/logging.h>

#include "msdeform/core/parallel.h"
#include "msdeform/core/timing.h"

namespace msdeform {

std::shared_ptr<const Precompute> Precompute::Create(const Mesh& mesh,
                                                     const DeformerOptions& options,
                                                     std::string* error) {
  std::shared_ptr<Precompute> precompute(new Precompute());
  if (!precompute->Build(mesh, options, error)) return nullptr;
  return precompute;
}

bool Precompute::Build(const Mesh& mesh, const DeformerOptions& options, std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  if (!options.Check(error)) return false;
  if (!ValidateMesh(mesh, error)) return false;
  options_ = options;
  stages_ = StageTimes();
  {
    ScopedStage stage(&stages_, "mesh_copy");
    CopyColumns(mesh.vertices, options_.num_threads, &mesh_.vertices);
    CopyColumns(mesh.faces, options_.num_threads, &mesh_.faces);
  }
  {
    ScopedStage stage(&stages_, "normals");
    rest_normals_ = VertexNormals(mesh_, options_.num_threads);
  }
  {
    ScopedStage stage(&stages_, "components");
    components_ = ConnectedComponents(mesh_, options_.num_threads);
    diagonal_ = BoundingBoxDiagonal(mesh_, options_.num_threads);
  }
  // The lattice's split_cells test reads the same normals and components.
  {
    ScopedStage stage(&stages_, "lattice");
    LatticeOptions lattice = options_.lattice;
    lattice.num_threads = options_.num_threads;
    if (!Lattice::Build(mesh_, lattice, rest_normals_, components_, &lattice_, error)) {
      return false;
    }
  }
  switch (options_.method) {
    case Method::kMultiScale:
      // The coarse scales are connected when first used (ConnectedGraph).
      if (!BuildMultiScaleGraphs(mesh_, lattice_, GraphBuildOptions(), &graphs_, error,
                                 Connect::kFinestOnly, &stages_)) {
        return false;
      }
      break;
    case Method::kStatic:
      // DG1 and one graph of static_nodes nodes by the same edge collapse.
      if (!BuildCollapsedGraphs(mesh_, lattice_, GraphBuildOptions(),
                                {std::min(options_.static_nodes, lattice_.num_surface_particles())},
                                &graphs_, error, Connect::kAll, &stages_)) {
        return false;
      }
      static_graph_ = 1;
      break;
    case Method::kStaticDense:
      if (!BuildCollapsedGraphs(mesh_, lattice_, GraphBuildOptions(), {}, &graphs_, error,
                                Connect::kAll, &stages_)) {
        return false;
      }
      static_graph_ = 0;
      break;
  }
  pins_.assign(graphs_.size(), 0);
  // The subspace ARAP energy's cotangent weights, once per mesh.
  if (options_.energy == Energy::kArap) {
    ScopedStage stage(&stages_, "cotangent_weights");
    cotangent_ = ComputeCotangentWeights(mesh_);
  }
  if (options_.method == Method::kMultiScale) {
    ScopedStage stage(&stages_, "rigidity_init");
    rigidity_estimator_ = std::make_unique<RigidityEstimator>();
    if (!rigidity_estimator_->Init(lattice_, options_.rigidity, error, options_.num_threads)) {
      return false;
    }
  }
  build_ms_ = MillisecondsSince(start);
  return true;
}

GraphOptions Precompute::GraphBuildOptions() const {
  // One thread count for the whole method unless the graphs ask for their own.
  GraphOptions graph = options_.graph;
  if (graph.num_threads == 0) graph.num_threads = options_.num_threads;
  return graph;
}

const DeformationGraph& Precompute::ConnectedGraph(int index) const {
  std::lock_guard<std::mutex> lock(graphs_mutex_);
  return ConnectLocked(index);
}

Precompute::GraphPin Precompute::ConnectAndPin(int index) const {
  std::lock_guard<std::mutex> lock(graphs_mutex_);
  ConnectLocked(index);
  ++pins_[index];
  return GraphPin(this, index);
}

DeformationGraph& Precompute::ConnectLocked(int index) const {
  CHECK(index >= 0 && index < static_cast<int>(graphs_.size())) << index;
  DeformationGraph& graph = graphs_[index];
  if (index == 0) return graph;  // DG1 is connected by Create
  const auto used = std::find(connected_coarse_.begin(), connected_coarse_.end(), index);
  if (used != connected_coarse_.end()) connected_coarse_.erase(used);
  connected_coarse_.push_back(index);
  if (!graph.is_connected()) ConnectGraph(mesh_, lattice_, GraphBuildOptions(), &graph);
  EvictLocked(index);
  return graph;
}

void Precompute::EvictLocked(int keep) const {
  // The least recently used first, never `keep` nor a pinned one.
  for (size_t i = 0; static_cast<int>(connected_coarse_.size()) > options_.cached_scales &&
                     i < connected_coarse_.size();) {
    const int evict = connected_coarse_[i];
    if (evict == keep || pins_[evict] > 0) {
      ++i;
      continue;
    }
    graphs_[evict].Disconnect();
    connected_coarse_.erase(connected_coarse_.begin() + i);
  }
}

Precompute::GraphPin::~GraphPin() {
  if (precompute_ == nullptr) return;
  std::lock_guard<std::mutex> lock(precompute_->graphs_mutex_);
  // The last pin gone, the cache comes back within its bound.
  if (--precompute_->pins_[index_] == 0) precompute_->EvictLocked(-1);
}

Precompute::GraphPin::GraphPin(GraphPin&& other) noexcept
    : precompute_(std::exchange(other.precompute_, nullptr)), index_(other.index_) {}

Precompute::GraphPin& Precompute::GraphPin::operator=(GraphPin&& other) noexcept {
  if (this != &other) {
    GraphPin old(std::move(*this));
    precompute_ = std::exchange(other.precompute_, nullptr);
    index_ = other.index_;
  }
  return *this;
}

bool Precompute::EstimateRigidity(const std::vector<int>& fixed_particles,
                                  const std::vector<int>& moveable_particles,
                                  RigidityEstimate* estimate, std::string* error) const {
  CHECK(rigidity_estimator_ != nullptr) << "rigidity is estimated for the multi-scale method only";
  std::lock_guard<std::mutex> lock(rigidity_mutex_);
  return rigidity_estimator_->Estimate(fixed_particles, moveable_particles, estimate, error);
}

}  // namespace msdeform
