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

// x -> A x + b as a scenario's "transform": a rotation R = A about the rest
// centroid c of `vertices`, then a translation t: R (x - c) + c + t, so
// t = A c + b - c. False when A is not a rotation, which a scenario cannot
// state exactly.
bool ScenarioTransform(const Mesh& mesh, const std::vector<int>& vertices,
                       const Eigen::Affine3d& deformed_from_rest, Json* transform,
                       std::string* error) {
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
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : vertices) centroid += mesh.vertices.col(v);
  centroid /= static_cast<double>(vertices.size());
  const Eigen::Vector3d translation = deformed_from_rest * centroid - centroid;
  const Eigen::AngleAxisd angle_axis(rotation);
  *transform = {{"translation", {translation.x(), translation.y(), translation.z()}}};
  if (angle_axis.angle() != 0.0) {
    const Eigen::Vector3d axis = angle_axis.axis();
    (*transform)["rotation"] = {{"axis", {axis.x(), axis.y(), axis.z()}},
                                {"angle_deg", angle_axis.angle() * 180.0 / M_PI},
                                {"center", "centroid"}};
  }
  return true;
}

}  // namespace

bool EditScenarioJson(const ScenarioText& what, const Mesh& mesh, const HandleLayout& layout,
                      const HandleTransforms& deformed_from_rest, std::string* text,
                      std::string* error) {
  if (!ValidateHandles(layout, mesh.num_vertices(), error) ||
      !deformed_from_rest.Fits(layout, error)) {
    return false;
  }
  if (what.frames < 1 || what.frames > kMaxScenarioFrames) {
    *error = "frames: " + std::to_string(what.frames) + ": expected 1.." +
             std::to_string(kMaxScenarioFrames);
    return false;
  }
  const int num_groups = layout.num_groups();
  // Each group's transform as the scenario states it (a rotation about the
  // group's rest centroid, then a translation), and its vertices.
  std::vector<Json> transforms;
  std::vector<std::vector<int>> group_vertices;
  for (int g = 0; g < num_groups; ++g) {
    group_vertices.push_back(num_groups == 1 ? layout.moveable : HandleGroupVertices(layout, g));
    Json transform;
    if (!ScenarioTransform(mesh, group_vertices.back(), deformed_from_rest[g], &transform,
                           error)) {
      if (num_groups > 1) *error = "handle group " + std::to_string(g) + ": " + *error;
      return false;
    }
    transforms.push_back(std::move(transform));
  }
  std::ostringstream out;
  out << "{\n"
      << "  \"name\": " << Json(what.name).dump() << ",\n"
      << "  \"description\": \"Made with msdeform_editor\",\n"
      << "  \"mesh\": " << Json(MeshReference(what.mesh_path, what.scenario_path)).dump() << ",\n";
  if (!layout.fixed.empty()) {
    out << "  \"fixed\": [{\"vertices\": " << IdList(layout.fixed, "                ") << "}],\n";
  }
  if (num_groups == 1) {
    out << "  \"handle\": {\"vertices\": " << IdList(layout.moveable, "                         ")
        << "},\n"
        << "  \"transform\": " << transforms[0].dump() << ",\n";
  } else {
    out << "  \"handles\": [\n";
    for (int g = 0; g < num_groups; ++g) {
      out << "    {\"region\": {\"vertices\": "
          << IdList(group_vertices[g], "                            ") << "},\n"
          << "     \"transform\": " << transforms[g].dump() << "}"
          << (g + 1 < num_groups ? "," : "") << "\n";
    }
    out << "  ],\n";
  }
  out << "  \"frames\": " << what.frames << "\n"
      << "}\n";
  *text = out.str();
  return true;
}

}  // namespace editor
}  // namespace msdeform
