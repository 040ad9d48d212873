#include "apps/editor/edit_session.h"

#include <chrono>
#include <sstream>
#include <utility>

#include "msdeform/core/timing.h"
#include "msdeform/methods/graph_method.h"
#include "msdeform/methods/registry.h"

namespace msdeform {
namespace editor {
namespace {

using Clock = std::chrono::steady_clock;

bool SameLayout(const HandleLayout& a, const HandleLayout& b) {
  return a.fixed == b.fixed && a.moveable == b.moveable && a.group == b.group;
}

}  // namespace

struct EditSession::Job {
  // In.
  bool init = false;
  bool set_handles = false;
  std::string method_name;
  MethodOptions options;
  const Mesh* mesh = nullptr;  // the session's, unchanged while the job runs
  std::string mesh_path;
  HandleLayout layout;
  std::vector<HandleTransforms> path;
  std::unique_ptr<EditingMethod> method;  // reused unless init
  Clock::time_point requested;
  std::function<void()> on_done;
  // Out.
  bool configured = false;
  std::string error;
  bool path_failed = false;
  DragStats last_frame;  // of the path, when one ran
  LayoutTiming timing;
};

namespace {

// The job's work, on the worker thread; the same steps and messages as the
// msdeform CLI (apps/msdeform_main.cc).
template <typename Job>
std::unique_ptr<Job> RunJob(std::unique_ptr<Job> job) {
  std::string error;
  if (job->init) {
    const auto start = Clock::now();
    job->method = CreateMethod(job->method_name, &error);
    if (job->method == nullptr || !job->method->Precompute(*job->mesh, job->options, &error)) {
      job->error = job->mesh_path + ": " + error;
      job->method.reset();
    }
    job->timing.init = true;
    job->timing.init_ms = MillisecondsSince(start);
  }
  if (job->method != nullptr && job->set_handles) {
    if (!job->method->SetHandles(job->layout, &error)) {
      job->error = "handles: " + error;
    } else {
      job->configured = true;
      job->timing.rigidity_ms = job->method->rigidity_ms();
      job->timing.setup_ms = job->method->setup_ms();
    }
  }
  if (job->configured && !job->path.empty()) {
    const auto start = Clock::now();
    DragAlongOptions drag_options;
    drag_options.continue_after_failure = true;  // as msdeform: only the last frame counts
    DragLog log;
    if (!DragAlong(job->method.get(), job->path, drag_options, &log, &error)) {
      job->error = job->mesh_path + ": " + error + "; " + std::to_string(log.failed_frames.size()) +
                   " failed frame(s)";
      job->path_failed = true;
    }
    if (!log.frames.empty()) job->last_frame = std::move(log.frames.back());
    job->timing.path_ms = MillisecondsSince(start);
  }
  job->timing.wall_ms = MillisecondsSince(job->requested);
  if (job->on_done) job->on_done();
  return job;
}

}  // namespace

// One polish on the worker: the polisher set up when it is not yet, then
// the polish of a copy of the pose.
struct EditSession::PolishJob {
  std::shared_ptr<Polisher> polisher;
  std::shared_ptr<std::atomic<bool>> cancel;
  const Mesh* mesh = nullptr;  // the session's: Open waits for the polish first
  HandleLayout layout;
  PolishOptions options;
  HandleTransforms transform;
  Eigen::Matrix3Xd vertices;   // the pose in, the polished mesh out
  int geometry_version = 0;    // of the pose polished
  PolishReport report;
  std::string error;
  std::function<void()> on_done;
};

namespace {

// (A template, as RunJob, so the private PolishJob needs no friend.)
template <typename PolishJob>
std::unique_ptr<PolishJob> RunPolish(std::unique_ptr<PolishJob> job) {
  double setup_ms = 0.0;
  if (!job->polisher->ready()) {
    if (!job->polisher->Setup(*job->mesh, job->layout, job->options, &job->error)) {
      if (job->on_done) job->on_done();
      return job;
    }
    setup_ms = job->polisher->setup_ms();
  } else if (!job->polisher->SetOptions(job->options, &job->error)) {
    if (job->on_done) job->on_done();
    return job;
  }
  job->report = job->polisher->Polish(job->transform, &job->vertices, job->cancel.get());
  job->report.setup_ms = setup_ms;
  if (job->on_done) job->on_done();
  return job;
}

}  // namespace

EditSession::EditSession() = default;

EditSession::~EditSession() {
  if (polish_cancel_) *polish_cancel_ = true;
  if (polish_job_.valid()) polish_job_.wait();
  if (job_.valid()) job_.wait();
}

bool EditSession::StartPolish(const PolishOptions& options) {
  if (!ready()) return false;
  polish_options_ = options;
  polish_requested_ = true;
  if (polish_job_.valid()) {
    CancelPolish();  // the older pose's; Poll starts this one when it ends
    polish_requested_ = true;
    return true;
  }
  LaunchPolish();
  return true;
}

void EditSession::LaunchPolish() {
  polish_requested_ = false;
  if (!ready()) return;
  if (polisher_ == nullptr) polisher_ = std::make_shared<Polisher>();
  auto job = std::make_unique<PolishJob>();
  job->polisher = polisher_;
  polish_cancel_ = std::make_shared<std::atomic<bool>>(false);
  job->cancel = polish_cancel_;
  job->mesh = &mesh_;
  job->layout = committed_layout_;
  job->options = polish_options_;
  job->transform = transform_;
  job->vertices = method_->deformed_vertices();
  job->geometry_version = geometry_version_;
  job->on_done = on_job_done_;
  polish_job_ = std::async(std::launch::async, RunPolish<PolishJob>, std::move(job));
}

void EditSession::CancelPolish() {
  polish_requested_ = false;
  if (polish_cancel_) *polish_cancel_ = true;
}

void EditSession::DropPolisher() {
  CancelPolish();
  // A running polish keeps its own reference; the next release sets up anew.
  polisher_.reset();
  if (show_polished_) ++geometry_version_;
  show_polished_ = false;
  has_polish_ = false;
}

bool EditSession::TakePolish() {
  std::unique_ptr<PolishJob> job = polish_job_.get();
  bool changed = false;
  if (!job->error.empty()) {
    error_ = "polish: " + job->error;
    error_in_path_ = false;
  } else if (!job->report.cancelled && job->polisher == polisher_ &&
             job->geometry_version == geometry_version_ && ready()) {
    polished_ = std::move(job->vertices);
    show_polished_ = true;
    last_polish_ = job->report;
    has_polish_ = true;
    ++geometry_version_;
    changed = true;
  }
  if (polish_requested_) LaunchPolish();
  return changed;
}

void EditSession::WaitForPolish() {
  while (polish_job_.valid()) TakePolish();
}

void EditSession::Open(EditInputs inputs, const DeformerOptions& options) {
  Wait();
  pending_init_ = pending_layout_ = false;
  inputs_ = std::move(inputs);
  mesh_ = std::move(inputs_.mesh);
  inputs_.mesh = Mesh();
  rest_normals_ = VertexNormals(mesh_);
  options_ = options;
  DropPolisher();
  if (polish_job_.valid()) polish_job_.wait();
  polish_job_ = {};
  method_.reset();
  configured_ = false;
  error_.clear();
  transform_ = HandleTransforms();
  committed_layout_ = inputs_.has_layout ? inputs_.layout : HandleLayout();
  labels_ = LabelsFromLayout(committed_layout_, mesh_.num_vertices());
  labels_changed_ = false;
  ++labels_version_;
  ++geometry_version_;
  layout_timings_.clear();
  move_timings_.clear();
  last_drag_ = DragStats();
  StartJob(/*init=*/true, /*set_handles=*/inputs_.has_layout, inputs_.path);
}

void EditSession::SetOptions(const DeformerOptions& options) {
  // A graph method chosen in the options replaces a non-graph one.
  if (options.method != options_.method) other_method_.clear();
  options_ = options;
  if (!has_mesh()) return;
  if (busy()) {
    pending_init_ = true;
    return;
  }
  std::vector<HandleTransforms> path;
  if (!transform_.IsIdentity()) path.push_back(transform_);
  StartJob(/*init=*/true, /*set_handles=*/!committed_layout_.moveable.empty(), std::move(path));
}

void EditSession::Label(const std::vector<int>& vertices, VertexLabel label) {
  bool changed = false;
  for (int v : vertices) {
    if (v < 0 || v >= static_cast<int>(labels_.size()) || labels_[v] == label) continue;
    labels_[v] = label;
    changed = true;
  }
  if (!changed) return;
  labels_changed_ = true;
  ++labels_version_;
}

void EditSession::ClearLabels() {
  labels_.assign(mesh_.num_vertices(), VertexLabel::kFree);
  labels_changed_ = true;
  ++labels_version_;
}

bool EditSession::CommitLayout(std::string* why) {
  if (!has_mesh()) return false;
  const HandleLayout layout = LayoutFromLabels(labels_);
  labels_changed_ = false;
  if (SameLayout(layout, committed_layout_) && (configured_ || busy())) return true;
  committed_layout_ = layout;
  transform_ = HandleTransforms();
  if (layout.moveable.empty()) {
    configured_ = false;
    ++geometry_version_;
    if (why != nullptr) *why = "no moveable handle: paint one (tool Handle) to drag";
    return false;
  }
  if (busy()) {
    pending_layout_ = true;
    return true;
  }
  StartJob(/*init=*/method_ == nullptr, /*set_handles=*/true, {});
  return true;
}

void EditSession::ResetPose() {
  if (committed_layout_.moveable.empty()) return;
  transform_ = HandleTransforms();
  if (busy()) {
    pending_layout_ = true;
    return;
  }
  StartJob(/*init=*/method_ == nullptr, /*set_handles=*/true, {});
}

void EditSession::StartJob(bool init, bool set_handles, std::vector<HandleTransforms> path) {
  auto job = std::make_unique<Job>();
  job->requested = Clock::now();
  job->init = init;
  job->set_handles = set_handles;
  job->method_name = method_name();
  job->options = method_options_;
  job->options.deformer = options_;
  job->mesh = &mesh_;
  job->mesh_path = inputs_.mesh_path;
  job->layout = committed_layout_;
  job->path = std::move(path);
  job->on_done = on_job_done_;
  if (!init) job->method = std::move(method_);
  DropPolisher();
  method_.reset();
  configured_ = false;
  ++geometry_version_;  // the rest pose is shown while the job runs
  job_ = std::async(std::launch::async, RunJob<Job>, std::move(job));
}

void EditSession::TakeJob() {
  std::unique_ptr<Job> job = job_.get();
  method_ = std::move(job->method);
  configured_ = job->configured;
  error_ = job->error;
  error_in_path_ = job->path_failed;
  last_drag_ = std::move(job->last_frame);
  if (job->configured && !job->path.empty()) transform_ = job->path.back();
  if (!job->configured) transform_ = HandleTransforms();
  layout_timings_.push_back(job->timing);
  ++geometry_version_;
  if (pending_init_ || pending_layout_) {
    std::vector<HandleTransforms> path;
    // New options keep the pose; a new layout starts from rest.
    if (!pending_layout_ && !transform_.IsIdentity()) path.push_back(transform_);
    if (pending_layout_) transform_ = HandleTransforms();
    const bool init = pending_init_ || method_ == nullptr;
    pending_init_ = pending_layout_ = false;
    StartJob(init, !committed_layout_.moveable.empty(), std::move(path));
  }
}

bool EditSession::Poll() {
  bool changed = false;
  if (polish_job_.valid() &&
      polish_job_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    changed = TakePolish();
  }
  if (!job_.valid() || job_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    return changed;
  }
  TakeJob();
  return true;
}

void EditSession::Wait() {
  while (job_.valid()) TakeJob();  // TakeJob blocks in get() and may start a follow-up
}

bool EditSession::WaitFor(std::chrono::milliseconds timeout) const {
  return !job_.valid() || job_.wait_for(timeout) == std::future_status::ready;
}

bool EditSession::ready() const { return !busy() && method_ != nullptr && configured_; }

bool EditSession::Drag(const HandleTransforms& deformed_from_rest, std::string* error) {
  if (!ready()) {
    *error = busy() ? "the method is being set up" : "no moveable handle set up";
    return false;
  }
  CancelPolish();
  if (show_polished_) ++geometry_version_;
  show_polished_ = false;
  DragStats stats;
  if (!method_->Drag(deformed_from_rest, &stats, error)) {
    error_ = *error;
    error_in_path_ = false;
    return false;
  }
  error_.clear();
  transform_ = deformed_from_rest;
  move_timings_.push_back({stats.solve_ms, stats.skin_ms, stats.frame_ms, stats.iterations});
  last_drag_ = std::move(stats);
  ++geometry_version_;
  return true;
}

const Eigen::Matrix3Xd& EditSession::positions() const {
  if (!ready()) return mesh_.vertices;
  return show_polished_ ? polished_ : method_->deformed_vertices();
}

const Eigen::Matrix3Xd& EditSession::normals() const {
  if (!ready()) return rest_normals_;
  if (const GraphMethod* graph = method_->graph_method(); graph != nullptr && !show_polished_) {
    return graph->deformed_normals();
  }
  // A method without skinned normals, or the polished mesh: the deformed
  // mesh's vertex normals, computed once per pose.
  if (method_normals_version_ != geometry_version_) {
    Mesh deformed = mesh_;
    deformed.vertices = positions();
    method_normals_ = VertexNormals(deformed);
    method_normals_version_ = geometry_version_;
  }
  return method_normals_;
}

std::string EditSession::method_name() const {
  return other_method_.empty() ? std::string(MethodName(options_.method)) : other_method_;
}

bool EditSession::SetMethod(const std::string& name, std::string* error) {
  if (!IsMethodName(name)) {
    *error = "--method=" + name + ": expected " + MethodNameList();
    return false;
  }
  DeformerOptions options = options_;
  Method graph;
  if (ParseMethod(name, &graph)) {
    other_method_.clear();
    options.method = graph;
  } else {
    other_method_ = name;
  }
  SetOptions(options);
  return true;
}

void EditSession::SetMethodOptions(const MethodOptions& options) {
  method_options_ = options;
  SetOptions(options_);
}

int EditSession::LayoutGroupOfLabel(int label_group) const {
  for (int i = 0; i < static_cast<int>(committed_layout_.moveable.size()); ++i) {
    if (HandleGroupOf(labels_[committed_layout_.moveable[i]]) == label_group) {
      return committed_layout_.group_of(i);
    }
  }
  return -1;
}

Eigen::Vector3d EditSession::HandleCentroid(int label_group) const {
  const Eigen::Matrix3Xd& points = positions();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (int v = 0; v < static_cast<int>(labels_.size()); ++v) {
    if (!IsHandle(labels_[v])) continue;
    if (label_group >= 0 && HandleGroupOf(labels_[v]) != label_group) continue;
    sum += points.col(v);
    ++count;
  }
  return count > 0 ? Eigen::Vector3d(sum / count) : Eigen::Vector3d(BoundingBox(mesh_).center());
}

std::string EditSession::Status() const {
  std::ostringstream text;
  if (!has_mesh()) return "no mesh: open one (File)";
  // The per-frame solver is a graph method's; another names none of it.
  text << inputs_.name << ": " << mesh_.num_vertices() << " vertices, " << method_name();
  if (IsGraphMethod(method_name())) text << " / " << SolverName(options_.backend);
  text << "; ";
  if (!error_.empty()) {
    text << "error: " << error_;
  } else if (busy()) {
    text << "setting up (rigidity, scale, classes)...";
  } else if (committed_layout_.moveable.empty()) {
    text << "paint the moveable handle (H) and the fixed region (F)";
  } else if (labels_changed_) {
    text << "selection changed: release the mouse to apply it";
  } else if (ready() && method_->graph_method() != nullptr) {
    const GraphMethod& d = *method_->graph_method();
    text << "scale " << d.active_graph() + 1 << " of " << d.graphs().size() << ", "
         << d.variables() << " variables";
  } else if (ready()) {
    text << method_->variables() << " variables";
  }
  return text.str();
}

bool MethodReadsDeformerRow(const std::string& method, const std::string& row) {
  if (IsGraphMethod(method)) return true;
  return row.rfind("lattice.", 0) == 0 || row == "num_threads";
}

}  // namespace editor
}  // namespace msdeform
