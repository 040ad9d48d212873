#include "apps/editor/inline_scenario.h"

#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <utility>

#include "msdeform/core/handles.h"
#include "msdeform/core/scenario.h"

namespace msdeform {
namespace editor {
namespace {

namespace fs = std::filesystem;

// `scenario` written to a fresh temporary file, read back by ReadScenario and
// resolved on `mesh`; the file is removed before returning. Messages name
// `where` instead of the file, with a field `from` renamed to `to`.
bool ResolveOneOff(const nlohmann::json& scenario, const Mesh& mesh, const std::string& where,
                   const std::string& from, const std::string& to, Scenario* parsed,
                   HandleLayout* layout, std::string* error) {
  std::string name = (fs::temp_directory_path() / "msdeform_editor_XXXXXX.json").string();
  const int fd = mkstemps(name.data(), 5);
  if (fd < 0) {
    *error = where + ": cannot create a temporary file in " + fs::temp_directory_path().string();
    return false;
  }
  const std::string text = scenario.dump();
  const bool written = write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  close(fd);
  std::string problem;
  std::vector<int> watch;
  HandleTransforms final_transform;
  const bool ok = written && ReadScenario(name, parsed, &problem) &&
                  ResolveScenario(*parsed, mesh, layout, &watch, &final_transform, &problem);
  std::error_code ignored;
  fs::remove(name, ignored);
  if (ok) return true;
  if (!written) {
    *error = where + ": cannot write a temporary file in " + fs::temp_directory_path().string();
    return false;
  }
  // "<file>: <field>...: <what>" -> "<where>.<renamed field>...: <what>".
  std::string rest = problem.rfind(name + ": ", 0) == 0 ? problem.substr(name.size() + 2) : problem;
  if (rest.rfind(from, 0) == 0) rest = to + rest.substr(from.size());
  *error = where + "." + rest;
  return false;
}

}  // namespace

bool SelectInlineRegion(const nlohmann::json& region, const Mesh& mesh, const std::string& where,
                        std::vector<int>* ids, std::string* error) {
  // The mesh is given, never read: "mesh" only satisfies the format.
  const nlohmann::json scenario = {{"mesh", "inline.off"}, {"handle", region}};
  Scenario parsed;
  HandleLayout layout;
  if (!ResolveOneOff(scenario, mesh, where, "handle", "region", &parsed, &layout, error)) {
    return false;
  }
  *ids = std::move(layout.moveable);
  return true;
}

bool InlineMotionPath(const nlohmann::json& transform, int frames, const Mesh& mesh,
                      const std::vector<int>& moveable, const std::string& where,
                      std::vector<HandleTransforms>* path, std::string* error) {
  const nlohmann::json scenario = {{"mesh", "inline.off"},
                                   {"handle", {{"vertices", moveable}}},
                                   {"transform", transform},
                                   {"frames", frames}};
  Scenario parsed;
  HandleLayout layout;
  if (!ResolveOneOff(scenario, mesh, where, "transform", "transform", &parsed, &layout, error)) {
    return false;
  }
  *path = DragPath(parsed, mesh, layout);
  return true;
}

}  // namespace editor
}  // namespace msdeform
