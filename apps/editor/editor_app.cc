#include "apps/editor/editor_app.h"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "apps/editor/overlays.h"
#include "apps/editor/screenshot.h"
#include "apps/outputs.h"
#include "msdeform/core/timing.h"

namespace msdeform {
namespace editor {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kPi = 3.14159265358979323846;
// Handle rotation per pixel of mouse motion, degrees.
constexpr double kRotateDegPerPixel = 0.4;

std::string& GlfwError() {
  static std::string message;
  return message;
}

void OnGlfwError(int code, const char* description) {
  GlfwError() = "GLFW error " + std::to_string(code) + ": " + description;
}

}  // namespace

std::string PanelMessage(std::string message) {
  const std::string flag = "pass --overwrite to replace it";
  const size_t at = message.find(flag);
  if (at != std::string::npos) message.replace(at, flag.size(), "tick \"replace existing files\"");
  return message;
}

namespace {

EditorApp* AppOf(GLFWwindow* window) {
  return static_cast<EditorApp*>(glfwGetWindowUserPointer(window));
}

bool UiWantsMouse() {
  return ImGui::GetCurrentContext() != nullptr && ImGui::GetIO().WantCaptureMouse;
}
bool UiWantsKeys() {
  return ImGui::GetCurrentContext() != nullptr && ImGui::GetIO().WantCaptureKeyboard;
}

}  // namespace

EditorApp::~EditorApp() {
  // A running job would wake a loop that is gone.
  session_->Wait();
  session_->set_on_job_done(nullptr);
  if (imgui_ready_) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  renderer_.reset();  // its GL objects go before the context
  if (window_ != nullptr) {
    glfwDestroyWindow(window_);
    glfwTerminate();
  }
}

bool EditorApp::Init(const EditorOptions& options, std::string* error) {
  options_ = options;
  brush_radius_ = options.brush_radius_px;
  save_png_ = options.screenshot_path;
  glfwSetErrorCallback(OnGlfwError);
  if (!glfwInit()) {
    *error = "cannot open a window (" + GlfwError() +
             "); without a display, run under xvfb-run -a -s \"-screen 0 1280x1024x24\"";
    return false;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  window_ = glfwCreateWindow(options.width, options.height, "msdeform editor", nullptr, nullptr);
  if (window_ == nullptr) {
    *error = "cannot open a " + std::to_string(options.width) + " x " +
             std::to_string(options.height) + " window with OpenGL 3.3 core (" + GlfwError() + ")";
    glfwTerminate();
    return false;
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(options.vsync ? 1 : 0);
  glfwSetWindowUserPointer(window_, this);
  // Ours first: ImGui's GLFW backend chains to the callbacks installed before it.
  glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int mods) {
    if (action == GLFW_PRESS && UiWantsMouse()) return;
    AppOf(w)->MouseButton(button, action == GLFW_PRESS, mods);
  });
  glfwSetCursorPosCallback(window_,
                           [](GLFWwindow* w, double x, double y) { AppOf(w)->MouseMove(x, y); });
  glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double dy) {
    if (!UiWantsMouse()) AppOf(w)->Scroll(dy);
  });
  glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int mods) {
    if (action != GLFW_RELEASE && !UiWantsKeys()) AppOf(w)->Key(key, mods);
  });
  glfwSetDropCallback(window_, [](GLFWwindow* w, int count, const char** paths) {
    AppOf(w)->DropFiles(std::vector<std::string>(paths, paths + count));
  });

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the working folder
  ImGui::StyleColorsLight();
  ImGui::GetStyle().WindowRounding = 3.0f;
  ImGui::GetStyle().ItemSpacing.y = 3.0f;  // (4) the panels fit a 1280 x 800 window
  if (!ImGui_ImplGlfw_InitForOpenGL(window_, true) || !ImGui_ImplOpenGL3_Init("#version 330")) {
    *error = "Dear ImGui: cannot set up its GLFW and OpenGL 3 backends";
    return false;
  }
  imgui_ready_ = true;
  session_->set_on_job_done([] { glfwPostEmptyEvent(); });
  renderer_ = std::make_unique<Renderer>();
  if (!renderer_->Init(error)) return false;
  if (session_->has_mesh()) MeshOpened();
  return true;
}

