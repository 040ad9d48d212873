// msdeform_editor: the interactive editor of issue 17 (README.md, "Editor").
//
//   msdeform_editor [--mesh=M [--sel=S --def=D] | --scenario=J] [method flags]
//       a window: select handles, drag them, watch the method's overlays;
//   msdeform_editor --mesh=M --sel=S --def=D --screenshot=OUT.png [--out=OUT.off]
//       one shot: open, apply the .def drag as msdeform does, draw, write, exit;
//   msdeform_editor --script=FILE [--timings=T.json]
//       replay a script of actions in a hidden window, then exit.
// Inputs are read and checked as msdeform reads them (apps/editor/edit_inputs.h),
// with msdeform's messages; the method, solver and ablation flags are
// msdeform's own (apps/flags/deformer_flags.h).

#include <gflags/gflags.h>
#include <glog/logging.h>

#include <iostream>
#include <string>
#include <vector>

#include "apps/editor/edit_files.h"
#include "apps/editor/edit_inputs.h"
#include "apps/editor/edit_session.h"
#include "apps/editor/editor_app.h"
#include "apps/editor/screenshot.h"
#include "apps/editor/script.h"
#include "apps/editor/script_runner.h"
#include "apps/editor/timing_report.h"
#include "apps/flags/deformer_flags.h"
#include "apps/flags/method_flags.h"
#include "apps/flags/program.h"
#include "apps/outputs.h"
#include "msdeform/core/build_info.h"
#include "msdeform/methods/registry.h"


namespace {
const msdeform::editor::EditorOptions kDefaults;
}  // namespace

DEFINE_string(mesh, "",
              "[input] Mesh to open (OFF, OBJ, PLY, STL); alone, it opens without handles.");
DEFINE_string(sel, "", "[input] Botsch-Sorkine .sel handle file (with --def and --mesh).");
DEFINE_string(def, "",
              "[input] Botsch-Sorkine .def 4x4 handle transform, world coordinates (with --sel); "
              "dragged to on opening, as msdeform does.");
DEFINE_string(scenario, "",
              "[input] JSON scenario (docs/formats.md); its drag is applied on opening. Default "
              "when no input is given: data/scenarios/armadillo_claw.json.");
DEFINE_int32(frames, 0,
             "[input] Drag frames from rest to the input's transform, 0..100000 (0: the "
             "scenario's, or 1).");
DEFINE_string(script, "",
              "[input] Replay this JSON script of actions (README.md, \"Editor\") in a hidden "
              "window and exit; it opens and writes its own files.");
DEFINE_string(screenshot, "",
              "[output] One shot: draw the opened and dragged mesh (fixed region blue, handle "
              "red) into this PNG, and exit.");
DEFINE_string(screenshot_camera, "",
              "[output] With --screenshot: its camera as JSON (view and projection matrices), "
              "to project points onto the image.");
DEFINE_string(out, "",
              "[output] One shot: write the deformed mesh (.off, .obj or .ply), and exit.");
DEFINE_string(timings, "",
              "[output] On exit, the timing panel of the session as JSON: every move's solve "
              "and skin, every layout change, every drawn frame, and their medians.");
DEFINE_bool(overwrite, false, "[output] Replace outputs that exist (otherwise an error).");
DEFINE_int32(width, kDefaults.width, "[output] Window and screenshot width, pixels, 320..8192.");
DEFINE_int32(height, kDefaults.height, "[output] Window and screenshot height, pixels, 240..8192.");
DEFINE_bool(screenshot_ui, false, "[output] The --screenshot image includes the panels.");
DEFINE_bool(keep_open, false,
            "[diagnostics] After --script, --screenshot or --out, keep the window open.");
DEFINE_bool(quiet, false, "[diagnostics] Print nothing but errors.");
DEFINE_bool(verbose, false,
            "[diagnostics] Also print the solver's own log (Ceres warnings and errors).");

