// The editor's window: GLFW, an OpenGL 3.3 core context, Dear ImGui panels,
// the renderer, and the mouse and keys turned into camera moves, handle
// selection and Drags of the session (apps/editor/edit_session.h).
//
// Mouse (README.md, "Editor"):
//   left      the tool: orbit | paint or lasso fixed / handle / erase | drag the handle
//             (drag: translate in the view plane; Shift: rotate; Ctrl: roll about the view axis)
//   Alt+left, middle   orbit;  right   pan;  wheel   zoom
// Keys: O orbit, F fixed, H handle, E erase, G drag, L brush/lasso, [ ] brush size,
//   W wireframe, S flat/smooth, R e' map, N nodes, K graph edges, C the first view,
//   Space rest pose, Tab panels, P screenshot, Esc cancel a lasso, Ctrl+Q quit.
// Every Drag of a mouse move is one GraphMethod::Drag, on this thread; layout
// changes run in the session's background job while the window keeps drawing.

#ifndef MSDEFORM_APPS_EDITOR_EDITOR_APP_H_
#define MSDEFORM_APPS_EDITOR_EDITOR_APP_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "apps/editor/camera.h"
#include "apps/editor/edit_session.h"
#include "apps/editor/gl.h"
#include "apps/editor/renderer.h"
#include "apps/editor/screenshot.h"
#include "apps/editor/selection.h"
#include "apps/editor/status_line.h"

namespace msdeform {
namespace editor {

struct EditorOptions {
  int width = 1280;  // window size (and screenshot size), pixels
  int height = 800;
  bool visible = true;            // false: a hidden window (one-shot screenshots, scripts)
  bool vsync = true;              // swap on the display's refresh (off for scripts)
  double brush_radius_px = 16.0;  // initial brush radius
  std::string screenshot_path = "msdeform_editor.png";  // the P key's and the panel's default
};

enum class Tool { kOrbit, kFixed, kHandle, kErase, kDrag };
enum class Overlay { kHandles, kRigidity, kNone };
enum class DragMode { kTranslate, kRotate, kRoll };

// What is drawn.
struct ViewState {
  bool flat_shading = false;
  bool wireframe = false;
  Overlay overlay = Overlay::kHandles;  // vertex colours: labels, e', or plain
  bool nodes = false;                   // node classes of the selected scale
  bool edges = false;                   // graph edges of the selected scale
  bool ui = true;                       // the panels
};

// CheckOutputs's message with the panel's checkbox instead of --overwrite.
std::string PanelMessage(std::string message);

class EditorApp {
 public:
  explicit EditorApp(EditSession* session) : session_(session) {}
  ~EditorApp();
  EditorApp(const EditorApp&) = delete;
  EditorApp& operator=(const EditorApp&) = delete;

  // Opens the window, the context, ImGui and the renderer. False with a
  // message (no display, no OpenGL 3.3).
  bool Init(const EditorOptions& options, std::string* error);
  // After the session opened a new mesh: uploads it and sets the first view.
  void MeshOpened();
  // The first view of the open edit: the whole mesh, seen from the side its
  // moveable handle faces (FacingDirection of its rest vertices); a mesh
  // without a handle from the front. MeshOpened calls it.
  void FirstView();

  // Draws one frame (polls the session first). CaptureFrame also reads the
  // frame back into *rgb (RGB, top row first), with or without the panels.
  void RenderFrame();
  void CaptureFrame(bool with_ui, std::vector<std::uint8_t>* rgb);
  // The interactive loop, until the window closes.
  void Run();

  // Input, in window pixels (the GLFW callbacks and scripts call these).
  void MouseButton(int button, bool press, int mods);
  void MouseMove(double x, double y);
  void Scroll(double steps);
  void Key(int key, int mods);
  void DropFiles(const std::vector<std::string>& paths);

  // The selection tools at a pixel or polygon (viewport pixels), on the last
  // drawn frame's depth: label the covered vertices and commit the layout.
  void PaintBrush(VertexLabel label, const Eigen::Vector2d& center, double radius, bool through);
  void PaintLasso(VertexLabel label, const std::vector<Eigen::Vector2d>& polygon, bool through);
  // The drag tool from a script: `steps` mouse moves adding up to `by` pixels.
  bool MouseDragHandle(const Eigen::Vector2d& by, int steps, DragMode mode, std::string* error);
  // The handle group the handle tool paints and the drag tool moves (label
  // group: 0 .. kMaxHandleGroups - 1; keys 1-9 pick 0-8).
  int active_group() const { return active_group_; }
  void set_active_group(int group) { active_group_ = group; }