Viewport EditorApp::viewport() const {
  Viewport viewport;
  glfwGetFramebufferSize(window_, &viewport.width, &viewport.height);
  viewport.width = std::max(viewport.width, 1);
  viewport.height = std::max(viewport.height, 1);
  return viewport;
}

Eigen::Vector2d EditorApp::ToViewport(double x, double y) const {
  int window_width = 1, window_height = 1;
  glfwGetWindowSize(window_, &window_width, &window_height);
  const Viewport vp = viewport();
  return Eigen::Vector2d(x * vp.width / std::max(window_width, 1),
                         y * vp.height / std::max(window_height, 1));
}

void EditorApp::MeshOpened() {
  const Mesh& mesh = session_->mesh();
  renderer_->SetTopology(mesh.faces, mesh.num_vertices());
  FirstView();
  uploaded_geometry_ = uploaded_labels_ = uploaded_jobs_ = -1;
  graph_uploaded_ = false;
  vertex_rigidity_.resize(0);
  const EditInputs& inputs = session_->inputs();
  open_mesh_ = inputs.scenario_path.empty() ? inputs.mesh_path : "";
  open_sel_ = inputs.scenario_path.empty() ? inputs.sel_path : "";
  open_def_ = inputs.scenario_path.empty() ? inputs.def_path : "";
  open_scenario_ = inputs.scenario_path;
  const std::string stem = inputs.name + "_edit";
  save_mesh_ = stem + ".off";
  save_sel_ = stem + ".sel";
  save_def_ = stem + ".def";
  save_scenario_ = stem + ".json";
}

void EditorApp::FirstView() {
  if (!session_->has_mesh()) return;
  const Mesh& mesh = session_->mesh();
  const std::vector<int>& handle = session_->committed_layout().moveable;
  // With a handle, from the side it faces (camera.h, FirstViewDirection); a
  // mesh alone from the front (+z).
  camera_.set_yaw_deg(0.0);
  camera_.set_pitch_deg(0.0);
  camera_.LookFrom(FirstViewDirection(mesh, handle));
  camera_.Fit(BoundingBox(mesh), viewport());
}

RenderSettings EditorApp::Settings() const {
  RenderSettings settings;
  const Viewport vp = viewport();
  settings.flat_shading = view_.flat_shading;
  settings.wireframe = view_.wireframe;
  const bool graph = session_->graph_method() != nullptr && session_->ready();
  settings.nodes = view_.nodes && graph;
  settings.edges = view_.edges && graph;
  settings.node_radius = node_radius_;
  settings.view = camera_.View();
  settings.projection = camera_.Projection(vp);
  return settings;
}

void EditorApp::UpdateColors() {
  const bool rigidity = view_.overlay == Overlay::kRigidity && vertex_rigidity_.size() > 0;
  std::vector<Rgb> colors;
  if (view_.overlay == Overlay::kNone) {
    colors.assign(session_->labels().size(), kFreeColor);
  } else {
    colors = VertexColors(session_->labels(), rigidity ? vertex_rigidity_ : Eigen::VectorXd());
  }
  renderer_->SetColors(colors);
}

void EditorApp::UpdateGraph() {
  const GraphMethod* graph_method = session_->graph_method();
  if (graph_method == nullptr || !session_->ready()) return;
  renderer_->SetGraph(DeformedNodePositions(*graph_method), NodeColors(*graph_method),
                      graph_method->active().edges);
  // A sphere a quarter of the mean edge length, at most 1.2% of the diagonal.
  const DeformationGraph& graph = graph_method->active();
  double total = 0.0;
  for (const auto& [a, b] : graph.edges) {
    total += (graph.positions.col(a) - graph.positions.col(b)).norm();
  }
  const double mean = graph.edges.empty() ? graph_method->diagonal() : total / graph.edges.size();
  node_radius_ = std::min(0.25 * mean, 0.012 * graph_method->diagonal());
  graph_uploaded_ = true;
}

