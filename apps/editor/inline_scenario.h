// Regions and handle motions written inline, in a script, in the scenario
// format of docs/formats.md, and resolved by the scenario reader itself
// (core/scenario.h), so a script's region means exactly what it means in a
// scenario file and its errors are the scenario reader's.
//
// core/scenario.h reads scenarios from files only; these functions hand the
// reader a one-off scenario file holding the inline part (see
// docs/decisions/editor.md) and rewrite the file name and the
// field in its messages to `where` (e.g. "edit.json: actions[3]").

#ifndef MSDEFORM_APPS_EDITOR_INLINE_SCENARIO_H_
#define MSDEFORM_APPS_EDITOR_INLINE_SCENARIO_H_

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"

namespace msdeform {
namespace editor {

// The vertices (sorted, unique, at least one) `region` selects on `mesh`.
// Messages read "<where>.region.<field>: <problem>".
bool SelectInlineRegion(const nlohmann::json& region, const Mesh& mesh, const std::string& where,
                        std::vector<int>* ids, std::string* error);

// The drag path of `transform` (a scenario "transform" object) in `frames`
// steps, for a handle made of `moveable` (its rest centroid is the rotation
// centre unless the transform gives one). Messages read
// "<where>.transform.<field>: <problem>".
bool InlineMotionPath(const nlohmann::json& transform, int frames, const Mesh& mesh,
                      const std::vector<int>& moveable, const std::string& where,
                      std::vector<HandleTransforms>* path, std::string* error);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_INLINE_SCENARIO_H_
