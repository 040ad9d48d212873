// An edit made in the editor, written as files msdeform and the experiment
// runner read unchanged (docs/formats.md): the Botsch-Sorkine .sel/.def pair
// (core/handles.h writes them) and a JSON scenario.
//
// The scenario is self-contained: the fixed and moveable vertices as vertex
// lists and the handle transform as a rotation about the handle's rest
// centroid followed by a translation, which is how scenarios state motions:
//
//   {
//     "name": "cactus_edit",
//     "description": "Made with msdeform_editor",
//     "mesh": "../meshes/cactus.off",             // relative to the scenario's folder
//     "fixed": [{"vertices": [0, 1, ...]}],       // left out when nothing is fixed
//     "handle": {"vertices": [17, 18, ...]},
//     "transform": {"translation": [x, y, z],
//                   "rotation": {"axis": [x, y, z], "angle_deg": a, "center": "centroid"}},
//     "frames": 30
//   }
//
// Numbers are printed so that they read back as the same doubles; the angle in
// degrees rounds once (about 1e-16 relative).

#ifndef MSDEFORM_APPS_EDITOR_SAVED_EDIT_H_
#define MSDEFORM_APPS_EDITOR_SAVED_EDIT_H_

#include <Eigen/Geometry>
#include <string>

#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"

namespace msdeform {
namespace editor {

struct ScenarioText {
  std::string name;           // "name"
  std::string mesh_path;      // the rest mesh's file, as the editor opened it
  std::string scenario_path;  // where the scenario goes ("mesh" is made relative to it)
  int frames = 30;            // "frames": msdeform's drag steps to the transform, 1..100000
};

// The scenario for `layout` (valid for `mesh`) and the handle transforms
// `deformed_from_rest` (one, or one a handle group; each a rotation and a
// translation: |A^T A - I| < 1e-9, det A > 0), with "handle" and "transform"
// for one group and "handles" for several. False with a message when a
// transform is not one (a scenario could state it only approximately, e.g. a
// .def written with six digits; save the .sel/.def pair instead) or frames is
// out of range.
bool EditScenarioJson(const ScenarioText& what, const Mesh& mesh, const HandleLayout& layout,
                      const HandleTransforms& deformed_from_rest, std::string* text,
                      std::string* error);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_SAVED_EDIT_H_
