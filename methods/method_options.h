// The options of every editing method (methods/method.h), one struct per
// method with its documented defaults. A method reads its own part: the graph
// methods `deformer` (whose `method` field the registry sets from the name),
// CGAL's `cgal`, FastLSM `fastlsm`, rigid cells `rigid_cells`. A method may
// instead keep its options struct in its own files and find it in `own` under
// its rows' prefix, as the converged mesh ARAP does ("full_arap"): then
// MethodOptions does not change for it.

#ifndef MSDEFORM_METHODS_METHOD_OPTIONS_H_
#define MSDEFORM_METHODS_METHOD_OPTIONS_H_

#include <any>
#include <functional>
#include <map>
#include <string>

#include <glog/logging.h>

#include "msdeform/core/option_table.h"
#include "msdeform/methods/cgal_arap.h"
#include "msdeform/methods/fastlsm.h"
#include "msdeform/methods/rigid_cells.h"
#include "msdeform/scales/deformer_options.h"

namespace msdeform {

// The options structs of the methods that keep theirs in their own files, by
// the prefix of their rows ("full_arap"); a struct not set is its defaults.
// Copies are deep, as for a member.
//
//   LocalGlobalArapOptions* o = options.own.Mutable<LocalGlobalArapOptions>("full_arap");
//   options.own.Get<LocalGlobalArapOptions>("full_arap").max_iterations;
class MethodOwnOptions {
 public:
  template <typename S>
  const S& Get(const std::string& prefix) const {
    const auto it = values_.find(prefix);
    if (it == values_.end()) {
      static const S defaults{};
      return defaults;
    }
    const S* value = std::any_cast<S>(&it->second);
    CHECK(value != nullptr) << "options '" << prefix << "' read as another type";
    return *value;
  }
  template <typename S>
  S* Mutable(const std::string& prefix) {
    std::any& slot = values_[prefix];
    if (!slot.has_value()) slot = S();
    S* value = std::any_cast<S>(&slot);
    CHECK(value != nullptr) << "options '" << prefix << "' written as another type";
    return value;
  }

 private:
  std::map<std::string, std::any> values_;
};

struct MethodOptions {
  // multiscale, static, static_dense; also the lattice options of fastlsm
  // (deformer.lattice) and the threads of every method (deformer.num_threads).
  DeformerOptions deformer;
  // cgal_arap, cgal_sr_arap.
  CgalArapOptions cgal;
  // fastlsm.
  FastLsmOptions fastlsm;
  // rigid_cells (with deformer.lattice and deformer.num_threads).
  RigidCellsOptions rigid_cells;
  // The methods' structs kept in their own files, by prefix (full_arap's
  // LocalGlobalArapOptions under "full_arap").
  MethodOwnOptions own;

  // The ranges of every row of MethodOptionTable() (methods/method_option_table.h),
  // then DeformerOptions::Check: one line naming the row.
  bool Check(std::string* error) const;
};

// Adds `rows` to `table` under `prefix`, bound to options.own's S of that
// prefix: a method's add_option_rows (methods/registry.h) for an options
// struct kept in its own files.
template <typename S>
void EmbedOwnOptions(const std::string& prefix, const OptionTable<S>& rows,
                     OptionTable<MethodOptions>* table) {
  table->Embed<S>(
      prefix, [prefix](const MethodOptions& o) -> const S& { return o.own.Get<S>(prefix); },
      [prefix](MethodOptions* o) { return o->own.Mutable<S>(prefix); }, rows);
}

}  // namespace msdeform

#endif  // MSDEFORM_METHODS_METHOD_OPTIONS_H_
