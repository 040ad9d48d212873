#include "apps/editor/edit_inputs.h"

#include <algorithm>
#include <filesystem>
#include <utility>

#include "msdeform/core/build_info.h"
#include "msdeform/core/drag_path.h"

namespace msdeform {
namespace editor {

namespace fs = std::filesystem;

bool ResolveInputNames(const OpenRequest& request, EditInputs* inputs, std::string* error) {
  *inputs = EditInputs();
  if (request.frames < 0 || request.frames > kMaxScenarioFrames) {
    *error = "--frames=" + std::to_string(request.frames) + ": expected 0.." +
             std::to_string(kMaxScenarioFrames);
    return false;
  }
  if (!request.sel.empty() || !request.def.empty()) {
    if (request.sel.empty() || request.def.empty() || request.mesh.empty() ||
        !request.scenario.empty()) {
      *error = "--sel and --def go together, with --mesh and without --scenario";
      return false;
    }
    inputs->mesh_path = request.mesh;
    inputs->sel_path = request.sel;
    inputs->def_path = request.def;
    inputs->name = fs::path(request.mesh).stem().string();
    return true;
  }
  if (!request.mesh.empty() && request.scenario.empty()) {
    inputs->mesh_path = request.mesh;
    inputs->name = fs::path(request.mesh).stem().string();
    return true;
  }
  inputs->scenario_path =
      request.scenario.empty() ? DataDir() + "/scenarios/armadillo_claw.json" : request.scenario;
  if (!ReadScenario(inputs->scenario_path, &inputs->scenario, error)) return false;
  if (request.frames > 0) inputs->scenario.frames = request.frames;
  inputs->name = inputs->scenario.name;
  inputs->mesh_path = request.mesh.empty() ? inputs->scenario.mesh_path : request.mesh;
  inputs->sel_path = inputs->scenario.sel_path;
  inputs->def_path = inputs->scenario.def_path;
  return true;
}

bool ReadInputFiles(const OpenRequest& request, EditInputs* inputs, std::string* error) {
  if (!ReadMesh(inputs->mesh_path, &inputs->mesh, &inputs->read_report, error)) return false;
  if (!inputs->scenario_path.empty()) {
    HandleTransforms deformed_from_rest;
    if (!ResolveScenario(inputs->scenario, inputs->mesh, &inputs->layout, &inputs->watch,
                         &deformed_from_rest, error)) {
      return false;
    }
    inputs->path = DragPath(inputs->scenario, inputs->mesh, inputs->layout);
    inputs->has_layout = true;
    return true;
  }
  if (inputs->sel_path.empty()) return true;  // a mesh alone
  if (!ReadSel(inputs->sel_path, inputs->mesh.num_vertices(), &inputs->layout, error)) {
    return false;
  }
  Eigen::Affine3d deformed_from_rest;
  if (!ReadDef(inputs->def_path, &deformed_from_rest, error)) return false;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : inputs->layout.moveable) centroid += inputs->mesh.vertices.col(v);
  centroid /= static_cast<double>(inputs->layout.moveable.size());
  const std::vector<Eigen::Affine3d> path =
      InterpolateDragPath(deformed_from_rest, centroid, std::max(request.frames, 1));
  inputs->path.assign(path.begin(), path.end());
  inputs->has_layout = true;
  return true;
}

bool LoadEditInputs(const OpenRequest& request, EditInputs* inputs, std::string* error) {
  return ResolveInputNames(request, inputs, error) && ReadInputFiles(request, inputs, error);
}

}  // namespace editor
}  // namespace msdeform
