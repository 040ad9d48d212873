// The options tables of the editing methods (core/option_table.h): one row
// per field of CgalArapOptions and FastLsmOptions, and MethodOptionTable(),
// the one table of MethodOptions that every front end reads: the Deformer's
// rows under their own names ("w_con", "lattice.cell_width"), then
// "cgal.<field>" and "fastlsm.<field>". The method rows' flags keep the
// command line's spellings (--cgal_iterations, --fastlsm_steps, ...).
//
//   MethodOptions options;
//   MethodOptionTable().Set("fastlsm.steps_per_frame", "40", &options, &error);

#ifndef MSDEFORM_METHODS_METHOD_OPTION_TABLE_H_
#define MSDEFORM_METHODS_METHOD_OPTION_TABLE_H_

#include <string>
#include <vector>

#include "msdeform/core/option_table.h"
#include "msdeform/methods/method_options.h"

namespace msdeform {

const OptionTable<CgalArapOptions>& CgalArapOptionTable();
const OptionTable<FastLsmOptions>& FastLsmOptionTable();
const OptionTable<MethodOptions>& MethodOptionTable();

// True for a row of MethodOptionTable() that is a method's own (not one of
// DeformerOptionTable()'s): "cgal.iterations", "fastlsm.damping".
bool IsMethodOwnRow(const std::string& name);
// The registered methods that read a method's own row, from their
// descriptors' prefixes (methods/registry.h): cgal_arap and cgal_sr_arap for
// "cgal.*", fastlsm for "fastlsm.*"; none for any other.
std::vector<std::string> MethodsOfRow(const std::string& name);

// Whether the registered method `method` reads the row `name` of
// MethodOptionTable(), from its descriptor (methods/registry.h): "method"
// for every method; a Deformer row for a graph method, or one of the
// descriptor's deformer_rows; a method's own row for the methods of its
// prefix. False for an unknown method or row.
bool MethodReadsRow(const std::string& method, const std::string& name);
// The registered methods that read the row `name`, in registration order.
std::vector<std::string> MethodsReadingRow(const std::string& name);
// The words every front end gives for an option that `method` does not read,
// naming the methods that read any of its `rows`: "not an option of the
// cgal_arap method (an option of multiscale, static, static_dense)", or "(no
// method reads it)".
std::string NotAnOptionOf(const std::string& method, const std::vector<std::string>& rows);

}  // namespace msdeform

#endif  // MSDEFORM_METHODS_METHOD_OPTION_TABLE_H_
