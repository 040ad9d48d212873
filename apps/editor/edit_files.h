// Writing what the editor holds: the deformed mesh, the committed handle
// layout as a .sel file, the handle transform as a .def file, and both as a
// JSON scenario (apps/editor/saved_edit.h). Each write is atomic (a temporary
// renamed into place); callers check output paths with CheckOutputs
// (apps/outputs.h) first and may stage them (StagedOutputs).

#ifndef MSDEFORM_APPS_EDITOR_EDIT_FILES_H_
#define MSDEFORM_APPS_EDITOR_EDIT_FILES_H_

#include <string>
#include <vector>

#include "apps/editor/edit_session.h"

namespace msdeform {
namespace editor {

enum class EditFile { kMesh, kSel, kDef, kScenario };

// The extensions each kind may be written as (lower case, with the dot).
std::vector<std::string> EditFileExtensions(EditFile kind);

// Writes `kind` to `path`. `final_path` is where the file ends up (differs
// from `path` for a staged write): a scenario's "mesh" is relative to its
// folder, and its "name" is its stem. `scenario_frames` is the scenario's
// "frames". False with a message naming `final_path`.
bool WriteEditFile(const EditSession& session, EditFile kind, const std::string& path,
                   const std::string& final_path, int scenario_frames, std::string* error);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_EDIT_FILES_H_