  OrbitCamera& camera() { return camera_; }
  ViewState& view() { return view_; }
  Viewport viewport() const;
  EditSession& session() { return *session_; }
  // The panel windows of the last frame drawn with the panels (empty without).
  const std::vector<PanelRect>& panels() const { return panels_; }
  const std::vector<double>& draw_ms() const { return draw_ms_; }
  // The frames drawn while a background job (a layout change) ran.
  const std::vector<double>& busy_draw_ms() const { return busy_draw_ms_; }
  // Reapplies the deformer flags the panel changed (method, solver, ablations).
  void ApplyOptions(const DeformerOptions& options);

 private:
  void SyncGpu();
  void UpdateColors();
  void UpdateGraph();
  void DrawPanels();
  void DrawFilePanel();
  void DrawToolPanel();
  void DrawMethodPanel();
  void DrawMethodChooser();
  void DrawViewPanel();
  void DrawStatePanel();
  void DrawTimingPanel();
  void DrawColorBar();
  void DrawStatusLine();
  // Records the window being drawn in panels_ (call before its End).
  void RecordPanel(const char* name);
  void DrawCursor();
  void SetFlagFromPanel(const std::string& name, const std::string& value);
  void OpenFromPanel();
  void SaveFromPanel(const std::string& which);
  void TakeScreenshot(const std::string& path);
  void BeginStroke(double x, double y);
  void EndStroke();
  void DragHandleBy(const Eigen::Vector2d& delta, DragMode mode);
  RenderSettings Settings() const;
  Eigen::Vector2d ToViewport(double x, double y) const;

  EditSession* session_;
  EditorOptions options_;
  GLFWwindow* window_ = nullptr;
  bool imgui_ready_ = false;
  std::unique_ptr<Renderer> renderer_;  // made once the context exists
  OrbitCamera camera_;
  ViewState view_;

  // GPU state against the session's versions.
  int uploaded_geometry_ = -1, uploaded_labels_ = -1, uploaded_jobs_ = -1;
  Overlay uploaded_overlay_ = Overlay::kHandles;
  bool graph_uploaded_ = false;
  Eigen::VectorXd vertex_rigidity_;
  double node_radius_ = 0.01;

  // Gestures.
  Tool tool_ = Tool::kOrbit;
  int active_group_ = 0;
  bool lasso_ = false;
  bool through_ = false;
  double brush_radius_ = 16.0;
  enum class Gesture { kNone, kOrbit, kPan, kPaint, kLasso, kDrag } gesture_ = Gesture::kNone;
  DragMode drag_mode_ = DragMode::kTranslate;
  // Polish on release (methods/polish.h): off until ticked in the timings
  // panel; a budget of 300 ms keeps the wait short on a large mesh.
  bool polish_on_release_ = false;
  PolishOptions polish_options_ = [] {
    PolishOptions options;
    options.time_budget_ms = 300.0;
    return options;
  }();
  Eigen::Vector2d mouse_ = Eigen::Vector2d::Zero();  // window pixels
  ScreenVertices stroke_screen_;
  std::vector<Eigen::Vector2d> lasso_points_;  // viewport pixels
  Eigen::Vector3d drag_anchor_ = Eigen::Vector3d::Zero();

  // Panel text fields and messages.
  std::string open_mesh_, open_sel_, open_def_, open_scenario_;
  std::string save_mesh_, save_sel_, save_def_, save_scenario_, save_png_;
  int save_frames_ = 30;
  bool overwrite_ = false;
  StatusLine status_;
  std::string browse_folder_;

  std::string pending_screenshot_;  // asked for during a frame, taken after it
  std::vector<PanelRect> panels_;

  std::vector<double> draw_ms_;
  std::vector<double> busy_draw_ms_;
  double last_draw_ms_ = 0.0;
};

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_EDITOR_APP_H_
