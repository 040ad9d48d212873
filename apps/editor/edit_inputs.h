// What the editor opens: a mesh, optionally with a Botsch-Sorkine .sel/.def
// pair or a JSON scenario, read with msdeform's own readers and checked by the
// same rules and in the same order as the msdeform command line, so that an
// input the CLI refuses is refused here with the CLI's message:
//   --sel and --def go together, with --mesh and without --scenario;
//   --scenario=S [--mesh=M overrides its mesh];
//   --frames: 0..100000 (0: the scenario's, or 1), the drag path of the input.
// Unlike the CLI, a --mesh alone opens that mesh without handles (the CLI
// would apply its default scenario to it), and nothing at all opens the CLI's
// default scenario (data/scenarios/armadillo_claw.json).
//
// Loading is split in two, as in the CLI: the names (and the scenario file)
// first, so that outputs can be checked against the inputs before any mesh is
// read, then the files.

#ifndef MSDEFORM_APPS_EDITOR_EDIT_INPUTS_H_
#define MSDEFORM_APPS_EDITOR_EDIT_INPUTS_H_

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "msdeform/core/handles.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/scenario.h"

namespace msdeform {
namespace editor {

// The inputs as the command line (or the Open panel, or a script) names them.
struct OpenRequest {
  std::string mesh;
  std::string sel;
  std::string def;
  std::string scenario;
  int frames = 0;  // 0: the scenario's frame count, or 1 for a .sel/.def pair
};

struct EditInputs {
  std::string name;  // the scenario's name or the mesh file's stem
  std::string mesh_path, sel_path, def_path, scenario_path;  // "" when not given
  Scenario scenario;                                         // parsed when scenario_path is set
  Mesh mesh;
  MeshReadReport read_report;
  // The handles and the drag path of the .sel/.def pair or the scenario;
  // has_layout is false for a mesh opened alone.
  bool has_layout = false;
  HandleLayout layout;
  std::vector<HandleTransforms> path;  // frame k's handle transform, deformed_from_rest
  std::vector<int> watch;             // the scenario's watch region, if any

  // Every input file, for output checks ("" entries skipped by them).
  std::vector<std::string> files() const { return {mesh_path, sel_path, def_path, scenario_path}; }
};

// Step 1: checks the request's combination and range (CLI messages), resolves
// the names and parses the scenario file.
bool ResolveInputNames(const OpenRequest& request, EditInputs* inputs, std::string* error);

// Step 2: reads the mesh, and the .sel/.def pair or resolves the scenario on
// the mesh, and makes the drag path (CLI semantics).
bool ReadInputFiles(const OpenRequest& request, EditInputs* inputs, std::string* error);

// Both steps.
bool LoadEditInputs(const OpenRequest& request, EditInputs* inputs, std::string* error);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_EDIT_INPUTS_H_