namespace msdeform {
namespace editor {
namespace {

int Fail(const std::string& message) {
  std::cerr << "msdeform_editor: " << message << "\n";
  return 1;
}

bool FlagGiven(const char* name) {
  gflags::CommandLineFlagInfo info;
  return gflags::GetCommandLineFlagInfo(name, &info) && !info.is_default;
}

// --timings: written when asked, on the way out.
bool WriteTimings(EditorApp* app, std::string* error) {
  const EditSession& session = app->session();
  if (!FLAGS_quiet && (!session.move_timings().empty() || !FLAGS_timings.empty())) {
    std::printf("msdeform_editor: %s\n",
                TimingsLine(SummarizeTimings(session.layout_timings(), session.move_timings(),
                                             app->draw_ms(), app->busy_draw_ms()))
                    .c_str());
  }
  if (FLAGS_timings.empty()) return true;
  return WriteText(
      FLAGS_timings,
      TimingsJson(session.inputs().name, session.mesh().num_vertices(), session.layout_timings(),
                  session.move_timings(), app->draw_ms(), app->busy_draw_ms()),
      error);
}

EditorOptions WindowOptions(bool visible) {
  EditorOptions options;
  options.width = FLAGS_width;
  options.height = FLAGS_height;
  options.visible = visible;
  options.vsync = visible;
  return options;
}

int RunScriptMode(DeformerOptions options, const MethodOptions& method_options,
                  const std::string& method) {
  for (const char* flag :
       {"mesh", "sel", "def", "scenario", "frames", "screenshot", "screenshot_camera", "out"}) {
    if (FlagGiven(flag)) {
      return Fail(std::string("--script and --") + flag +
                  " do not go together: open and write files in the script");
    }
  }
  std::string error;
  Script script;
  if (!ReadScript(FLAGS_script, &script, &error)) return Fail(error);
  if (!CheckScriptOutputs(script, {{FLAGS_timings, "--timings", {".json"}}}, FLAGS_overwrite,
                          &error)) {
    return Fail(error);
  }
  EditSession session;
  if (!session.SetMethod(method, &error)) return Fail(error);
  session.SetMethodOptions(method_options);
  EditorApp app(&session);
  if (!app.Init(WindowOptions(FLAGS_keep_open), &error)) return Fail(error);
  StagedOutputs staged;
  if (!RunScript(script, &app, &options, FLAGS_quiet, &staged, &error)) {
    return Fail(error + "; no output written");
  }
  if (!staged.Commit(&error)) return Fail(error);
  if (!WriteTimings(&app, &error)) return Fail(error);
  if (FLAGS_keep_open) app.Run();
  return 0;
}

int RunFilesMode(const DeformerOptions& options, const MethodOptions& method_options,
                 const std::string& method) {
  OpenRequest request;
  request.mesh = FLAGS_mesh;
  request.sel = FLAGS_sel;
  request.def = FLAGS_def;
  request.scenario = FLAGS_scenario;
  request.frames = FLAGS_frames;
  std::string error;
  EditInputs inputs;
  if (!ResolveInputNames(request, &inputs, &error)) return Fail(error);
  const bool one_shot = !FLAGS_screenshot.empty() || !FLAGS_out.empty();
  if (!FLAGS_screenshot_camera.empty() && FLAGS_screenshot.empty()) {
    return Fail("--screenshot_camera goes with --screenshot");
  }
  if (!CheckOutputs({{FLAGS_screenshot, "--screenshot", {".png"}},
                     {FLAGS_screenshot_camera, "--screenshot_camera", {".json"}},
                     {FLAGS_out, "--out", EditFileExtensions(EditFile::kMesh)},
                     {FLAGS_timings, "--timings", {".json"}}},
                    inputs.files(), FLAGS_overwrite, &error)) {
    return Fail(error);
  }
  if (!ReadInputFiles(request, &inputs, &error)) return Fail(error);
  if (!inputs.read_report.notice.empty() && !FLAGS_quiet) {
    std::cerr << "msdeform_editor: notice: " << inputs.read_report.notice << "\n";
  }
  EditSession session;
  if (!session.SetMethod(method, &error)) return Fail(error);
  session.SetMethodOptions(method_options);
  session.Open(std::move(inputs), options);
  if (!one_shot) {
    EditorApp app(&session);
    if (!app.Init(WindowOptions(true), &error)) return Fail(error);
    app.Run();
    if (!WriteTimings(&app, &error)) return Fail(error);
    return 0;
  }

  // One shot: the edit as msdeform makes it, before a window opens, so an
  // input msdeform refuses fails here with msdeform's message.
  session.Wait();
  if (!session.error().empty()) {
    return Fail(session.error() + (session.error_in_path() ? "; no output written" : ""));
  }
  EditorApp app(&session);
  if (!app.Init(WindowOptions(FLAGS_keep_open), &error)) return Fail(error);
  app.view().ui = FLAGS_screenshot_ui;
  StagedOutputs staged;
  std::string staged_path;
  if (!FLAGS_screenshot.empty()) {
    std::vector<std::uint8_t> rgb;
    // The panels lay themselves out in their first frame (sizes, scroll bars).
    if (FLAGS_screenshot_ui) app.RenderFrame();
    app.CaptureFrame(FLAGS_screenshot_ui, &rgb);
    const Viewport viewport = app.viewport();
    if (!staged.Stage(FLAGS_screenshot, &staged_path, &error) ||
        !WritePng(staged_path, viewport.width, viewport.height, rgb, &error)) {
      return Fail(staged.Translate(error));
    }
    if (!FLAGS_screenshot_camera.empty() &&
        (!staged.Stage(FLAGS_screenshot_camera, &staged_path, &error) ||
         !WriteText(staged_path, CameraJson(app.camera(), viewport, app.panels()), &error))) {
      return Fail(staged.Translate(error));
    }
  }
  if (!FLAGS_out.empty() &&
      (!staged.Stage(FLAGS_out, &staged_path, &error) ||
       !WriteEditFile(session, EditFile::kMesh, staged_path, FLAGS_out, 1, &error))) {
    return Fail(staged.Translate(error));
  }
  if (!staged.Commit(&error)) return Fail(error);
  if (!WriteTimings(&app, &error)) return Fail(error);
  if (FLAGS_keep_open) {
    app.view().ui = true;
    app.Run();
  }
  return 0;
}

int Run() {
  DeformerOptions options;
  std::string error;
  // --method names any registered method (as msdeform's); the methods' own
  // flags (--cgal_iterations, --fastlsm_steps, ...) are rows of the one table.
  const std::string method = MethodFlag();
  if (!IsMethodName(method)) return Fail("--method=" + method + ": expected " + MethodNameList());
  // As msdeform: a flag the starting method does not read is refused, not
  // kept silently for a method the user may switch to.
  if (!CheckFlagsReadBy(method, &error)) return Fail(error);
  MethodOptions method_options;
  if (!MethodOptionsFromFlags(&method_options, &error)) return Fail(error);
  options = method_options.deformer;
  if (FLAGS_width < 320 || FLAGS_width > 8192) {
    return Fail("--width=" + std::to_string(FLAGS_width) + ": expected 320..8192 pixels");
  }
  if (FLAGS_height < 240 || FLAGS_height > 8192) {
    return Fail("--height=" + std::to_string(FLAGS_height) + ": expected 240..8192 pixels");
  }
  return FLAGS_script.empty() ? RunFilesMode(options, method_options, method)
                             : RunScriptMode(options, method_options, method);
}

}  // namespace
}  // namespace editor
}  // namespace msdeform

int main(int argc, char** argv) {
  msdeform::ProgramInfo info;
  info.name = "msdeform_editor";
  info.usage =
      "msdeform_editor: select handles and drag them with the multi-scale method of Liu & Su "
      "2008.\n"
      "  msdeform_editor [--mesh=PATH [--sel=PATH --def=PATH] | --scenario=PATH] [flags]\n"
      "  msdeform_editor --mesh=M --sel=S --def=D --screenshot=OUT.png   (one shot, then exit)\n"
      "  msdeform_editor --script=FILE                                   (replay, then exit)\n"
      "With no input: msdeform's default edit (data/scenarios/armadillo_claw.json).";
  info.version =
      std::string(msdeform::MsdeformVersion()) + " (commit " + msdeform::MsdeformCommit() + ")";
  info.quiet_log_level = 3;
  info.verbose = &FLAGS_verbose;
  return msdeform::RunProgram(
      info, [](const std::vector<std::string>&) { return msdeform::editor::Run(); }, argc, argv);
}
