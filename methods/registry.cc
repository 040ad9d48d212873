#include "msdeform/methods/registry.h"

#include <utility>

namespace msdeform {

// The registration function of each file of methods/CMakeLists.txt's
// method_files, declared, then called in the list's order.
#define MSDEFORM_METHOD_FILE(file) \
  MSDEFORM_REGISTER_METHODS(file, registry);
#include "registered_methods.inc"
#undef MSDEFORM_METHOD_FILE

namespace {

std::vector<MethodDescriptor> BuildRegistry() {
  std::vector<MethodDescriptor> registry;
#define MSDEFORM_METHOD_FILE(file) RegisterMethodsOf_##file(&registry);
#include "registered_methods.inc"
#undef MSDEFORM_METHOD_FILE
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
