#include "experiments/experiment_scenario.h"

#include <algorithm>
#include <filesystem>

#include "msdeform/core/mesh_io.h"
#include "msdeform/core/scenario.h"

namespace msdeform {

bool LoadExperimentScenario(const std::string& path, int frames, ExperimentScenario* scenario,
                            std::string* error, const std::string& mesh_path) {
  *scenario = ExperimentScenario();
  scenario->file = path;
  if (frames < 0 || frames > kMaxScenarioFrames) {
    *error = "frames: expected 0.." + std::to_string(kMaxScenarioFrames) +
             " (0: the scenario's), got " + std::to_string(frames);
    return false;
  }
  Scenario parsed;
  if (!ReadScenario(path, &parsed, error)) return false;
  if (frames > 0) parsed.frames = frames;
  scenario->name = parsed.name;
  scenario->mesh_path = mesh_path.empty() ? parsed.mesh_path : mesh_path;
  if (!ReadMesh(scenario->mesh_path, &scenario->mesh, error)) return false;
  HandleTransforms target;
  if (!ResolveScenario(parsed, scenario->mesh, &scenario->layout, &scenario->watch, &target,
                       error)) {
    *error = path + " on " + scenario->mesh_path + ": " + *error;
    return false;
  }
  scenario->has_watch = parsed.has_watch;
  scenario->path = DragPath(parsed, scenario->mesh, scenario->layout);
  return true;
}

bool ListScenarioFiles(const std::string& folder, std::vector<std::string>* files,
                       std::string* error) {
  files->clear();
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    if (entry.path().extension() == ".json") files->push_back(entry.path().string());
  }
  if (ec) {
    *error = folder + ": " + ec.message();
    return false;
  }
  std::sort(files->begin(), files->end());
  return true;
}

}  // namespace msdeform
