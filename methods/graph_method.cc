#include "msdeform/methods/graph_method.h"

#include "msdeform/methods/method_options.h"

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

}  // namespace msdeform
