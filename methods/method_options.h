// The options of every editing method (methods/method.h), one struct per
// method with its documented defaults. A method reads its own part: the graph
// methods `deformer` (whose `method` field the registry sets from the name),
// CGAL's `cgal`, FastLSM `fastlsm`, rigid cells `rigid_cells`, the converged
// mesh ARAP `full_arap`.

#ifndef MSDEFORM_METHODS_METHOD_OPTIONS_H_
#define MSDEFORM_METHODS_METHOD_OPTIONS_H_

#include <string>

#include "msdeform/methods/cgal_arap.h"
#include "msdeform/methods/fastlsm.h"
#include "msdeform/methods/rigid_cells.h"
#include "msdeform/solvers/local_global_arap.h"
#include "msdeform/scales/deformer_options.h"

namespace msdeform {

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
  // full_arap (with deformer.num_threads; its own num_threads is not read).
  LocalGlobalArapOptions full_arap;

  // The ranges of every row of MethodOptionTable() (methods/method_option_table.h),
  // then DeformerOptions::Check: one line naming the row.
  bool Check(std::string* error) const;
};

}  // namespace msdeform

#endif  // MSDEFORM_METHODS_METHOD_OPTIONS_H_
