#include "msdeform/methods/graph_method.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>
#include <utility>

#include <glog/logging.h>

#include "msdeform/core/timing.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/methods/registry.h"

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

GraphMethod::GraphMethod(Method method) : EditingMethod(MethodName(method)), method_(method) {}
GraphMethod::~GraphMethod() = default;

bool GraphMethod::Precompute(const Mesh& mesh, const DeformerOptions& options,
                             std::string* error) {
  if (options.method != method_) {
    *error = name() + ": the options name the method " + MethodName(options.method);
    return false;
  }
  MethodOptions method_options;
  method_options.deformer = options;
  return EditingMethod::Precompute(mesh, method_options, error);
}

bool GraphMethod::DoPrecompute(const Mesh& mesh, const MethodOptions& options,
                               std::string* error) {
  const auto start = std::chrono::steady_clock::now();
  // A failed Precompute leaves the method empty (EditingMethod then accepts
  // only Precompute).
  ResetSetup();
  precompute_.reset();
  DeformerOptions deformer_options = options.deformer;
  deformer_options.method = method_;
  // Create checks the options and the mesh first.
  precompute_ = msdeform::Precompute::Create(mesh, deformer_options, error);
  if (precompute_ == nullptr) return false;
  options_ = deformer_options;
  precompute_ms_ = MillisecondsSince(start);
  return true;
}

bool GraphMethod::DoSetHandles(const HandleLayout& layout, std::string* error) {
  // A failure leaves no handle layout (EditingMethod then refuses Drag).
  ResetSetup();
  std::shared_ptr<const HandleSetup> setup = HandleSetup::Create(precompute_, layout, error);
  if (setup == nullptr) return false;
  std::unique_ptr<Session> session = Session::Create(setup, error);
  if (session == nullptr) return false;
  setup_ = std::move(setup);
  session_ = std::move(session);
  return true;
}

bool GraphMethod::DoDrag(const HandleTransforms& deformed_from_rest, MethodStats* stats,
                         std::string* error) {
  return session_->Drag(deformed_from_rest, stats, error);
}

void GraphMethod::ResetSetup() {
  // The session first: it holds the set-up, which pins its graph.
  session_.reset();
  setup_.reset();
}

int GraphMethod::nodes_optimized() const {
  int count = 0;
  for (NodeClass c : node_classes()) count += c != NodeClass::kFixed;
  return count;
}

StageTimes GraphMethod::stages() const {
  StageTimes times;
  if (precompute_) times.Append(precompute_->stages(), "precompute.");
  // The report's keys: "layout." is the time spent per handle layout.
  if (setup_) times.Append(setup_->stages(), "layout.");
  if (session_) times.Add("session.solver_setup", session_->setup_ms());
  return times;
}

const Mesh& GraphMethod::rest_mesh() const {
  return precompute_ ? precompute_->mesh() : Nothing().mesh;
}

const Eigen::Matrix3Xd& GraphMethod::deformed_vertices() const {
  return session_ ? session_->deformed_vertices() : rest_mesh().vertices;
}

const Eigen::Matrix3Xd& GraphMethod::deformed_normals() const {
  if (session_) return session_->deformed_normals();
  return precompute_ ? precompute_->rest_normals() : Nothing().matrix;
}

const Lattice* GraphMethod::lattice() const {
  return precompute_ ? &precompute_->lattice() : &Nothing().lattice;
}

const std::vector<DeformationGraph>& GraphMethod::graphs() const {
  return precompute_ ? precompute_->graphs() : Nothing().graphs;
}

const DeformationGraph& GraphMethod::ConnectedGraph(int index) const {
  CHECK(precompute_ != nullptr) << "ConnectedGraph before a successful Precompute";
  return precompute_->ConnectedGraph(index);
}

int GraphMethod::active_graph() const {
  if (setup_) return setup_->active_graph();
  return precompute_ ? std::max(precompute_->static_graph(), 0) : 0;
}

const NodeTransforms& GraphMethod::transforms() const {
  return session_ ? session_->transforms() : Nothing().transforms;
}

const RigidityEstimate& GraphMethod::rigidity() const {
  return setup_ ? setup_->rigidity() : Nothing().rigidity;
}

const ScaleSelection& GraphMethod::selection() const {
  return setup_ ? setup_->selection() : Nothing().selection;
}

const std::vector<NodeClass>& GraphMethod::node_classes() const {
  return setup_ ? setup_->node_classes() : Nothing().node_classes;
}

const DeformationEnergy& GraphMethod::energy() const {
  return setup_ ? setup_->energy() : Nothing().energy;
}

namespace {

MethodDescriptor GraphDescriptor(Method method) {
  MethodDescriptor d;
  d.name = MethodName(method);
  d.graph = true;
  d.create = [method] { return std::make_unique<GraphMethod>(method); };
  return d;
}

}  // namespace

MSDEFORM_REGISTER_METHODS(graph_method, registry) {
  registry->push_back(GraphDescriptor(Method::kMultiScale));
  registry->push_back(GraphDescriptor(Method::kStatic));
  registry->push_back(GraphDescriptor(Method::kStaticDense));
}

}  // namespace msdeform
