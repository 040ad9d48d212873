#include "apps/editor/edit_files.h"

#include <filesystem>

#include "apps/editor/saved_edit.h"
#include "apps/outputs.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/mesh_io.h"

namespace msdeform {
namespace editor {

std::vector<std::string> EditFileExtensions(EditFile kind) {
  switch (kind) {
    case EditFile::kMesh:
      return {".off", ".obj", ".ply"};
    case EditFile::kSel:
      return {".sel"};
    case EditFile::kDef:
      return {".def"};
    case EditFile::kScenario:
      return {".json"};
  }
  return {};
}

bool WriteEditFile(const EditSession& session, EditFile kind, const std::string& path,
                   const std::string& final_path, int scenario_frames, std::string* error) {
  if (!session.has_mesh()) {
    *error = final_path + ": no mesh is open";
    return false;
  }
  const HandleLayout& layout = session.committed_layout();
  std::string problem;
  switch (kind) {
    case EditFile::kMesh: {
      Mesh deformed = session.mesh();
      deformed.vertices = session.positions();
      if (!deformed.vertices.allFinite()) {
        *error = final_path + ": the deformed mesh has non-finite coordinates; not written";
        return false;
      }
      if (WriteMesh(path, deformed, &problem)) return true;
      break;
    }
    case EditFile::kSel:
      if (WriteSel(path, layout, session.mesh().num_vertices(), &problem)) return true;
      break;
    case EditFile::kDef:
      if (session.transform().size() > 1) {
        problem = "a .def file holds one transform; this edit has " +
                  std::to_string(session.transform().size()) +
                  " handle groups (save a scenario instead)";
        break;
      }
      if (WriteDef(path, session.transform()[0], &problem)) return true;
      break;
    case EditFile::kScenario: {
      ScenarioText what;
      what.name = std::filesystem::path(final_path).stem().string();
      what.mesh_path = session.inputs().mesh_path;
      what.scenario_path = final_path;
      what.frames = scenario_frames;
      std::string text;
      if (!EditScenarioJson(what, session.mesh(), layout, session.transform(), &text, &problem)) {
        *error = final_path + ": " + problem;
        return false;
      }
      if (WriteText(path, text, &problem)) return true;
      break;
    }
  }
  // The writers name the file they wrote; name the final one.
  if (path != final_path) {
    for (size_t at = problem.find(path); at != std::string::npos;
         at = problem.find(path, at + final_path.size())) {
      problem.replace(at, path.size(), final_path);
    }
  }
  *error = problem.find(final_path) == std::string::npos ? final_path + ": " + problem : problem;
  return false;
}

}  // namespace editor
}  // namespace msdeform
