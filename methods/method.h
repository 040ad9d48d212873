// One interface for every editing method: the multi-scale method, the static
// graph baselines, CGAL's ARAP and SR-ARAP, and fast lattice shape matching.
// The command line, the Python module, the experiment runner, the sweeps and
// the editor choose a method by name (methods/registry.h) and use only this.
//
//   std::unique_ptr<EditingMethod> method = CreateMethod("fastlsm", &error);
//   method->Precompute(mesh, options, &error);     // what depends on the mesh only
//   method->SetHandles(layout, &error);            // a handle layout
//   method->Drag(deformed_from_rest, &stats, &error);  // one frame, warm-started
//   method->deformed_vertices();
//
// The calls go Precompute, SetHandles, then any number of Drags; a new
// SetHandles or Precompute starts over from that stage. A call out of order
// returns false with a message (the base class enforces it, so a method
// cannot forget to).

#ifndef MSDEFORM_METHODS_METHOD_H_
#define MSDEFORM_METHODS_METHOD_H_

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "msdeform/core/handles.h"
#include "msdeform/core/lattice.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/timing.h"
#include "msdeform/scales/session.h"

namespace msdeform {

// Per-frame numbers (scales/session.h's DragStats): frame_ms (the whole
// Drag), solve_ms, skin_ms, iterations, final_cost (NaN for a method without
// an energy it minimises), converged.
using MethodStats = DragStats;

struct MethodOptions;  // methods/method_options.h
class GraphMethod;    // methods/graph_method.h

class EditingMethod {
 public:
  explicit EditingMethod(std::string name) : name_(std::move(name)) {}
  virtual ~EditingMethod();
  EditingMethod(const EditingMethod&) = delete;
  EditingMethod& operator=(const EditingMethod&) = delete;

  // The registered name ("multiscale", "cgal_arap", ...).
  const std::string& name() const { return name_; }

  // Everything that depends only on the mesh. False with a message on invalid
  // options or a mesh the method cannot take; the method is then empty.
  bool Precompute(const Mesh& mesh, const MethodOptions& options, std::string* error);
  // A new handle layout; the deformation restarts from the rest pose. False
  // with a message on an invalid layout (then only SetHandles or Precompute
  // are accepted).
  bool SetHandles(const HandleLayout& layout, std::string* error);
  // Moves each handle group g to deformed_from_rest[g] * (its rest
  // positions) and deforms the mesh, starting from the previous frame. One
  // transform moves every group; else one a group, or false with a message.
  // `stats` may be null.
  bool Drag(const HandleTransforms& deformed_from_rest, MethodStats* stats, std::string* error);
  // Moves each moveable vertex to its own target (`targets`: 3 by #moveable,
  // in the layout's moveable order; libigl's bc) and deforms the mesh, for a
  // method that places the handle vertices one by one
  // (takes_vertex_targets()). The others take a transform a handle group
  // (core/handles.h, HandleTransformsFromTargets fits one) and refuse this
  // with a message.
  bool DragTo(const Eigen::Matrix3Xd& targets, MethodStats* stats, std::string* error);
  virtual bool takes_vertex_targets() const { return false; }

  // #V by 3 (as 3 by #V): the rest vertices until the first Drag.
  virtual const Eigen::Matrix3Xd& deformed_vertices() const = 0;

  // What the runner reports for any method, valid after SetHandles.
  // Unknowns of the per-frame problem and the elements that carry them (graph
  // nodes optimised, ROI vertices, free lattice particles).
  virtual int nodes_optimized() const = 0;
  virtual int variables() const = 0;
  // Milliseconds of Precompute, of the rigidity estimate (0 without one) and
  // of the rest of SetHandles.
  virtual double precompute_ms() const = 0;
  virtual double rigidity_ms() const { return 0.0; }
  virtual double setup_ms() const = 0;
  // The same by stage (precompute.lattice, layout.rigidity, session.solver_setup,
  // ...; the report's timings_ms.stages), empty for a method without them.
  virtual StageTimes stages() const { return {}; }
  // The lattice the method runs on, or null (CGAL's methods have none).
  virtual const Lattice* lattice() const { return nullptr; }
  // The method as a deformation-graph method (graphs, scale, node classes,
  // transforms, its stages), or null for a method that is not a graph.
  virtual const GraphMethod* graph_method() const { return nullptr; }

  bool precomputed() const { return stage_ != Stage::kEmpty; }
  bool handles_set() const { return stage_ == Stage::kHandlesSet; }
  // The handle groups of the last SetHandles' layout.
  int num_handle_groups() const { return num_handle_groups_; }

 protected:
  // The stages, called by the public ones in order only.
  virtual bool DoPrecompute(const Mesh& mesh, const MethodOptions& options,
                            std::string* error) = 0;
  virtual bool DoSetHandles(const HandleLayout& layout, std::string* error) = 0;
  virtual bool DoDrag(const HandleTransforms& deformed_from_rest, MethodStats* stats,
                      std::string* error) = 0;
  // Called with a checked `targets` when takes_vertex_targets().
  virtual bool DoDragTo(const Eigen::Matrix3Xd& targets, MethodStats* stats, std::string* error);

 private:
  enum class Stage { kEmpty, kPrecomputed, kHandlesSet };
  std::string name_;
  Stage stage_ = Stage::kEmpty;
  int num_handle_groups_ = 1;
  int num_moveable_ = 0;
};

// A drag along a path of handle transforms: the per-frame loop of msdeform,
// the experiment runner, the figure data and the benchmarks.
struct DragAlongOptions {
  // A frame whose solve fails keeps the last good state (Drag restores it).
  // false: stop at the first failure. true: go on from the last good frame;
  // only a failure of the last frame, the result, is an error.
  bool continue_after_failure = false;
  // Called after each successful frame (1-based frame number), e.g. for
  // progress lines or to write the frame's mesh.
  std::function<void(int frame, const MethodStats& stats)> on_frame;
};

struct DragLog {
  std::vector<MethodStats> frames;  // successful frames, in order
  std::vector<int> failed_frames;   // 1-based
};

// Drags `method` (SetHandles done) through `path`; false with "frame F of N:
// <what failed>" in *error.
bool DragAlong(EditingMethod* method, const std::vector<HandleTransforms>& path,
               const DragAlongOptions& options, DragLog* log, std::string* error);
// The same for a path of one transform a frame that every handle group follows.
bool DragAlong(EditingMethod* method, const std::vector<Eigen::Affine3d>& path,
               const DragAlongOptions& options, DragLog* log, std::string* error);

}  // namespace msdeform

#endif  // MSDEFORM_METHODS_METHOD_H_