void EditorApp::SyncGpu() {
  const int jobs = static_cast<int>(session_->layout_timings().size());
  const bool new_job = jobs != uploaded_jobs_;
  if (new_job) {
    uploaded_jobs_ = jobs;
    const GraphMethod* graph_method = session_->graph_method();
    vertex_rigidity_ = graph_method != nullptr && session_->ready() ? VertexRigidity(*graph_method)
                                                                    : Eigen::VectorXd();
  }
  if (session_->geometry_version() != uploaded_geometry_) {
    uploaded_geometry_ = session_->geometry_version();
    renderer_->SetGeometry(session_->positions(), session_->normals());
    graph_uploaded_ = false;
  }
  if ((view_.nodes || view_.edges) && !graph_uploaded_) UpdateGraph();
  if (new_job || session_->labels_version() != uploaded_labels_ ||
      view_.overlay != uploaded_overlay_) {
    uploaded_labels_ = session_->labels_version();
    uploaded_overlay_ = view_.overlay;
    UpdateColors();
  }
}

void EditorApp::RenderFrame() { CaptureFrame(false, nullptr); }

void EditorApp::CaptureFrame(bool with_ui, std::vector<std::uint8_t>* rgb) {
  if (session_->Poll() && session_->has_mesh() && !session_->error().empty()) {
    status_.Show(session_->error());
  }
  status_.Update(*session_);
  const auto start = Clock::now();
  const bool busy = session_->busy();
  SyncGpu();
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  panels_.clear();
  if (view_.ui) DrawPanels();
  DrawCursor();
  ImGui::Render();
  const Viewport vp = viewport();
  renderer_->DrawScene(vp, Settings());
  if (rgb != nullptr && !with_ui) *rgb = renderer_->ReadColor();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());  // into the offscreen framebuffer
  if (rgb != nullptr && with_ui) *rgb = renderer_->ReadColor();
  renderer_->Present(vp);
  glFinish();
  last_draw_ms_ = MillisecondsSince(start);
  draw_ms_.push_back(last_draw_ms_);
  if (busy) busy_draw_ms_.push_back(last_draw_ms_);
  glfwSwapBuffers(window_);
}

void EditorApp::Run() {
  while (!glfwWindowShouldClose(window_)) {
    // Draw on input, when a background job finishes (it posts an empty
    // event), and a few times a second otherwise: a layout change keeps the
    // window live without drawing over and over on the cores it runs on.
    glfwWaitEventsTimeout(session_->busy() ? 0.1 : 0.25);
    RenderFrame();
    if (!pending_screenshot_.empty()) {
      TakeScreenshot(pending_screenshot_);
      pending_screenshot_.clear();
    }
  }
}

// ---------------------------------------------------------------------------
// Input.

void EditorApp::MouseButton(int button, bool press, int mods) {
  if (!press) {
    if (gesture_ == Gesture::kPaint || gesture_ == Gesture::kLasso) EndStroke();
    if (gesture_ == Gesture::kDrag && polish_on_release_) {
      PolishOptions options = polish_options_;
      options.num_threads = std::max(1, session_->options().num_threads);
      session_->StartPolish(options);
    }
    gesture_ = Gesture::kNone;
    return;
  }
  if (gesture_ != Gesture::kNone || !session_->has_mesh()) return;
  if (button == GLFW_MOUSE_BUTTON_RIGHT) {
    gesture_ = Gesture::kPan;
  } else if (button == GLFW_MOUSE_BUTTON_MIDDLE ||
             (button == GLFW_MOUSE_BUTTON_LEFT &&
              ((mods & GLFW_MOD_ALT) || tool_ == Tool::kOrbit))) {
    gesture_ = Gesture::kOrbit;
  } else if (button == GLFW_MOUSE_BUTTON_LEFT && tool_ == Tool::kDrag) {
    if (!session_->ready()) {
      if (session_->busy()) {
        status_.Show("wait: the new layout is being set up", Until::kSetUp);
      } else if (session_->committed_layout().moveable.empty()) {
        status_.Show("paint a moveable handle (H) before dragging", Until::kMoveableHandle);
      } else {
        // A handle is there but its layout was refused: say why, and keep it.
        status_.Show(session_->error().empty() ? "the handle layout was not set up"
                                               : session_->error());
      }
      return;
    }
    gesture_ = Gesture::kDrag;
    drag_mode_ = (mods & GLFW_MOD_SHIFT)     ? DragMode::kRotate
                 : (mods & GLFW_MOD_CONTROL) ? DragMode::kRoll
                                             : DragMode::kTranslate;
    const bool one_group = session_->committed_layout().num_groups() == 1;
    drag_anchor_ = session_->HandleCentroid(one_group ? -1 : active_group_);
  } else if (button == GLFW_MOUSE_BUTTON_LEFT) {
    BeginStroke(mouse_.x(), mouse_.y());
  }
}

