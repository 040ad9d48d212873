#include "experiments/experiment_scenario.h"

#include "core/mesh_io.h"
#include "core/scenario.h"

namespace msdeform {

bool LoadExperimentScenario(const std::string& path, int frames, ExperimentScenario* scenario,
                            std::string* error, const std::string& mesh_path) {
  *scenario = ExperimentScenario();
  scenario->file = path;
  Scenario parsed;
  if (!ReadScenario(path, &parsed, error)) return false;
  if (frames > 0) parsed.frames = frames;
  scenario->name = parsed.name;
  scenario->mesh_path = mesh_path.empty() ? parsed.mesh_path : mesh_path;
  if (!ReadMesh(scenario->mesh_path, &scenario->mesh, error)) return false;
  Eigen::Affine3d target;
  if (!ResolveScenario(parsed, scenario->mesh, &scenario->layout, &scenario->watch, &target,
                       error)) {
    *error = path + " on " + scenario->mesh_path + ": " + *error;
    return false;
  }
  scenario->has_watch = parsed.has_watch;
  scenario->path = DragPath(parsed, scenario->mesh, scenario->layout);
  return true;
}

}  // namespace msdeform
