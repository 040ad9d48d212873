// Editor scripts (--script FILE): a JSON array of actions replayed without a
// person, for tests and figures. `//` and `/* */` comments are allowed; paths
// are relative to the script's folder unless absolute (as in scenarios).
//
//   [
//     {"do": "open", "mesh": "../meshes/cactus.off"},       // also sel+def, or scenario; frames
//     {"do": "label", "as": "fixed", "region": {"slab": {"axis": "z", "from": 0, "to": 0.1}}},
//     {"do": "label", "as": "handle", "region": {"sphere": {"center_vertex": 17, "radius_rel":
//     0.05}}},
//     {"do": "drag", "transform": {"translation_rel": [0, 0, 0.1]}, "frames": 1},
//     {"do": "screenshot", "path": "edit.png"},
//     {"do": "save", "mesh": "edit.off", "sel": "edit.sel", "def": "edit.def", "scenario":
//     "edit.json"}
//   ]
//
// Actions ("do") and their fields (docs: README.md, "Editor"):
//   open        mesh, sel, def, scenario, frames     as the command line's flags
//   label       as (fixed|handle|free), region       a scenario REGION; one layout change;
//               group (handle group, default 0: several handles move independently)
//   clear                                            every vertex free; one layout change
//   brush       as, group, at [x, y] | at_vertex, radius_px, through    the mouse brush
//   lasso       as, group, polygon [[x, y], ...], through   the mouse lasso
//   drag        transform (scenario "transform") | matrix (16 numbers, row by row, as .def)
//               | def (a .def file); frames (default 1): that many Drags from the current
//               pose; group: only that handle group moves (default: every group)
//   mouse_drag  by [dx, dy] pixels, steps (default 10), mode (translate|rotate|roll),
//               group (the drag tool's handle group, as keys 1-9 pick it)
//   reset                                            back to the rest pose
//   set         flag, value                          any method/solver/weights/rigidity/
//                                                    ablation flag of msdeform
//   view        shading (flat|smooth), wireframe, overlay (handles|rigidity|none), nodes,
//               edges, ui                            display toggles
//   camera      fit, yaw_deg, pitch_deg, zoom, target [x, y, z], pan [dx, dy] pixels
//               (applied in this order)
//   screenshot  path (.png), ui (default false), camera (a .json file of the camera)
//   save        mesh, sel, def, scenario, frames (the scenario's, default 30)
// Outputs are staged and appear together when the whole script has run.

#ifndef MSDEFORM_APPS_EDITOR_SCRIPT_H_
#define MSDEFORM_APPS_EDITOR_SCRIPT_H_

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace msdeform {
namespace editor {

struct ScriptAction {
  std::string kind;     // "open", "label", ...
  nlohmann::json args;  // the action's object, "do" included
  std::string where;    // "edit.json: actions[3]", for messages
};

struct Script {
  std::string path;
  std::vector<ScriptAction> actions;
  // `file` relative to the script's folder unless absolute ("" stays "").
  std::string Resolve(const std::string& file) const;
};

// Reads and checks a script: valid JSON, an array of objects, each with a
// known "do" and only that action's fields, of the right JSON types, and
// enumerated values among the allowed ones. Regions, transforms and flag
// values are checked when the action runs (by the scenario reader and the
// flag parser). False with one line naming the file, the action and the
// field.
bool ReadScript(const std::string& path, Script* script, std::string* error);

// The output files the script writes, with the action and field that name
// them ("actions[5].mesh"), resolved against its folder.
struct ScriptOutput {
  std::string path;
  std::string field;
  std::vector<std::string> extensions;
};
std::vector<ScriptOutput> ScriptOutputs(const Script& script);

// Its input files (open's mesh/sel/def/scenario, drag's def), resolved.
std::vector<std::string> ScriptInputs(const Script& script);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_SCRIPT_H_
