#include "apps/editor/script_runner.h"

#include <cmath>
#include <iostream>
#include <utility>

#include "apps/editor/edit_files.h"
#include "apps/editor/edit_inputs.h"
#include "apps/editor/inline_scenario.h"
#include "apps/editor/option_flags.h"
#include "apps/editor/screenshot.h"
#include "msdeform/core/drag_path.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/scenario.h"

namespace msdeform {
namespace editor {
namespace {

using Json = nlohmann::json;

// One script being run.
class Runner {
 public:
  Runner(const Script& script, EditorApp* app, DeformerOptions* options, bool quiet,
         StagedOutputs* staged)
      : script_(script),
        app_(app),
        session_(app->session()),
        options_(options),
        quiet_(quiet),
        staged_(staged) {}

  bool Run(std::string* error) {
    for (const ScriptAction& action : script_.actions) {
      std::string problem;
      if (!Do(action, &problem)) {
        *error = action.where + " (" + action.kind + "): " + problem;
        return false;
      }
    }
    return true;
  }

 private:
  bool Do(const ScriptAction& action, std::string* error) {
    const Json& args = action.args;
    const std::string& kind = action.kind;
    if (kind == "open") return Open(args, error);
    if (!session_.has_mesh()) {
      *error = "no mesh is open (an \"open\" action comes first)";
      return false;
    }
    if (kind == "label") return Label(args, action.where, error);
    if (kind == "clear") {
      session_.ClearLabels();
      return Commit(error);
    }
    if (kind == "brush") return Brush(args, error);
    if (kind == "lasso") {
      app_->RenderFrame();  // the depth of the current view
      std::vector<Eigen::Vector2d> polygon;
      for (const Json& p : args["polygon"])
        polygon.emplace_back(p[0].get<double>(), p[1].get<double>());
      app_->PaintLasso(Label(args), polygon, args.value("through", false));
      return Settled(error);
    }
    if (kind == "drag") return Drag(args, action.where, error);
    if (kind == "mouse_drag") {
      const std::string mode = args.value("mode", "translate");
      if (args.contains("group")) {
        const int group = args["group"].get<int>();
        if (session_.ready() && session_.LayoutGroupOfLabel(group) < 0) {
          *error = "group: handle group " + std::to_string(group) + " has no vertex";
          return false;
        }
        app_->set_active_group(group);
      }
      return app_->MouseDragHandle(
          Eigen::Vector2d(args["by"][0].get<double>(), args["by"][1].get<double>()),
          args.value("steps", 10),
          mode == "rotate" ? DragMode::kRotate
          : mode == "roll" ? DragMode::kRoll
                           : DragMode::kTranslate,
          error);
    }
    if (kind == "reset") {
      session_.ResetPose();
      return Settled(error);
    }
    if (kind == "set") return Set(args, error);
    if (kind == "view") {
      ViewState& view = app_->view();
      if (args.contains("shading")) view.flat_shading = args["shading"] == "flat";
      view.wireframe = args.value("wireframe", view.wireframe);
      if (args.contains("overlay")) {
        view.overlay = args["overlay"] == "rigidity" ? Overlay::kRigidity
                       : args["overlay"] == "none"   ? Overlay::kNone
                                                     : Overlay::kHandles;
      }
      view.nodes = args.value("nodes", view.nodes);
      view.edges = args.value("edges", view.edges);
      view.ui = args.value("ui", view.ui);
      app_->RenderFrame();
      return true;
    }
    if (kind == "camera") {
      OrbitCamera& camera = app_->camera();
      if (args.value("fit", false)) camera.Fit(BoundingBox(session_.mesh()), app_->viewport());
      if (args.contains("yaw_deg")) camera.set_yaw_deg(args["yaw_deg"].get<double>());
      if (args.contains("pitch_deg")) camera.set_pitch_deg(args["pitch_deg"].get<double>());
      if (args.contains("target")) {
        camera.set_target(Eigen::Vector3d(args["target"][0].get<double>(),
                                          args["target"][1].get<double>(),
                                          args["target"][2].get<double>()));
      }
      if (args.contains("zoom")) {
        const double zoom = args["zoom"].get<double>();
        if (!(zoom > 0.0)) {
          *error = "zoom: must be more than 0";
          return false;
        }
        camera.set_distance(camera.distance() / zoom);
      }
      if (args.contains("pan")) {
        camera.Pan(args["pan"][0].get<double>(), args["pan"][1].get<double>(), app_->viewport());
      }
      app_->RenderFrame();
      return true;
    }
    if (kind == "screenshot") return Screenshot(args, error);
    if (kind == "save") return Save(args, error);
    *error = "unknown action";
    return false;
  }

