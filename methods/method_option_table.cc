#include "msdeform/methods/method_option_table.h"

#include <algorithm>
#include <limits>

#include "msdeform/methods/registry.h"
#include "msdeform/scales/rigidity.h"

namespace msdeform {

namespace {
constexpr double kIntMax = std::numeric_limits<int>::max();
}  // namespace

const OptionTable<CgalArapOptions>& CgalArapOptionTable() {
  static const OptionTable<CgalArapOptions> table = [] {
    using O = CgalArapOptions;
    OptionTable<O> t;
    t.Int("iterations", &O::iterations,
          "cgal_arap, cgal_sr_arap: local/global iterations per frame.")
        .Range(1, kIntMax, "an integer >= 1")
        .Alias("cgal_iterations")
        .Flag("method");
    t.Double("tolerance", &O::tolerance,
             "cgal_arap, cgal_sr_arap: CGAL's relative energy tolerance (0: run every iteration).")
        .AtLeast(0, "a finite number >= 0")
        .Alias("cgal_tolerance")
        .Flag("method");
    t.Double("sre_alpha", &O::sre_alpha,
             "cgal_sr_arap: SR-ARAP's rotation smoothing weight (CGAL's set_sre_arap_alpha).")
        .AtLeast(0, "a finite number >= 0")
        .Alias("cgal_sre_alpha")
        .Flag("method");
    return t;
  }();
  return table;
}

const OptionTable<FastLsmOptions>& FastLsmOptionTable() {
  static const OptionTable<FastLsmOptions> table = [] {
    using O = FastLsmOptions;
    OptionTable<O> t;
    t.Int("steps_per_frame", &O::steps_per_frame, "fastlsm: shape-matching steps per frame.")
        .Range(1, 100000, "an integer in 1..100000")
        .Alias("fastlsm_steps")
        .Flag("method");
    t.Int("region_half_width", &O::region_half_width,
          "fastlsm: r, a region is a particle and its r-ring.")
        .Range(1, kMaxRegionHalfWidth,
               "an integer in 1.." + std::to_string(kMaxRegionHalfWidth))
        .Alias("fastlsm_region_half_width")
        .Flag("method");
    t.Double("damping", &O::damping,
             "fastlsm: fraction of each particle's velocity removed per step, [0, 1).")
        .Range(0, 1, "a number in [0, 1)", /*high_open=*/true)
        .Alias("fastlsm_damping")
        .Flag("method");
    return t;
  }();
  return table;
}

const OptionTable<MethodOptions>& MethodOptionTable() {
  static const OptionTable<MethodOptions> table = [] {
    OptionTable<MethodOptions> t;
    t.Embed("", &MethodOptions::deformer, DeformerOptionTable());
    // Each method's own rows, from its descriptor, once per prefix.
    std::vector<std::string> added;
    for (const MethodDescriptor& method : RegisteredMethods()) {
      if (!method.add_option_rows ||
          std::find(added.begin(), added.end(), method.options) != added.end()) {
        continue;
      }
      method.add_option_rows(&t);
      added.push_back(method.options);
    }
    return t;
  }();
  return table;
}

bool IsMethodOwnRow(const std::string& name) { return !MethodsOfRow(name).empty(); }

std::vector<std::string> MethodsOfRow(const std::string& name) {
  std::vector<std::string> methods;
  for (const MethodDescriptor& method : RegisteredMethods()) {
    if (!method.options.empty() && name.rfind(method.options + ".", 0) == 0) {
      methods.push_back(method.name);
    }
  }
  return methods;
}

bool MethodReadsRow(const std::string& method, const std::string& name) {
  const MethodDescriptor* d = FindMethod(method);
  if (d == nullptr || MethodOptionTable().Find(name) == nullptr) return false;
  if (name == "method") return true;
  if (IsMethodOwnRow(name)) {
    const std::vector<std::string> methods = MethodsOfRow(name);
    return std::find(methods.begin(), methods.end(), method) != methods.end();
  }
  if (d->graph) return true;
  for (const std::string& row : d->deformer_rows) {
    if (name == row || name.rfind(row + ".", 0) == 0) return true;
  }
  return false;
}

std::vector<std::string> MethodsReadingRow(const std::string& name) {
  std::vector<std::string> methods;
  for (const MethodDescriptor& d : RegisteredMethods()) {
    if (MethodReadsRow(d.name, name)) methods.push_back(d.name);
  }
  return methods;
}

std::string NotAnOptionOf(const std::string& method, const std::vector<std::string>& rows) {
  std::vector<std::string> readers;
  for (const std::string& row : rows) {
    for (const std::string& reader : MethodsReadingRow(row)) {
      if (std::find(readers.begin(), readers.end(), reader) == readers.end()) {
        readers.push_back(reader);
      }
    }
  }
  std::string words;
  for (const std::string& reader : readers) words += (words.empty() ? "" : ", ") + reader;
  return "not an option of the " + method + " method (" +
         (readers.empty() ? "no method reads it" : "an option of " + words) + ")";
}

bool MethodOptions::Check(std::string* error) const {
  // Every row's range (the methods' own under their prefix: "cgal.iterations=0:
  // ..."), then what the Deformer's rows cannot say.
  return MethodOptionTable().CheckRanges(*this, error) && deformer.Check(error);
}

}  // namespace msdeform
