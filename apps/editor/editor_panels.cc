// The editor's Dear ImGui panels: files, tools, view, the method's state for
// the current layout (scale, classes, variables), timings, the e' colour bar
// and the status line (the Method panel: method_panel.cc). Part of EditorApp
// (apps/editor/editor_app.h).

#include <imgui.h>
#include <imgui_internal.h>  // the window's extents, for RecordPanel
#include <imgui_stdlib.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <system_error>
#include <vector>

#include "apps/editor/edit_files.h"
#include "apps/editor/edit_inputs.h"
#include "apps/editor/editor_app.h"
#include "apps/editor/overlays.h"
#include "apps/editor/panel_widgets.h"
#include "apps/editor/timing_report.h"
#include "apps/outputs.h"
#include "msdeform/methods/registry.h"

namespace msdeform {
namespace editor {
namespace {

namespace fs = std::filesystem;

// The panel column: its width and its distance from the window's edges, pixels.
constexpr float kPanelWidth = 400.0f;
constexpr float kMargin = 8.0f;

ImU32 Packed(const Rgb& rgb) { return IM_COL32(rgb[0], rgb[1], rgb[2], 255); }

const char* const kHelpText =
    "Mouse\n"
    "  left         the tool (below)\n"
    "  Alt+left, middle   orbit\n"
    "  right        pan\n"
    "  wheel        zoom\n"
    "Drag tool: left drags the handle in the view plane;\n"
    "  Shift+left rotates it, Ctrl+left rolls it about the view axis.\n"
    "  Each mouse move is one solve + skin.\n"
    "Keys\n"
    "  O orbit  F fixed  H handle  E erase  G drag\n"
    "  L brush / lasso   [ ] brush size\n"
    "  W wireframe  S flat / smooth  R e' colour map\n"
    "  N node classes  K graph edges  C first view\n"
    "  Space rest pose  Tab panels  P screenshot\n"
    "  Esc cancel a lasso  Ctrl+Q quit\n"
    "Files can be dropped on the window.";

}  // namespace

// The panels fit a 1280 x 800 window (the default size) without scrolling:
// the column above the status line holds Tools, Method, View, the state and
// the timings open, and File, the method's ablations and details and Help
// closed. RecordPanel measures what each window would cut or scroll away,
// and the screenshot tests check it (tests/editor/editor_test.sh).
void EditorApp::DrawPanels() {
  const Viewport vp = viewport();
  DrawStatusLine();
  const float status_height = panels_.empty() ? 30.0f : panels_.back().height;
  ImGui::SetNextWindowPos(ImVec2(kMargin, kMargin), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(
      ImVec2(kPanelWidth, std::max(200.0f, vp.height - status_height - 2 * kMargin)),
      ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.92f);
  if (ImGui::Begin("msdeform editor")) {
    DrawFilePanel();
    DrawToolPanel();
    DrawMethodPanel();
    DrawViewPanel();
    DrawStatePanel();
    DrawTimingPanel();
    if (ImGui::CollapsingHeader("Help")) ImGui::TextUnformatted(kHelpText);
    RecordPanel("msdeform editor");
  }
  ImGui::End();
  DrawColorBar();
}

void EditorApp::DrawStatusLine() {
  // The full width at the bottom, as high as its (wrapped) text.
  const Viewport vp = viewport();
  ImGui::SetNextWindowPos(ImVec2(0, static_cast<float>(vp.height)), ImGuiCond_Always,
                          ImVec2(0, 1));
  ImGui::SetNextWindowSize(ImVec2(static_cast<float>(vp.width), 0.0f));
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin("status", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoInputs |
                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing);
  std::string text = session_->Status();
  if (!status_.text().empty()) text += "  | " + status_.text();
  ImGui::TextWrapped("%s", text.c_str());
  RecordPanel("status");
  ImGui::End();
}

void EditorApp::RecordPanel(const char* name) {
  const ImGuiWindow* window = ImGui::GetCurrentWindow();
  PanelRect panel;
  panel.name = name;
  panel.x = window->Pos.x;
  panel.y = window->Pos.y;
  panel.width = window->Size.x;
  panel.height = window->Size.y;
  // The contents' extent this frame against the rectangle the window shows
  // them in (inside its borders and scroll bars; ImGui clips there). An
  // auto-sized window fits its contents from its next frame.
  panel.overflow_x = window->DC.CursorMaxPos.x - window->InnerClipRect.Max.x;
  panel.overflow_y = window->DC.CursorMaxPos.y - window->InnerClipRect.Max.y;
  panels_.push_back(panel);
}

void EditorApp::DrawFilePanel() {
  if (!ImGui::CollapsingHeader("File")) return;
  ImGui::PushItemWidth(-90);
  ImGui::InputText("mesh", &open_mesh_);
  ImGui::InputText(".sel", &open_sel_);
  ImGui::InputText(".def", &open_def_);
  ImGui::InputText("scenario", &open_scenario_);
  ImGui::PopItemWidth();
  if (ImGui::Button("Open")) OpenFromPanel();
  Help(
      "A mesh alone, a mesh with a .sel/.def pair, or a JSON scenario (with an optional mesh "
      "that replaces its own), as msdeform's --mesh, --sel, --def, --scenario. Files can also "
      "be dropped on the window.");
  if (ImGui::TreeNode("Browse")) {
    if (browse_folder_.empty()) {
      browse_folder_ = fs::current_path().string();
      if (!open_mesh_.empty()) {
        browse_folder_ = fs::absolute(open_mesh_).parent_path().string();
      } else if (!open_scenario_.empty()) {
        browse_folder_ = fs::absolute(open_scenario_).parent_path().string();
      }
    }
    ImGui::TextWrapped("%s", browse_folder_.c_str());
    ImGui::BeginChild("files", ImVec2(0, 130), true);
    if (ImGui::Selectable("../")) {
      browse_folder_ = fs::path(browse_folder_).parent_path().string();
    }
    std::vector<fs::directory_entry> entries;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(browse_folder_, ec)) entries.push_back(entry);
    std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
      if (a.is_directory() != b.is_directory()) return a.is_directory();
      return a.path().filename() < b.path().filename();
    });
    for (const auto& entry : entries) {
      const std::string name = entry.path().filename().string();
      if (name.empty() || name[0] == '.') continue;
      if (entry.is_directory()) {
        if (ImGui::Selectable((name + "/").c_str())) browse_folder_ = entry.path().string();
        continue;
      }
      std::string extension = entry.path().extension().string();
      std::transform(extension.begin(), extension.end(), extension.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      std::string* field = extension == ".sel"    ? &open_sel_
                           : extension == ".def"  ? &open_def_
                           : extension == ".json" ? &open_scenario_
                           : (extension == ".off" || extension == ".obj" || extension == ".ply" ||
                              extension == ".stl")
                               ? &open_mesh_
                               : nullptr;
      if (field != nullptr && ImGui::Selectable(name.c_str())) *field = entry.path().string();
    }
    ImGui::EndChild();
    ImGui::TreePop();
  }
  ImGui::Separator();
  ImGui::PushItemWidth(-150);
  ImGui::InputText("##save_mesh", &save_mesh_);
  ImGui::SameLine();
  if (ImGui::Button("Save mesh")) SaveFromPanel("mesh");
  ImGui::InputText("##save_sel", &save_sel_);
  ImGui::SameLine();
  if (ImGui::Button("Save .sel")) SaveFromPanel("sel");
  ImGui::InputText("##save_def", &save_def_);
  ImGui::SameLine();
  if (ImGui::Button("Save .def")) SaveFromPanel("def");
  ImGui::InputText("##save_scenario", &save_scenario_);
  ImGui::SameLine();
  if (ImGui::Button("Save scenario")) SaveFromPanel("scenario");
  ImGui::InputText("##save_png", &save_png_);
  ImGui::SameLine();
  if (ImGui::Button("Screenshot")) pending_screenshot_ = save_png_;
  ImGui::PopItemWidth();
  ImGui::SetNextItemWidth(100);
  ImGui::InputInt("scenario frames", &save_frames_);
  save_frames_ = std::clamp(save_frames_, 1, 100000);
  ImGui::Checkbox("replace existing files", &overwrite_);
}

void EditorApp::DrawToolPanel() {
  if (!ImGui::CollapsingHeader("Tools", ImGuiTreeNodeFlags_DefaultOpen)) return;
  int tool = static_cast<int>(tool_);
  ImGui::RadioButton("orbit (O)", &tool, static_cast<int>(Tool::kOrbit));
  ImGui::SameLine();
  ImGui::RadioButton("drag (G)", &tool, static_cast<int>(Tool::kDrag));
  ImGui::RadioButton("fixed (F)", &tool, static_cast<int>(Tool::kFixed));
  ImGui::SameLine();
  ImGui::RadioButton("handle (H)", &tool, static_cast<int>(Tool::kHandle));
  ImGui::SameLine();
  ImGui::RadioButton("erase (E)", &tool, static_cast<int>(Tool::kErase));
  tool_ = static_cast<Tool>(tool);
  int group = active_group_;
  ImGui::SetNextItemWidth(100);
  if (ImGui::InputInt("handle group", &group)) {
    active_group_ = std::clamp(group, 0, kMaxHandleGroups - 1);
  }
  ImGui::SameLine();
  ImGui::TextColored(Color(HandleGroupColor(active_group_)), "painted and dragged");
  Help("Several handles move independently: paint each as its own group (keys 1-9 pick "
       "groups 0-8); the drag tool moves the group picked here, the others stay where they "
       "are.");
  int shape = lasso_ ? 1 : 0;
  ImGui::RadioButton("brush", &shape, 0);
  ImGui::SameLine();
  ImGui::RadioButton("lasso (L)", &shape, 1);
  lasso_ = shape == 1;
  ImGui::SameLine();
  ImGui::Checkbox("through", &through_);
  Help("Select hidden vertices too (the whole depth of the mesh under the brush or lasso).");
  float radius = static_cast<float>(brush_radius_);
  ImGui::SetNextItemWidth(160);
  if (ImGui::SliderFloat("brush radius, px", &radius, 2.0f, 200.0f, "%.0f")) {
    brush_radius_ = radius;
  }
  if (ImGui::Button("Clear selection")) {
    session_->ClearLabels();
    std::string why;
    if (!session_->CommitLayout(&why)) status_.Show(why, Until::kMoveableHandle);
  }
  ImGui::SameLine();
  if (ImGui::Button("Rest pose (Space)")) session_->ResetPose();
  ImGui::TextColored(Color(kFixedColor), "fixed");
  ImGui::SameLine();
  ImGui::TextColored(Color(kHandleColor), "moveable handle");
  ImGui::SameLine();
  ImGui::TextDisabled("(%zu / %zu vertices)", session_->committed_layout().fixed.size(),
                      session_->committed_layout().moveable.size());
}

void EditorApp::DrawViewPanel() {
  if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
  int shading = view_.flat_shading ? 1 : 0;
  ImGui::RadioButton("smooth", &shading, 0);
  ImGui::SameLine();
  ImGui::RadioButton("flat (S)", &shading, 1);
  view_.flat_shading = shading == 1;
  ImGui::SameLine();
  ImGui::Checkbox("wireframe (W)", &view_.wireframe);
  // e', the node classes and the graph edges are a graph method's.
  const bool graph = IsGraphMethod(session_->method_name());
  int overlay = static_cast<int>(view_.overlay);
  ImGui::RadioButton("handles", &overlay, static_cast<int>(Overlay::kHandles));
  ImGui::SameLine();
  ImGui::BeginDisabled(!graph);
  ImGui::RadioButton("e' (R)", &overlay, static_cast<int>(Overlay::kRigidity));
  ImGui::EndDisabled();
  ImGui::SameLine();
  ImGui::RadioButton("plain", &overlay, static_cast<int>(Overlay::kNone));
  view_.overlay = static_cast<Overlay>(overlay);
  ImGui::BeginDisabled(!graph);
  ImGui::Checkbox("node classes (N)", &view_.nodes);
  ImGui::SameLine();
  ImGui::Checkbox("graph edges (K)", &view_.edges);
  ImGui::EndDisabled();
  ImGui::SameLine();
  // The whole mesh, seen from the side the moveable handle faces.
  if (ImGui::Button("First view (C)")) FirstView();
}

void EditorApp::DrawStatePanel() {
  if (!ImGui::CollapsingHeader("Scale and classes", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const GraphMethod* graph_method = session_->ready() ? session_->graph_method() : nullptr;
  const EditingMethod* method = session_->ready() ? session_->method() : nullptr;
  if (graph_method == nullptr && method != nullptr) {
    // Not a graph method: no scales or node classes.
    ImGui::Text("%s: %d variables", session_->method_name().c_str(), method->variables());
    ImGui::TextDisabled("not a deformation graph: no scales or node classes");
    return;
  }
  if (graph_method == nullptr) {
    ImGui::TextDisabled(session_->busy() ? "setting up the layout..." : "no layout set up");
    return;
  }
  const bool multiscale = graph_method->options().method == Method::kMultiScale;
  const ScaleSelection& selection = graph_method->selection();
  if (multiscale) {
    ImGui::Text("scale %d of %zu (Eq. 6 gives %d)%s", graph_method->active_graph() + 1,
                graph_method->graphs().size(), selection.eq6_scale,
                selection.local_detail_edit ? ", local detail edit" : "");
    ImGui::Text("threshold T = %.3f (Eq. 7), group 1: %d nodes", selection.threshold,
                selection.group1_size);
  } else {
    ImGui::Text("static graph: %d nodes (%s)", graph_method->active().num_nodes(),
                MethodName(graph_method->options().method));
  }
  const std::array<int, 3> counts = CountNodeClasses(*graph_method);
  ImGui::TextColored(Color(kTotallyFreeColor), "Totally Free %d", counts[0]);
  ImGui::SameLine();
  ImGui::TextColored(Color(kHalfFreeColor), "Half Free %d", counts[1]);
  ImGui::SameLine();
  ImGui::TextColored(Color(kFixedNodeColor), "Fixed %d", counts[2]);
  ImGui::Text("variables %d = 12 x %d + 9 x %d", graph_method->variables(), counts[0], counts[1]);
  ImGui::Text("coherence terms %d, position terms %d", graph_method->num_coherence_terms(),
              graph_method->num_position_terms());
  ImGui::Text("skinned vertices %d of %d", graph_method->num_skinned_vertices(),
              session_->mesh().num_vertices());
}

void EditorApp::DrawTimingPanel() {
  if (!ImGui::CollapsingHeader("Timings (ms)", ImGuiTreeNodeFlags_DefaultOpen)) return;
  if (!session_->layout_timings().empty()) {
    const LayoutTiming& last = session_->layout_timings().back();
    ImGui::Text("layout: rigidity %.1f, setup %.1f", last.rigidity_ms, last.setup_ms);
    Help(
        "The last handle-layout change (GraphMethod::SetHandles): rigidity estimation, then scale "
        "selection, node classes and the solver's set-up. It runs in the background.");
    if (last.init) {
      ImGui::Text("  after Init (lattice, graphs) %.1f; waited %.1f", last.init_ms, last.wall_ms);
    } else {
      ImGui::Text("  waited %.1f in all", last.wall_ms);
    }
  }
  const DragStats& drag = session_->last_drag();
  ImGui::Text("last move: solve %.2f, skin %.2f", drag.solve_ms, drag.skin_ms);
  Help(
      "One GraphMethod::Drag: the Gauss-Newton (or Ceres) solve of Eq. 17 on the free nodes, then "
      "skinning the mesh. Each mouse move of the drag tool is one.");
  ImGui::Text("  %d iterations", drag.iterations);
  ImGui::Checkbox("polish on release", &polish_on_release_);
  Help(
      "After a drag, a few accelerated full_arap iterations (handle and fixed vertices exact) "
      "on a worker thread, within 300 ms; the polished mesh replaces the frame when it is "
      "ready, and dragging again cancels it. The first release for a layout also factorises.");
  if (session_->polishing()) {
    ImGui::Text("polishing...");
  } else if (session_->has_polish()) {
    const PolishReport& polish = session_->last_polish();
    ImGui::TextWrapped("polish: ARAP %.4g -> %.4g, %d it, %.1f (setup %.1f)",
                       polish.energy_before, polish.energy_after, polish.iterations, polish.ms,
                       polish.setup_ms);
  }
  ImGui::Text("draw %.2f per frame", last_draw_ms_);
  const TimingSummary summary =
      SummarizeTimings(session_->layout_timings(), session_->move_timings(), draw_ms_);
  if (summary.moves > 0) {
    ImGui::Text("median of %d moves: solve+skin %.2f", summary.moves, summary.solve_skin_median_ms);
  }
}

void EditorApp::DrawColorBar() {
  if (view_.overlay != Overlay::kRigidity) return;
  const Viewport vp = viewport();
  ImGui::SetNextWindowPos(ImVec2(vp.width - 96.0f, vp.height - 330.0f), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(88.0f, 290.0f), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin("e'", nullptr,
               ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_NoSavedSettings);
  if (vertex_rigidity_.size() == 0) {
    ImGui::TextWrapped("multi-scale only");
    ImGui::End();
    return;
  }
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float width = 22.0f, height = 220.0f;
  const int segments = 20;
  for (int i = 0; i < segments; ++i) {
    // Top is e' = 1.
    const double top = 1.0 - static_cast<double>(i) / segments;
    const double bottom = 1.0 - static_cast<double>(i + 1) / segments;
    const float y0 = origin.y + height * i / segments, y1 = origin.y + height * (i + 1) / segments;
    const ImU32 c0 = Packed(RigidityColor(top)), c1 = Packed(RigidityColor(bottom));
    draw->AddRectFilledMultiColor(ImVec2(origin.x, y0), ImVec2(origin.x + width, y1), c0, c0, c1,
                                  c1);
  }
  for (double tick : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    const float y = origin.y + static_cast<float>((1.0 - tick) * height);
    char label[16];
    std::snprintf(label, sizeof(label), "%.2f", tick);
    draw->AddLine(ImVec2(origin.x + width, y), ImVec2(origin.x + width + 4, y),
                  IM_COL32(0, 0, 0, 255));
    draw->AddText(ImVec2(origin.x + width + 6, y - 7), IM_COL32(0, 0, 0, 255), label);
  }
  const GraphMethod* graph_method = session_->graph_method();
  if (graph_method != nullptr && session_->ready()) {
    const double threshold = std::clamp(graph_method->selection().threshold, 0.0, 1.0);
    const float y = origin.y + static_cast<float>((1.0 - threshold) * height);
    draw->AddLine(ImVec2(origin.x - 3, y), ImVec2(origin.x + width + 3, y),
                  IM_COL32(230, 30, 30, 255), 2.0f);
    draw->AddText(ImVec2(origin.x + width + 34, y - 7), IM_COL32(230, 30, 30, 255), "T");
  }
  ImGui::Dummy(ImVec2(width, height + 4));
  ImGui::TextDisabled("rigid = 0");
  RecordPanel("e'");
  ImGui::End();
}

void EditorApp::OpenFromPanel() {
  OpenRequest request;
  request.mesh = open_mesh_;
  request.sel = open_sel_;
  request.def = open_def_;
  request.scenario = open_scenario_;
  EditInputs inputs;
  std::string error;
  if (request.mesh.empty() && request.scenario.empty()) {
    status_.Show("give a mesh or a scenario");
    return;
  }
  if (!LoadEditInputs(request, &inputs, &error)) {
    status_.Show(error);
    return;
  }
  status_.Show(inputs.read_report.notice);
  session_->Open(std::move(inputs), session_->options());
  MeshOpened();
}

void EditorApp::SaveFromPanel(const std::string& which) {
  const EditFile kind = which == "mesh"  ? EditFile::kMesh
                        : which == "sel" ? EditFile::kSel
                        : which == "def" ? EditFile::kDef
                                         : EditFile::kScenario;
  const std::string& path = which == "mesh"  ? save_mesh_
                            : which == "sel" ? save_sel_
                            : which == "def" ? save_def_
                                             : save_scenario_;
  std::string error;
  if (!CheckOutputs({{path, which, EditFileExtensions(kind)}}, session_->inputs().files(),
                    overwrite_, &error) ||
      !WriteEditFile(*session_, kind, path, path, save_frames_, &error)) {
    status_.Show(PanelMessage(error));
    return;
  }
  status_.Show("wrote " + path);
}

}  // namespace editor
}  // namespace msdeform