  static VertexLabel Label(const Json& args) {
    VertexLabel label = VertexLabel::kFree;
    ParseVertexLabel(args["as"].get<std::string>(), &label);  // checked by ReadScript
    if (label == VertexLabel::kHandle) label = HandleLabel(args.value("group", 0));
    return label;
  }

  // Waits for the session's job, drawing a frame every 100 ms meanwhile as
  // the window does (their times show it stays responsive); its failure is
  // the action's.
  bool Settled(std::string* error) {
    do {
      app_->RenderFrame();  // takes a finished job's result
    } while (!session_.WaitFor(std::chrono::milliseconds(100)) || session_.busy());
    app_->RenderFrame();  // the result drawn
    if (!session_.error().empty()) {
      *error = session_.error();
      return false;
    }
    return true;
  }

  bool Commit(std::string* error) {
    session_.CommitLayout();  // without a handle there is nothing to set up yet
    return Settled(error);
  }

  bool Open(const Json& args, std::string* error) {
    OpenRequest request;
    request.mesh = script_.Resolve(args.value("mesh", ""));
    request.sel = script_.Resolve(args.value("sel", ""));
    request.def = script_.Resolve(args.value("def", ""));
    request.scenario = script_.Resolve(args.value("scenario", ""));
    request.frames = args.value("frames", 0);
    if (request.mesh.empty() && request.scenario.empty()) {
      *error = "needs a mesh or a scenario";
      return false;
    }
    EditInputs inputs;
    if (!LoadEditInputs(request, &inputs, error)) return false;
    if (!inputs.read_report.notice.empty() && !quiet_) {
      std::cerr << "msdeform_editor: notice: " << inputs.read_report.notice << "\n";
    }
    session_.Open(std::move(inputs), *options_);
    app_->MeshOpened();
    return Settled(error);
  }

  bool Label(const Json& args, const std::string& where, std::string* error) {
    std::vector<int> ids;
    if (!SelectInlineRegion(args["region"], session_.mesh(), where, &ids, error)) {
      // SelectInlineRegion names the action itself; drop the prefix Run adds.
      error->erase(0, std::min(error->size(), where.size() + 1));
      return false;
    }
    session_.Label(ids, Label(args));
    return Commit(error);
  }

  bool Brush(const Json& args, std::string* error) {
    app_->RenderFrame();  // the depth of the current view
    Eigen::Vector2d center;
    if (args.contains("at_vertex")) {
      const long long v = args["at_vertex"].get<long long>();
      if (v < 0 || v >= session_.mesh().num_vertices()) {
        *error = "at_vertex: vertex " + std::to_string(v) + " is outside the mesh's 0.." +
                 std::to_string(session_.mesh().num_vertices() - 1);
        return false;
      }
      center = app_->camera()
                   .Project(session_.positions().col(static_cast<int>(v)), app_->viewport())
                   .head<2>();
    } else {
      center = Eigen::Vector2d(args["at"][0].get<double>(), args["at"][1].get<double>());
    }
    app_->PaintBrush(Label(args), center, args.value("radius_px", 16.0),
                     args.value("through", false));
    return Settled(error);
  }

