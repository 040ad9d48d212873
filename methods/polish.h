// Polish on release: a few accelerated full_arap iterations (solvers/
// local_global_arap.h) warm-started from any method's last frame, with the
// moveable handle at deformed_from_rest * rest and the fixed vertices at rest,
// both exactly. It lowers the mesh's own ARAP energy (core/metrics.h's
// NormalisedArapEnergy, the tables' arap_energy) toward the converged
// full_arap result within a budget of iterations and milliseconds. The
// iterations never raise it (the local/global step and Anderson's safeguard
// are monotone); moving soft handles onto their exact targets first can.
//
//   Polisher polisher;
//   polisher.Setup(mesh, layout, options, &error);        // factorises, once per layout
//   PolishReport report = polisher.Polish(transform, &vertices);  // per release
//
// The command line (--polish), the Python Method.polish() and the editor (on
// mouse release, on a worker thread, cancelled by the next drag) use it.

#ifndef MSDEFORM_METHODS_POLISH_H_
#define MSDEFORM_METHODS_POLISH_H_

#include <atomic>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"
#include "msdeform/solvers/local_global_arap.h"

namespace msdeform {

struct PolishOptions {
  // Local/global iterations at most (each one local and one global step).
  int max_iterations = 30;
  // Milliseconds of iterating at most, 0 for no limit: an iteration is not
  // started when the mean iteration so far would end past the budget. The
  // default has none, so a polish gives the same bytes on every machine; the
  // editor sets one.
  double time_budget_ms = 0.0;
  // Stop earlier when a plain step lowers the energy by at most this
  // fraction of it (LocalGlobalArapOptions::relative_tolerance).
  double relative_tolerance = 1e-7;
  // Anderson acceleration's window; 0 runs plain local/global.
  int anderson_window = 5;
  // Threads of the iterations (at least 1).
  int num_threads = 1;

  // Messages name the field ("max_iterations must be >= 0").
  bool Check(std::string* error) const;
};

struct PolishReport {
  double energy_before = 0.0;  // normalised ARAP energy of the frame as given
  // The energy once the constraints are at their targets, where the
  // iterations start: above energy_before for a method whose handles are soft
  // (the multi-scale method's position terms), equal for one that holds them.
  // The iterations never raise it.
  double energy_start = 0.0;
  double energy_after = 0.0;   // of the polished mesh (== before when cancelled)
  int iterations = 0;
  double ms = 0.0;        // the polish (the energy before included), setup excluded
  double setup_ms = 0.0;  // factorising, when the caller set up for this polish (else 0)
  bool converged = false;  // stopped by the tolerance, not a budget
  bool cancelled = false;  // `cancel` was set: the vertices are as given
};

class Polisher {
 public:
  // Factorises the Laplacian of the free vertices for `layout` on `rest`
  // (LocalGlobalArap::Setup). False with a message on bad options or layout.
  bool Setup(const Mesh& rest, const HandleLayout& layout, const PolishOptions& options,
             std::string* error);
  // New options for the next Polish: a new budget costs nothing; a new
  // tolerance, window or thread count factorises again. False with a message
  // (the options unchanged) on bad options or before Setup.
  bool SetOptions(const PolishOptions& options, std::string* error);
  bool ready() const { return ready_; }
  const PolishOptions& options() const { return options_; }
  // Milliseconds of the last Setup.
  double setup_ms() const { return arap_.setup_ms(); }
  // The layout's constrained vertices at `deformed_from_rest`.
  Eigen::Matrix3Xd Targets(const HandleTransforms& deformed_from_rest) const;

  // Polishes *vertices (3 by #V) in place. The handle and fixed vertices are
  // set to their targets exactly; the free ones iterate from where they are.
  // `cancel`, when given, is read before each iteration; once true the polish
  // stops and *vertices is left as given (report.cancelled).
  PolishReport Polish(const HandleTransforms& deformed_from_rest, Eigen::Matrix3Xd* vertices,
                      const std::atomic<bool>* cancel = nullptr);
  // The same with each moveable vertex's target given (3 by #moveable, in
  // the layout's moveable order: EditingMethod::DragTo's).
  PolishReport PolishTo(const Eigen::Matrix3Xd& moveable_targets, Eigen::Matrix3Xd* vertices,
                        const std::atomic<bool>* cancel = nullptr);

 private:
  // Polish with the constrained vertices at `targets` (3 by #constrained).
  PolishReport PolishConstrained(const Eigen::Matrix3Xd& targets, Eigen::Matrix3Xd* vertices,
                                 const std::atomic<bool>* cancel);

  Mesh rest_;
  PolishOptions options_;
  LocalGlobalArap arap_;
  std::vector<int> constrained_;   // sorted
  std::vector<int> handle_group_;  // per entry of constrained_: its handle group, -1 fixed
  bool ready_ = false;
};

// The one-off call: Setup on `rest` and `layout`, then Polish.
// False with a message when Setup fails.
bool PolishOnce(const Mesh& rest, const HandleLayout& layout,
                const HandleTransforms& deformed_from_rest, const PolishOptions& options,
                Eigen::Matrix3Xd* vertices, PolishReport* report, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_METHODS_POLISH_H_
