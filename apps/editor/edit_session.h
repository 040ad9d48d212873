// The editor's model, without a window: the mesh, the vertex labels the user
// paints, the editing method (any registered one, methods/registry.h: by
// default the graph method of the options), and the handle transform being
// dragged.
//
//   EditSession session;
//   session.Open(std::move(inputs), options);   // Init (+ SetHandles + path) in the background
//   session.Label(vertices, VertexLabel::kHandle);
//   session.CommitLayout();                     // SetHandles in the background
//   ... each UI frame: session.Poll();
//   if (session.ready()) session.Drag(transform, &error);   // one solve + skin, here
//
// What takes long runs on a worker thread, so the window keeps drawing: a new
// mesh or new options (GraphMethod::Precompute: lattice, graphs), a new handle layout
// (SetHandles: rigidity, scale selection, classes, the solver's set-up), and
// the drag path an input comes with. Requests made while a job runs are
// merged into one follow-up job with the latest labels and options. A Drag
// runs on the caller's thread (a few milliseconds) and only when no job runs.
//
// Polish on release (methods/polish.h): StartPolish polishes the pose on a
// second worker thread (the polisher is set up there on the first release for
// a layout, then reused); Poll swaps the polished mesh in when it is ready
// and no Drag came in between; a Drag cancels it. The next Drag continues
// from the method's own frame, not the polished one.
//
// Messages of failed jobs are the msdeform CLI's: "<mesh>: <Init error>",
// "handles: <SetHandles error>", "<mesh>: frame F of N (the result): ...".

#ifndef MSDEFORM_APPS_EDITOR_EDIT_SESSION_H_
#define MSDEFORM_APPS_EDITOR_EDIT_SESSION_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <atomic>
#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "apps/editor/edit_inputs.h"
#include "apps/editor/selection.h"
#include "msdeform/methods/graph_method.h"
#include "msdeform/methods/method.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/methods/polish.h"

namespace msdeform {
namespace editor {

// One background job: what it did and how long it took (milliseconds).
struct LayoutTiming {
  bool init = false;         // GraphMethod::Precompute ran (new mesh or options)
  double init_ms = 0.0;      // wall time of Init
  double rigidity_ms = 0.0;  // GraphMethod::rigidity_ms (multi-scale only)
  double setup_ms = 0.0;     // GraphMethod::setup_ms
  double path_ms = 0.0;      // the drag path after SetHandles, if any
  double wall_ms = 0.0;      // request to result, as the user waits for it
};

// One Drag from the window (a mouse move, a script step).
struct MoveTiming {
  double solve_ms = 0.0;
  double skin_ms = 0.0;
  double frame_ms = 0.0;  // the whole GraphMethod::Drag
  int iterations = 0;
};

class EditSession {
 public:
  EditSession();
  ~EditSession();  // waits for a running job
  EditSession(const EditSession&) = delete;
  EditSession& operator=(const EditSession&) = delete;

  // Replaces the edit: the mesh, the labels of `inputs` (all free without a
  // layout) and, when it has one, its drag path, applied after SetHandles as
  // msdeform applies it. Waits for a running job first.
  void Open(EditInputs inputs, const DeformerOptions& options);
  // New options (method, backend, ablations): Init again, the committed layout
  // again, and the current handle transform again (one Drag), so methods can
  // be compared at the same pose.
  void SetOptions(const DeformerOptions& options);
  // The method by its registered name (msdeform --method): a graph method
  // sets options().method, another (cgal_arap, cgal_sr_arap, fastlsm) runs
  // with options() for what it uses and method_options() for its own. Then
  // as SetOptions. False, with "--method=<name>: expected <names>", for an
  // unknown name (nothing changes).
  bool SetMethod(const std::string& name, std::string* error);
  // The methods' own options (every part of `options` but its deformer,
  // which SetOptions sets: CGAL's iterations, FastLSM's steps, ...); applied
  // as SetOptions.
  void SetMethodOptions(const MethodOptions& options);
  // The registered name of the method in use.
  std::string method_name() const;
  const MethodOptions& method_options() const { return method_options_; }

  // Labels `vertices` (ids of the mesh); the layout takes effect at
  // CommitLayout.
  void Label(const std::vector<int>& vertices, VertexLabel label);
  void ClearLabels();
  // A handle-layout change: when the labels differ from the last committed
  // layout, starts SetHandles for them (if they have a handle vertex), which
  // resets the pose to rest. Returns false, with the reason, when the labels
  // have no handle vertex.
  bool CommitLayout(std::string* why = nullptr);
  // Back to the rest pose (SetHandles again for the committed layout).
  void ResetPose();

  // Takes a finished job's result (and starts a merged follow-up); true when
  // the displayed state changed. Call once per UI frame.
  bool Poll();
  // Blocks until no job runs, taking the results.
  void Wait();
  // Blocks until the running job finishes or `timeout` passes (without taking
  // the result: Poll does); true when no job is still running.
  bool WaitFor(std::chrono::milliseconds timeout) const;
  // Called on the worker thread when a job finishes (e.g. to wake an event
  // loop with glfwPostEmptyEvent); set before the first job.
  void set_on_job_done(std::function<void()> callback) { on_job_done_ = std::move(callback); }
  bool busy() const { return job_.valid(); }

  // The deformer is set up for the committed layout and no job runs.
  bool ready() const;
  // One frame: moves each handle group g to deformed_from_rest[g] * (rest
  // position). False (and the pose kept) when not ready or the solve fails.
  bool Drag(const HandleTransforms& deformed_from_rest, std::string* error);

