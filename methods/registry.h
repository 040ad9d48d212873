// Editing methods by name. Adding a method is its files and one line in
// methods/registry.cc (docs/extending.md, "Adding a method").
//
//   std::unique_ptr<EditingMethod> method = CreateMethod(name, &error);
//   if (method == nullptr) { /* error: "unknown method 'x' (expected ...)" */ }

#ifndef MSDEFORM_METHODS_REGISTRY_H_
#define MSDEFORM_METHODS_REGISTRY_H_

#include <memory>
#include <string>
#include <vector>

#include "msdeform/methods/method.h"

namespace msdeform {

// Every registered name, in registration order: multiscale, static,
// static_dense, cgal_arap, cgal_sr_arap (when built with CGAL), fastlsm, rigid_cells.
std::vector<std::string> MethodNames();
// The names joined by ", " (for help texts and errors).
std::string MethodNameList();
bool IsMethodName(const std::string& name);
// A new method, or null with "unknown method '<name>' (expected <names>)".
std::unique_ptr<EditingMethod> CreateMethod(const std::string& name, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_METHODS_REGISTRY_H_
