// "full_arap": the mesh's own ARAP energy (one rotation per vertex, cotangent
// weights: the energy core/metrics.h measures) minimised to convergence by
// accelerated local/global iterations (solvers/local_global_arap.h). The
// converged reference the tables measure every method against, and an edit
// of its own.
//
// SetHandles factorises the Laplacian of the free vertices (every vertex
// that is neither fixed nor in the moveable handle and that a constraint
// reaches); each Drag holds the handle at deformed_from_rest * rest and the
// fixed vertices at rest, both exactly, and iterates from the previous frame
// until the energy's relative decrease falls to the tolerance.

#ifndef MSDEFORM_METHODS_FULL_ARAP_H_
#define MSDEFORM_METHODS_FULL_ARAP_H_

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/option_table.h"
#include "msdeform/methods/method.h"
#include "msdeform/solvers/local_global_arap.h"

namespace msdeform {

// The rows of full_arap's options ("full_arap.relative_tolerance", flags
// --full_arap_tolerance, --full_arap_max_iterations, --full_arap_anderson_window).
const OptionTable<LocalGlobalArapOptions>& FullArapOptionTable();

class FullArapMethod : public EditingMethod {
 public:
  FullArapMethod() : EditingMethod("full_arap") {}

  const Eigen::Matrix3Xd& deformed_vertices() const override { return deformed_; }
  // The free vertices, 3 unknowns each.
  int nodes_optimized() const override { return arap_.num_free(); }
  int variables() const override { return 3 * arap_.num_free(); }
  double precompute_ms() const override { return precompute_ms_; }
  double setup_ms() const override { return arap_.setup_ms(); }

  bool takes_vertex_targets() const override { return true; }
  // The last Drag's solve (iterations, energies, trace).
  const LocalGlobalArapSummary& last_summary() const { return summary_; }

 protected:
  bool DoPrecompute(const Mesh& mesh, const MethodOptions& options, std::string* error) override;
  bool DoSetHandles(const HandleLayout& layout, std::string* error) override;
  bool DoDrag(const HandleTransforms& deformed_from_rest, MethodStats* stats,
              std::string* error) override;
  bool DoDragTo(const Eigen::Matrix3Xd& targets, MethodStats* stats, std::string* error) override;

 private:
  // One frame with the constrained vertices at `targets` (ConstrainedTargets).
  void Solve(const Eigen::Matrix3Xd& targets, MethodStats* stats);

  Mesh mesh_;
  LocalGlobalArapOptions options_;
  LocalGlobalArap arap_;
  // The constrained vertices (sorted) and, per entry, its handle group (-1:
  // fixed at rest).
  std::vector<int> constrained_;
  std::vector<int> handle_group_;  // per entry of constrained_, -1 fixed
  Eigen::Matrix3Xd deformed_;
  LocalGlobalArapSummary summary_;
  double precompute_ms_ = 0.0;
};

}  // namespace msdeform

#endif  // MSDEFORM_METHODS_FULL_ARAP_H_
