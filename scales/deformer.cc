#include "msdeform/scales/deformer.h"

#include <algorithm>
#include <chrono>
#include <string>
#include <utility>

#include <glog/logging.h>

#include "msdeform/core/timing.h"

namespace msdeform {
namespace {

// What the accessors read without a stage.
struct Empty {
  Mesh mesh;
  Eigen::Matrix3Xd matrix;
  Lattice lattice;
  std::vector<DeformationGraph> graphs;
  NodeTransforms transforms;
  RigidityEstimate rigidity;
  ScaleSelection selection;
  std::vector<NodeClass> node_classes;
  DeformationEnergy energy;
};

const Empty& Nothing() {
  static const Empty* const empty = new Empty();
  return *empty;
}

}  // namespace

Deformer::Deformer() = default;
Deformer::~Deformer() = default;

bool Deformer::Init(const Mesh& mesh, const DeformerOptions& options, std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  // Bad options or a bad mesh leave the object as it was; a failure after
  // this point (the lattice, the graphs) leaves it empty: every call but Init
  // is refused until an Init succeeds.
  if (!options.Check(error)) return false;
  if (!ValidateMesh(mesh, error)) return false;
  ResetSetup();
  precompute_.reset();
  options_ = options;
  precompute_ = Precompute::Create(mesh, options, error);
  if (precompute_ == nullptr) return false;
  precompute_ms_ = MillisecondsSince(start);
  return true;
}

StageTimes Deformer::stages() const {
  StageTimes times;
  if (precompute_) times.Append(precompute_->stages(), "precompute.");
  // The report's keys: "layout." is the time spent per handle layout.
  if (setup_) times.Append(setup_->stages(), "layout.");
  if (session_) times.Add("session.solver_setup", session_->setup_ms());
  return times;
}

void Deformer::ResetSetup() {
  // The session first: it holds the set-up, which pins its graph.
  session_.reset();
  setup_.reset();
}

bool Deformer::SetHandles(const HandleLayout& layout, std::string* error) {
  if (precompute_ == nullptr) {
    *error = "SetHandles before a successful Init";
    return false;
  }
  // An invalid layout leaves the current one in place; a failure after this
  // point leaves no layout (Drag is refused until a SetHandles succeeds).
  if (!ValidateHandles(layout, precompute_->mesh().num_vertices(), error)) return false;
  ResetSetup();
  std::shared_ptr<const HandleSetup> new_setup = HandleSetup::Create(precompute_, layout, error);
  if (new_setup == nullptr) return false;
  std::unique_ptr<Session> session = Session::Create(new_setup, error);
  if (session == nullptr) return false;
  setup_ = std::move(new_setup);
  session_ = std::move(session);
  return true;
}

bool Deformer::Drag(const Eigen::Affine3d& deformed_from_rest, DragStats* stats,
                    std::string* error) {
  if (session_ == nullptr) {
    *error = precompute_ == nullptr ? "Drag before a successful Init"
                                    : "Drag before a successful SetHandles";
    return false;
  }
  return session_->Drag(deformed_from_rest, stats, error);
}

const Mesh& Deformer::rest_mesh() const {
  return precompute_ ? precompute_->mesh() : Nothing().mesh;
}

const Eigen::Matrix3Xd& Deformer::deformed_vertices() const {
  return session_ ? session_->deformed_vertices() : rest_mesh().vertices;
}

const Eigen::Matrix3Xd& Deformer::deformed_normals() const {
  if (session_) return session_->deformed_normals();
  return precompute_ ? precompute_->rest_normals() : Nothing().matrix;
}

const Lattice& Deformer::lattice() const {
  return precompute_ ? precompute_->lattice() : Nothing().lattice;
}

const std::vector<DeformationGraph>& Deformer::graphs() const {
  return precompute_ ? precompute_->graphs() : Nothing().graphs;
}

const DeformationGraph& Deformer::ConnectedGraph(int index) {
  CHECK(precompute_ != nullptr) << "ConnectedGraph before a successful Init";
  return precompute_->ConnectedGraph(index);
}

int Deformer::active_graph() const {
  if (setup_) return setup_->active_graph();
  return precompute_ ? std::max(precompute_->static_graph(), 0) : 0;
}

const NodeTransforms& Deformer::transforms() const {
  return session_ ? session_->transforms() : Nothing().transforms;
}

const RigidityEstimate& Deformer::rigidity() const {
  return setup_ ? setup_->rigidity() : Nothing().rigidity;
}

const ScaleSelection& Deformer::selection() const {
  return setup_ ? setup_->selection() : Nothing().selection;
}

const std::vector<NodeClass>& Deformer::node_classes() const {
  return setup_ ? setup_->node_classes() : Nothing().node_classes;
}

const DeformationEnergy& Deformer::energy() const {
  return setup_ ? setup_->energy() : Nothing().energy;
}

}  // namespace msdeform
