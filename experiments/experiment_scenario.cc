#include "experiments/experiment_scenario.h"

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/drag_path.h"
#include "core/mesh_io.h"
#include "core/scenario.h"

namespace msdeform {

namespace fs = std::filesystem;

bool LoadExperimentScenario(const std::string& path, int frames, ExperimentScenario* scenario,
                            std::string* error) {
  *scenario = ExperimentScenario();
  scenario->file = path;
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot open";
    return false;
  }
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/true);
  } catch (const std::exception& e) {
    *error = path + ": not valid JSON: " + e.what();
    return false;
  }
  if (!json.is_object()) {
    *error = path + ": expected a JSON object";
    return false;
  }
  if (!json.contains("sel")) {
    Scenario parsed;
    if (!ReadScenario(path, &parsed, error)) return false;
    if (frames > 0) parsed.frames = frames;
    scenario->name = parsed.name;
    scenario->mesh_path = parsed.mesh_path;
    if (!ReadMesh(parsed.mesh_path, &scenario->mesh, error)) return false;
    Eigen::Affine3d target;
    if (!ResolveScenario(parsed, scenario->mesh, &scenario->layout, &scenario->watch, &target,
                         error)) {
      return false;
    }
    scenario->has_watch = parsed.has_watch;
    scenario->path = DragPath(parsed, scenario->mesh, scenario->layout);
    return true;
  }

  // A Botsch-Sorkine entry.
  const fs::path folder = fs::path(path).parent_path();
  auto string_field = [&](const char* key, std::string* value) {
    if (!json.contains(key) || !json[key].is_string()) {
      *error = path + ": " + key + ": expected a string";
      return false;
    }
    *value = json[key].get<std::string>();
    return true;
  };
  std::string mesh, sel, def;
  if (!string_field("mesh", &mesh) || !string_field("sel", &sel) || !string_field("def", &def)) {
    return false;
  }
  for (const auto& [key, value] : json.items()) {
    if (key != "name" && key != "description" && key != "mesh" && key != "sel" && key != "def" &&
        key != "frames") {
      *error = path + ": " + key + ": unknown field of a .sel/.def entry";
      return false;
    }
  }
  scenario->name = fs::path(path).stem().string();
  if (json.contains("name") && !string_field("name", &scenario->name)) return false;
  int file_frames = 1;
  if (json.contains("frames")) {
    if (!json["frames"].is_number_integer() || json["frames"].get<int>() < 1) {
      *error = path + ": frames: expected an integer >= 1";
      return false;
    }
    file_frames = json["frames"].get<int>();
  }
  scenario->mesh_path = (folder / mesh).lexically_normal().string();
  if (!ReadMesh(scenario->mesh_path, &scenario->mesh, error)) return false;
  if (!ReadSel((folder / sel).lexically_normal().string(), scenario->mesh.num_vertices(),
               &scenario->layout, error)) {
    return false;
  }
  Eigen::Affine3d target;
  if (!ReadDef((folder / def).lexically_normal().string(), &target, error)) return false;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : scenario->layout.moveable) centroid += scenario->mesh.vertices.col(v);
  centroid /= static_cast<double>(scenario->layout.moveable.size());
  scenario->path = InterpolateDragPath(target, centroid, frames > 0 ? frames : file_frames);
  return true;
}

}  // namespace msdeform