void EditorApp::MouseMove(double x, double y) {
  const Eigen::Vector2d previous = mouse_;
  mouse_ = Eigen::Vector2d(x, y);
  const Eigen::Vector2d delta = ToViewport(x, y) - ToViewport(previous.x(), previous.y());
  switch (gesture_) {
    case Gesture::kOrbit:
      camera_.Orbit(delta.x(), delta.y());
      break;
    case Gesture::kPan:
      camera_.Pan(delta.x(), delta.y(), viewport());
      break;
    case Gesture::kPaint: {
      const VertexLabel label = tool_ == Tool::kFixed    ? VertexLabel::kFixed
                                : tool_ == Tool::kHandle ? HandleLabel(active_group_)
                                                         : VertexLabel::kFree;
      session_->Label(VerticesAlongStroke(stroke_screen_, ToViewport(previous.x(), previous.y()),
                                          ToViewport(x, y), brush_radius_, through_),
                      label);
      break;
    }
    case Gesture::kLasso:
      lasso_points_.push_back(ToViewport(x, y));
      break;
    case Gesture::kDrag:
      DragHandleBy(delta, drag_mode_);
      break;
    case Gesture::kNone:
      break;
  }
}

void EditorApp::Scroll(double steps) { camera_.Zoom(steps); }

void EditorApp::Key(int key, int mods) {
  switch (key) {
    case GLFW_KEY_O:
      tool_ = Tool::kOrbit;
      break;
    case GLFW_KEY_F:
      tool_ = Tool::kFixed;
      break;
    case GLFW_KEY_H:
      tool_ = Tool::kHandle;
      break;
    case GLFW_KEY_E:
      tool_ = Tool::kErase;
      break;
    case GLFW_KEY_G:
      tool_ = Tool::kDrag;
      break;
    case GLFW_KEY_1:
    case GLFW_KEY_2:
    case GLFW_KEY_3:
    case GLFW_KEY_4:
    case GLFW_KEY_5:
    case GLFW_KEY_6:
    case GLFW_KEY_7:
    case GLFW_KEY_8:
    case GLFW_KEY_9:
      active_group_ = key - GLFW_KEY_1;
      break;
    case GLFW_KEY_L:
      lasso_ = !lasso_;
      break;
    case GLFW_KEY_LEFT_BRACKET:
      brush_radius_ = std::max(2.0, brush_radius_ / 1.25);
      break;
    case GLFW_KEY_RIGHT_BRACKET:
      brush_radius_ = std::min(400.0, brush_radius_ * 1.25);
      break;
    case GLFW_KEY_W:
      view_.wireframe = !view_.wireframe;
      break;
    case GLFW_KEY_S:
      view_.flat_shading = !view_.flat_shading;
      break;
    case GLFW_KEY_R:
      view_.overlay = view_.overlay == Overlay::kRigidity ? Overlay::kHandles : Overlay::kRigidity;
      break;
    case GLFW_KEY_N:
      view_.nodes = !view_.nodes;
      break;
    case GLFW_KEY_K:
      view_.edges = !view_.edges;
      break;
    case GLFW_KEY_C:
      FirstView();
      break;
    case GLFW_KEY_SPACE:
      session_->ResetPose();
      break;
    case GLFW_KEY_TAB:
      view_.ui = !view_.ui;
      break;
    case GLFW_KEY_P:
      pending_screenshot_ = save_png_;
      break;
    case GLFW_KEY_Q:
      if (mods & GLFW_MOD_CONTROL) glfwSetWindowShouldClose(window_, GLFW_TRUE);
      break;
    case GLFW_KEY_ESCAPE:
      if (gesture_ == Gesture::kLasso) {
        lasso_points_.clear();
        gesture_ = Gesture::kNone;
      }
      break;
    default:
      break;
  }
}

