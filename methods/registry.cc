#include "msdeform/methods/registry.h"

#include <functional>
#include <utility>

#include "msdeform/methods/fastlsm.h"
#include "msdeform/methods/graph_method.h"
#include "msdeform/methods/rigid_cells.h"
#ifdef MSDEFORM_HAVE_CGAL
#include "msdeform/methods/cgal_arap.h"
#endif

namespace msdeform {
namespace {

using Factory = std::function<std::unique_ptr<EditingMethod>()>;

// The registered methods, one line each, in the order MethodNames lists them.
const std::vector<std::pair<std::string, Factory>>& Registry() {
  static const std::vector<std::pair<std::string, Factory>> registry = {
      {"multiscale", [] { return std::make_unique<GraphMethod>(Method::kMultiScale); }},
      {"static", [] { return std::make_unique<GraphMethod>(Method::kStatic); }},
      {"static_dense", [] { return std::make_unique<GraphMethod>(Method::kStaticDense); }},
#ifdef MSDEFORM_HAVE_CGAL
      {"cgal_arap",
       [] { return std::make_unique<CgalArapMethod>("cgal_arap", ArapVariant::kOriginal); }},
      {"cgal_sr_arap",
       [] { return std::make_unique<CgalArapMethod>("cgal_sr_arap", ArapVariant::kSmoothRotationEnhanced); }},
#endif
      {"fastlsm", [] { return std::make_unique<FastLsm>(); }},
      {"rigid_cells", [] { return std::make_unique<RigidCells>(); }},
  };
  return registry;
}

}  // namespace

std::vector<std::string> MethodNames() {
  std::vector<std::string> names;
  for (const auto& entry : Registry()) names.push_back(entry.first);
  return names;
}

std::string MethodNameList() {
  std::string list;
  for (const auto& entry : Registry()) list += (list.empty() ? "" : ", ") + entry.first;
  return list;
}

bool IsMethodName(const std::string& name) {
  for (const auto& entry : Registry()) {
    if (entry.first == name) return true;
  }
  return false;
}

std::unique_ptr<EditingMethod> CreateMethod(const std::string& name, std::string* error) {
  for (const auto& entry : Registry()) {
    if (entry.first == name) return entry.second();
  }
  *error = "unknown method '" + name + "' (expected " + MethodNameList() + ")";
  return nullptr;
}

}  // namespace msdeform
