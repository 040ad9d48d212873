#include "apps/editor/saved_edit.h"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "msdeform/core/scenario.h"

namespace msdeform {
namespace editor {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// A vertex list on few lines: 16 ids per line, indented by `indent`.
std::string IdList(const std::vector<int>& ids, const std::string& indent) {
  std::ostringstream text;
  text << "[";
  for (size_t i = 0; i < ids.size(); ++i) {
    if (i > 0) text << (i % 16 == 0 ? ",\n" + indent : ", ");
    text << ids[i];
  }
  text << "]";
  return text.str();
}

// `mesh` relative to the folder of `scenario` when they share a folder below
// the root (a scenario beside its data moves with it), else absolute.
std::string MeshReference(const std::string& mesh, const std::string& scenario) {
  const fs::path mesh_abs = fs::absolute(mesh).lexically_normal();
  const fs::path folder = fs::absolute(scenario).lexically_normal().parent_path();
  auto m = mesh_abs.begin(), f = folder.begin();
  int shared = 0;
  for (; m != mesh_abs.end() && f != folder.end() && *m == *f; ++m, ++f) ++shared;
  const fs::path relative = mesh_abs.lexically_relative(folder);
  // One shared element is the root "/" alone.
  return shared <= 1 || relative.empty() ? mesh_abs.string() : relative.string();
}

}  // namespace

bool EditScenarioJson(const ScenarioText& what, const Mesh& mesh, const HandleLayout& layout,
                      const Eigen::Affine3d& deformed_from_rest, std::string* text,
                      std::string* error) {
  if (!ValidateHandles(layout, mesh.num_vertices(), error)) return false;
  if (what.frames < 1 || what.frames > kMaxScenarioFrames) {
    *error = "frames: " + std::to_string(what.frames) + ": expected 1.." +
             std::to_string(kMaxScenarioFrames);
    return false;
  }
  const Eigen::Matrix3d rotation = deformed_from_rest.linear();
  const double off_rotation =
      (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).norm();
  if (!(off_rotation < 1e-9) || !(rotation.determinant() > 0.0)) {
    std::ostringstream text;
    text << "the handle transform is not a rotation and a translation (|A^T A - I| = "
         << off_rotation << "), which a scenario cannot state exactly; save the .sel/.def pair "
         << "instead";
    *error = text.str();
    return false;
  }
  // x -> A x + b read as a rotation R = A about the rest centroid c, then a
  // translation t: R (x - c) + c + t, so t = A c + b - c.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : layout.moveable) centroid += mesh.vertices.col(v);
  centroid /= static_cast<double>(layout.moveable.size());
  const Eigen::Vector3d translation = deformed_from_rest * centroid - centroid;
  const Eigen::AngleAxisd angle_axis(rotation);

  Json transform = {{"translation", {translation.x(), translation.y(), translation.z()}}};
  if (angle_axis.angle() != 0.0) {
    const Eigen::Vector3d axis = angle_axis.axis();
    transform["rotation"] = {{"axis", {axis.x(), axis.y(), axis.z()}},
                             {"angle_deg", angle_axis.angle() * 180.0 / M_PI},
                             {"center", "centroid"}};
  }
  std::ostringstream out;
  out << "{\n"
      << "  \"name\": " << Json(what.name).dump() << ",\n"
      << "  \"description\": \"Made with msdeform_editor\",\n"
      << "  \"mesh\": " << Json(MeshReference(what.mesh_path, what.scenario_path)).dump() << ",\n";
  if (!layout.fixed.empty()) {
    out << "  \"fixed\": [{\"vertices\": " << IdList(layout.fixed, "                ") << "}],\n";
  }
  out << "  \"handle\": {\"vertices\": " << IdList(layout.moveable, "                         ")
      << "},\n"
      << "  \"transform\": " << transform.dump() << ",\n"
      << "  \"frames\": " << what.frames << "\n"
      << "}\n";
  *text = out.str();
  return true;
}

}  // namespace editor
}  // namespace msdeform
