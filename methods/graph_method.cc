#include "msdeform/methods/graph_method.h"

#include <memory>

#include "msdeform/methods/method_options.h"
#include "msdeform/methods/registry.h"

namespace msdeform {

bool GraphMethod::DoPrecompute(const Mesh& mesh, const MethodOptions& options,
                               std::string* error) {
  DeformerOptions deformer_options = options.deformer;
  deformer_options.method = method_;
  return deformer_.Init(mesh, deformer_options, error);
}

int GraphMethod::nodes_optimized() const {
  int count = 0;
  for (NodeClass c : deformer_.node_classes()) count += c != NodeClass::kFixed;
  return count;
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