  bool has_mesh() const { return mesh_.num_vertices() > 0; }
  const Mesh& mesh() const { return mesh_; }
  const EditInputs& inputs() const { return inputs_; }
  const DeformerOptions& options() const { return options_; }
  const std::vector<VertexLabel>& labels() const { return labels_; }
  // The labels since the last CommitLayout differ from the committed layout.
  bool layout_pending() const { return labels_changed_; }
  const HandleLayout& committed_layout() const { return committed_layout_; }
  // The graph method when the method is one and no job runs (for
  // overlays), else null (also for a method that is not a graph).
  const GraphMethod* graph_method() const {
    return busy() || method_ == nullptr ? nullptr : method_->graph_method();
  }
  // The method when one exists and no job runs, else null.
  const EditingMethod* method() const { return busy() ? nullptr : method_.get(); }
  // The pose: each handle group's transform (one for all after a reset).
  const HandleTransforms& transform() const { return transform_; }
  // Positions and normals to draw: the deformer's when ready, else the rest
  // mesh's. 3 by #V.
  const Eigen::Matrix3Xd& positions() const;
  const Eigen::Matrix3Xd& normals() const;
  // Bumped whenever positions() or labels() change, for the renderer.
  int geometry_version() const { return geometry_version_; }
  int labels_version() const { return labels_version_; }
  // The handle's current centroid (deformed positions of the vertices
  // labelled handle group `label_group`, or of every handle vertex for -1);
  // the mesh's bounding-box centre without one.
  Eigen::Vector3d HandleCentroid(int label_group = -1) const;
  // The committed layout's group of the vertices labelled handle group
  // `label_group` (layouts number the groups without gaps), or -1 for none.
  int LayoutGroupOfLabel(int label_group) const;

  // The last failure of a job or a Drag, "" when the last one succeeded;
  // error_in_path(): it was the input's drag path (the CLI adds "no output
  // written" to that one).
  const std::string& error() const { return error_; }
  bool error_in_path() const { return error_in_path_; }
  // One line for the status bar: the edit, the method (and a graph method's
  // per-frame solver), then the state of the layout.
  std::string Status() const;

  const std::vector<LayoutTiming>& layout_timings() const { return layout_timings_; }
  const std::vector<MoveTiming>& move_timings() const { return move_timings_; }
  // The last Drag's numbers (a move, or the last frame of an input's path);
  // zero after a layout change.
  const DragStats& last_drag() const { return last_drag_; }

  // Polishes the current pose on a worker thread (the release of a drag);
  // a polish still running (cancelled) is waited for by Poll, which then
  // starts this one. False (nothing started) when not ready.
  bool StartPolish(const PolishOptions& options);
  // Sets the running polish's cancel flag; its result will not be shown.
  void CancelPolish();
  // A polish runs or waits to start.
  bool polishing() const { return polish_job_.valid() || polish_requested_; }
  // Blocks until no polish runs, then takes the result as Poll does.
  void WaitForPolish();
  // The polished mesh is what positions() shows.
  bool showing_polished() const { return show_polished_; }
  // The last polish that finished uncancelled (shown or not), and whether
  // there was one since the layout was set.
  const PolishReport& last_polish() const { return last_polish_; }
  bool has_polish() const { return has_polish_; }

 private:
  struct Job;
  struct PolishJob;
  void StartJob(bool init, bool set_handles, std::vector<HandleTransforms> path);
  void TakeJob();
  // Takes a finished polish; true when positions() changed.
  bool TakePolish();
  void LaunchPolish();
  // Cancels and forgets the polisher (a new mesh, layout or options).
  void DropPolisher();

  EditInputs inputs_;
  Mesh mesh_;  // the rest mesh (inputs_.mesh moved here)
  Eigen::Matrix3Xd rest_normals_;
  DeformerOptions options_;
  // Empty: the graph method options_.method; else a registered method that is
  // not a graph.
  std::string other_method_;
  MethodOptions method_options_;  // the methods' own parts (deformer: options_)
  mutable Eigen::Matrix3Xd method_normals_;  // normals of a non-graph method's pose
  mutable int method_normals_version_ = -1;
  std::vector<VertexLabel> labels_;
  bool labels_changed_ = false;
  HandleLayout committed_layout_;
  bool configured_ = false;  // SetHandles succeeded for committed_layout_
  std::unique_ptr<EditingMethod> method_;
  std::future<std::unique_ptr<Job>> job_;
  std::function<void()> on_job_done_;
  // A follow-up requested while a job runs.
  bool pending_init_ = false;
  bool pending_layout_ = false;
  HandleTransforms transform_;
  std::string error_;
  bool error_in_path_ = false;
  int geometry_version_ = 0;
  int labels_version_ = 0;
  std::vector<LayoutTiming> layout_timings_;
  std::vector<MoveTiming> move_timings_;
  DragStats last_drag_;
  // Polish on release: the polisher of the committed layout (shared with a
  // running polish), the running one, and a request waiting for it to end.
  std::shared_ptr<Polisher> polisher_;
  std::future<std::unique_ptr<PolishJob>> polish_job_;
  std::shared_ptr<std::atomic<bool>> polish_cancel_;
  bool polish_requested_ = false;
  PolishOptions polish_options_;
  Eigen::Matrix3Xd polished_;
  bool show_polished_ = false;
  PolishReport last_polish_;
  bool has_polish_ = false;
};

// Whether `method` (a registered name) reads the row `row` of
// DeformerOptionTable(): a graph method every row; another only the lattice
// rows ("lattice.*") and num_threads (methods/registry.h, MethodDescriptor::
// graph). The panels grey out the rest for such a method.
bool MethodReadsDeformerRow(const std::string& method, const std::string& row);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_EDIT_SESSION_H_
