// Editing methods by name, each with its descriptor: what the front ends
// (the command line, the editor, the runner, the sweeps, Python, the tests)
// read instead of naming a method. Adding a method is its files and one
// descriptor in methods/registry.cc (docs/extending.md, "Adding a method").
//
//   std::unique_ptr<EditingMethod> method = CreateMethod(name, &error);
//   if (method == nullptr) { /* error: "unknown method 'x' (expected ...)" */ }
//   const MethodDescriptor* d = FindMethod("fastlsm");  // d->graph == false

#ifndef MSDEFORM_METHODS_REGISTRY_H_
#define MSDEFORM_METHODS_REGISTRY_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "msdeform/core/option_table.h"
#include "msdeform/methods/method.h"
#include "msdeform/methods/method_options.h"

namespace msdeform {

struct MethodDescriptor {
  // The registered name ("multiscale", "cgal_arap", ...).
  std::string name;
  // A deformation-graph method (scales/deformer.h): graphs, node classes,
  // and DeformerOptions::energy to choose (ed or arap). The others minimise
  // one energy of their own and read only the lattice and thread rows of
  // the Deformer's.
  bool graph = false;
  // What a method that is not a graph minimises, as the tables name it
  // ("arap", "sr_arap", "shape_matching"); a graph method's is its options'
  // energy (MinimisedEnergy).
  std::string energy;
  // The prefix of the method's own rows in MethodOptionTable() ("cgal" for
  // "cgal.iterations"); empty when it has none. Methods may share one.
  std::string options;
  // Adds the method's own rows to MethodOptionTable() (once per prefix);
  // null when it has none.
  std::function<void(OptionTable<MethodOptions>* table)> add_option_rows;
  std::function<std::unique_ptr<EditingMethod>()> create;
};

// Every registered method, in registration order: multiscale, static,
// static_dense, cgal_arap, cgal_sr_arap (when built with CGAL), fastlsm, rigid_cells, full_arap.
const std::vector<MethodDescriptor>& RegisteredMethods();
// The descriptor of `name`, or null.
const MethodDescriptor* FindMethod(const std::string& name);

// Every registered name, in registration order.
std::vector<std::string> MethodNames();
// The names joined by ", " (for help texts and errors).
std::string MethodNameList();
bool IsMethodName(const std::string& name);
// A registered deformation-graph method (descriptor's `graph`).
bool IsGraphMethod(const std::string& name);
// A new method, or null with "unknown method '<name>' (expected <names>)".
std::unique_ptr<EditingMethod> CreateMethod(const std::string& name, std::string* error);
// What `name` minimises with `options`: a graph method's options.energy
// ("ed", "arap"), another's descriptor energy; "-" for an unknown name.
std::string MinimisedEnergy(const std::string& name, const DeformerOptions& options);

}  // namespace msdeform

#endif  // MSDEFORM_METHODS_REGISTRY_H_
