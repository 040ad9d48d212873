// The deformation-graph methods through the one interface: the multi-scale
// method and the static baselines (scales/deformer.h) as an adapter over
// the Deformer's public API. The registry makes one per Method; Precompute
// runs the Deformer with options.deformer and its method set to that one.

#ifndef MSDEFORM_METHODS_GRAPH_METHOD_H_
#define MSDEFORM_METHODS_GRAPH_METHOD_H_

#include "msdeform/methods/method.h"

namespace msdeform {

class GraphMethod : public EditingMethod {
 public:
  explicit GraphMethod(Method method) : EditingMethod(MethodName(method)), method_(method) {}

  const Eigen::Matrix3Xd& deformed_vertices() const override {
    return deformer_.deformed_vertices();
  }
  // Totally and Half Free nodes of the active graph.
  int nodes_optimized() const override;
  int variables() const override { return deformer_.num_variables(); }
  double precompute_ms() const override { return deformer_.precompute_ms(); }
  double rigidity_ms() const override { return deformer_.rigidity_ms(); }
  double setup_ms() const override { return deformer_.setup_ms(); }
  StageTimes stages() const override { return deformer_.stages(); }
  const Lattice* lattice() const override { return &deformer_.lattice(); }
  const Deformer* deformer() const override { return &deformer_; }
  // The Deformer for callers that need more than the interface (normals,
  // ConnectedGraph): the editor, the Python module.
  Deformer* mutable_deformer() { return &deformer_; }

 protected:
  bool DoPrecompute(const Mesh& mesh, const MethodOptions& options, std::string* error) override;
  bool DoSetHandles(const HandleLayout& layout, std::string* error) override {
    return deformer_.SetHandles(layout, error);
  }
  bool DoDrag(const Eigen::Affine3d& deformed_from_rest, MethodStats* stats,
              std::string* error) override {
    return deformer_.Drag(deformed_from_rest, stats, error);
  }

 private:
  Method method_;
  Deformer deformer_;
};

}  // namespace msdeform

#endif  // MSDEFORM_METHODS_GRAPH_METHOD_H_
