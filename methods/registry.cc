#include "msdeform/methods/registry.h"

#include <utility>

#include "msdeform/methods/fastlsm.h"
#include "msdeform/methods/full_arap.h"
#include "msdeform/methods/rigid_cells.h"
#include "msdeform/methods/graph_method.h"
#include "msdeform/methods/method_option_table.h"
#ifdef MSDEFORM_HAVE_CGAL
#include "msdeform/methods/cgal_arap.h"
#endif

namespace msdeform {
namespace {

MethodDescriptor GraphDescriptor(Method method) {
  MethodDescriptor d;
  d.name = MethodName(method);
  d.graph = true;
  d.create = [method] { return std::make_unique<GraphMethod>(method); };
  return d;
}

#ifdef MSDEFORM_HAVE_CGAL
MethodDescriptor CgalDescriptor(const std::string& name, ArapVariant variant,
                                const std::string& energy) {
  MethodDescriptor d;
  d.name = name;
  d.energy = energy;
  d.options = "cgal";
  d.add_option_rows = [](OptionTable<MethodOptions>* t) {
    t->Embed("cgal", &MethodOptions::cgal, CgalArapOptionTable());
  };
  d.create = [name, variant] { return std::make_unique<CgalArapMethod>(name, variant); };
  return d;
}
#endif

// The registered methods, one descriptor each, in the order MethodNames lists them.
std::vector<MethodDescriptor> BuildRegistry() {
  std::vector<MethodDescriptor> registry;
  registry.push_back(GraphDescriptor(Method::kMultiScale));
  registry.push_back(GraphDescriptor(Method::kStatic));
  registry.push_back(GraphDescriptor(Method::kStaticDense));
#ifdef MSDEFORM_HAVE_CGAL
  registry.push_back(CgalDescriptor("cgal_arap", ArapVariant::kOriginal, "arap"));
  registry.push_back(
      CgalDescriptor("cgal_sr_arap", ArapVariant::kSmoothRotationEnhanced, "sr_arap"));
#endif
  MethodDescriptor fastlsm;
  fastlsm.name = "fastlsm";
  fastlsm.energy = "shape_matching";
  fastlsm.options = "fastlsm";
  fastlsm.add_option_rows = [](OptionTable<MethodOptions>* t) {
    t->Embed("fastlsm", &MethodOptions::fastlsm, FastLsmOptionTable());
  };
  fastlsm.create = [] { return std::make_unique<FastLsm>(); };
  registry.push_back(std::move(fastlsm));
  MethodDescriptor rigid_cells;
  rigid_cells.name = "rigid_cells";
  rigid_cells.energy = "rigid_cells";
  rigid_cells.create = [] { return std::make_unique<RigidCells>(); };
  registry.push_back(std::move(rigid_cells));
  MethodDescriptor full_arap;
  full_arap.name = "full_arap";
  full_arap.energy = "arap";
  full_arap.options = "full_arap";
  full_arap.add_option_rows = [](OptionTable<MethodOptions>* t) {
    t->Embed("full_arap", &MethodOptions::full_arap, FullArapOptionTable());
  };
  full_arap.create = [] { return std::make_unique<FullArapMethod>(); };
  registry.push_back(std::move(full_arap));
  return registry;
}

}  // namespace

const std::vector<MethodDescriptor>& RegisteredMethods() {
  static const std::vector<MethodDescriptor> registry = BuildRegistry();
  return registry;
}

const MethodDescriptor* FindMethod(const std::string& name) {
  for (const MethodDescriptor& d : RegisteredMethods()) {
    if (d.name == name) return &d;
  }
  return nullptr;
}

std::vector<std::string> MethodNames() {
  std::vector<std::string> names;
  for (const MethodDescriptor& d : RegisteredMethods()) names.push_back(d.name);
  return names;
}

std::string MethodNameList() {
  std::string list;
  for (const MethodDescriptor& d : RegisteredMethods()) list += (list.empty() ? "" : ", ") + d.name;
  return list;
}

bool IsMethodName(const std::string& name) { return FindMethod(name) != nullptr; }

bool IsGraphMethod(const std::string& name) {
  const MethodDescriptor* d = FindMethod(name);
  return d != nullptr && d->graph;
}

std::unique_ptr<EditingMethod> CreateMethod(const std::string& name, std::string* error) {
  if (const MethodDescriptor* d = FindMethod(name)) return d->create();
  *error = "unknown method '" + name + "' (expected " + MethodNameList() + ")";
  return nullptr;
}

std::string MinimisedEnergy(const std::string& name, const DeformerOptions& options) {
  const MethodDescriptor* d = FindMethod(name);
  if (d == nullptr) return "-";
  return d->graph ? EnergyName(options.energy) : d->energy;
}

}  // namespace msdeform