  bool Drag(const Json& args, const std::string& where, std::string* error) {
    if (!session_.ready()) {
      *error = "no handle is set up (label or paint a handle first)";
      return false;
    }
    const int frames = args.value("frames", 1);
    const Mesh& mesh = session_.mesh();
    const HandleLayout& layout = session_.committed_layout();
    // "group": that handle group moves about its own centroid, the others stay.
    int moved = -1;
    std::vector<int> moveable = layout.moveable;
    if (args.contains("group")) {
      moved = session_.LayoutGroupOfLabel(args["group"].get<int>());
      if (moved < 0) {
        *error = "group: handle group " + std::to_string(args["group"].get<int>()) +
                 " has no vertex";
        return false;
      }
      moveable = HandleGroupVertices(layout, moved);
    }
    const HandleTransforms start = session_.transform();
    std::vector<HandleTransforms> path;
    if (args.contains("transform")) {
      if (!InlineMotionPath(args["transform"], frames, mesh, moveable, where, &path, error)) {
        error->erase(0, std::min(error->size(), where.size() + 1));
        return false;
      }
    } else {
      Eigen::Affine3d target = Eigen::Affine3d::Identity();
      if (args.contains("def")) {
        if (!ReadDef(script_.Resolve(args["def"].get<std::string>()), &target, error)) {
          return false;
        }
      } else {
        Eigen::Matrix4d matrix;
        for (int i = 0; i < 16; ++i) matrix(i / 4, i % 4) = args["matrix"][i].get<double>();
        if (!matrix.allFinite() ||
            (matrix.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9) {
          *error = "matrix: expected finite numbers and a last row 0 0 0 1";
          return false;
        }
        target.matrix() = matrix;
      }
      // As msdeform --sel/--def: interpolated about the handle's rest centroid.
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (int v : moveable) centroid += mesh.vertices.col(v);
      centroid /= static_cast<double>(moveable.size());
      const std::vector<Eigen::Affine3d> steps = InterpolateDragPath(target, centroid, frames);
      path.assign(steps.begin(), steps.end());
    }
    for (size_t f = 0; f < path.size() && moved >= 0; ++f) {
      std::vector<Eigen::Affine3d> frame;
      for (int g = 0; g < layout.num_groups(); ++g) frame.push_back(g == moved ? path[f][0] : start[g]);
      path[f] = HandleTransforms(std::move(frame));
    }
    for (size_t f = 0; f < path.size(); ++f) {
      if (!session_.Drag(path[f], error)) {
        *error =
            "frame " + std::to_string(f + 1) + " of " + std::to_string(path.size()) + ": " + *error;
        return false;
      }
      app_->RenderFrame();
    }
    return true;
  }

  bool Set(const Json& args, std::string* error) {
    const Json& value = args["value"];
    const std::string text = value.is_string()    ? value.get<std::string>()
                             : value.is_boolean() ? (value.get<bool>() ? "true" : "false")
                                                  : value.dump();
    const std::string flag = args["flag"].get<std::string>();
    if (IsMethodOption(flag)) {
      // A method's own option (--fastlsm_steps, fastlsm.damping).
      MethodOptions options = session_.method_options();
      if (!SetMethodFlag(flag, text, &options, error)) return false;
      session_.SetMethodOptions(options);
      return Settled(error);
    }
    if (!SetDeformerFlag(flag, text, options_, error)) return false;
    if (flag == "method") {
      // Any registered method, as the panel's chooser.
      if (!session_.SetMethod(text, error)) return false;
      return Settled(error);
    }
    app_->ApplyOptions(*options_);
    return Settled(error);
  }

  bool Stage(const std::string& path, std::string* staged, std::string* error) {
    return staged_->Stage(path, staged, error);
  }

  bool Screenshot(const Json& args, std::string* error) {
    std::vector<std::uint8_t> rgb;
    app_->CaptureFrame(args.value("ui", false), &rgb);
    const Viewport viewport = app_->viewport();
    const std::string path = script_.Resolve(args["path"].get<std::string>());
    std::string staged;
    if (!Stage(path, &staged, error) ||
        !WritePng(staged, viewport.width, viewport.height, rgb, error)) {
      *error = staged_->Translate(*error);
      return false;
    }
    if (args.contains("camera")) {
      const std::string camera = script_.Resolve(args["camera"].get<std::string>());
      if (!Stage(camera, &staged, error) ||
          !WriteText(staged, CameraJson(app_->camera(), viewport, app_->panels()), error)) {
        *error = staged_->Translate(*error);
        return false;
      }
    }
    return true;
  }

  bool Save(const Json& args, std::string* error) {
    const std::pair<const char*, EditFile> kinds[] = {{"mesh", EditFile::kMesh},
                                                      {"sel", EditFile::kSel},
                                                      {"def", EditFile::kDef},
                                                      {"scenario", EditFile::kScenario}};
    for (const auto& [key, kind] : kinds) {
      if (!args.contains(key)) continue;
      const std::string path = script_.Resolve(args[key].get<std::string>());
      std::string staged;
      if (!Stage(path, &staged, error) ||
          !WriteEditFile(session_, kind, staged, path, args.value("frames", 30), error)) {
        *error = std::string(key) + ": " + staged_->Translate(*error);
        return false;
      }
    }
    return true;
  }

  const Script& script_;
  EditorApp* app_;
  EditSession& session_;
  DeformerOptions* options_;
  bool quiet_;
  StagedOutputs* staged_;
};

}  // namespace

bool CheckScriptOutputs(const Script& script, const std::vector<OutputCheck>& extra, bool overwrite,
                        std::string* error) {
  std::vector<OutputCheck> outputs;
  for (const ScriptOutput& output : ScriptOutputs(script)) {
    outputs.push_back({output.path, script.path + ": " + output.field, output.extensions});
  }
  outputs.insert(outputs.end(), extra.begin(), extra.end());
  return CheckOutputs(outputs, ScriptInputs(script), overwrite, error);
}

bool RunScript(const Script& script, EditorApp* app, DeformerOptions* options, bool quiet,
               StagedOutputs* staged, std::string* error) {
  return Runner(script, app, options, quiet, staged).Run(error);
}

}  // namespace editor
}  // namespace msdeform
