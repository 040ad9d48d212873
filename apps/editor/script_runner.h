// Replays an editor script (apps/editor/script.h) in the editor's window:
// each action goes through the code the mouse and the panels use (the brush,
// the lasso, the drag tool, the flags), and every Drag is drawn, so a script's
// timings are the window's. Layout changes are waited for, so a script is
// deterministic.

#ifndef MSDEFORM_APPS_EDITOR_SCRIPT_RUNNER_H_
#define MSDEFORM_APPS_EDITOR_SCRIPT_RUNNER_H_

#include <string>
#include <vector>

#include "apps/editor/editor_app.h"
#include "apps/editor/script.h"
#include "apps/outputs.h"
#include "msdeform/scales/deformer_options.h"

namespace msdeform {
namespace editor {

// Before anything runs: the script's outputs (and `extra`, e.g. --timings)
// checked with CheckOutputs against its inputs; false with the message.
bool CheckScriptOutputs(const Script& script, const std::vector<OutputCheck>& extra, bool overwrite,
                        std::string* error);

// Runs every action; outputs are staged in *staged (the caller commits them,
// so a failing script leaves none). *options holds the deformer flags and
// changes with "set". False with "<script>: actions[i]: <problem>".
bool RunScript(const Script& script, EditorApp* app, DeformerOptions* options, bool quiet,
               StagedOutputs* staged, std::string* error);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_SCRIPT_RUNNER_H_