void EditorApp::DropFiles(const std::vector<std::string>& paths) {
  std::string mesh, sel, def, scenario;
  for (const std::string& path : paths) {
    const size_t dot = path.find_last_of('.');
    std::string extension = dot == std::string::npos ? "" : path.substr(dot);
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    (extension == ".sel"    ? sel
     : extension == ".def"  ? def
     : extension == ".json" ? scenario
                            : mesh) = path;
  }
  // A dropped .sel/.def pair goes with the dropped mesh or the open one; a
  // scenario with a dropped mesh replaces its own.
  if (mesh.empty() && scenario.empty() && session_->has_mesh()) {
    mesh = session_->inputs().mesh_path;
  }
  open_mesh_ = mesh;
  open_sel_ = sel;
  open_def_ = def;
  open_scenario_ = scenario;
  OpenFromPanel();
}

// ---------------------------------------------------------------------------
// Selection and dragging.

void EditorApp::BeginStroke(double x, double y) {
  // The depth of the frame on screen: the camera does not move during a stroke.
  stroke_screen_ =
      ProjectVertices(session_->positions(), camera_, viewport(), renderer_->ReadDepth());
  if (lasso_) {
    gesture_ = Gesture::kLasso;
    lasso_points_ = {ToViewport(x, y)};
    return;
  }
  gesture_ = Gesture::kPaint;
  const VertexLabel label = tool_ == Tool::kFixed    ? VertexLabel::kFixed
                            : tool_ == Tool::kHandle ? HandleLabel(active_group_)
                                                     : VertexLabel::kFree;
  session_->Label(VerticesInBrush(stroke_screen_, ToViewport(x, y), brush_radius_, through_),
                  label);
}

void EditorApp::EndStroke() {
  if (gesture_ == Gesture::kLasso) {
    const VertexLabel label = tool_ == Tool::kFixed    ? VertexLabel::kFixed
                              : tool_ == Tool::kHandle ? HandleLabel(active_group_)
                                                       : VertexLabel::kFree;
    session_->Label(VerticesInLasso(stroke_screen_, lasso_points_, through_), label);
    lasso_points_.clear();
  }
  gesture_ = Gesture::kNone;
  std::string why;
  if (!session_->CommitLayout(&why)) status_.Show(why, Until::kMoveableHandle);
}

void EditorApp::PaintBrush(VertexLabel label, const Eigen::Vector2d& center, double radius,
                           bool through) {
  const ScreenVertices screen =
      ProjectVertices(session_->positions(), camera_, viewport(), renderer_->ReadDepth());
  session_->Label(VerticesInBrush(screen, center, radius, through), label);
  session_->CommitLayout();
}

void EditorApp::PaintLasso(VertexLabel label, const std::vector<Eigen::Vector2d>& polygon,
                           bool through) {
  const ScreenVertices screen =
      ProjectVertices(session_->positions(), camera_, viewport(), renderer_->ReadDepth());
  session_->Label(VerticesInLasso(screen, polygon, through), label);
  session_->CommitLayout();
}

void EditorApp::DragHandleBy(const Eigen::Vector2d& delta, DragMode mode) {
  if (!session_->ready() || delta.isZero()) return;
  // With several handle groups only the active one moves.
  const int num_groups = session_->committed_layout().num_groups();
  const int moved_group = num_groups > 1 ? session_->LayoutGroupOfLabel(active_group_) : -1;
  if (num_groups > 1 && moved_group < 0) {
    status_.Show("handle group " + std::to_string(active_group_) +
                 " has no vertex: paint it (tool Handle) or pick another group (keys 1-9)");
    return;
  }
  Eigen::Affine3d change = Eigen::Affine3d::Identity();
  if (mode == DragMode::kTranslate) {
    const Eigen::Vector3d move = camera_.ViewPlaneDelta(delta, drag_anchor_, viewport());
    change.translate(move);
    drag_anchor_ += move;
  } else {
    // About the handle's current centroid: a trackball (the front of the
    // handle follows the mouse), or a roll about the view axis.
    const Eigen::Vector3d pivot =
        session_->HandleCentroid(moved_group >= 0 ? active_group_ : -1);
    Eigen::Vector3d axis;
    double angle;
    if (mode == DragMode::kRotate) {
      axis = (camera_.Up() * delta.x() + camera_.Right() * delta.y()).normalized();
      angle = delta.norm() * kRotateDegPerPixel * kPi / 180.0;
    } else {
      axis = camera_.Forward();
      angle = delta.x() * kRotateDegPerPixel * kPi / 180.0;
    }
    change.translate(pivot);
    change.rotate(Eigen::AngleAxisd(angle, axis));
    change.translate(-pivot);
  }
  // The moved group (every group for one) by the change, the others where they are.
  std::vector<Eigen::Affine3d> moved;
  const HandleTransforms& current = session_->transform();
  for (int g = 0; g < std::max(current.size(), num_groups); ++g) {
    moved.push_back(moved_group < 0 || g == moved_group ? change * current[g] : current[g]);
  }
  std::string error;
  if (!session_->Drag(HandleTransforms(std::move(moved)), &error)) status_.Show(error);
}

bool EditorApp::MouseDragHandle(const Eigen::Vector2d& by, int steps, DragMode mode,
                                std::string* error) {
  if (!session_->ready()) {
    *error = "no handle to drag (paint or label one first)";
    return false;
  }
  if (session_->committed_layout().num_groups() > 1 &&
      session_->LayoutGroupOfLabel(active_group_) < 0) {
    *error = "handle group " + std::to_string(active_group_) + " has no vertex";
    return false;
  }
  const bool one_group = session_->committed_layout().num_groups() == 1;
  drag_anchor_ = session_->HandleCentroid(one_group ? -1 : active_group_);
  for (int step = 0; step < steps; ++step) {
    const size_t moves = session_->move_timings().size();
    DragHandleBy(by / steps, mode);
    if (session_->move_timings().size() == moves) {
      *error =
          "step " + std::to_string(step + 1) + " of " + std::to_string(steps) + ": " +
          (session_->error().empty() ? std::string("the handle did not move") : session_->error());
      return false;
    }
    RenderFrame();
  }
  return true;
}

void EditorApp::ApplyOptions(const DeformerOptions& options) { session_->SetOptions(options); }

void EditorApp::TakeScreenshot(const std::string& path) {
  std::string error;
  if (!CheckOutputs({{path, "screenshot", {".png"}}}, session_->inputs().files(), overwrite_,
                    &error)) {
    status_.Show(PanelMessage(error));
    return;
  }
  std::vector<std::uint8_t> rgb;
  CaptureFrame(view_.ui, &rgb);
  const Viewport vp = viewport();
  status_.Show(WritePng(path, vp.width, vp.height, rgb, &error) ? "wrote " + path : error);
}

// ---------------------------------------------------------------------------
// Drawn over the scene: the brush and the lasso.

void EditorApp::DrawCursor() {
  const bool painting = tool_ == Tool::kFixed || tool_ == Tool::kHandle || tool_ == Tool::kErase;
  if (!painting || UiWantsMouse()) return;
  ImDrawList* draw = ImGui::GetForegroundDrawList();
  const ImU32 color =
      tool_ == Tool::kFixed    ? IM_COL32(kFixedColor[0], kFixedColor[1], kFixedColor[2], 255)
      : tool_ == Tool::kHandle ? IM_COL32(HandleGroupColor(active_group_)[0],
                                          HandleGroupColor(active_group_)[1],
                                          HandleGroupColor(active_group_)[2], 255)
                               : IM_COL32(60, 60, 60, 255);
  if (gesture_ == Gesture::kLasso && lasso_points_.size() > 1) {
    std::vector<ImVec2> points;
    const Viewport vp = viewport();
    int window_width = 1, window_height = 1;
    glfwGetWindowSize(window_, &window_width, &window_height);
    for (const Eigen::Vector2d& p : lasso_points_) {
      points.emplace_back(static_cast<float>(p.x() * window_width / vp.width),
                          static_cast<float>(p.y() * window_height / vp.height));
    }
    draw->AddPolyline(points.data(), static_cast<int>(points.size()), color, ImDrawFlags_Closed,
                      2.0f);
  } else if (!lasso_) {
    draw->AddCircle(ImVec2(static_cast<float>(mouse_.x()), static_cast<float>(mouse_.y())),
                    static_cast<float>(brush_radius_), color, 32, 2.0f);
  }
}

}  // namespace editor
}  // namespace msdeform
